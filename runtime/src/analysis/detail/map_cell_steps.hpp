// How a map's cells count their steps and vectors, shared by the CPU's cells (chaos_map.cpp)
// and the GPU's (map_device.cpp), so that both take the same steps.
#pragma once

#include <cmath>
#include <cstddef>

#include "npend/analysis/chaos/chaos_map.hpp"
#include "npend/analysis/chaos/lyapunov.hpp"
#include "npend/chain.hpp"

namespace npend::detail {

/// The whole rk4 steps of dt up to t_end (a last shorter step, where a quantity takes one,
/// lands on t_end).
inline long long whole_steps(double t_end, double dt) {
  return static_cast<long long>(std::floor(t_end / dt + 1e-9));
}

/// The deviation vectors an indicator map integrates: GALI_k's k, 2 for the others.
inline std::size_t indicator_vectors(const chain& c, const map_cell_options& o) {
  const int k = o.gali_order == 0 ? c.links() + 1 : o.gali_order;
  return o.quantity == map_quantity::gali ? static_cast<std::size_t>(k) : 2;
}

/// What a Lyapunov map integrates: rk4 at dt (or dopri5), one tangent vector.
inline lyapunov_options map_lyapunov_options(const map_cell_options& o) {
  lyapunov_options lo;
  lo.integration.stepper = o.stepping.stepper;
  lo.integration.t_end = o.t_end;
  lo.integration.dt = o.dt;
  lo.integration.abs_tol = o.stepping.abs_tol;
  lo.integration.rel_tol = o.stepping.rel_tol;
  lo.integration.control = o.control;
  return lo;
}

}  // namespace npend::detail
