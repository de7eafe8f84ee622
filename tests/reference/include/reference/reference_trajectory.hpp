// Reference solutions for the integrator tests: the independent dense implementation
// (dense_chain.hpp) integrated by odeint's controlled Runge–Kutta–Fehlberg 7(8) at a tight
// tolerance, called directly — no npend integration code involved.
#pragma once

#include <boost/numeric/odeint/integrate/integrate_adaptive.hpp>
#include <boost/numeric/odeint/stepper/generation.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta_fehlberg78.hpp>
#include <vector>

#include "reference/dense_chain.hpp"

namespace npend::reference {

/// The states at `times` (ascending, from t = 0) of the chain started at x0 (dim 2n).
/// Tolerance 1e-14 (absolute and relative): a few 1e-13 relative over a few seconds.
inline std::vector<std::vector<double>> reference_trajectory(const dense_chain& ref,
                                                             std::vector<double> x0,
                                                             const std::vector<double>& times,
                                                             double tolerance = 1e-14) {
  namespace odeint = boost::numeric::odeint;
  using state = std::vector<double>;
  const auto rhs = [&ref](const state& x, state& dxdt, double) {
    const Eigen::VectorXd f =
        ref.rhs(Eigen::Map<const Eigen::VectorXd>(x.data(), static_cast<Eigen::Index>(x.size())));
    dxdt.assign(f.data(), f.data() + f.size());
  };
  auto stepper =
      odeint::make_controlled(tolerance, tolerance, odeint::runge_kutta_fehlberg78<state>());
  std::vector<state> out;
  double t = 0;
  for (double target : times) {
    if (target > t) odeint::integrate_adaptive(stepper, rhs, x0, t, target, 1e-3);
    t = target;
    out.push_back(x0);
  }
  return out;
}

/// The dense reference for a chain's parameters.
inline dense_chain dense_chain_of(const chain_parameters& p) {
  return dense_chain(p.masses, p.lengths, p.g);
}

}  // namespace npend::reference
