// The integration engine behind npend::integrate, for any system and any stepper.
//
// integrate_with drives any odeint stepper (or ours) over the output grid of
// integration_options, choosing its loop by the stepper's category as odeint's own
// integrate functions do: fixed steps from grid point to grid point (stepper_tag,
// error_stepper_tag), controlled steps cut at the grid points (controlled_stepper_tag), or
// free steps with dense output at the grid points (dense_output_stepper_tag).
// integrate_system is the factory on top that turns a stepper_kind (the names users type)
// into a configured stepper. Analyses that integrate something other than a bare chain
// (e.g. a chain with its variational equations) call these directly.
#pragma once

#include <algorithm>
#include <boost/numeric/odeint/stepper/bulirsch_stoer_dense_out.hpp>
#include <boost/numeric/odeint/stepper/generation.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta4.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta_dopri5.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta_fehlberg78.hpp>
#include <boost/numeric/odeint/stepper/stepper_categories.hpp>
#include <boost/numeric/odeint/util/odeint_error.hpp>
#include <cmath>
#include <cstddef>
#include <memory>
#include <span>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "npend/integrators/detail/rejecting_range_algebra.hpp"
#include "npend/integrators/detail/rosenbrock4_dense_output.hpp"
#include "npend/integrators/gauss_legendre.hpp"
#include "npend/integrators/integrate.hpp"
#include "npend/integrators/integration_error.hpp"

namespace npend {

class taylor_stepper;  // npend/integrators/taylor.hpp

namespace detail {

/// How error messages name the stepper: by the name users type for the steppers of
/// integrate_system, neutrally for a stepper handed to integrate_with.
struct stepper_label {
  /// "rk4", or "supplied stepper's": "the state became non-finite in the <step> step".
  std::string step;
  /// "dopri5", or "the supplied stepper": "the adaptive step size of <owner> collapsed".
  std::string owner;
  bool adaptive = false;
};

/// The bookkeeping every stepper loop shares: the grid, the observers, the run control, the
/// result.
class integration_run {
 public:
  integration_run(const integration_options& options, const observer_function& observer,
                  const step_observer_function& step_observer, stepper_label label)
      : m_options(options),
        m_observer(observer),
        m_step_observer(step_observer),
        m_label(std::move(label)),
        m_grid(make_output_grid(options)),
        m_steps(output_intervals(options)) {}

  /// The output steps: the whole steps of dt, and the shorter last one up to t_end if any.
  std::size_t grid_steps() const { return m_steps; }
  double dt() const { return m_options.dt; }
  /// t_k, computed from k (not accumulated, so no drift over long runs); the point after the
  /// last whole step is t_end itself.
  double grid_time(std::size_t k) const { return m_grid.time(k); }
  /// The length of output step k (from t_(k-1) to t_k): dt, or what is left to t_end.
  double step_length(std::size_t k) const {
    return k > m_grid.whole_steps ? m_options.t_end - grid_time(m_grid.whole_steps) : m_options.dt;
  }
  double min_step() const { return m_options.min_step_ratio * std::fabs(m_options.dt); }
  integration_result& result() { return m_result; }

  /// Passes grid point k to the observer and the run control and records it; false if
  /// either stops the run.
  bool observe(std::size_t k, std::span<const double> x) {
    m_result.t = grid_time(k);
    ++m_result.outputs;
    const bool observer_stops = m_observer && m_observer(m_result.t, x) == observer_action::stop;
    const bool control_stops =
        report_progress(m_options.control, static_cast<double>(k), static_cast<double>(m_steps));
    const bool stop = observer_stops || control_stops;
    if (stop) {
      m_result.stopped = true;
      m_result.state.assign(x.begin(), x.end());
    }
    return !stop;
  }

  /// Whether a step observer wants to see the steps.
  bool watches_steps() const { return static_cast<bool>(m_step_observer); }

  /// Passes a step to the step observer; false if it stops the run (the result then holds
  /// the end of the step).
  bool observe_step(const integration_step& step) {
    if (m_step_observer(step) == observer_action::proceed) return true;
    m_result.stopped = true;
    m_result.t = step.t_end();
    m_result.state.assign(step.x_end().begin(), step.x_end().end());
    return false;
  }

