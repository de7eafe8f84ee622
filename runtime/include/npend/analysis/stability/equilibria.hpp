// The 2ⁿ equilibria of the chain and their linear stability (paper §6.5.1).
#pragma once

#include <complex>
#include <vector>

#include "npend/chain.hpp"

namespace npend {

struct equilibrium {
  std::vector<double> angles;  ///< each φ_i ∈ {0, π} (dim n); p = 0
  double energy = 0;           ///< H = V(φ*) in J
  /// The 2n eigenvalues of the Jacobian there: ±iω for each stable mode, ±κ for each
  /// unstable one; sorted by real part, then imaginary part, descending.
  std::vector<std::complex<double>> eigenvalues;
  bool stable = false;          ///< elliptic: every eigenvalue purely imaginary
  int unstable_directions = 0;  ///< eigenvalues with positive real part
};

/// Largest link count for find_equilibria (2ⁿ eigenproblems).
inline constexpr int max_equilibria_links = 16;

/// All 2ⁿ equilibria φ_i ∈ {0, π}, p = 0, in binary order with φ_1 the most significant
/// digit: (0,…,0), (0,…,0,π), …, (π,…,π). The eigenvalues come from the linearisation
/// M ÿ + K y = 0 (normal_modes), whose κ² = −ω² are exactly the squared eigenvalues of the
/// Jacobian [[0, A⁻¹], [−K, 0]] there. Throws std::invalid_argument for n above
/// max_equilibria_links.
std::vector<equilibrium> find_equilibria(const chain& c);

/// One equilibrium with each φ_i ∈ {0, π} (dim n), p = 0: its energy, the Jacobian's
/// eigenvalues and its stability, as find_equilibria gives them — for long chains, whose 2ⁿ
/// equilibria cannot all be listed. Throws std::invalid_argument (from normal_modes) for
/// angles of the wrong count or that are not an equilibrium.
equilibrium classify_equilibrium(const chain& c, std::vector<double> angles);

}  // namespace npend
