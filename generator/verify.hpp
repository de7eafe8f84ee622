// Proof by evaluation: the emitted kernels against GiNaC's derivation, in exact arithmetic.
#pragma once

#include <iosfwd>

#include "chain_functions.hpp"

namespace npend::gen {

/// Evaluates the emitted functions of the chain `sym` at `points` exact rational states
/// (angles at rational points of the unit circle, rational parameters and momenta) and
/// checks, with exact equality, the identities that define them:
///   A φ̇ = p,  momenta(φ̇) = p,  ṗ = ∂L/∂φ,  H = T + V (= closed form for n ≤ 3),
///   A·∂φ̇/∂p = I,  A·∂φ̇/∂φ = −∂²L/∂φ̇∂φ,  ∂ṗ/∂φ = L_φφ + L_φφ̇ ∂φ̇/∂φ,
///   ∂ṗ/∂p = L_φφ̇ ∂φ̇/∂p,  det_mass_matrix = det A.
/// A, L and its derivatives come from GiNaC; the kinetic functions are those `solver` forms.
/// Prints a report; returns true if all hold.
bool verify_chain(const chain_symbols& sym, int points, std::ostream& report,
                  kinetic_solver solver);

}  // namespace npend::gen
