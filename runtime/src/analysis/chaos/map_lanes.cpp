// The map's cells on the batch lanes of one ISA: compiled for the compiler's own ISA and
// again for each lane variant above it (cmake/npend_lanes.cmake), each compilation filling
// one detail::map_lanes (map_lanes.hpp) that the map picks from at run time.

// clang-format off
// Every header that is not lane code first: in a lane variant's unit,
// integrators/batch_lanes.hpp switches what follows to the variant's ISA (npend/batch_math.hpp),
// and an inline function first seen after it would be compiled for that ISA, whichever unit's
// copy the linker keeps.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numbers>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "analysis/chaos/map_lanes.hpp"
#include "analysis/detail/map_cell_common.hpp"
#include "analysis/detail/map_cell_steps.hpp"
#include "npend/analysis/chaos/chaos_indicators.hpp"
#include "npend/analysis/chaos/chaos_map.hpp"
#include "npend/chain.hpp"
#include "npend/integrators/gauss_legendre.hpp"
#include "npend/integrators/integrate.hpp"
#include "npend/run_control.hpp"

#include "integrators/batch_lanes.hpp"
// clang-format on

namespace npend {

namespace {

using detail::all_cells;
using detail::by_library;
using detail::flip_energy_holds;
using detail::has_flipped;
using detail::hermite_flip_time;
using detail::locate_flip;
using detail::watches_arm;
using detail::whole_steps;

// Calls visit(make), make(dt) making the fixed-step lane stepper `stepper` names (rk4,
// gauss4 or gauss6) on the chain's state alone.
template <class Visit>
void with_fixed_step_lanes(const batch_kernels& k, const chain& c, stepper_kind stepper,
                           const Visit& visit) {
  const auto system = [&] {
    return detail::lane_system(k, c.packed_parameters().data(), c.links(), 0, false);
  };
  switch (stepper) {
    case stepper_kind::gauss4:
      return visit([&](double dt) { return detail::lane_gauss<2>(system(), dt); });
    case stepper_kind::gauss6:
      return visit([&](double dt) { return detail::lane_gauss<3>(system(), dt); });
    default:
      return visit([&](double dt) { return detail::lane_rk4(system(), dt); });
  }
}

using detail::lane_dopri5;
using detail::lane_kernels;
using detail::lane_rk4;
using detail::lane_slot;
using detail::lane_system;

// detail::run_on_lanes under a run control (null: none), polled every 16 steps: once it asks
// to stop, every lane's cell ends at its next step as NaN, and so does each cell still
// queued (one step each), so that the caller gets back at once.
template <class Stepper, class Start, class Done, class Watch = detail::always_look>
void run_on_lanes(run_control* control, Stepper& rk, const std::vector<std::size_t>& queue,
                  const Start& start, const Done& done, std::vector<double>& out,
                  const Watch& watch = {}) {
  if (control == nullptr) return detail::run_on_lanes(rk, queue, start, done, out, watch);
  bool stopping = control->stop_requested();
  long long polls = 0;
  const auto watch_or_stop = [&](const double* x, std::size_t b, long long most) {
    if (b == 0 && ++polls % 16 == 0) stopping = stopping || control->stop_requested();
    return stopping || watch(x, b, most);
  };
  const auto done_or_stop = [&](double* x, std::size_t l,
                                lane_slot& slot) -> std::optional<double> {
    if (stopping) return std::numeric_limits<double>::quiet_NaN();
    return done(x, l, slot);
  };
  detail::run_on_lanes(rk, queue, start, done_or_stop, out, watch_or_stop);
}

// Σ v_i² of the vector at coordinates first .. first + d - 1 of lane l.
template <class Stepper>
double lane_squares(const Stepper& rk, const double* x, std::size_t first, std::size_t d,
                    std::size_t l) {
  double squares = 0;
  for (std::size_t i = 0; i < d; ++i) {
    const double v = x[rk.at(first + i, l)];
    squares += v * v;
  }
  return squares;
}

// That vector divided by `norm`.
template <class Stepper>
void divide_lane(const Stepper& rk, double* x, std::size_t first, std::size_t d, std::size_t l,
                 double norm) {
  for (std::size_t i = 0; i < d; ++i) x[rk.at(first + i, l)] /= norm;
}

// The flip times of the starts `queue` (indices of states in `starts`) on the lanes of a
// fixed-step stepper (rk4 or Gauss–Legendre, made by make(dt)): located inside the first
// step at whose end an arm is upright, NaN where the energy does not back the flip, as
// flip_time finds them. A cell whose Gauss–Legendre lane could
// not solve its stage equations by fixed-point iteration goes to flip_time (the library's
// Newton iteration).
template <class Make>
void flip_on_lanes(const chain& c, std::span<const double> starts,
                   const std::vector<std::size_t>& queue, const flip_options& o, const Make& make,
                   std::vector<double>& out) {
  const auto n = static_cast<std::size_t>(c.links());
  const std::size_t m = 2 * n;
  auto rk = make(o.dt);
  const long long steps = whole_steps(o.t_end, o.dt);
  double angles[chain_layout::max_links], angles_before[chain_layout::max_links],
      rates[chain_layout::max_links], rates_before[chain_layout::max_links];
  std::vector<double> after(m);
  std::vector<std::size_t> to_library;
  const auto start = [&](double* x, std::size_t l, std::size_t cell) {
    for (std::size_t i = 0; i < m; ++i) x[rk.at(i, l)] = starts[cell * m + i];
    rk.restart(l);
  };
  const auto done = [&](const double* x, std::size_t l,
                        const lane_slot& s) -> std::optional<double> {
    if (rk.failed(l)) {
      to_library.push_back(s.cell);
      return std::numeric_limits<double>::quiet_NaN();
    }
    for (std::size_t i = 0; i < n; ++i) angles[i] = x[rk.at(i, l)];
    if (has_flipped(angles, n, o)) {
      // As located_flip: the energy first, then the step's Hermite interpolant, the rates
      // from the lane's own rhs at the two ends.
      const double t0 = static_cast<double>(s.steps - 1) * o.dt;
      for (std::size_t i = 0; i < m; ++i) after[i] = x[rk.at(i, l)];
      if (!flip_energy_holds(c, c.hamiltonian(starts.subspan(s.cell * m, m)), after, t0 + o.dt))
        return std::numeric_limits<double>::quiet_NaN();
      const double* before = rk.state_before();
      for (std::size_t i = 0; i < n; ++i) angles_before[i] = before[rk.at(i, l)];
      rk.derivative_at(before, l, 0, n, rates_before);
      rk.derivative_at(x, l, 0, n, rates);
      return hermite_flip_time(angles_before, rates_before, angles, rates, n, t0, o.dt, o);
    }
    if (!std::isfinite(angles[0])) return std::numeric_limits<double>::quiet_NaN();
    if (s.steps == steps) return std::numeric_limits<double>::infinity();
    return std::nullopt;
  };
  // A block needs a look when a lane may have flipped (or is no longer finite: NaN fails
  // |φ| < π too), failed, or reached t_end.
  constexpr std::size_t W = detail::lane_layout::W;
  const auto watch = [&](const double* x, std::size_t b, long long most) {
    if (most >= steps) return true;
    bool look = false;
    for (std::size_t k = 0; k < n; ++k) {
      if (!watches_arm(o.link, k + 1)) continue;
      const double* angle = x + rk.at(k, b * W);
      int below = 0;  // a count, where a flag would not vectorise
#pragma omp simd reduction(+ : below)
      for (std::size_t l = 0; l < W; ++l) below += std::fabs(angle[l]) < std::numbers::pi ? 1 : 0;
      look |= below != static_cast<int>(W);
    }
    for (std::size_t l = b * W; l < (b + 1) * W; ++l) look |= rk.failed(l);
    return look;
  };
  run_on_lanes(o.control, rk, queue, start, done, out, watch);
  by_library(
      starts, m, to_library, [&](std::span<const double> x0) { return flip_time(c, x0, o); }, out);
}

// Where a dopri5 lane's step has gone wrong, as npend::integrate finds it: too many tries,
// a non-finite state (its first `checked` coordinates), a collapsed step size.
bool dopri5_lane_failed(const lane_dopri5& rk, const double* x, std::size_t l, std::size_t checked,
                        double min_step) {
  if (rk.tries(l) >= lane_dopri5::max_tries) return true;
  if (!rk.accepted(l)) return false;
  for (std::size_t i = 0; i < checked; ++i)
    if (!std::isfinite(x[rk.at(i, l)])) return true;
  return rk.step_size(l) < min_step;
}

// Runs the starts `queue` (the state alone) on dopri5 lanes, each from t = 0 with the
// trial step dt under the tolerances of `stepping`: after every accepted step,
// settle(rk, x, l, cell) gives the cell's value or std::nullopt to go on. A lane whose step fails
// (where npend::integrate would throw integration_error) gives NaN.
template <class Settle>
void run_dopri5_cells(const batch_kernels& k, const chain& c, std::span<const double> starts,
                      const std::vector<std::size_t>& queue, const map_stepping& stepping,
                      double dt, run_control* control, const Settle& settle,
                      std::vector<double>& out) {
  const auto m = static_cast<std::size_t>(c.state_size());
  lane_dopri5 rk(lane_system(k, c.packed_parameters().data(), c.links(), 0, false),
                 stepping.abs_tol, stepping.rel_tol);
  const double min_step = integration_options{}.min_step_ratio * dt;
  const auto start = [&](double* x, std::size_t l, std::size_t cell) {
    for (std::size_t i = 0; i < m; ++i) x[rk.at(i, l)] = starts[cell * m + i];
    rk.restart(l, 0, dt);
  };
  const auto done = [&](const double* x, std::size_t l,
                        const lane_slot& s) -> std::optional<double> {
    if (dopri5_lane_failed(rk, x, l, m, min_step)) return std::numeric_limits<double>::quiet_NaN();
    if (!rk.accepted(l)) return std::nullopt;
    return settle(rk, x, l, s.cell);
  };
  run_on_lanes(control, rk, queue, start, done, out);
}

// flip_on_lanes with dopri5: each lane under its own step control, the flip located in the
// step where it happens as flip_time_dopri5 locates it.
void flip_on_dopri5_lanes(const batch_kernels& k, const chain& c, std::span<const double> starts,
                          const std::vector<std::size_t>& queue, const flip_options& o,
                          std::vector<double>& out) {
  const auto n = static_cast<std::size_t>(c.links());
  const std::size_t m = 2 * n;
  double angles[chain_layout::max_links];
  std::vector<double> after(m);
  const auto settle = [&](const lane_dopri5& rk, const double* x, std::size_t l,
                          std::size_t cell) -> std::optional<double> {
    for (std::size_t i = 0; i < n; ++i) angles[i] = x[rk.at(i, l)];
    if (has_flipped(angles, n, o)) {
      for (std::size_t i = 0; i < m; ++i) after[i] = x[rk.at(i, l)];
      const double t = locate_flip(rk.step_begin(l), rk.time(l), [&](double at) {
        rk.state_at(l, at, 0, n, angles);
        return has_flipped(angles, n, o);
      });
      if (t > o.t_end) return std::numeric_limits<double>::infinity();
      const double h0 = c.hamiltonian(starts.subspan(cell * m, m));
      return flip_energy_holds(c, h0, after, rk.time(l)) ? t
                                                         : std::numeric_limits<double>::quiet_NaN();
    }
    if (rk.time(l) >= o.t_end) return std::numeric_limits<double>::infinity();
    return std::nullopt;
  };
  run_dopri5_cells(k, c, starts, queue, o.stepping, o.dt, o.control, settle, out);
}

// The maximal Lyapunov exponents of the starts `queue` on the lanes, as
// maximal_lyapunov_exponent computes them with `lo` (rk4, no transient): the tangent vector
// starts as (1, …, 1)/√(2n) and is renormalised every round(interval / dt) steps and at the
// end; the exponent is Σ ln(growth) / t_end. NaN where the state or the tangent becomes
// non-finite (where the library throws integration_error).
void lyapunov_on_lanes(const batch_kernels& k, const chain& c, std::span<const double> starts,
                       const std::vector<std::size_t>& queue, const lyapunov_options& lo,
                       std::vector<double>& out) {
  const auto m = static_cast<std::size_t>(c.state_size());
  const double dt = lo.integration.dt;
  lane_rk4 rk(lane_system(k, c.packed_parameters().data(), c.links(), 1, false), dt);
  const auto total = static_cast<long long>(output_steps(lo.integration));
  const long long chunk = std::max<long long>(1, std::llround(lo.renormalisation_interval / dt));
  const double t_total = static_cast<double>(total) * dt;
  const double w0 = 1.0 / std::sqrt(static_cast<double>(m));
  const auto start = [&](double* x, std::size_t l, std::size_t cell) {
    for (std::size_t i = 0; i < m; ++i) {
      x[rk.at(i, l)] = starts[cell * m + i];
      x[rk.at(m + i, l)] = w0;
    }
  };
  const auto done = [&](double* x, std::size_t l, lane_slot& s) -> std::optional<double> {
    if (s.steps % chunk != 0 && s.steps != total) return std::nullopt;
    for (std::size_t i = 0; i < 2 * m; ++i)  // the state, then the tangent
      if (!std::isfinite(x[rk.at(i, l)])) return std::numeric_limits<double>::quiet_NaN();
    const double norm = std::sqrt(lane_squares(rk, x, m, m, l));
    s.sum += std::log(norm);
    divide_lane(rk, x, m, m, l, norm);
    if (s.steps == total) return s.sum / t_total;
    return std::nullopt;
  };
  run_on_lanes(lo.integration.control, rk, queue, start, done, out);
}

// lyapunov_on_lanes with dopri5, as maximal_lyapunov_exponent runs it: each renormalisation
// interval (round(interval / dt) steps of dt, the last one shorter) is a run of its own —
// the stepper restarted with the trial step dt, the state and tangent taken from its dense
// output at the interval's end, then the tangent renormalised.
void lyapunov_on_dopri5_lanes(const batch_kernels& k, const chain& c,
                              std::span<const double> starts, const std::vector<std::size_t>& queue,
                              const lyapunov_options& lo, std::vector<double>& out) {
  const auto m = static_cast<std::size_t>(c.state_size());
  const double dt = lo.integration.dt;
  lane_dopri5 rk(lane_system(k, c.packed_parameters().data(), c.links(), 1, false),
                 lo.integration.abs_tol, lo.integration.rel_tol);
  const auto total = static_cast<long long>(output_steps(lo.integration));
  const long long chunk = std::max<long long>(1, std::llround(lo.renormalisation_interval / dt));
  const double t_total = static_cast<double>(total) * dt;
  const double min_step = lo.integration.min_step_ratio * dt;
  const double w0 = 1.0 / std::sqrt(static_cast<double>(m));
  std::vector<double> y(2 * m);
  const auto start = [&](double* x, std::size_t l, std::size_t cell) {
    for (std::size_t i = 0; i < m; ++i) {
      x[rk.at(i, l)] = starts[cell * m + i];
      x[rk.at(m + i, l)] = w0;
    }
    rk.restart(l, 0, dt);
  };
  const auto done = [&](double* x, std::size_t l, lane_slot& s) -> std::optional<double> {
    if (dopri5_lane_failed(rk, x, l, 2 * m, min_step))
      return std::numeric_limits<double>::quiet_NaN();
    if (!rk.accepted(l)) return std::nullopt;
    const long long steps = std::min(chunk, total - s.reached);
    const double target = static_cast<double>(s.reached) * dt + static_cast<double>(steps) * dt;
    if (rk.time(l) < target) return std::nullopt;
    rk.state_at(l, target, 0, 2 * m, y.data());
    for (std::size_t i = 0; i < 2 * m; ++i) {
      if (!std::isfinite(y[i])) return std::numeric_limits<double>::quiet_NaN();
      x[rk.at(i, l)] = y[i];
    }
    s.reached += steps;
    const double norm = std::sqrt(lane_squares(rk, x, m, m, l));
    s.sum += std::log(norm);
    divide_lane(rk, x, m, m, l, norm);
    if (s.reached == total) return s.sum / t_total;
    rk.restart(l, static_cast<double>(s.reached) * dt, dt);
    return std::nullopt;
  };
  run_on_lanes(lo.integration.control, rk, queue, start, done, out);
}

// The chaos indicators of the starts `queue` on the lanes, as chaos_indicators computes them
// (rk4 at dt with `vectors` deviation vectors from chaos_indicator_start, each normalised
// after every step, MEGNO's integrals riding along), sampled at the last step;
// pick(sample) is the map's value. NaN where the state or a vector becomes non-finite
// (where the library throws integration_error).
template <class Pick>
void indicators_on_lanes(const batch_kernels& k, const chain& c, std::span<const double> starts,
                         const std::vector<std::size_t>& queue, double t_end, double dt,
                         std::size_t vectors, run_control* control, const Pick& pick,
                         std::vector<double>& out) {
  const auto d = static_cast<std::size_t>(c.state_size());
  lane_rk4 rk(
      lane_system(k, c.packed_parameters().data(), c.links(), static_cast<int>(vectors), true), dt);
  const lane_system& sys = rk.system();
  const std::vector<double> w0 = chaos_indicator_start(d, vectors);
  const auto total = whole_steps(t_end, dt);
  std::vector<double> w(d * vectors);
  const auto start = [&](double* x, std::size_t l, std::size_t cell) {
    for (std::size_t i = 0; i < d; ++i) x[rk.at(i, l)] = starts[cell * d + i];
    for (std::size_t j = 0; j < vectors; ++j)
      for (std::size_t i = 0; i < d; ++i) x[rk.at(sys.vector(j) + i, l)] = w0[j * d + i];
    for (const std::size_t i : {sys.time(), sys.y(), sys.z()}) x[rk.at(i, l)] = 0;
  };
  const auto done = [&](double* x, std::size_t l, lane_slot& s) -> std::optional<double> {
    for (std::size_t j = 0; j < vectors; ++j) {
      const double norm = std::sqrt(lane_squares(rk, x, sys.vector(j), d, l));
      if (!std::isfinite(norm) || norm == 0 || !std::isfinite(x[rk.at(0, l)]))
        return std::numeric_limits<double>::quiet_NaN();
      divide_lane(rk, x, sys.vector(j), d, l, norm);
      if (j == 0) {
        s.sum += std::log(norm);
        s.peak = std::max(s.peak, s.sum);
      }
    }
    if (s.steps != total) return std::nullopt;
    for (std::size_t i = 0; i < d * vectors; ++i) w[i] = x[rk.at(sys.vector(0) + i, l)];
    return pick(chaos_indicator_sample_of(static_cast<double>(total) * dt, s.peak,
                                          x[rk.at(sys.y(), l)], x[rk.at(sys.z(), l)], w, d));
  };
  run_on_lanes(control, rk, queue, start, done, out);
}

// Coordinate o.component of each start's state at o.t_end on the lanes, as final_coordinate
// computes it: fixed steps of dt (rk4, or Gauss–Legendre), then — where t_end is not a whole
// number of steps — one shorter step to land on t_end, a second pass on lanes whose step is
// that rest; make(dt) makes the stepper. NaN where the state becomes non-finite (where
// final_coordinate throws integration_error). The cells whose Gauss–Legendre lane failed are
// left for the library: their indices go to `failed`.
template <class Make>
void final_coordinates_on_lanes(const chain& c, std::span<const double> starts,
                                const std::vector<std::size_t>& queue, const map_cell_options& o,
                                const Make& make, std::vector<double>& out,
                                std::vector<std::size_t>& failed) {
  const auto m = static_cast<std::size_t>(c.state_size());
  const auto steps = whole_steps(o.t_end, o.dt);
  const double rest = o.t_end - static_cast<double>(steps) * o.dt;
  std::vector<double> ends(starts.begin(), starts.end());  // each cell's state, advanced
  std::vector<double> unused(out.size());
  std::vector<char> lost(out.size(), 0);
  const auto advance = [&](double dt, long long count) {
    auto rk = make(dt);
    const auto start = [&](double* x, std::size_t l, std::size_t cell) {
      for (std::size_t i = 0; i < m; ++i) x[rk.at(i, l)] = ends[cell * m + i];
      rk.restart(l);
    };
    const auto done = [&](const double* x, std::size_t l,
                          const lane_slot& s) -> std::optional<double> {
      if (rk.failed(l)) {
        lost[s.cell] = 1;
        return 0.0;
      }
      if (s.steps != count) return std::nullopt;
      for (std::size_t i = 0; i < m; ++i) ends[s.cell * m + i] = x[rk.at(i, l)];
      return 0.0;
    };
    std::vector<std::size_t> live;
    for (const std::size_t cell : queue)
      if (!lost[cell]) live.push_back(cell);
    run_on_lanes(o.control, rk, live, start, done, unused);
  };
  advance(o.dt, steps);
  if (rest > 1e-9 * o.dt) advance(rest, 1);
  if (stop_requested(o.control)) {  // the cells did not all reach t_end
    for (const std::size_t cell : queue) out[cell] = std::numeric_limits<double>::quiet_NaN();
    return;
  }
  for (const std::size_t cell : queue) {
    if (lost[cell]) {
      failed.push_back(cell);
      continue;
    }
    const std::span<const double> x(ends.data() + cell * m, m);
    out[cell] = std::all_of(x.begin(), x.end(), [](double v) { return std::isfinite(v); })
                    ? x[static_cast<std::size_t>(o.component)]
                    : std::numeric_limits<double>::quiet_NaN();
  }
}

// final_coordinates_on_lanes with dopri5: each lane steps under its own control until a
// step ends at or past t_end, and the value is the dense output at t_end, as
// final_coordinate takes it.
void final_coordinates_on_dopri5_lanes(const batch_kernels& k, const chain& c,
                                       std::span<const double> starts,
                                       const std::vector<std::size_t>& queue,
                                       const map_cell_options& o, std::vector<double>& out) {
  std::vector<double> y(static_cast<std::size_t>(c.state_size()));
  const auto settle = [&](const lane_dopri5& rk, const double*, std::size_t l,
                          std::size_t) -> std::optional<double> {
    if (rk.time(l) < o.t_end) return std::nullopt;
    rk.state_at(l, o.t_end, 0, y.size(), y.data());
    return std::all_of(y.begin(), y.end(), [](double v) { return std::isfinite(v); })
               ? y[static_cast<std::size_t>(o.component)]
               : std::numeric_limits<double>::quiet_NaN();
  };
  run_dopri5_cells(k, c, starts, queue, o.stepping, o.dt, o.control, settle, out);
}

// The entries of map_lanes: each picks the lane stepper the options name.

bool serves(const chain& c) { return lane_kernels(c) != nullptr; }

void flip_times_entry(const chain& c, std::span<const double> starts,
                      const std::vector<std::size_t>& queue, const flip_options& o,
                      std::vector<double>& out) {
  const batch_kernels& k = *lane_kernels(c);
  if (o.stepping.stepper == stepper_kind::dopri5)
    flip_on_dopri5_lanes(k, c, starts, queue, o, out);
  else
    with_fixed_step_lanes(k, c, o.stepping.stepper,
                          [&](const auto& make) { flip_on_lanes(c, starts, queue, o, make, out); });
}

void lyapunov_entry(const chain& c, std::span<const double> starts, const lyapunov_options& lo,
                    std::vector<double>& out) {
  const batch_kernels& k = *lane_kernels(c);
  if (lo.integration.stepper == stepper_kind::dopri5)
    lyapunov_on_dopri5_lanes(k, c, starts, all_cells(out.size()), lo, out);
  else
    lyapunov_on_lanes(k, c, starts, all_cells(out.size()), lo, out);
}

void indicators_entry(const chain& c, std::span<const double> starts, const map_cell_options& o,
                      std::size_t vectors, std::vector<double>& out) {
  const auto pick = [&](const chaos_indicator_sample& sample) {
    return detail::indicator_value(o.quantity, sample);
  };
  indicators_on_lanes(*lane_kernels(c), c, starts, all_cells(out.size()), o.t_end, o.dt, vectors,
                      o.control, pick, out);
}

void final_coordinates_entry(const chain& c, std::span<const double> starts,
                             const map_cell_options& o, std::vector<double>& out,
                             std::vector<std::size_t>& failed) {
  const batch_kernels& k = *lane_kernels(c);
  if (o.stepping.stepper == stepper_kind::dopri5)
    return final_coordinates_on_dopri5_lanes(k, c, starts, all_cells(out.size()), o, out);
  with_fixed_step_lanes(k, c, o.stepping.stepper, [&](const auto& make) {
    final_coordinates_on_lanes(c, starts, all_cells(out.size()), o, make, out, failed);
  });
}

}  // namespace

namespace detail {
inline namespace NPEND_BATCH_ISA_NAMESPACE {

const map_lanes& lanes_of_this_isa() {
  static constexpr map_lanes entry{
      batch_isa(),       lane_layout::lanes,      &serves, &flip_times_entry, &lyapunov_entry,
      &indicators_entry, &final_coordinates_entry};
  return entry;
}

}  // namespace NPEND_BATCH_ISA_NAMESPACE
}  // namespace detail

}  // namespace npend
