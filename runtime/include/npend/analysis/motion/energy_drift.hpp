// How well a trajectory keeps its energy: the chain is conservative (paper §6.3), so the
// drift of H along a computed trajectory measures the integration error. One definition
// for every report (simulate, poincare, analyze, lyapunov, demo). A damped chain loses
// energy to its joints' friction, and then the balance of H against the friction's work
// measures it instead (energy_balance).
#pragma once

#include <span>
#include <vector>

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

/// The joint friction's power P = −Σ_j b_j θ̇_j² (W) at the state x (dim 2n), θ̇_j = φ̇_j −
/// φ̇_{j−1} the rate of joint j (joint 1 is the pivot, φ̇_0 = 0) and b_j the damping of
/// chain_parameters (0 for an undamped chain). Throws std::invalid_argument for a state of the
/// wrong size.
double friction_power(const chain& c, std::span<const double> x);

/// The energy balance of a damped chain along a trajectory. On a fixed pivot only the joints'
/// friction changes H: dH/dt = P (friction_power), so H(t) − ∫₀ᵗ P dt stays H(0). The
/// integral is taken by the trapezoid rule over the states shown, so the balance holds to
/// that rule's error and the trajectory's.
class energy_balance {
 public:
  /// For the chain `c` (which must outlive this object). Throws std::invalid_argument for a
  /// chain whose pivot moves (the drive does work as well).
  explicit energy_balance(const chain& c);

  /// Takes the state x (dim 2n) at time t (s; after the previous state's) into account;
  /// returns H(x) (J).
  double add(double t, std::span<const double> x);

  double initial() const { return m_initial; }  ///< H of the first state (J; 0 before any)
  double energy() const { return m_energy; }    ///< H of the last state (J)
  /// ∫ P dt from the first state to the last (J; ≤ 0: the friction takes energy out).
  double work() const { return m_work; }
  /// H − ∫ P dt at the last state (J): H of the first state up to the errors.
  double balance() const { return m_energy - m_work; }
  /// The largest |balance − initial| so far (J).
  double max_imbalance() const { return m_max; }

 private:
  const chain* m_chain;
  std::vector<double> m_dphi;
  bool m_started = false;
  double m_t = 0, m_power = 0;
  double m_initial = 0, m_energy = 0, m_work = 0, m_max = 0;
};

}  // namespace npend