  /// Throws integration_error if x has a non-finite entry after the step from `from` to `t`;
  /// its time() is `from`, the last time with a finite state.
  void check_finite(std::span<const double> x, double from, double t) const {
    for (double v : x)
      if (!std::isfinite(v)) {
        std::ostringstream msg;
        msg.precision(10);
        msg << "the state became non-finite in the " << m_label.step << " step from t = " << from
            << " to t = " << t << "; try "
            << (m_label.adaptive ? "tighter tolerances or a smaller dt"
                                 : "a smaller dt or an adaptive stepper (dopri5, rkf78)");
        throw integration_error(msg.str(), from);
      }
  }

  /// Throws integration_error reporting a collapsed adaptive step size at time t.
  [[noreturn]] void step_collapsed(double t, double step, const char* detail = nullptr) const {
    std::ostringstream msg;
    msg.precision(6);
    msg << "the adaptive step size of " << m_label.owner << " collapsed at t = " << t;
    if (step != 0) msg << " (step " << step << ")";
    if (detail != nullptr) msg << " (" << detail << ")";
    msg << "; the tolerances (abs " << m_options.abs_tol << ", rel " << m_options.rel_tol
        << ") may be too tight or the motion too violent: loosen them, or use a fixed-step "
           "stepper (gauss6) with a small dt";
    throw integration_error(msg.str(), t);
  }

 private:
  const integration_options& m_options;
  const observer_function& m_observer;
  const step_observer_function& m_step_observer;
  stepper_label m_label;
  output_grid m_grid;
  std::size_t m_steps;
  integration_result m_result;
};

/// The adaptive steppers of visit_stepper, on rejecting_range_algebra.
using checked_dopri5 =
    boost::numeric::odeint::runge_kutta_dopri5<std::vector<double>, double, std::vector<double>,
                                               double, rejecting_range_algebra>;
using checked_fehlberg78 =
    boost::numeric::odeint::runge_kutta_fehlberg78<std::vector<double>, double, std::vector<double>,
                                                   double, rejecting_range_algebra>;
using checked_bulirsch_stoer = boost::numeric::odeint::bulirsch_stoer_dense_out<
    std::vector<double>, double, std::vector<double>, double, rejecting_range_algebra>;

/// The cubic Hermite interpolant of a step through the states at its ends with the
/// derivatives f there (evaluated on the first request): the dense output of the steppers
/// that have none of their own.
template <class Rhs>
class hermite_interpolant final : public step_interpolant {
 public:
  explicit hermite_interpolant(const Rhs& rhs) : m_rhs(rhs) {}

  /// The step from (t0, x0) to (t1, x1); both states must stay alive while it is used.
  void reset(double t0, const std::vector<double>& x0, double t1, const std::vector<double>& x1) {
    m_t0 = t0;
    m_t1 = t1;
    m_x0 = &x0;
    m_x1 = &x1;
    m_have_derivatives = false;
  }

  void state_at(double t, std::span<double> x) const override {
    const std::vector<double>& x0 = *m_x0;
    const std::vector<double>& x1 = *m_x1;
    if (!m_have_derivatives) {
      m_f0.resize(x0.size());
      m_f1.resize(x0.size());
      m_rhs(x0, m_f0, m_t0);
      m_rhs(x1, m_f1, m_t1);
      m_have_derivatives = true;
    }
    const double h = m_t1 - m_t0, s = (t - m_t0) / h, r = 1 - s;
    const double a0 = (1 + 2 * s) * r * r, b0 = s * r * r * h;
    const double a1 = s * s * (3 - 2 * s), b1 = -s * s * r * h;
    for (std::size_t i = 0; i < x.size(); ++i)
      x[i] = a0 * x0[i] + b0 * m_f0[i] + a1 * x1[i] + b1 * m_f1[i];
  }
  int degree() const override { return 3; }

