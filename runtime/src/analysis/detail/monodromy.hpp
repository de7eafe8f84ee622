// The tangent integration behind floquet_analysis and the periodic-orbit shooting: one
// Gauss–Legendre (order 6) pass over a period that carries the monodromy matrix along.
#pragma once

#include <Eigen/Dense>
#include <functional>
#include <span>
#include <vector>

#include "npend/chain.hpp"
#include "npend/run_control.hpp"

namespace npend::detail {

/// The monodromy over one period in `steps` Gauss–Legendre steps; x ends at x(T) and
/// `tangent` at ∂x(T)/∂x(0). `each_step` (may be empty) sees the state after every step.
/// False if the control asked to stop (`done` steps before this run count towards its
/// progress out of `total`).
bool monodromy(const chain& c, std::vector<double>& x, double period, int steps, int done,
               int total, run_control* control, Eigen::MatrixXd& tangent,
               const std::function<void(std::span<const double>)>& each_step = {});

}  // namespace npend::detail
