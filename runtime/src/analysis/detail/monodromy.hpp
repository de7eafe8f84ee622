// The tangent integration behind floquet_analysis and the shootings of periodic and forced
// orbits: one Gauss–Legendre (order 6) pass over a period that carries the monodromy matrix
// along, or one Taylor pass over the variational equations.
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
/// it gives up (its steps collapsed); the shootings stop far sooner
/// (taylor_shooting_max_steps).
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

/// A Newton iterate far from an orbit can spin the chain fast, where Taylor's adaptive steps
/// would shrink without end (gauss6's fixed steps fail at once there): the shootings count a
/// pass that needs more than this many Taylor steps per drive period (forced orbits) or per
/// segment (free orbits) as a failed iterate. gauss6 takes 400 steps per period by default.
inline constexpr int taylor_shooting_max_steps = 10'000;

/// Taylor's steps are long (a dozen per period), so amplitudes sample the state's polynomial
/// at this many points of each step, its end included.
inline constexpr int taylor_samples_per_step = 16;

/// An each_step for taylor_monodromy that shows `track` the state at taylor_samples_per_step
/// evenly spaced points of each step.
std::function<void(const taylor_tangents&)> sampled_steps(
    std::function<void(std::span<const double>)> track);

}  // namespace npend::detail
