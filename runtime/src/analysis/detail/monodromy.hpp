// The tangent integration behind floquet_analysis and the periodic-orbit shooting: one
// Gauss–Legendre (order 6) pass over a period that carries the monodromy matrix along, or
// (floquet_analysis) one Taylor pass over the variational equations.
#pragma once

#include <Eigen/Dense>
#include <functional>
#include <span>
#include <vector>

#include "npend/chain.hpp"
#include "npend/integrators/taylor.hpp"
#include "npend/run_control.hpp"

namespace npend::detail {

/// The monodromy over one period in `steps` Gauss–Legendre steps; x ends at x(T) and
/// `tangent` at ∂x(T)/∂x(0). `each_step` (may be empty) sees the state after every step.
/// False if the control asked to stop (`done` steps before this run count towards its
/// progress out of `total`).
bool monodromy(const chain& c, std::vector<double>& x, double period, int steps, int done,
               int total, run_control* control, Eigen::MatrixXd& tangent,
               const std::function<void(std::span<const double>)>& each_step = {});

/// The most Taylor steps floquet_analysis lets taylor_monodromy take over one period before
/// it gives up (its steps collapsed).
inline constexpr int taylor_monodromy_max_steps = 10'000'000;

/// The monodromy over one period by Taylor's method at abs = rel = `tolerance` on the state
/// and the 2n tangent vectors (taylor_tangents); x ends at x(T), `tangent` at ∂x(T)/∂x(0),
/// `steps` at the steps taken. `each_step` (may be empty) sees the integrator after every
/// step (its polynomials span step_begin() .. time()). Progress in periods: `done` before
/// this run, of `total`. False if the control asked to stop. Throws integration_error where
/// the state or the tangents become non-finite, or after max_steps steps.
bool taylor_monodromy(const chain& c, std::vector<double>& x, double period, double tolerance,
                      double done, double total, run_control* control, Eigen::MatrixXd& tangent,
                      int& steps, int max_steps,
                      const std::function<void(const taylor_tangents&)>& each_step = {});

}  // namespace npend::detail
