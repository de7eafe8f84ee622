// Hamilton's equations and their Jacobian for any Lagrangian L = ½ φ̇ᵀA(φ)φ̇ − V(φ) that GiNaC
// derives (φ standing for any generalised coordinates q, lagrangian.hpp) — no assumption
// about the model's structure: the mass matrix A comes from the
// derivation's polynomials and is factored in the emitted code, A = L D Lᵀ (L unit lower
// triangular, D diagonal; A is symmetric positive definite for any physical chain), and
//   φ̇ = A⁻¹ p                        (forward substitution, scaling, back substitution)
//   ṗ_i = ∂L/∂φ_i (φ, φ̇)             (the derived polynomial at the computed φ̇)
//   ∂φ̇/∂p = A⁻¹,  ∂φ̇/∂φ_k = −A⁻¹ ∂²L/∂φ̇∂φ_k,
//   ∂ṗ/∂φ = L_φφ + L_φφ̇ ∂φ̇/∂φ,  ∂ṗ/∂p = L_φφ̇ A⁻¹ = −(∂φ̇/∂φ)ᵀ,
// all from implicit differentiation of p = ∂L/∂φ̇ (the identities npend-gen --verify checks).
// O(n³) per evaluation; the articulated-body form (articulated_form.hpp) is the O(n)
// optimisation for the structures it fits. npend-gen --verify checks either against the same
// exact identities (--solver).
#pragma once

#include <vector>

#include "chain_model.hpp"
#include "expr_graph.hpp"
#include "polynomial.hpp"

namespace npend::gen {

/// Graph nodes of the general formulation of one chain (see the file comment).
class general_form {
 public:
  /// Builds A and its L D Lᵀ factors from the derived mechanics, in `graph`.
  general_form(const polynomial_space& space, const chain_mechanics& mech,
               const lagrangian_hessians& hessians, expr_graph& graph);

  /// A⁻¹ b (b dim n, the number of coordinates).
  std::vector<sx> solve(const std::vector<sx>& b) const;

  /// φ̇ = A⁻¹ p at the momentum inputs.
  const std::vector<sx>& velocities() const { return m_dphi; }
  /// ṗ_i = ∂L/∂φ_i at (φ, φ̇) (dim n).
  std::vector<sx> momentum_rates() const;
  /// H = ½ pᵀφ̇ + V.
  sx hamiltonian() const;
  /// det A = Π D_jj.
  sx mass_matrix_determinant() const;
  /// The exact Jacobian of (φ̇, ṗ) with respect to (φ, p), row-major (2n × 2n).
  std::vector<sx> jacobian() const;

 private:
  // A polynomial of the derivation evaluated at the graph's inputs and the computed φ̇.
  sx node(const GiNaC::ex& e) const;

  const polynomial_space* m_space;
  const chain_mechanics* m_mech;
  const lagrangian_hessians* m_hessians;
  expr_graph* m_graph;
  int m_n;
  std::vector<sx> m_vars;                ///< variable nodes, φ̇ replaced by the computed φ̇
  std::vector<std::vector<sx>> m_lower;  ///< L (unit lower triangular, entries below the diagonal)
  std::vector<sx> m_pivots;              ///< D
  std::vector<sx> m_p, m_dphi;
};

}  // namespace npend::gen
