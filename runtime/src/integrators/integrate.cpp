#include "npend/integrators/integrate.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

#include "npend/chain_system.hpp"
#include "npend/integrators/integrate_system.hpp"
#include "npend/integrators/taylor.hpp"

namespace npend {

void integration_options::validate() const {
  const auto finite = [](double v, const char* name) {
    if (!std::isfinite(v))
      throw std::invalid_argument(
          fmt::format("integration option {} is {}: it must be finite", name, v));
  };
  finite(t_start, "t_start");
  finite(t_end, "t_end");
  finite(dt, "dt");
  finite(abs_tol, "abs_tol");
  finite(rel_tol, "rel_tol");
  if (dt == 0) throw std::invalid_argument("integration option dt must not be 0");
  if ((t_end - t_start) / dt < 1 - 1e-9)
    throw std::invalid_argument(fmt::format(
        "integration interval [{}, {}] holds no step of dt = {}: dt must point from t_start to "
        "t_end and be no longer than the interval",
        t_start, t_end, dt));
  if (abs_tol < 0 || rel_tol < 0 || (abs_tol == 0 && rel_tol == 0))
    throw std::invalid_argument(fmt::format(
        "integration tolerances abs_tol = {}, rel_tol = {}: both must be >= 0 and one > 0", abs_tol,
        rel_tol));
  if (taylor_order != 0 && (taylor_order < 2 || taylor_order > taylor_max_order))
    throw std::invalid_argument(fmt::format(
        "integration option taylor_order is {}: it must be 0 (from the tolerances) or 2..{}",
        taylor_order, taylor_max_order));
  if (!(min_step_ratio > 0 && min_step_ratio < 1))
    throw std::invalid_argument(fmt::format(
        "integration option min_step_ratio is {}: it must lie in (0, 1)", min_step_ratio));
}

std::size_t output_steps(const integration_options& options) {
  options.validate();
  const double steps = std::floor((options.t_end - options.t_start) / options.dt + 1e-9);
  // Beyond 2^53 the grid index stops being exact in double.
  if (steps > 9007199254740992.0)
    throw std::invalid_argument(fmt::format(
        "integration interval needs {:.3g} steps of dt = {}: too many", steps, options.dt));
  return static_cast<std::size_t>(steps);
}

output_grid make_output_grid(const integration_options& options) {
  return {options.t_start, options.t_end, options.dt, output_steps(options)};
}

std::size_t output_intervals(const integration_options& options) {
  const std::size_t whole = output_steps(options);
  const double last = options.t_start + static_cast<double>(whole) * options.dt;
  const bool short_step_left = std::fabs(options.t_end - last) > 1e-9 * std::fabs(options.dt);
  return whole + (short_step_left ? 1 : 0);
}

namespace {

// `F` (the chain's rhs or its Jacobian) that counts its calls into *count, for
// integration_result's evaluation counts. odeint copies systems freely: the copies share the
// count.
template <class F>
class counted {
 public:
  counted(F f, std::size_t* count) : m_f(std::move(f)), m_count(count) {}
  template <class... Args>
  void operator()(Args&&... args) const {
    ++*m_count;
    m_f(std::forward<Args>(args)...);
  }
  int size() const { return m_f.size(); }

 private:
  F m_f;
  std::size_t* m_count;
};

}  // namespace

void check_stepper_fits(const chain& c, stepper_kind stepper) {
  if (stepper == stepper_kind::taylor) taylor_integrator<double>(c.kernels_in_use(), 1e-10, 1e-10);
}

void integration_step::state_at(double t, std::span<double> x) const {
  if (x.size() != m_x_begin.size())
    throw std::invalid_argument(
        fmt::format("integration_step::state_at: x has {} entries; the system has dimension {}",
                    x.size(), m_x_begin.size()));
  // A few units of rounding of the step's ends are tolerated (t_begin + h need not be t_end).
  const double slack = 4 * std::numeric_limits<double>::epsilon() *
                       std::max(std::fabs(m_t_begin), std::fabs(m_t_end));
  if (!(t >= std::min(m_t_begin, m_t_end) - slack && t <= std::max(m_t_begin, m_t_end) + slack))
    throw std::invalid_argument(
        fmt::format("integration_step::state_at: t = {} is outside the step [{}, {}]", t,
                    std::min(m_t_begin, m_t_end), std::max(m_t_begin, m_t_end)));
  m_interpolant->state_at(t, x);
}

integration_result integrate(const chain& c, std::span<const double> x0,
                             const integration_options& options, const observer_function& observer,
                             const step_observer_function& step_observer) {
  if (x0.size() != static_cast<std::size_t>(c.state_size()))
    throw std::invalid_argument(
        fmt::format("start state x0 has {} entries; the {}-link chain needs {}", x0.size(),
                    c.links(), c.state_size()));
  std::size_t evaluations = 0, jacobian_evaluations = 0;
  const auto [rhs, jacobian] = make_implicit_system(c);
  const std::pair system(counted(rhs, &evaluations), counted(jacobian, &jacobian_evaluations));
  integration_result result;
  if (options.stepper == stepper_kind::taylor) {
    options.validate();
    taylor_stepper stepper(c.kernels_in_use(), options.abs_tol, options.rel_tol,
                           options.taylor_order);
    result = detail::integrate_visited(stepper, system, x0, options, observer, step_observer);
  } else {
    result = integrate_system(system, x0, options, observer, step_observer);
  }
  result.evaluations = evaluations;
  result.jacobian_evaluations = jacobian_evaluations;
  return result;
}

}  // namespace npend
