// The per-cell quantities of a chaos map (npend map): the time to the first flip of an arm
// (J. Heyl, "The double pendulum fractal", 2008) and the maximal Lyapunov exponent, for one
// start state each. The grid, its tiles, threads and files are the command's
// (apps/npend/map_command.cpp).
#pragma once

#include <span>

#include "npend/analysis/lyapunov.hpp"
#include "npend/chain.hpp"

namespace npend {

/// Whether the energy of x0 forbids a flip — an arm passing the upright position — so that
/// the cell needs no integration. Arm k upright (φ_k = π) needs V ≥ 2 g G_k, the least V with
/// φ_k = π (the others hanging: V is a sum of g G_j (1 − cos φ_j), G_j = m_j c_j + l_j μ_{j+1}
/// the moment gravity acts on, c = l for point masses). `link` = 0: any arm (the least of
/// those bounds); k ≥ 1: arm k. Conservative chains only (throws std::invalid_argument).
bool energy_forbids_flip(const chain& c, std::span<const double> x0, int link = 0);

struct flip_options {
  double t_end = 100;  ///< give up after this time (s): the cell is +inf
  double dt = 0.01;    ///< rk4's step (s); the flip time is resolved to a step
  int link = 0;        ///< 0: any arm; k ≥ 1: arm k only
};

/// The time (s) at which an arm (or arm `link`) of the chain started at x0 first passes the
/// upright position, |φ_k| ≥ π (the angles are not wrapped): the end of the first rk4 step
/// of `dt` at which it does. +inf if it does not by t_end, or if energy_forbids_flip (then
/// without integrating). Throws std::invalid_argument for bad options or a non-conservative
/// chain, npend::integration_error if the state becomes non-finite.
double flip_time(const chain& c, std::span<const double> x0, const flip_options& options);

}  // namespace npend
