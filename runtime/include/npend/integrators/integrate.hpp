// One way to integrate a chain with any stepper, onto a fixed output grid.
#pragma once

#include <concepts>
#include <cstddef>
#include <functional>
#include <span>
#include <type_traits>
#include <vector>

#include "npend/chain.hpp"
#include "npend/integrators/stepper_kind.hpp"
#include "npend/run_control.hpp"

namespace npend {

/// The highest order the taylor stepper takes.
inline constexpr int taylor_max_order = 60;

/// What npend::integrate does and where it reports.
///
/// The output grid is t_k = t_start + k·dt for k = 0 … N with
/// N = output_steps(options) = ⌊(t_end − t_start)/dt⌋ (a grid point within 1e-9·dt of t_end
/// counts), and then t_end itself when it lies between grid points, after a shorter last
/// step: the run always ends at t_end. dt < 0 integrates backwards in time. Fixed-step
/// steppers (rk4, gauss4, gauss6) step exactly from grid point to grid point. Adaptive ones choose
/// their own steps under abs_tol and rel_tol (odeint's error norm: |err_i| ≤ abs_tol +
/// rel_tol·|x_i|) and reach the grid by dense output (dopri5, bs, rosenbrock4, taylor) or by steps
/// cut to end on each grid point (rkf78); dt is also their first trial step.
struct integration_options {
  stepper_kind stepper = stepper_kind::gauss6;
  double t_start = 0;
  double t_end = 0;
  double dt = 1e-3;
  double abs_tol = 1e-10;
  double rel_tol = 1e-10;
  /// The order of the taylor stepper: 0 chooses it from the tolerances (taylor_order_for),
  /// 2..taylor_max_order fixes it. Other steppers ignore it.
  int taylor_order = 0;
  /// An adaptive stepper whose step falls below min_step_ratio·|dt| stops the integration
  /// (a collapsed step size).
  double min_step_ratio = 1e-9;
  /// Progress reports (grid points done of N) and stop requests, polled at every grid
  /// point; a stop ends the run like an observer's.
  /// Not owned; may be null.
  run_control* control = nullptr;

  /// Throws std::invalid_argument naming the field: non-finite values, dt = 0 or pointing
  /// away from t_end, an interval shorter than one dt, negative tolerances or both zero,
  /// min_step_ratio outside (0, 1), taylor_order outside 0 and 2..taylor_max_order.
  void validate() const;
};

/// Throws std::invalid_argument where `stepper` cannot integrate `c`: taylor on a chain
/// without Taylor kernels (the loop kernels of an unbuilt link count) or with a custom pivot
/// path. npend::integrate refuses the same; front ends call this to refuse it with the other
/// bad input, before a run starts.
void check_stepper_fits(const chain& c, stepper_kind stepper);

/// N, the number of whole steps of dt within the interval (see integration_options).
/// Validates the options.
std::size_t output_steps(const integration_options& options);

/// The output grid of npend::integrate: t_k = t_start + k·dt for k = 0 … N, then t_end.
struct output_grid {
  double t_start = 0, t_end = 0, dt = 1;
  std::size_t whole_steps = 0;  ///< N = output_steps
  /// t_k, computed from k (not accumulated, so no drift over long runs); the point after the
  /// last whole step is t_end itself.
  double time(std::size_t k) const {
    return k > whole_steps ? t_end : t_start + static_cast<double>(k) * dt;
  }
};
/// The grid of `options`. Validates them.
output_grid make_output_grid(const integration_options& options);

/// The number of output steps of npend::integrate: N, plus one when t_end lies between grid
/// points (the shorter last step to t_end). The output has output_intervals + 1 points.
/// Validates the options.
std::size_t output_intervals(const integration_options& options);

/// How an integration ended.
struct integration_result {
  /// The state at `t` (dim of the system, 2n for a chain).
  std::vector<double> state;
  /// The last grid time reached: t_end, or earlier if the observer stopped; if
  /// the step observer stopped the run, the end of that step.
  double t = 0;
  /// Grid points passed to the observer, including t_start.
  std::size_t outputs = 0;
  /// Steps the stepper took: N for the fixed-step ones, accepted internal steps for the
  /// adaptive ones.
  std::size_t steps = 0;
  /// True if an observer, the step observer or the run control asked to stop before the end
  /// of the grid.
  bool stopped = false;
  /// Evaluations of the right-hand side f(x, t), as npend::integrate counts them (0 from
  /// integrate_system and integrate_with): the stepper's stages, the Newton iterations of
  /// the implicit Gauss–Legendre steps, and the derivatives a cubic Hermite dense output
  /// takes at the ends of a step that a step observer looks into. The taylor stepper makes
  /// none: it expands the solution with the generated Taylor kernels, once per step.
  std::size_t evaluations = 0;
  /// Evaluations of the Jacobian ∂f/∂x (gauss4 and gauss6 where their simplified Newton
  /// iteration renews it, rosenbrock4 once per attempted step), counted likewise.
  std::size_t jacobian_evaluations = 0;
};

/// An observer's answer after seeing a grid point.
enum class observer_action { proceed, stop };

/// Called at every grid point with the time t and the state x (dim of the system); x is
/// valid only during the call.
using observer_function = std::function<observer_action(double t, std::span<const double> x)>;

namespace detail {

/// The continuous extension of one step, behind integration_step::state_at.
class step_interpolant {
 public:
  /// x(t) for t within the step (x: dim of the system; both checked by the caller).
  virtual void state_at(double t, std::span<double> x) const = 0;
  /// A bound on state_at's degree as a polynomial in t over the step, or -1 where it is not
  /// known (a stepper handed to integrate_with).
  virtual int degree() const = 0;

