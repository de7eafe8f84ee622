// Langevin dynamics of a damped chain at a temperature: the dynamic check of the canonical
// ensemble (analysis/partition_function.hpp) — the time average of H along a thermostatted
// trajectory equals ⟨E⟩ from Z.
//
// The joint damping b_j (Rayleigh function R = ½ φ̇ᵀΓφ̇, Γ = Dᵀ diag(b) D with D the joint
// differences θ = Dφ) is the friction, and random joint torques with variance 2 k T b_j per
// unit time are the noise:
//   dφ = ∂H/∂p dt,   dp = (−∂H/∂φ − Γ φ̇) dt + Dᵀ diag(√(2 k T b)) dW.
// Fluctuation and dissipation balance, so e^{−H/kT} dφ dp is invariant whatever Γ.
//
// Integrator: Strang splitting O(h/2) H(h) O(h/2).
//   - H is one step of the undamped chain by the symplectic Gauss–Legendre method of order 6.
//   - O is the momenta's Ornstein–Uhlenbeck process at fixed angles, solved exactly: with
//     q = A^{-1/2} p it is dq = −G q dt + √(2kT G) dW for the symmetric G = A^{-1/2} Γ A^{-1/2}.
//     So q ← U (e^{−Λh} Uᵀq + √(kT (1 − e^{−2Λh})) ξ), G = U Λ Uᵀ. That preserves p ~ N(0, kT A)
//     exactly, and the splitting's error in the invariant measure is O(h²).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "npend/chain.hpp"
#include "npend/run_control.hpp"

namespace npend {

struct langevin_options {
  double dt = 0.01;        ///< step (s)
  double t_end = 1000;     ///< length of the run (s)
  double transient = 50;   ///< discarded at the start (s)
  int blocks = 20;         ///< block means for the standard error (≥ 2)
  std::uint64_t seed = 1;  ///< of the noise (std::mt19937_64)
  double boltzmann = 1;    ///< k (J/K); 1: T in J
  run_control* control = nullptr;
};

struct langevin_result {
  double mean_energy = 0;     ///< time average of H after the transient (J)
  double standard_error = 0;  ///< of the block means
  std::size_t samples = 0;    ///< steps averaged
  std::vector<double> final_state;
  bool stopped = false;
};

/// Runs the Langevin dynamics of `c` (its damping as the friction; at least one b_j > 0, a
/// fixed pivot) at `temperature` from x0 = [φ, p] and returns the time average of H. Throws
/// std::invalid_argument naming a bad argument, npend::integration_error if a step fails.
langevin_result langevin_mean_energy(const chain& c, std::span<const double> x0, double temperature,
                                     const langevin_options& options = {});

}  // namespace npend
