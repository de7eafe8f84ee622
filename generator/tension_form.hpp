// The chain's kinetic structure in O(n): Hamilton's equations and their Jacobian without
// inverting the mass matrix.
//
// Why this works. Write the bob velocities as v_k = Σ_{i≤k} l_i φ̇_i n_i with the unit
// vectors n_i = (cos φ_i, −sin φ_i) = ∂u_i/∂φ_i, u_i = (sin φ_i, cos φ_i) along rod i.
// Completing each n_i with u_i gives a square 2n × 2n "Cartesian" mass matrix K in the
// basis (n_i, u_i); the mass matrix A is its (n, n) block. K⁻¹ is tridiagonal in the
// links, because the inverse of μ_max(i,j) (the mass hanging below both joints) is the
// tridiagonal matrix of the rods' reduced inverse masses: diagonal 1/m_i + 1/m_{i−1},
// off-diagonal −1/m_i. Scaled by the lengths, the blocks of K⁻¹ are
//   Ẑ = tridiag(−a_{i} cd_i | a_i + a_{i−1} | −a_i cd_i),   Q̂ = antisym. tridiag(a_i sd_i),
// with a_i = 1/m_i, cd_i = cos(φ_i − φ_{i+1}), sd_i = sin(φ_i − φ_{i+1}); the (u, u) block
// equals the (n, n) block Ẑ. The block-inverse identity A⁻¹ = Y_nn − Y_nu Y_uu⁻¹ Y_un then
// gives, with q_i = p_i / l_i and ω_i = l_i φ̇_i (tangential speed of rod i),
//   τ = Ẑ⁻¹ Q̂ᵀ q           (rod tensions: one tridiagonal solve)
//   ω = Ẑ q − Q̂ τ,         φ̇_i = ω_i / l_i,         ṗ_i = ω_i τ_i − ∂V/∂φ_i,
// because −∂T/∂φ_i at fixed p is exactly −ω_i τ_i. For the Jacobian J = [[B, W], [C, −Bᵀ]]
// (Hamiltonian structure), with M = Ẑ⁻¹ (O(n²) from the LDLᵀ factors), X̂ = M Q̂ᵀ and
// Ŵ = Ẑ − Q̂ X̂ = diag(l) A⁻¹ diag(l):
//   W_ik = Ŵ_ik / (l_i l_k)                                    (∂φ̇/∂p = A⁻¹)
//   B_ik = −(X̂_ki ω_k + Ŵ_ik τ_k) / l_i                         (∂φ̇/∂φ)
//   C_ik = ω_i (M_ik ω_k − X̂_ik τ_k) − τ_i (X̂_ki ω_k + Ŵ_ik τ_k)
//          − δ_ik ω_i q_i − ∂²V/∂φ_i∂φ_k                        (∂ṗ/∂φ, symmetric)
// Every step is exact algebra; `npend-gen --verify` checks the result against GiNaC's
// derivatives of the Lagrangian at exact rational points.
#pragma once

#include "expr_graph.hpp"

#include <vector>

namespace npend::gen {

/// Graph nodes of the tension formulation for one chain (see the file comment).
struct tension_form {
  /// Builds the nodes from the angle, mass and length inputs of `graph`.
  tension_form(int links, expr_graph& graph);

  int n;
  std::vector<sx> s, c;         ///< sin φ_i, cos φ_i (the only trigonometric calls)
  std::vector<sx> inv_mass;     ///< a_i = 1/m_i
  std::vector<sx> inv_length;   ///< 1/l_i
  std::vector<sx> cd, sd;       ///< cos, sin of φ_i − φ_{i+1}, i < n − 1
  std::vector<sx> z_diag;       ///< Ẑ_ii
  std::vector<sx> z_off;        ///< Ẑ_{i,i+1} = Ẑ_{i+1,i}
  std::vector<sx> q_off;        ///< Q̂_{i,i+1} = −Q̂_{i+1,i}
  std::vector<sx> pivot;        ///< d_i of Ẑ = L D Lᵀ
  std::vector<sx> inv_pivot;    ///< 1/d_i
  std::vector<sx> ell;          ///< L_{i+1,i}

  /// τ = Ẑ⁻¹ Q̂ᵀ q and ω = Ẑ q − Q̂ τ for q_i = p_i / l_i.
  struct flow {
    std::vector<sx> q, tau, omega;
  };
  flow solve(const std::vector<sx>& p) const;

  /// M = Ẑ⁻¹ as a dense symmetric matrix (row-major n × n).
  std::vector<sx> z_inverse() const;

  /// det Ẑ = Π d_i.
  sx z_determinant() const;
};

}  // namespace npend::gen