 protected:
  ~step_interpolant() = default;
};

}  // namespace detail

/// One step of the stepper, as a step observer sees it: from (t_begin, x_begin) to
/// (t_end, x_end) (t_end < t_begin when integrating backwards), with the stepper's
/// continuous approximation of the solution in between. Only valid during the call.
///
/// The steps are the stepper's own: dt for the fixed-step steppers (rk4, gauss4, gauss6),
/// the accepted steps for the adaptive ones (rkf78's cut at the grid points). state_at is
/// the stepper's dense output for dopri5, bs and rosenbrock4 (their own interpolation
/// formulas), and for rk4, rkf78, gauss4 and gauss6 the cubic Hermite interpolant of the
/// end states and their derivatives f(x_begin), f(x_end) — error O(h⁴) over the step, as
/// good as gauss6's own collocation polynomial (degree 3) and better than gauss4's (degree
/// 2); the two derivatives are evaluated on the first call only.
class integration_step {
 public:
  integration_step(double t_begin, std::span<const double> x_begin, double t_end,
                   std::span<const double> x_end, const detail::step_interpolant& interpolant)
      : m_t_begin(t_begin),
        m_t_end(t_end),
        m_x_begin(x_begin),
        m_x_end(x_end),
        m_interpolant(&interpolant) {}

  double t_begin() const { return m_t_begin; }
  double t_end() const { return m_t_end; }
  /// The states at the ends of the step (dim of the system).
  std::span<const double> x_begin() const { return m_x_begin; }
  std::span<const double> x_end() const { return m_x_end; }

  /// The interpolated state at t, which must lie within the step, into x (dim of the
  /// system). Throws std::invalid_argument for t outside the step or x of the wrong size.
  void state_at(double t, std::span<double> x) const;
  /// state_at is a polynomial in t over the step of at most this degree (3 for the cubic
  /// Hermite interpolant, the stepper's own for the others: 3 for rosenbrock4, 6 for dopri5,
  /// 18 for bs, the order for taylor), so that degree() + 1 of its values give all of it; -1
  /// where it is not known (a stepper handed to integrate_with).
  int degree() const { return m_interpolant->degree(); }

 private:
  double m_t_begin, m_t_end;
  std::span<const double> m_x_begin, m_x_end;
  const detail::step_interpolant* m_interpolant;
};

/// Called after every step of the stepper, before the grid points the step reached are
/// passed to the grid observer; it may stop the run by returning observer_action::stop.
/// Locating events between the grid points (Poincaré sections) is what it is for.
using step_observer_function = std::function<observer_action(const integration_step& step)>;

/// Integrates Hamilton's equations of `c` from x0 (dim 2n = [φ, p]) over the grid of
/// `options` with the chosen stepper, calling `observer` (if given) at t_start and at every
/// grid point after it, and `step_observer` (if given) after every step of the stepper.
/// Either may stop the run by returning observer_action::stop; the result then holds the
/// grid point, or the end of the step, where it stopped.
///
/// The taylor stepper runs the chain's generated Taylor kernels (npend/integrators/taylor.hpp),
/// which every built link count has; a chain on the loop kernels or with a custom pivot path
/// has none and is refused.
///
/// Throws std::invalid_argument for bad options or a start state of the wrong size or with
/// non-finite entries, and npend::integration_error (with the time) when the state becomes
/// non-finite, an adaptive step size collapses, or a Gauss–Legendre step's Newton iteration
/// does not converge.
integration_result integrate(const chain& c, std::span<const double> x0,
                             const integration_options& options,
                             const observer_function& observer = {},
                             const step_observer_function& step_observer = {});

/// As above, for an observer that returns nothing (it never stops the run).
template <class Observer>
requires std::invocable<Observer&, double, std::span<const double>> &&
    std::is_void_v<std::invoke_result_t<Observer&, double, std::span<const double>>>
        integration_result integrate(const chain& c, std::span<const double> x0,
                                     const integration_options& options, Observer&& observer) {
  return integrate(c, x0, options,
                   observer_function([&observer](double t, std::span<const double> x) {
                     observer(t, x);
                     return observer_action::proceed;
                   }));
}

}  // namespace npend
