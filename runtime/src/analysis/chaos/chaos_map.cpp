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

#include "analysis/chaos/map_lanes.hpp"
#include "analysis/detail/argument_checks.hpp"
#include "analysis/detail/map_cell_common.hpp"
#include "analysis/detail/map_cell_steps.hpp"
#include "gpu/host_kernels.hpp"
#include "npend/chain_system.hpp"
#include "npend/integrators/gauss_legendre.hpp"
#include "npend/integrators/integrate.hpp"
#include "npend/integrators/integration_error.hpp"

namespace npend {

using detail::all_cells;
using detail::by_library;
using detail::flip_energy_holds;
using detail::has_flipped;
using detail::hermite_flip_time;
using detail::indicator_value;
using detail::indicator_vectors;
using detail::locate_flip;
using detail::map_lyapunov_options;
using detail::watches_arm;
using detail::whole_steps;

namespace {

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
  // A stepper the flip code has no path for must not fall through to rk4's.
  if (!map_takes_stepper(map_quantity::flip, o.stepping.stepper))
    throw std::invalid_argument(
        fmt::format("flip: {} maps only the chaos indicators (fli, megno, sali, gali)",
                    stepper_name(o.stepping.stepper)));
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

namespace detail {

// The upright fraction of each arm's step is the GPU kernels' function
// (runtime/src/gpu/map_kernels.cuh, compiled here for the CPU), so that both locate a flip
// by the same operations.
double hermite_flip_time(const double* phi0, const double* dphi0, const double* phi1,
                         const double* dphi1, std::size_t n, double t0, double h,
                         const flip_options& o) {
  double theta = 1;
  for (std::size_t k = 0; k < n; ++k)
    if (watches_arm(o.link, k + 1) && std::fabs(phi1[k]) >= std::numbers::pi)
      theta =
          std::min(theta, gpu::hermite_upright_fraction(phi0[k], dphi0[k], phi1[k], dphi1[k], h));
  return t0 + theta * h;
}

bool flip_energy_holds(const chain& c, double h0, std::span<const double> x1, double t1) {
  const chain_parameters& p = c.parameters();
  if (p.pivot.moves()) return true;
  const double drift = c.hamiltonian(x1, t1) - h0;
  const double allowed = flip_energy_tolerance * h0;
  return p.is_damped() ? drift <= allowed : std::fabs(drift) <= allowed;
}

}  // namespace detail

bool is_map_stepper(stepper_kind stepper) {
  return serves(stepper, stepper_use::map) || serves(stepper, stepper_use::indicators);
}

std::string map_stepper_names() {
  std::string out;
  for (const stepper_kind kind : all_stepper_kinds())
    if (is_map_stepper(kind))
      out += fmt::format("{}{}", out.empty() ? "" : ", ", stepper_name(kind));
  return out;
}

void map_stepping::validate(std::string_view what) const {
  if (!is_map_stepper(stepper))
    throw std::invalid_argument(fmt::format("{}: maps integrate with one of {}, not {}", what,
                                            map_stepper_names(), stepper_name(stepper)));
  if (stepper != stepper_kind::dopri5 && stepper != stepper_kind::taylor) return;
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
  // chaos_indicators' Taylor steps take one tolerance for both.
  if (stepper != stepper_kind::taylor) return;
  if (abs_tol != rel_tol)
    throw std::invalid_argument(fmt::format(
        "{}: taylor takes one tolerance: abs_tol and rel_tol must be equal, got {} and {}", what,
        abs_tol, rel_tol));
  if (!(rel_tol <= 1e-6))
    throw std::invalid_argument(
        fmt::format("{}: the taylor tolerance must lie in (0, 1e-6], got {}", what, rel_tol));
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

// Each start's value by `cell`, one after another: by_library of every start.
template <class Cell>
std::vector<double> cell_by_cell(std::span<const double> starts, std::size_t m, const Cell& cell,
                                 run_control* control = nullptr) {
  std::vector<double> out(starts.size() / m);
  by_library(starts, m, all_cells(out.size()), cell, out, control);
  return out;
}

}  // namespace

int batch_lanes(const chain& c) {
  const detail::map_lanes& lanes = detail::active_map_lanes();
  return lanes.serves(c) ? lanes.lanes : 0;
}

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
  const detail::map_lanes& lanes = detail::active_map_lanes();
  if (!lanes.serves(c))
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
  lanes.flip_times(c, starts, queue, o, out);
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

double detail::indicator_value(map_quantity quantity, const chaos_indicator_sample& sample) {
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

namespace {

bool is_indicator(map_quantity quantity) {
  return quantity == map_quantity::fli || quantity == map_quantity::megno ||
         quantity == map_quantity::sali || quantity == map_quantity::gali;
}

}  // namespace

bool map_takes_stepper(map_quantity quantity, stepper_kind stepper) {
  return is_indicator(quantity) ? serves(stepper, stepper_use::indicators)
                                : serves(stepper, stepper_use::map);
}

namespace {

// FLI, MEGNO, SALI or GALI_k at t_end, cell by cell.
double indicator_cell(const chain& c, std::span<const double> x0, const map_cell_options& o) {
  chaos_indicator_options io;
  io.t_end = o.t_end;
  io.dt = o.dt;
  io.vectors = indicator_vectors(c, o);
  io.stepper = o.stepping.stepper;
  io.tolerance = o.stepping.rel_tol;
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
  if (!map_takes_stepper(quantity, stepping.stepper)) {
    if (is_indicator(quantity))
      throw std::invalid_argument(fmt::format(
          "{}: the chaos indicators integrate with one of {}, not {}", map_quantity_name(quantity),
          stepper_names(stepper_use::indicators), stepper_name(stepping.stepper)));
    throw std::invalid_argument(
        fmt::format("{}: {} maps only the chaos indicators (fli, megno, sali, gali)",
                    map_quantity_name(quantity), stepper_name(stepping.stepper)));
  }
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
  const detail::map_lanes& lanes = detail::active_map_lanes();
  const bool on_lanes = lanes.serves(c);
  const auto check_starts = [&](std::string_view prefix) {
    for (std::size_t i = 0; i < out.size(); ++i)
      detail::require_finite_start(starts.subspan(i * m, m), prefix);
  };
  if (options.quantity == map_quantity::lyapunov) {
    const lyapunov_options lo = map_lyapunov_options(options);
    // Gauss–Legendre's Lyapunov exponents come from its tangent map (the derivative of each
    // step, lyapunov.cpp), which the lanes do not have: cell by cell.
    if (!on_lanes || is_gauss_legendre(options.stepping.stepper))
      return cell_by_cell(
          starts, m,
          [&](std::span<const double> x0) {
            const lyapunov_result r = maximal_lyapunov_exponent(c, x0, lo);
            return r.stopped ? std::numeric_limits<double>::quiet_NaN() : r.exponents.front();
          },
          options.control);
    check_starts("");
    lanes.lyapunov(c, starts, lo, out);
  } else if (is_indicator(options.quantity)) {
    // The lanes have no Taylor steps: taylor's maps go cell by cell.
    if (!on_lanes || options.stepping.stepper == stepper_kind::taylor)
      return cell_by_cell(
          starts, m, [&](std::span<const double> x0) { return indicator_cell(c, x0, options); },
          options.control);
    check_starts("chaos indicators: ");
    lanes.indicators(c, starts, options, indicator_vectors(c, options), out);
  } else {
    if (!on_lanes)
      return cell_by_cell(
          starts, m, [&](std::span<const double> x0) { return final_coordinate(c, x0, options); },
          options.control);
    std::vector<std::size_t> failed;
    lanes.final_coordinates(c, starts, options, out, failed);
    // Cells a Gauss–Legendre lane could not solve: the library's Newton iteration.
    by_library(
        starts, m, failed,
        [&](std::span<const double> x0) { return final_coordinate(c, x0, options); }, out,
        options.control);
  }
  return out;
}

double grid_value(double from, double to, int count, int i) {
  return count == 1 ? from : from + (to - from) * static_cast<double>(i) / (count - 1);
}

}  // namespace npend
