#include "npend/analysis/chaos/chaos_map.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <boost/numeric/odeint/stepper/runge_kutta4.hpp>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
#include <optional>
#include <stdexcept>
#include <utility>
#include <vector>

#include "analysis/detail/argument_checks.hpp"
#include "analysis/detail/map_cell_steps.hpp"
#include "gpu/host_kernels.hpp"
#include "integrators/batch_lanes.hpp"
#include "npend/batch_kernels.hpp"
#include "npend/chain_system.hpp"
#include "npend/integrators/gauss_legendre.hpp"
#include "npend/integrators/integrate.hpp"
#include "npend/integrators/integration_error.hpp"

namespace npend {

using detail::indicator_vectors;
using detail::map_lyapunov_options;
using detail::whole_steps;

namespace {

// Whether a flip of arm k (1..n) counts: `link` is the one arm asked about, or 0 for any.
bool watches_arm(int link, std::size_t k) {
  return link == 0 || static_cast<std::size_t>(link) == k;
}

// The least energy a flip of a watched arm needs: min over the arms k watched of 2 g G_k,
// G_k = m_k c_k + l_k μ_{k+1} (μ_{k+1} the mass below link k; c = l for point masses).
// Without allocating: a map asks once per cell.
double least_flip_energy(const chain_parameters& p, int link) {
  double needed = std::numeric_limits<double>::infinity(), below = 0;
  for (std::size_t k = p.masses.size(); k-- > 0;) {
    const double reach = p.com.empty() ? p.lengths[k] : p.com[k];
    const double moment = p.masses[k] * reach + p.lengths[k] * below;
    below += p.masses[k];
    if (watches_arm(link, k + 1)) needed = std::min(needed, 2 * p.g * moment);
  }
  return needed;
}

}  // namespace

bool energy_forbids_flip(const chain& c, std::span<const double> x0, int link) {
  const int n = c.links();
  if (link < 0 || link > n)
    throw std::invalid_argument(
        fmt::format("flip: the arm must be 1..{} (or 0: any), got {}", n, link));
  if (c.parameters().pivot.moves()) return false;
  return c.hamiltonian(x0) < least_flip_energy(c.parameters(), link);
}

namespace {

// Refuses (std::invalid_argument, as npend::output_steps) a cell of more steps of dt up to
// t_end than a step count holds exactly (2^53): the lanes count them in long long.
void check_cell_steps(double t_end, double dt) {
  integration_options io;
  io.t_end = t_end;
  io.dt = dt;
  output_steps(io);
}

void check_flip_options(const flip_options& o) {
  if (!(o.dt > 0) || !(o.t_end >= o.dt) || !std::isfinite(o.t_end))
    throw std::invalid_argument(
        fmt::format("flip: need 0 < dt <= t_end, got dt = {}, t_end = {}", o.dt, o.t_end));
  check_cell_steps(o.t_end, o.dt);
  o.stepping.validate("flip");
}

// A run control that passes on only the stop requests: a map's cells run on many threads at
// once, and each cell's own progress means nothing to the caller.
class stop_only final : public run_control {
 public:
  explicit stop_only(run_control* parent) : m_parent(parent) {}
  bool stop_requested() override { return npend::stop_requested(m_parent); }
  /// This control, or null where there is no parent to ask.
  run_control* get() { return m_parent != nullptr ? this : nullptr; }

