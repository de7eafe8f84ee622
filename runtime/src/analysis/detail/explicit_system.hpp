// A right-hand side alone as the implicit system (rhs, jacobian) that npend::integrate_system
// takes, for analyses that integrate something other than a bare chain with the explicit
// steppers only (private to the runtime).
#pragma once

#include <stdexcept>
#include <utility>

namespace npend::detail {

/// The Jacobian slot of a system integrated with explicit steppers only: calling it is a
/// logic error (the callers refuse rosenbrock4 and take other routes for Gauss–Legendre).
struct no_jacobian {
  template <class State, class Matrix, class Deriv>
  void operator()(const State&, Matrix&, double, Deriv&) const {
    throw std::logic_error("this system has no Jacobian: integrate it with an explicit stepper");
  }
};

/// (rhs, no_jacobian) for npend::integrate_system with rk4, dopri5, rkf78 or bs.
template <class Rhs>
std::pair<Rhs, no_jacobian> explicit_system(Rhs rhs) {
  return {std::move(rhs), no_jacobian{}};
}

}  // namespace npend::detail
