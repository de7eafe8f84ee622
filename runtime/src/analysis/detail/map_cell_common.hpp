// What a map's cells share, whether they run one at a time (chaos_map.cpp) or on the batch
// lanes of an ISA (map_lanes.cpp, compiled once per ISA): the flip test and its location in
// a step, the library's path for the cells the lanes hand back, and an indicator map's value.
// The lanes' units include this before their ISA switch, so its inline functions and
// templates are compiled for the baseline ISA wherever they are used.
#pragma once

#include <cmath>
#include <cstddef>
#include <limits>
#include <numbers>
#include <numeric>
#include <span>
#include <vector>

#include "npend/analysis/chaos/chaos_indicators.hpp"
#include "npend/analysis/chaos/chaos_map.hpp"
#include "npend/chain.hpp"
#include "npend/integrators/integration_error.hpp"
#include "npend/run_control.hpp"

namespace npend::detail {

/// Whether a flip of arm k (1..n) counts: `link` is the one arm asked about, or 0 for any.
inline bool watches_arm(int link, std::size_t k) {
  return link == 0 || static_cast<std::size_t>(link) == k;
}

/// Whether an arm (or arm o.link) of the n-link state x is at or past the upright position.
inline bool has_flipped(const double* x, std::size_t n, const flip_options& o) {
  for (std::size_t k = 0; k < n; ++k)
    if (watches_arm(o.link, k + 1) && std::fabs(x[k]) >= std::numbers::pi) return true;
  return false;
}

/// The flip time inside a fixed step from t0 to t0 + h, at whose end a watched arm is upright
/// (and none at its start): the earliest of the watched arms' upright times by the step's
/// cubic Hermite interpolant, from the angles phi0, phi1 and their rates dphi0, dphi1 (dim
/// n) at the ends. Accurate to O(h⁴) as rk4 is; the lanes and the library call it with the
/// same numbers, so that they agree to round-off.
double hermite_flip_time(const double* phi0, const double* dphi0, const double* phi1,
                         const double* dphi1, std::size_t n, double t0, double h,
                         const flip_options& o);

/// Whether the energy at x1, the state at time t1 at the end of the step in which a flip was
/// seen, lets the flip be believed: |H(x1) − h0| ≤ flip_energy_tolerance · h0, h0 = H(x0)
/// (for a damped chain, whose H only falls, H(x1) − h0 ≤ flip_energy_tolerance · h0). A
/// driven chain is fed energy by its pivot and is not checked. False for a non-finite state.
bool flip_energy_holds(const chain& c, double h0, std::span<const double> x1, double t1);

/// The flip time inside a step from t0 (not flipped) to t1 (flipped), flipped_at(t) telling
/// the dense output's verdict: bisection down to adjacent doubles, the first time found
/// flipped. The scalar path and the lanes bisect alike, so that they agree to round-off.
template <class Flipped>
double locate_flip(double t0, double t1, const Flipped& flipped_at) {
  for (;;) {
    const double mid = t0 + 0.5 * (t1 - t0);
    if (mid <= t0 || mid >= t1) return t1;
    (flipped_at(mid) ? t1 : t0) = mid;
  }
}

/// The values of the starts `cells` by `cell` (the library's scalar path; starts of m numbers
/// each, one after another) into out, NaN where the integration fails (integration_error),
/// and where `control` asked to stop before the cell began.
template <class Cell>
void by_library(std::span<const double> starts, std::size_t m,
                const std::vector<std::size_t>& cells, const Cell& cell, std::vector<double>& out,
                run_control* control = nullptr) {
  for (const std::size_t i : cells) try {
      out[i] = stop_requested(control) ? std::numeric_limits<double>::quiet_NaN()
                                       : cell(starts.subspan(i * m, m));
    } catch (const integration_error&) {
      out[i] = std::numeric_limits<double>::quiet_NaN();
    }
}

/// The queue of every start, in order: 0, 1, …, count - 1.
inline std::vector<std::size_t> all_cells(std::size_t count) {
  std::vector<std::size_t> queue(count);
  std::iota(queue.begin(), queue.end(), std::size_t{0});
  return queue;
}

/// The map's value of an indicator sample: FLI, MEGNO ⟨Y⟩, SALI or GALI_k.
double indicator_value(map_quantity quantity, const chaos_indicator_sample& sample);

}  // namespace npend::detail
