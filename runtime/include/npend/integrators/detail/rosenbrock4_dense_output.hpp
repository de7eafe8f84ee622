// odeint's rosenbrock4 with dense output behind a small interface of plain types.
//
// Boost 1.74's ublas, which rosenbrock4 is built on, does not compile as C++20 (it calls
// std::allocator::construct, removed in C++20), so the stepper lives in a translation unit
// compiled as C++17 (src/integrators/rosenbrock4_dense_output.cpp) and this header stays
// C++17-clean. It offers the dense-output interface that npend's integration loop uses for odeint's
// dense-output steppers.
#pragma once

#include <boost/numeric/odeint/stepper/stepper_categories.hpp>
#include <cstddef>
#include <functional>
#include <memory>
#include <vector>

namespace npend::detail {

class rosenbrock4_dense_output {
 public:
  using stepper_category = boost::numeric::odeint::dense_output_stepper_tag;
  /// dxdt = f(x, t); x and dxdt point to `dim` doubles.
  using rhs_function = std::function<void(const double* x, double* dxdt, double t)>;
  /// J = ∂f/∂x at (x, t), row-major dim × dim, and dfdt = ∂f/∂t (dim doubles; rosenbrock4
  /// needs it for a time-dependent system such as a driven chain).
  using jacobian_function = std::function<void(const double* x, double* J, double t, double* dfdt)>;

  rosenbrock4_dense_output(std::size_t dim, double abs_tol, double rel_tol, rhs_function rhs,
                           jacobian_function jacobian);
  ~rosenbrock4_dense_output();
  rosenbrock4_dense_output(rosenbrock4_dense_output&&) noexcept;
  rosenbrock4_dense_output& operator=(rosenbrock4_dense_output&&) noexcept;

  void initialize(const std::vector<double>& x0, double t0, double dt0);
  /// One adaptive step (odeint's dense-output do_step); throws
  /// boost::numeric::odeint::step_adjustment_error after 500 rejected attempts.
  void step();
  /// As step(): the loop that drives odeint's dense-output steppers passes their system
  /// here; this one was given its system at construction.
  template <class System>
  void do_step(const System& /*given at construction*/) {
    step();
  }
  double current_time() const;
  double current_time_step() const;
  const std::vector<double>& current_state() const;
  /// The interpolated state at t within the last step (x: dim doubles).
  void calc_state(double t, std::vector<double>& x) const;

 private:
  struct impl;
  std::unique_ptr<impl> m_impl;
};

}  // namespace npend::detail
