// Linear-quadratic regulation of a chain at an equilibrium: the linearisation (A, B) from the
// exact Jacobian and the input matrix, controllability, the LQR gain from SLICOT's Riccati
// solver, and the feedback u = −K(x − x*) as a system the integrators take.
#pragma once

#include <Eigen/Dense>
#include <complex>
#include <span>
#include <utility>
#include <vector>

#include "npend/chain.hpp"
#include "npend/integrators/integrate.hpp"

namespace npend {

/// Q = diag(angle · I_n, momentum · I_n) on the state deviation, R = torque · I_m on the m
/// actuated joints' torques (on a cart, `angle` weighs the cart's position too and
/// `torque` its force).
struct lqr_weights {
  double angle = 10;
  double momentum = 1;
  double torque = 1;
};

struct lqr_design {
  std::vector<double> equilibrium;  ///< x* = [φ*, 0] (dim 2n)
  std::vector<int> actuated;        ///< the actuators driven (chain::actuators), 0-based, ascending
  std::vector<double> A;            ///< ∂f/∂x at x*, row-major 2n × 2n
  std::vector<double> B;            ///< ∂f/∂u of the actuated joints, row-major 2n × m
  std::vector<std::complex<double>> open_loop;  ///< eigenvalues of A, by descending real part
  /// Eigenvalues of A that the inputs cannot move (the Popov–Belevitch–Hautus test: rank of
  /// [A − λI, B] below 2n); empty when (A, B) is controllable.
  std::vector<std::complex<double>> uncontrollable;
  bool controllable = false;
  std::vector<double> gain;                       ///< K, row-major m × 2n
  std::vector<double> riccati;                    ///< X, row-major 2n × 2n
  std::vector<std::complex<double>> closed_loop;  ///< eigenvalues of A − B K, descending real part
  /// ‖AᵀX + XA − XGX + Q‖ / (2‖A‖‖X‖ + ‖G‖‖X‖² + ‖Q‖) (Frobenius norms, G = BR⁻¹Bᵀ): how
  /// well X solves the Riccati equation, relative to the size of its terms.
  double riccati_residual = 0;
  double riccati_rcond = 0;  ///< SLICOT's estimate of the reciprocal condition number
};

/// The LQR design at the equilibrium φ* (dim n, rad; p = 0; on a cart q* = [x_c, φ*], dim
/// n + 1) with motors at the `actuated` joints (0-based actuator indices, chain::actuators:
/// on a cart 0 is the cart's force and j the joint j; empty: every actuator). Throws
/// std::invalid_argument if φ* has the wrong size, is not an equilibrium (|∂V/∂φ| > 1e-9 per unit
/// of the largest term), a joint index is out of range or repeated, a weight is not positive and
/// finite, the pivot moves (the linearisation would depend on t), or (A, B) cannot be stabilised
/// (an unstable uncontrollable eigenvalue: the message names it).
lqr_design lqr(const chain& c, std::span<const double> angles, std::span<const int> actuated = {},
               const lqr_weights& weights = {});

/// The chain under the feedback u = −K(x − x*) of a design, as the (rhs, jacobian) pair
/// npend::integrate_system and the Gauss–Legendre steppers take: ẋ = f(x, t, u(x)), with
/// the Jacobian ∂f/∂x − B(φ) K (B(φ) the input matrix at the current angles, so the
/// Jacobian is exact). The chain and the design must outlive it.
class feedback_rhs {
 public:
  feedback_rhs(const chain& c, const lqr_design& design) : m_chain(&c), m_design(&design) {}
  void operator()(const std::vector<double>& x, std::vector<double>& dxdt, double t) const;
  /// The actuation u = −K(x − x*) of every actuator (zero at unactuated ones; dim
  /// chain::actuators(): the joint torques, after the cart's force on a cart).
  std::vector<double> torques(std::span<const double> x) const;

 private:
  const chain* m_chain;
  const lqr_design* m_design;
};

class feedback_jacobian {
 public:
  feedback_jacobian(const chain& c, const lqr_design& design) : m_chain(&c), m_design(&design) {}
  void operator()(const std::vector<double>& x,
                  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>& J,
                  double t, std::vector<double>& dfdt) const;

 private:
  const chain* m_chain;
  const lqr_design* m_design;
};

inline std::pair<feedback_rhs, feedback_jacobian> make_feedback_system(const chain& c,
                                                                       const lqr_design& d) {
  return {feedback_rhs(c, d), feedback_jacobian(c, d)};
}

/// Integrates the chain under the feedback of `design` (make_feedback_system) from x0, as
/// npend::integrate integrates a free chain: the same options, observers and errors, with the
/// steppers of npend::integrate_system (no taylor: the feedback has no Taylor kernels). Compiled
/// once in the library, so that front ends need not instantiate the integrators themselves.
integration_result integrate_under_feedback(const chain& c, const lqr_design& design,
                                            std::span<const double> x0,
                                            const integration_options& options,
                                            const observer_function& observer = {},
                                            const step_observer_function& step_observer = {});

}  // namespace npend
