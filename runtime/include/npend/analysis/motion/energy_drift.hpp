// How well a trajectory keeps its energy: the chain is conservative (paper §6.3), so the
// drift of H along a computed trajectory measures the integration error. One definition
// for every report (simulate, poincare, analyze, lyapunov, demo).
#pragma once

#include <span>

#include "npend/chain.hpp"

namespace npend {

/// |h − h0| / |h0|, or |h − h0| when h0 = 0 (the hanging chain at rest has H = 0, where a
/// relative error means nothing).
double relative_energy_error(double h, double h0);

/// The largest relative_energy_error of H over the states shown to it.
class energy_drift {
 public:
  /// Measures against the energy h0 (J) of the chain `c` (which must outlive this object).
  energy_drift(const chain& c, double h0) : m_chain(&c), m_initial(h0), m_last(h0) {}

  /// Takes the state x (dim 2n) at time t into account; returns H(x, t) (J). (On a damped
  /// or driven chain H is not conserved and the drift is the physics, not an error: see
  /// chain_parameters::is_conservative.)
  double add(std::span<const double> x, double t = 0);

  double initial() const { return m_initial; }  ///< h0 (J)
  double last() const { return m_last; }        ///< H of the last state added (h0 if none)
  /// The largest relative error so far (0 before any state).
  double max_relative_error() const { return m_max; }

 private:
  const chain* m_chain;
  double m_initial, m_last, m_max = 0;
};

}  // namespace npend
