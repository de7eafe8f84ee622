// The chain's canonical ensemble (paper §6.3.2): the partition function, free energy, mean
// energy, heat capacity and ⟨cos φ_i⟩ at given temperatures.
//
// With H = ½ pᵀA(φ)⁻¹p + V(φ) the momentum integral is Gaussian and done analytically (the
// paper's step): ∫ dⁿp e^{−βH} = (2π k T)^{n/2} √det A(φ) e^{−βV(φ)}, so
//   Z = (2π k T)^{n/2} Q,   Q = ∫_{[−π, π]ⁿ} dⁿφ √det A(φ) e^{−βV(φ)}
// (classical, without the 1/hⁿ that only shifts F by a constant). With w = √det A e^{−βV}
// and ⟨·⟩ its average over the angles:
//   F = −k T ln Z,   ⟨E⟩ = −∂ ln Z/∂β = (n/2) k T + ⟨V⟩,   C = ∂⟨E⟩/∂T = (n/2) k + Var(V)/(k T²).
// The angle integral Q is periodic and smooth, so:
//   - for n ≤ 3 the periodic trapezoid rule on an M-point grid per angle converges
//     exponentially in M; the grid of every other point (M/2) comes free, and the change
//     from it is the error estimate (an upper bound once the rule converges);
//   - for larger n, randomised quasi-Monte Carlo: Boost.Random's Sobol sequence, shifted by R
//     independent uniform random vectors (Cranley–Patterson), the replicas' spread giving a
//     standard error.
// det A and V are evaluated once per point for all temperatures that share a box. V ≥ 0
// (zero at the hanging rest position), so e^{−βV} never overflows.
//
// At low temperatures the well of e^{−βV} around the hanging position is narrower than the
// circle (its width √(kT/a_i) per angle, V = Σ a_i (1 − cos φ_i)), and a grid over [−π, π]ⁿ
// would miss it. Each rule then covers the box [−L_i, L_i] outside which
// β a_i (1 − cos φ_i) > 50 (a part e^{−50} of the integral at most), with its points spread
// over it: L_i = π while k T ≥ a_i/25, about ten well widths below. So the rule resolves the
// well at every temperature down to the smallest normal k T, where it gives the harmonic
// limit ⟨E⟩ = n k T, C = n k (n momenta and n angles, each a quadratic term), and the error
// estimates stay those of the rule. Temperatures with different boxes are separate runs.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "npend/chain.hpp"
#include "npend/run_control.hpp"

namespace npend {

enum class partition_rule { automatic, trapezoid, quasi_monte_carlo };

struct partition_options {
  partition_rule rule = partition_rule::automatic;  ///< automatic: trapezoid for n ≤ 3
  int grid = 0;        ///< trapezoid points per angle, even (0: 256, 128, 64 for n = 1, 2, 3)
  int points = 65536;  ///< quasi-Monte Carlo points per replica
  int replicas = 16;   ///< quasi-Monte Carlo random shifts (≥ 2)
  std::uint64_t seed = 1;
  double boltzmann = 1;  ///< k (J/K); 1: temperatures in energy units (J)
  run_control* control = nullptr;
};

/// The rule `rule` stands for on a chain of `links` links: automatic is the trapezoid rule
/// for n ≤ 3 and quasi-Monte Carlo beyond. Only the chosen rule's options (grid, resp.
/// points, replicas and seed) have an effect.
inline partition_rule chosen_partition_rule(partition_rule rule, int links) {
  if (rule != partition_rule::automatic) return rule;
  return links <= 3 ? partition_rule::trapezoid : partition_rule::quasi_monte_carlo;
}

/// The ensemble at one temperature. Errors are estimates of the absolute error (of ln Z for
/// the partition function and the free energy).
struct canonical_state {
  double temperature = 0;
  double log_partition_function = 0;  ///< ln Z
  double partition_function = 0;      ///< Z (inf if it overflows; ln Z stays finite)
  double free_energy = 0;             ///< F = −k T ln Z (J)
  double mean_energy = 0;             ///< ⟨E⟩ (J)
  double heat_capacity = 0;           ///< C (J/K; in units of k when k = 1)
  double mean_potential = 0;          ///< ⟨V⟩ (J)
  std::vector<double> mean_cos;       ///< ⟨cos φ_i⟩ (dim n)
  double log_partition_error = 0, free_energy_error = 0, mean_energy_error = 0,
         heat_capacity_error = 0;
};

struct partition_result {
  std::string rule;                     ///< "trapezoid" or "quasi-monte-carlo"
  long long evaluations = 0;            ///< points at which det A and V were evaluated
  int grid = 0;                         ///< trapezoid: points per angle
  int points = 0, replicas = 0;         ///< quasi-Monte Carlo
  std::vector<canonical_state> states;  ///< one per temperature, in the given order
  bool stopped = false;                 ///< the control asked to stop: states are empty
};

/// The canonical ensemble of a conservative chain on a fixed pivot (rigid links allowed; no
/// springs, which make V non-periodic in φ, and no damping or drive, which have no canonical
/// ensemble) at each of `temperatures` (> 0, with k T a finite normal double).
/// Throws std::invalid_argument naming the problem.
partition_result canonical_ensemble(const chain& c, std::span<const double> temperatures,
                                    const partition_options& options = {});

}  // namespace npend