 private:
  mutable Rhs m_rhs;
  double m_t0 = 0, m_t1 = 0;
  const std::vector<double>* m_x0 = nullptr;
  const std::vector<double>* m_x1 = nullptr;
  mutable std::vector<double> m_f0, m_f1;
  mutable bool m_have_derivatives = false;
};

/// A bound on the degree in t of a dense-output stepper's calc_state over its last step: 3
/// for rosenbrock4 (odeint's formula in s = (t - t_old)/dt), 6 for dopri5 (its continuous
/// extension, degree 5 in the weights times θ), 2 k_max + 2 = 18 for bs (its interpolation
/// in θ), the step's order for taylor; -1 for other steppers.
template <class Stepper>
int dense_output_degree(const Stepper& stepper) {
  if constexpr (std::is_same_v<Stepper, taylor_stepper>)
    return stepper.order();
  else if constexpr (std::is_same_v<Stepper, rosenbrock4_dense_output>)
    return 3;
  else if constexpr (std::is_same_v<Stepper, checked_bulirsch_stoer>)
    return 18;
  else if constexpr (requires { typename Stepper::controlled_stepper_type::stepper_type; }) {
    if constexpr (std::is_same_v<typename Stepper::controlled_stepper_type::stepper_type,
                                 checked_dopri5>)
      return 6;
    else
      return -1;
  } else
    return -1;
}

/// A dense-output stepper's own interpolation within its last step; `reversed` as in
/// run_dense (the stepper's clock runs as τ = 2 t0 − t).
template <class Stepper, class State>
class dense_interpolant final : public step_interpolant {
 public:
  dense_interpolant(const Stepper& stepper, const State& like, bool reversed, double t0)
      : m_stepper(stepper), m_buffer(like), m_reversed(reversed), m_t0(t0) {}

  void state_at(double t, std::span<double> x) const override {
    m_stepper.calc_state(m_reversed ? 2 * m_t0 - t : t, m_buffer);
    std::copy(&m_buffer[0], &m_buffer[0] + x.size(), x.begin());
  }
  int degree() const override { return dense_output_degree(m_stepper); }