 private:
  run_control* m_parent;
};

// How often (in steps) a cell stepped one at a time polls its run control.
constexpr long long steps_between_polls = 256;

// Whether an arm (or arm o.link) of the n-link state x is at or past the upright position.
bool has_flipped(const double* x, std::size_t n, const flip_options& o) {
  for (std::size_t k = 0; k < n; ++k)
    if (watches_arm(o.link, k + 1) && std::fabs(x[k]) >= std::numbers::pi) return true;
  return false;
}

// The first θ in [0, 1] at which the cubic Hermite interpolant of an angle over a step of h
// — p(0) = y0, p(1) = y1, p'(0) = h f0, p'(1) = h f1 — reaches the upright ±π it passed:
// the GPU kernels' function (runtime/src/gpu/map_kernels.cuh), compiled here for the CPU, so
// that both locate a flip by the same operations.
using gpu::hermite_upright_fraction;

// The flip time inside a fixed step from t0 to t0 + h, at whose end a watched arm is upright
// (and none at its start): the earliest hermite_upright_fraction of the watched arms upright
// at the end, from the angles phi0, phi1 and their rates dphi0, dphi1 (dim n) at the ends.
// The step's own interpolant, accurate to O(h⁴) as rk4 is; the lanes and the library call
// it with the same numbers, so that they agree to round-off.
double hermite_flip_time(const double* phi0, const double* dphi0, const double* phi1,
                         const double* dphi1, std::size_t n, double t0, double h,
                         const flip_options& o) {
  double theta = 1;
  for (std::size_t k = 0; k < n; ++k)
    if (watches_arm(o.link, k + 1) && std::fabs(phi1[k]) >= std::numbers::pi)
      theta = std::min(theta, hermite_upright_fraction(phi0[k], dphi0[k], phi1[k], dphi1[k], h));
  return t0 + theta * h;
}

// Whether the energy at x1, the state at time t1 at the end of the step in which a flip was
// seen, lets the flip be believed: |H(x1) − h0| ≤ flip_energy_tolerance · h0, h0 = H(x0)
// (for a damped chain, whose H only falls, H(x1) − h0 ≤ flip_energy_tolerance · h0). A
// driven chain is fed energy by its pivot and is not checked. False for a non-finite state.
bool flip_energy_holds(const chain& c, double h0, std::span<const double> x1, double t1) {
  const chain_parameters& p = c.parameters();
  if (p.pivot.moves()) return true;
  const double drift = c.hamiltonian(x1, t1) - h0;
  const double allowed = flip_energy_tolerance * h0;
  return p.is_damped() ? drift <= allowed : std::fabs(drift) <= allowed;
}

// flip_time's failure for a flip the energy does not back.
[[noreturn]] void throw_untrusted_flip(double t1) {
  throw integration_error(
      fmt::format("flip: the energy at t = {} is off by more than {:g} of the start's, so the "
                  "flip there is a numerical artefact; try a smaller dt",
                  t1, flip_energy_tolerance),
      t1);
}

// The flip time inside a fixed step from t0 (state before, flipped at none) to t0 + h
// (state after, flipped), by hermite_flip_time with the rates from `system`; throws
// integration_error where flip_energy_holds does not.
template <class System>
double located_flip(const chain& c, const System& system, double h0,
                    const std::vector<double>& before, const std::vector<double>& after, double t0,
                    double h, const flip_options& o) {
  const std::size_t n = before.size() / 2;
  if (!flip_energy_holds(c, h0, after, t0 + h)) throw_untrusted_flip(t0 + h);
  std::vector<double> f0(before.size()), f1(before.size());
  system(before, f0, t0);
  system(after, f1, t0 + h);
  return hermite_flip_time(before.data(), f0.data(), after.data(), f1.data(), n, t0, h, o);
}

// The flip time inside a step from t0 (not flipped) to t1 (flipped), flipped_at(t) telling
// the dense output's verdict: bisection down to adjacent doubles, the first time found
// flipped. The scalar path and the lanes bisect alike, so that they agree to round-off.
template <class Flipped>
double locate_flip(double t0, double t1, const Flipped& flipped_at) {
  for (;;) {
    const double mid = t0 + 0.5 * (t1 - t0);
    if (mid <= t0 || mid >= t1) return t1;
    (flipped_at(mid) ? t1 : t0) = mid;
  }
}

// dopri5 from x0 as npend::integrate runs it (first trial step dt, the options' tolerances),
// calling on_step(step) after every accepted step until it returns true or a step ends at
// or past t_end. The steps do not depend on integrate's output grid, which is only laid
// past t_end so that the steps, not the grid, end the run.
template <class OnStep>
void dopri5_steps(const chain& c, std::span<const double> x0, double t_end, double dt,
                  const map_stepping& stepping, run_control* control, const OnStep& on_step) {
  stop_only stop(control);
  integration_options io;
  io.control = stop.get();
  io.stepper = stepper_kind::dopri5;
  io.dt = dt;
  io.t_end = dt * (std::ceil(t_end / dt) + 1);
  io.abs_tol = stepping.abs_tol;
  io.rel_tol = stepping.rel_tol;
  integrate(c, x0, io, {}, [&](const integration_step& step) {
    return on_step(step) || step.t_end() >= t_end ? observer_action::stop
                                                  : observer_action::proceed;
  });
}

// flip_time with a Gauss–Legendre stepper, through npend::integrate's grid of dt (its steps):
// the first step at whose end an arm is upright, the flip located inside it as rk4's.
double flip_time_gauss(const chain& c, std::span<const double> x0, const flip_options& o) {
  const auto n = static_cast<std::size_t>(c.links());
  stop_only stop(o.control);
  integration_options io;
  io.stepper = o.stepping.stepper;
  io.dt = o.dt;
  io.t_end = o.t_end;
  io.control = stop.get();
  const double h0 = c.hamiltonian(x0);
  const chain_system system(c);
  std::vector<double> before(x0.begin(), x0.end()), after(2 * n);
  double t_before = 0, found = std::numeric_limits<double>::infinity();
  const auto r = integrate(c, x0, io, [&](double t, std::span<const double> x) {
    if (t == 0) return observer_action::proceed;
    if (!has_flipped(x.data(), n, o)) {
      std::copy(x.begin(), x.end(), before.begin());
      t_before = t;
      return observer_action::proceed;
    }
    std::copy(x.begin(), x.end(), after.begin());
    found = located_flip(c, system, h0, before, after, t_before, o.dt, o);
    return observer_action::stop;
  });
  return r.stopped && std::isinf(found) ? std::numeric_limits<double>::quiet_NaN() : found;
}

double flip_time_dopri5(const chain& c, std::span<const double> x0, const flip_options& o) {
  const auto n = static_cast<std::size_t>(c.links());
  const double h0 = c.hamiltonian(x0);
  double found = std::numeric_limits<double>::infinity(), untrusted = 0;
  std::vector<double> x(2 * n);
  dopri5_steps(c, x0, o.t_end, o.dt, o.stepping, o.control, [&](const integration_step& step) {
    if (!has_flipped(step.x_end().data(), n, o)) return false;
    const double t = locate_flip(step.t_begin(), step.t_end(), [&](double at) {
      step.state_at(at, x);
      return has_flipped(x.data(), n, o);
    });
    if (t > o.t_end) return true;
    if (flip_energy_holds(c, h0, step.x_end(), step.t_end()))
      found = t;
    else
      untrusted = step.t_end();
    return true;
  });
  if (untrusted > 0) throw_untrusted_flip(untrusted);
  return std::isinf(found) && stop_requested(o.control) ? std::numeric_limits<double>::quiet_NaN()
                                                        : found;
}

}  // namespace

bool is_map_stepper(stepper_kind stepper) { return serves(stepper, stepper_use::map); }

void map_stepping::validate(std::string_view what) const {
  if (!is_map_stepper(stepper))
    throw std::invalid_argument(fmt::format("{}: maps integrate with one of {}, not {}", what,
                                            stepper_names(stepper_use::map),
                                            stepper_name(stepper)));
  if (stepper != stepper_kind::dopri5) return;
  const auto check = [&](double tol, std::string_view name) {
    if (!(tol >= 0) || !std::isfinite(tol))
      throw std::invalid_argument(
          fmt::format("{}: {} must be finite and not negative, got {}", what, name, tol));
  };
  check(abs_tol, "abs_tol");
  check(rel_tol, "rel_tol");
  if (abs_tol == 0 && rel_tol == 0)
    throw std::invalid_argument(
        fmt::format("{}: abs_tol and rel_tol are both 0; at least one must be positive", what));
}

double flip_time(const chain& c, std::span<const double> x0, const flip_options& o) {
  const auto n = static_cast<std::size_t>(c.links());
  if (x0.size() != 2 * n)
    throw std::invalid_argument(
        fmt::format("flip: the {}-link chain needs a state of {}, got {}", n, 2 * n, x0.size()));
  check_flip_options(o);
  const double inf = std::numeric_limits<double>::infinity();
  if (energy_forbids_flip(c, x0, o.link)) return inf;
  const auto flipped = [&](const std::vector<double>& x) { return has_flipped(x.data(), n, o); };
  std::vector<double> x(x0.begin(), x0.end());
  if (flipped(x)) return 0;
  if (o.stepping.stepper == stepper_kind::dopri5) return flip_time_dopri5(c, x0, o);
  if (is_gauss_legendre(o.stepping.stepper)) return flip_time_gauss(c, x0, o);
  boost::numeric::odeint::runge_kutta4<std::vector<double>> stepper;
  const chain_system system(c);
  const auto steps = whole_steps(o.t_end, o.dt);
  const double h0 = c.hamiltonian(x0);
  std::vector<double> before(x.size());
  for (long long k = 1; k <= steps; ++k) {
    if (k % steps_between_polls == 0 && stop_requested(o.control))
      return std::numeric_limits<double>::quiet_NaN();
    const double t0 = static_cast<double>(k - 1) * o.dt;
    std::copy(x.begin(), x.end(), before.begin());
    stepper.do_step(system, x, t0, o.dt);
    if (flipped(x)) return located_flip(c, system, h0, before, x, t0, o.dt, o);
    if (!std::isfinite(x[0]))
      throw integration_error(
          fmt::format("flip: the state became non-finite at t = {}; try a smaller dt",
                      static_cast<double>(k) * o.dt),
          static_cast<double>(k) * o.dt);
  }
  return inf;
}

namespace {

// The values of the starts `cells` by `cell` (the library's scalar path; starts of m numbers
// each, one after another) into out, NaN where the integration fails (integration_error),
// and where `control` asked to stop before the cell began.
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

// The queue of every start, in order: 0, 1, …, count - 1.
std::vector<std::size_t> all_cells(std::size_t count) {
  std::vector<std::size_t> queue(count);
  std::iota(queue.begin(), queue.end(), std::size_t{0});
  return queue;
}

// Each start's value by `cell`, one after another: by_library of every start.
template <class Cell>
std::vector<double> cell_by_cell(std::span<const double> starts, std::size_t m, const Cell& cell,
                                 run_control* control = nullptr) {
  std::vector<double> out(starts.size() / m);
  by_library(starts, m, all_cells(out.size()), cell, out, control);
  return out;
}

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

}  // namespace

int batch_lanes(const chain& c) { return lane_kernels(c) != nullptr ? lane_rk4::lanes : 0; }

std::vector<double> flip_times(const chain& c, std::span<const double> starts,
                               const flip_options& o) {
  const auto m = static_cast<std::size_t>(c.state_size());
  if (starts.size() % m != 0)
    throw std::invalid_argument(
        fmt::format("flip: the {}-link chain needs states of {} one after another, got {} numbers",
                    c.links(), m, starts.size()));
  check_flip_options(o);
  energy_forbids_flip(c, std::vector<double>(m, 0.0), o.link);  // its checks, even for no cells
  const std::size_t count = starts.size() / m;
  const batch_kernels* k = lane_kernels(c);
  if (k == nullptr)
    return cell_by_cell(
        starts, m, [&](std::span<const double> x0) { return flip_time(c, x0, o); }, o.control);
  std::vector<double> out(count, std::numeric_limits<double>::quiet_NaN());
  // What flip_time settles without integrating; the rest queue for the lanes.
  std::vector<std::size_t> queue;
  for (std::size_t i = 0; i < count; ++i) {
    const auto x0 = starts.subspan(i * m, m);
    if (energy_forbids_flip(c, x0, o.link))
      out[i] = std::numeric_limits<double>::infinity();
    else if (has_flipped(x0.data(), m / 2, o))
      out[i] = 0;
    else
      queue.push_back(i);
  }
  if (o.stepping.stepper == stepper_kind::dopri5)
    flip_on_dopri5_lanes(*k, c, starts, queue, o, out);
  else
    with_fixed_step_lanes(*k, c, o.stepping.stepper,
                          [&](const auto& make) { flip_on_lanes(c, starts, queue, o, make, out); });
  return out;
}

namespace {

constexpr std::array all_map_quantities{
    map_quantity::flip, map_quantity::lyapunov, map_quantity::fli,  map_quantity::megno,
    map_quantity::sali, map_quantity::gali,     map_quantity::state};

}  // namespace

std::string_view map_quantity_name(map_quantity quantity) {
  switch (quantity) {
    case map_quantity::flip:
      return "flip";
    case map_quantity::lyapunov:
      return "lyapunov";
    case map_quantity::fli:
      return "fli";
    case map_quantity::megno:
      return "megno";
    case map_quantity::sali:
      return "sali";
    case map_quantity::gali:
      return "gali";
    case map_quantity::state:
      return "state";
  }
  return "?";
}

map_quantity parse_map_quantity(std::string_view name) {
  for (const auto q : all_map_quantities)
    if (name == map_quantity_name(q)) return q;
  throw std::invalid_argument(fmt::format(
      "quantity: one of flip, lyapunov, fli, megno, sali, gali, state, got '{}'", name));
}

namespace {

// The map's value of an indicator sample: FLI, MEGNO ⟨Y⟩, SALI or GALI_k.
double indicator_value(map_quantity quantity, const chaos_indicator_sample& sample) {
  switch (quantity) {
    case map_quantity::fli:
      return sample.fli;
    case map_quantity::megno:
      return sample.mean_megno;
    case map_quantity::sali:
      return sample.sali;
    default:
      return sample.gali.back();
  }
}

bool is_indicator(map_quantity quantity) {
  return quantity == map_quantity::fli || quantity == map_quantity::megno ||
         quantity == map_quantity::sali || quantity == map_quantity::gali;
}

}  // namespace

bool map_takes_stepper(map_quantity quantity, stepper_kind stepper) {
  return is_map_stepper(stepper) && (stepper == stepper_kind::rk4 || !is_indicator(quantity));
}

namespace {

// FLI, MEGNO, SALI or GALI_k at t_end, cell by cell.
double indicator_cell(const chain& c, std::span<const double> x0, const map_cell_options& o) {
  chaos_indicator_options io;
  io.t_end = o.t_end;
  io.dt = o.dt;
  io.vectors = indicator_vectors(c, o);
  io.control = o.control;
  const chaos_indicator_result r = chaos_indicators(c, x0, io);
  return r.stopped ? std::numeric_limits<double>::quiet_NaN() : indicator_value(o.quantity, r.last);
}

// Coordinate o.component of the state at t_end: rk4 steps of dt (the last one shortened to
// land on t_end), as the other quantities integrate, or dopri5's dense output at t_end.
double final_coordinate(const chain& c, std::span<const double> x0, const map_cell_options& o) {
  if (o.stepping.stepper == stepper_kind::dopri5) {
    std::vector<double> x(x0.size());
    bool reached = false;
    dopri5_steps(c, x0, o.t_end, o.dt, o.stepping, o.control, [&](const integration_step& step) {
      if (step.t_end() < o.t_end) return false;
      step.state_at(o.t_end, x);
      return reached = true;
    });
    if (!reached) return std::numeric_limits<double>::quiet_NaN();  // asked to stop
    for (const double v : x)
      if (!std::isfinite(v)) throw integration_error("state: the state became non-finite", o.t_end);
    return x[static_cast<std::size_t>(o.component)];
  }
  std::vector<double> x(x0.begin(), x0.end());
  const auto steps = whole_steps(o.t_end, o.dt);
  const double rest = o.t_end - static_cast<double>(steps) * o.dt;
  const auto run = [&](auto& stepper, const auto& system) {
    for (long long k = 1; k <= steps; ++k) {
      if (k % steps_between_polls == 0 && stop_requested(o.control)) return false;
      stepper.do_step(system, x, static_cast<double>(k - 1) * o.dt, o.dt);
    }
    if (rest > 1e-9 * o.dt) stepper.do_step(system, x, static_cast<double>(steps) * o.dt, rest);
    return true;
  };
  bool reached = false;  // false: asked to stop
  if (o.stepping.stepper == stepper_kind::gauss4) {
    gauss_legendre4 stepper;
    reached = run(stepper, make_implicit_system(c));
  } else if (o.stepping.stepper == stepper_kind::gauss6) {
    gauss_legendre6 stepper;
    reached = run(stepper, make_implicit_system(c));
  } else {
    boost::numeric::odeint::runge_kutta4<std::vector<double>> stepper;
    reached = run(stepper, chain_system(c));
  }
  if (!reached) return std::numeric_limits<double>::quiet_NaN();
  for (const double v : x)
    if (!std::isfinite(v))
      throw integration_error("state: the state became non-finite; try a smaller dt", o.t_end);
  return x[static_cast<std::size_t>(o.component)];
}

// A flip map's value: the flip time, NaN where the energy rules a flip out. flip_times
// gives those cells +inf, so only its +inf cells need the energy looked at again.
void mark_forbidden(const chain& c, std::span<const double> starts, int link,
                    std::vector<double>& times) {
  const auto m = static_cast<std::size_t>(c.state_size());
  for (std::size_t i = 0; i < times.size(); ++i)
    if (std::isinf(times[i]) && energy_forbids_flip(c, starts.subspan(i * m, m), link))
      times[i] = std::numeric_limits<double>::quiet_NaN();
}

}  // namespace

void map_cell_options::validate(const chain& c) const {
  // A flip is an arm passing the pivot's upright; the maps' axes and lanes know the angles of
  // a chain on a fixed pivot only.
  if (c.has_cart())
    throw std::invalid_argument(
        fmt::format("{}: the chain is on a cart; maps take chains on a fixed pivot",
                    map_quantity_name(quantity)));
  if (!(dt > 0) || !(t_end >= dt) || !std::isfinite(t_end))
    throw std::invalid_argument(fmt::format("{}: need 0 < dt <= t_end, got dt = {}, t_end = {}",
                                            map_quantity_name(quantity), dt, t_end));
  check_cell_steps(t_end, dt);
  stepping.validate(map_quantity_name(quantity));
  if (!map_takes_stepper(quantity, stepping.stepper))
    throw std::invalid_argument(
        fmt::format("{}: the chaos indicators integrate with rk4 only, not {}",
                    map_quantity_name(quantity), stepper_name(stepping.stepper)));
  if (quantity == map_quantity::flip) {
    energy_forbids_flip(c, std::vector<double>(static_cast<std::size_t>(c.state_size()), 0.0),
                        flip_link);
  } else if (quantity == map_quantity::lyapunov) {
    const auto lo = map_lyapunov_options(*this);
    lo.validate();
    lo.integration.validate();
  } else if (quantity == map_quantity::gali) {
    const int k = gali_order == 0 ? c.links() + 1 : gali_order;
    if (k < 2 || k > c.state_size())
      throw std::invalid_argument(fmt::format(
          "gali: the order k of GALI_k must be 2..{} (2n) for the {}-link chain, got {}",
          c.state_size(), c.links(), gali_order));
  } else if (quantity == map_quantity::state) {
    if (component < 0 || component >= c.state_size())
      throw std::invalid_argument(
          fmt::format("state: the component must be 0..{} (2n - 1) for the {}-link chain, got {}",
                      c.state_size() - 1, c.links(), component));
  }
}

double map_cell(const chain& c, std::span<const double> x0, const map_cell_options& options) {
  if (x0.size() != static_cast<std::size_t>(c.state_size()))
    throw std::invalid_argument(fmt::format("{}: the {}-link chain needs a state of {}, got {}",
                                            map_quantity_name(options.quantity), c.links(),
                                            c.state_size(), x0.size()));
  return map_cells(c, x0, options).front();
}

std::vector<double> map_cells(const chain& c, std::span<const double> starts,
                              const map_cell_options& requested) {
  // The cells' own integrations hear only the stop requests of the caller's control.
  stop_only stop(requested.control);
  map_cell_options options = requested;
  options.control = stop.get();
  if (options.quantity == map_quantity::flip) {
    auto times = flip_times(
        c, starts,
        {options.t_end, options.dt, options.flip_link, options.stepping, options.control});
    mark_forbidden(c, starts, options.flip_link, times);
    return times;
  }
  const auto m = static_cast<std::size_t>(c.state_size());
  if (starts.size() % m != 0)
    throw std::invalid_argument(
        fmt::format("{}: the {}-link chain needs states of {} one after another, got {} numbers",
                    map_quantity_name(options.quantity), c.links(), m, starts.size()));
  options.validate(c);
  std::vector<double> out(starts.size() / m);
  const batch_kernels* k = lane_kernels(c);
  const auto check_starts = [&](std::string_view prefix) {
    for (std::size_t i = 0; i < out.size(); ++i)
      detail::require_finite_start(starts.subspan(i * m, m), prefix);
  };
  if (options.quantity == map_quantity::lyapunov) {
    const lyapunov_options lo = map_lyapunov_options(options);
    // Gauss–Legendre's Lyapunov exponents come from its tangent map (the derivative of each
    // step, lyapunov.cpp), which the lanes do not have: cell by cell.
    if (k == nullptr || is_gauss_legendre(options.stepping.stepper))
      return cell_by_cell(
          starts, m,
          [&](std::span<const double> x0) {
            const lyapunov_result r = maximal_lyapunov_exponent(c, x0, lo);
            return r.stopped ? std::numeric_limits<double>::quiet_NaN() : r.exponents.front();
          },
          options.control);
    check_starts("");
    if (options.stepping.stepper == stepper_kind::dopri5)
      lyapunov_on_dopri5_lanes(*k, c, starts, all_cells(out.size()), lo, out);
    else
      lyapunov_on_lanes(*k, c, starts, all_cells(out.size()), lo, out);
  } else if (is_indicator(options.quantity)) {
    if (k == nullptr)
      return cell_by_cell(
          starts, m, [&](std::span<const double> x0) { return indicator_cell(c, x0, options); },
          options.control);
    check_starts("chaos indicators: ");
    const auto pick = [&](const chaos_indicator_sample& sample) {
      return indicator_value(options.quantity, sample);
    };
    indicators_on_lanes(*k, c, starts, all_cells(out.size()), options.t_end, options.dt,
                        indicator_vectors(c, options), options.control, pick, out);
  } else {
    if (k == nullptr)
      return cell_by_cell(
          starts, m, [&](std::span<const double> x0) { return final_coordinate(c, x0, options); },
          options.control);
    if (options.stepping.stepper == stepper_kind::dopri5) {
      final_coordinates_on_dopri5_lanes(*k, c, starts, all_cells(out.size()), options, out);
    } else {
      std::vector<std::size_t> failed;
      with_fixed_step_lanes(*k, c, options.stepping.stepper, [&](const auto& make) {
        final_coordinates_on_lanes(c, starts, all_cells(out.size()), options, make, out, failed);
      });
      // Cells a Gauss–Legendre lane could not solve: the library's Newton iteration.
      by_library(
          starts, m, failed,
          [&](std::span<const double> x0) { return final_coordinate(c, x0, options); }, out,
          options.control);
    }
  }
  return out;
}

double grid_value(double from, double to, int count, int i) {
  return count == 1 ? from : from + (to - from) * static_cast<double>(i) / (count - 1);
}

}  // namespace npend
