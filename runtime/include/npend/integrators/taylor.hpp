// Taylor's method on the generated Taylor kernels: adaptive order and step, and the Taylor
// polynomial of each step as its dense output.
//
// Each step computes the Taylor coefficients x^[0..p] of the solution through the current
// state by the emitted recurrences (generated/taylor_<model>_<n>.cpp, no JIT), chooses the
// step from the last two coefficients and sums the polynomial. The error is controlled a
// priori, so no step is rejected. Order and step follow Jorba & Zou, "A software package for
// the numerical integration of ODEs by means of high-order Taylor methods", Experimental
// Mathematics 14 (2005), section 3.2: with ε the tolerance, p = ⌈−½ ln ε + 1⌉ and
// h = min_{j = p−1, p} (ε·s / ‖x^[j]‖∞)^{1/j} · e^{−0.7/(p−1)}, where s = 1 under the
// absolute tolerance and s = ‖x‖∞ under the relative one (whichever is the larger of
// abs_tol and rel_tol·‖x‖∞ rules).
#pragma once

#include <boost/numeric/odeint/stepper/stepper_categories.hpp>
#include <cstddef>
#include <utility>
#include <vector>

#include "npend/integrators/integrate.hpp"
#include "npend/integrators/taylor_recurrences.hpp"
#include "npend/kernel_set.hpp"

namespace npend {

/// The order Taylor's method uses for a tolerance ε: ⌈−½ ln ε + 1⌉ (at least 2).
int taylor_order_for(double tolerance);

/// Taylor's method for one chain's equations (a kernel_set with Taylor kernels), in the
/// number type T (double, or long double for reference runs). Not copyable across chains:
/// it keeps a reference to the kernel set, which must outlive it.
template <class T>
class taylor_integrator {
 public:
  /// Tolerances as odeint's (both ≥ 0, one > 0); `order` 0 chooses it from the smaller
  /// positive tolerance, else it is fixed (2..taylor_max_order). Throws std::invalid_argument for a
  /// model without Taylor kernels, bad tolerances or a bad order.
  taylor_integrator(const kernel_set& kernels, double abs_tol, double rel_tol, int order = 0);

  /// Starts at (t, x) (x: dim of the state).
  void reset(T t, const T* x);
  /// One step towards sign(direction), no longer than |limit| (0: no limit). Returns the
  /// step taken. A state whose coefficients all vanish (an equilibrium) takes the limit,
  /// or |fallback| without one.
  T step(T direction, T limit, T fallback);
  /// The Taylor polynomial of the last step at t_begin + τ, into x.
  void state_at(T tau, T* x) const;

  const std::vector<T>& state() const { return m_x; }
  T time() const { return m_t; }
  /// The start and length of the last step.
  T step_begin() const { return m_t_begin; }
  T last_step() const { return m_h; }
  int order() const { return m_order; }
  std::size_t dimension() const { return m_x.size(); }

 private:
  void coefficients();

  const kernel_set* m_kernels;
  const taylor_kernels* m_taylor;
  double m_abs_tol, m_rel_tol;
  int m_order;
  std::vector<T> m_params, m_inputs, m_series, m_work, m_x;
  T m_t = 0, m_t_begin = 0, m_h = 0;
};

extern template class taylor_integrator<double>;
extern template class taylor_integrator<long double>;

/// Taylor's method for a state and k tangent vectors: x' = f(x) with w_j' = J(x) w_j, the
/// variational equations (Lyapunov exponents). Their coefficients come from the same
/// generated recurrences run on dual numbers (taylor_kernels::coefficients_dual), once per
/// vector; each run also gives the state's coefficients, the same in every run. Order and
/// step as taylor_integrator's, the norms taken over the state and the vectors together.
class taylor_tangents {
 public:
  /// `vectors` ≥ 1 tangent vectors; tolerances and order as taylor_integrator's.
  taylor_tangents(const kernel_set& kernels, double abs_tol, double rel_tol, int vectors,
                  int order = 0);

  /// Starts at (t, x) with the vectors W (column-major, dim × vectors: vector j at j·dim).
  void reset(double t, const double* x, const double* W);
  /// One step towards sign(direction), no longer than |limit| (0: no limit), as
  /// taylor_integrator::step. Returns the step taken.
  double step(double direction, double limit, double fallback);
  /// The Taylor polynomials of the last step at step_begin() + τ, into x and W.
  void state_at(double tau, double* x, double* W) const;
  /// The state's polynomials alone at step_begin() + τ, into x (dim dimension()): for
  /// sampling the orbit within a step without evaluating the vectors.
  void state_values_at(double tau, double* x) const;

  const std::vector<double>& state() const { return m_x; }
  /// The vectors, column-major (vector j at j·dimension()).
  const std::vector<double>& tangents() const { return m_w; }
  double time() const { return m_t; }
  double step_begin() const { return m_t_begin; }
  int order() const { return m_order; }
  std::size_t dimension() const { return m_x.size(); }

 private:
  void coefficients();

  const kernel_set* m_kernels;
  const taylor_kernels* m_taylor;
  double m_abs_tol, m_rel_tol;
  int m_order;
  std::size_t m_vectors;
  std::vector<taylor::dual> m_params, m_inputs, m_series, m_work;
  std::vector<double> m_input_values, m_x, m_w;
  double m_t = 0, m_t_begin = 0;
};

/// taylor_integrator<double> as an odeint dense-output stepper: initialize, do_step,
/// calc_state, current_state/time/time_step — so integrate_with, npend::integrate and
/// users' odeint loops take it. do_step ignores the system it is given: the stepper
/// integrates the equations of the kernel set it was made for.
class taylor_stepper {
 public:
  using state_type = std::vector<double>;
  using deriv_type = std::vector<double>;
  using value_type = double;
  using time_type = double;
  using order_type = unsigned short;
  using stepper_category = boost::numeric::odeint::dense_output_stepper_tag;

  taylor_stepper(const kernel_set& kernels, double abs_tol, double rel_tol, int order = 0)
      : m_integrator(kernels, abs_tol, rel_tol, order) {}

  /// Starts at (t0, x0); dt0 gives the direction (and the step an equilibrium takes).
  void initialize(const state_type& x0, double t0, double dt0);
  /// One step; returns (t_begin, t_end).
  template <class System>
  std::pair<double, double> do_step(System&& /*system*/) {
    return step();
  }
  std::pair<double, double> step();
  /// x(t) for t within the last step, from its Taylor polynomial.
  void calc_state(double t, state_type& x) const;
  const state_type& current_state() const { return m_integrator.state(); }
  double current_time() const { return m_integrator.time(); }
  double current_time_step() const { return m_integrator.last_step(); }
  order_type order() const { return static_cast<order_type>(m_integrator.order()); }

 private:
  taylor_integrator<double> m_integrator;
  double m_dt0 = 0;
};

}  // namespace npend