 private:
  const Stepper& m_stepper;
  mutable State m_buffer;
  bool m_reversed;
  double m_t0;
};

/// A fixed-step stepper from grid point to grid point.
template <class Stepper, class System, class Rhs>
void run_fixed(Stepper& stepper, System system, const Rhs& rhs, std::vector<double>& x,
               integration_run& run) {
  if (!run.observe(0, x)) return;
  std::vector<double> begin;
  hermite_interpolant<Rhs> interpolant(rhs);
  for (std::size_t k = 1; k <= run.grid_steps(); ++k) {
    const double t = run.grid_time(k - 1);
    if (run.watches_steps()) begin = x;
    stepper.do_step(system, x, t, run.step_length(k));
    ++run.result().steps;
    run.check_finite(x, t, run.grid_time(k));
    if (run.watches_steps()) {
      interpolant.reset(t, begin, run.grid_time(k), x);
      if (!run.observe_step(integration_step(t, begin, run.grid_time(k), x, interpolant))) return;
    }
    if (!run.observe(k, x)) return;
  }
  run.result().state = x;
}

inline bool all_finite(const std::vector<double>& x) {
  return std::all_of(x.begin(), x.end(), [](double v) { return std::isfinite(v); });
}

/// A controlled stepper (try_step) with its steps cut to end on each grid point. A step that
/// the stepper accepts with a non-finite state is rejected here (and shrunk).
template <class Stepper, class System>
void run_controlled(Stepper& stepper, System system, std::vector<double>& x, integration_run& run) {
  namespace odeint = boost::numeric::odeint;
  if (!run.observe(0, x)) return;
  const double direction = run.dt() > 0 ? 1.0 : -1.0;
  double t = run.grid_time(0);
  double h = run.dt();  // the controller's proposal, kept across grid points
  std::vector<double> begin;
  hermite_interpolant<System> interpolant(system);
  for (std::size_t k = 1; k <= run.grid_steps(); ++k) {
    const double target = run.grid_time(k);
    int failures = 0;
    while (direction * (target - t) > 0) {
      const bool cut = direction * (t + h - target) >= 0;
      double step = cut ? target - t : h;
      double t_new = t;
      const double tried = step;
      begin = x;
      auto outcome = stepper.try_step(system, x, t_new, step);
      if (outcome == odeint::success && !all_finite(x)) {
        // A trial step that overflowed is a step that was too long, also for a supplied
        // stepper whose error norm let it through: back to its start, and 1/5 of it (the
        // Runge-Kutta controller's largest cut).
        x = begin;
        step = tried / 5;
        outcome = odeint::fail;
      }
      if (outcome == odeint::success) {
        ++run.result().steps;
        if (!cut && std::fabs(tried) < run.min_step()) run.step_collapsed(t, tried);
        const double from = t;
        t = cut ? target : t_new;
        if (run.watches_steps()) {
          interpolant.reset(from, begin, t, x);
          if (!run.observe_step(integration_step(from, begin, t, x, interpolant))) return;
        }
        h = cut ? direction * std::max(std::fabs(h), std::fabs(step)) : step;
        failures = 0;
      } else {
        h = step;
        if (std::fabs(h) < run.min_step()) run.step_collapsed(t, h);
        if (++failures > 500) run.step_collapsed(t, h, "500 rejected steps in a row");
      }
    }
    if (!run.observe(k, x)) return;
  }
  run.result().state = x;
}

/// dx/dτ = −f(x, 2 t0 − τ): the system run backwards in time from t0, as τ grows from t0.
template <class Rhs>
struct time_reversed {
  Rhs rhs;
  double t0;
  template <class State, class Deriv>
  void operator()(const State& x, Deriv& dxdt, double tau) const {
    rhs(x, dxdt, 2 * t0 - tau);
    for (auto& v : dxdt) v = -v;
  }
};

/// A dense-output stepper: it steps freely and interpolates at the grid points. With
/// `reversed` (for dt < 0) the stepper runs forwards in τ = 2 t_start − t on a
/// time_reversed system: odeint 1.74's bulirsch_stoer_dense_out cannot step backwards (a
/// rejected negative step is never shortened, odeint-v2 issue #55).
template <class Stepper, class System, class State>
void run_dense(Stepper& stepper, System system, State& x, integration_run& run,
               bool reversed = false) {
  namespace odeint = boost::numeric::odeint;
  const auto view = [](const State& s) { return std::span<const double>(&s[0], s.size()); };
  if (!run.observe(0, view(x))) return;
  const double t0 = run.grid_time(0);
  // The stepper's clock from physical time and back (an involution).
  const auto clock = [&](double t) { return reversed ? 2 * t0 - t : t; };
  const double step = reversed ? -run.dt() : run.dt();
  const double direction = step > 0 ? 1.0 : -1.0;
  stepper.initialize(x, t0, step);
  State begin = x;
  const dense_interpolant<Stepper, State> interpolant(stepper, x, reversed, t0);
  for (std::size_t k = 1; k <= run.grid_steps(); ++k) {
    const double target = clock(run.grid_time(k));
    while (direction * (stepper.current_time() - target) < 0) {
      const double from = stepper.current_time();
      if (run.watches_steps()) begin = stepper.current_state();
      try {
        stepper.do_step(system);
      } catch (const odeint::step_adjustment_error& e) {
        run.step_collapsed(clock(from), 0, e.what());
      }
      ++run.result().steps;
      run.check_finite(view(stepper.current_state()), clock(from), clock(stepper.current_time()));
      if (std::fabs(stepper.current_time_step()) < run.min_step())
        run.step_collapsed(clock(stepper.current_time()), stepper.current_time_step());
      if (run.watches_steps() && !run.observe_step(integration_step(
                                     clock(from), view(begin), clock(stepper.current_time()),
                                     view(stepper.current_state()), interpolant)))
        return;
    }
    stepper.calc_state(target, x);
    if (!run.observe(k, view(x))) return;
  }
  run.result().state.assign(&x[0], &x[0] + x.size());
}

/// odeint's rosenbrock4 (dense output) on `system`, through its C++17 wrapper: the wrapper
/// hands over raw arrays, which are copied into the vectors and the row-major Eigen matrix
/// the system's functions take.
template <class Rhs, class Jacobian>
rosenbrock4_dense_output make_rosenbrock4(const std::pair<Rhs, Jacobian>& system, std::size_t dim,
                                          double abs_tol, double rel_tol) {
  struct workspace {
    std::vector<double> x, dxdt, dfdt;
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> J;
  };
  auto w = std::make_shared<workspace>();
  w->x.resize(dim);
  w->dxdt.resize(dim);
  w->dfdt.resize(dim);
  w->J.resize(static_cast<Eigen::Index>(dim), static_cast<Eigen::Index>(dim));
  auto rhs = [w, f = system.first](const double* x, double* dxdt, double t) {
    std::copy(x, x + w->x.size(), w->x.begin());
    f(w->x, w->dxdt, t);
    std::copy(w->dxdt.begin(), w->dxdt.end(), dxdt);
  };
  auto jacobian = [w, jac = system.second](const double* x, double* J, double t, double* dfdt) {
    std::copy(x, x + w->x.size(), w->x.begin());
    jac(w->x, w->J, t, w->dfdt);
    std::copy(w->J.data(), w->J.data() + w->J.size(), J);
    std::copy(w->dfdt.begin(), w->dfdt.end(), dfdt);
  };
  return rosenbrock4_dense_output(dim, abs_tol, rel_tol, rhs, jacobian);
}

/// The right-hand side of a system: the rhs of an implicit system (rhs, jacobian), else
/// the system itself.
template <class System>
const auto& rhs_of(const System& system) {
  if constexpr (requires {
                  system.first;
                  system.second;
                })
    return system.first;
  else
    return system;
}

/// Checks the start state and runs the loop that fits the stepper's category; `reversed` as
/// in run_dense (dense-output steppers only).
template <class Stepper, class System>
integration_result run_stepper(Stepper& stepper, const System& system, std::span<const double> x0,
                               integration_run& run, bool reversed = false) {
  namespace odeint = boost::numeric::odeint;
  using category = typename odeint::unwrap_reference<Stepper>::type::stepper_category;
  for (std::size_t i = 0; i < x0.size(); ++i)
    if (!std::isfinite(x0[i]))
      throw std::invalid_argument("start state entry " + std::to_string(i + 1) + " is not finite");
  std::vector<double> x(x0.begin(), x0.end());
  if constexpr (std::is_base_of_v<odeint::dense_output_stepper_tag, category>) {
    run_dense(stepper, system, x, run, reversed);
  } else if constexpr (std::is_base_of_v<odeint::controlled_stepper_tag, category>) {
    run_controlled(stepper, system, x, run);
  } else {
    static_assert(std::is_base_of_v<odeint::stepper_tag, category> ||
                      std::is_base_of_v<odeint::error_stepper_tag, category>,
                  "integrate_with: not an odeint stepper category");
    run_fixed(stepper, system, rhs_of(system), x, run);
  }
  return std::move(run.result());
}

}  // namespace detail

/// Integrates `system` from x0 over the grid of `options` with the given stepper — any
/// odeint stepper (runge_kutta4, a controlled or dense-output stepper from
/// make_controlled/make_dense_output, bulirsch_stoer_dense_out, …) or npend's
/// gauss_legendre — and calls the observers and options.control as npend::integrate does
/// (see there). The loop follows the stepper's category: fixed-step steppers step exactly
/// from grid point to grid point, controlled ones have their steps cut to end on each grid
/// point, dense-output ones step freely and interpolate at the grid points (they are
/// (re)initialised at x0 with options.dt as their first step). options.stepper and the
/// tolerances are not used: the stepper brings its own.
///
/// `system` is what the stepper takes: odeint's System (x, dxdt, t), or the pair (rhs,
/// jacobian) of an implicit system for gauss_legendre and rosenbrock4. The stepper is used
/// by reference and may be reused for further runs. Throws as npend::integrate.
template <class Stepper, class System>
integration_result integrate_with(Stepper& stepper, const System& system,
                                  std::span<const double> x0, const integration_options& options,
                                  const observer_function& observer = {},
                                  const step_observer_function& step_observer = {}) {
  namespace odeint = boost::numeric::odeint;
  using category = typename odeint::unwrap_reference<Stepper>::type::stepper_category;
  constexpr bool adaptive = std::is_base_of_v<odeint::dense_output_stepper_tag, category> ||
                            std::is_base_of_v<odeint::controlled_stepper_tag, category>;
  detail::integration_run run(options, observer, step_observer,
                              {"supplied stepper's", "the supplied stepper", adaptive});
  return detail::run_stepper(stepper, system, x0, run);
}

/// Calls visit(stepper) with the stepper `kind` names, configured by the tolerances of
/// `options` — the one place where a stepper_kind becomes a stepper. `system` is the
/// implicit system (rhs, jacobian) the steppers will integrate (rosenbrock4 is built
/// around it); visit must integrate forwards in time with it (bulirsch_stoer_dense_out
/// cannot step backwards: integrate_system runs it on the time-reversed system).
template <class Rhs, class Jacobian, class Visitor>
decltype(auto) visit_stepper(stepper_kind kind, const integration_options& options,
                             const std::pair<Rhs, Jacobian>& system, std::size_t dim,
                             Visitor&& visit) {
  namespace odeint = boost::numeric::odeint;
  using state = std::vector<double>;
  const double atol = options.abs_tol, rtol = options.rel_tol;
  switch (kind) {
    case stepper_kind::rk4: {
      odeint::runge_kutta4<state> stepper;
      return visit(stepper);
    }
    case stepper_kind::gauss4: {
      gauss_legendre4 stepper;
      return visit(stepper);
    }
    case stepper_kind::gauss6: {
      gauss_legendre6 stepper;
      return visit(stepper);
    }
    // The adaptive steppers take their error norm from rejecting_range_algebra: a trial
    // step that overflows is rejected and shrunk, not accepted with a non-finite state.
    case stepper_kind::dopri5: {
      auto stepper = odeint::make_dense_output(atol, rtol, detail::checked_dopri5());
      return visit(stepper);
    }
    case stepper_kind::rkf78: {
      auto stepper = odeint::make_controlled(atol, rtol, detail::checked_fehlberg78());
      return visit(stepper);
    }
    case stepper_kind::bulirsch_stoer: {
      // Controlling the interpolation error too: its steps are long, and the dense output
      // between them must meet the tolerances as well.
      detail::checked_bulirsch_stoer stepper(atol, rtol, 1.0, 1.0, 0.0, true);
      return visit(stepper);
    }
    case stepper_kind::rosenbrock4: {
      auto stepper = detail::make_rosenbrock4(system, dim, atol, rtol);
      return visit(stepper);
    }
    case stepper_kind::taylor:
      throw std::invalid_argument(
          "the taylor stepper integrates a chain's own equations (its generated Taylor "
          "kernels), not a system given as functions such as this one: choose one of " +
          stepper_names(stepper_use::system));
  }
  throw std::logic_error("visit_stepper: unknown stepper kind");
}

namespace detail {

/// Runs `stepper` (made by visit_stepper for options.stepper) on the implicit system, or on
/// its rhs alone for the explicit steppers, naming options.stepper in error messages.
template <class Stepper, class Rhs, class Jacobian>
integration_result integrate_visited(Stepper& stepper, const std::pair<Rhs, Jacobian>& system,
                                     std::span<const double> x0, const integration_options& options,
                                     const observer_function& observer = {},
                                     const step_observer_function& step_observer = {}) {
  const std::string name(stepper_name(options.stepper));
  integration_run run(options, observer, step_observer, {name, name, is_adaptive(options.stepper)});
  if constexpr (std::is_same_v<Stepper, gauss_legendre4> ||
                std::is_same_v<Stepper, gauss_legendre6> ||
                std::is_same_v<Stepper, rosenbrock4_dense_output>) {
    return run_stepper(stepper, system, x0, run);
  } else if constexpr (std::is_same_v<Stepper, checked_bulirsch_stoer>) {
    if (options.dt < 0)
      return run_stepper(stepper, time_reversed<Rhs>{system.first, options.t_start}, x0, run, true);
    return run_stepper(stepper, system.first, x0, run);
  } else {
    return run_stepper(stepper, system.first, x0, run);
  }
}

}  // namespace detail

/// Integrates the implicit system `system` = (rhs, jacobian) — odeint's convention:
/// rhs(x, dxdt, t) and jacobian(x, J, t, dfdt) — from x0 (dim d) over the grid of `options`
/// with the stepper options.stepper names, as npend::integrate does for a chain (see there
/// for the observers and the errors). x and dxdt are std::vector<double> (dim d); J is a
/// row-major Eigen matrix (d × d), dfdt a std::vector<double> (∂f/∂t, which rosenbrock4
/// uses; the Gauss–Legendre steppers evaluate f at the stage times instead). Only
/// rosenbrock4, gauss4 and gauss6 call the jacobian.
template <class Rhs, class Jacobian>
integration_result integrate_system(const std::pair<Rhs, Jacobian>& system,
                                    std::span<const double> x0, const integration_options& options,
                                    const observer_function& observer = {},
                                    const step_observer_function& step_observer = {}) {
  return visit_stepper(options.stepper, options, system, x0.size(), [&](auto& stepper) {
    return detail::integrate_visited(stepper, system, x0, options, observer, step_observer);
  });
}

}  // namespace npend
