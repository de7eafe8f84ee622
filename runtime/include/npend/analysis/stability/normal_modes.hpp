// Linearisation around an equilibrium in the form M ÿ + K y = 0 (seed 2) and its normal modes.
#pragma once

#include <span>
#include <vector>

#include "npend/chain.hpp"

namespace npend {

/// One solution y = v e^{±iωt} (or e^{±κt}) of M ÿ + K y = 0.
struct normal_mode {
  double omega_squared = 0;  ///< eigenvalue ω² of K v = ω² M v (1/s²); negative when unstable
  double frequency = 0;      ///< ω = √(ω²) in rad/s for ω² > 0, else 0
  double growth_rate = 0;    ///< κ = √(−ω²) in 1/s for ω² < 0, else 0
  /// Mode shape v (dim n): M-normalised (vᵀ M v = 1), its largest-magnitude entry positive.
  std::vector<double> shape;
};

/// M ÿ + K y = 0 around φ*: M = A(φ*), K = ∇²V(φ*), and the modes.
struct linearisation {
  std::vector<double> angles;            ///< φ* (dim n)
  std::vector<double> mass_matrix;       ///< M, row-major (n × n)
  std::vector<double> stiffness_matrix;  ///< K, row-major (n × n)
  std::vector<normal_mode> modes;        ///< n modes, ascending ω²
};

/// The linearisation of the chain around the equilibrium `angles` (dim n, rad; p = 0) and
/// the generalised symmetric eigenproblem K v = ω² M v. At the hanging position (all 0) the
/// frequencies are the pendulum's normal-mode frequencies, and the Jacobian's eigenvalues
/// are ±iω_k. Throws std::invalid_argument if `angles` has the wrong size or is not an
/// equilibrium (∂V/∂φ ≠ 0).
linearisation normal_modes(const chain& c, std::span<const double> angles);

}  // namespace npend
