// Proof by evaluation: the emitted kernels against GiNaC's derivation, in exact arithmetic.
#pragma once

#include <iosfwd>

#include "chain_functions.hpp"

namespace npend::gen {

/// Evaluates the emitted functions of the chain `sym` at `points` exact rational states
/// (angles at rational points of the unit circle, rational parameters and momenta) and
/// checks, with exact equality, the identities that define them (q the coordinates, Q the
/// generalised forces, F = L_qq̇ + ∂Q/∂q̇):
///   A q̇ = p,  momenta(q̇) = p,  mass_matrix = A = Aᵀ,  ṗ = ∂L/∂q + Q,
///   H = T + V (= closed form for n ≤ 3),
///   A·∂q̇/∂p = I,  A·∂q̇/∂q = −∂²L/∂q̇∂q,  ∂ṗ/∂q = L_qq + F ∂q̇/∂q,  ∂ṗ/∂p = F ∂q̇/∂p,
///   Lagrange's equations with q̈ = (J f)_q,  input_matrix = f(w + e_j) − f(w),
///   det_mass_matrix = det A.
/// A, L and its derivatives come from GiNaC; the kinetic functions are those `solver` forms.
/// Prints a report; returns true if all hold.
bool verify_chain(const chain_symbols& sym, int points, std::ostream& report,
                  kinetic_solver solver);

}  // namespace npend::gen
