// The chain's kinetic structure in O(n): Hamilton's equations and their Jacobian without
// inverting the mass matrix, by an articulated-body elimination from the tip to the pivot
// in which every mass enters through sums of masses, never through inverse masses.
//
// Kinematics. Rod k has the unit vectors u_k = (sin φ_k, cos φ_k) along it and
// n_k = (cos φ_k, −sin φ_k) = ∂u_k/∂φ_k across it; bob k moves with v_k = v_{k−1} + ω_k n_k,
// ω_k = l_k φ̇_k, v_0 = 0. Neighbouring frames turn by δ_k = φ_{k+1} − φ_k:
//   n_{k+1} = C_k n_k − S_k u_k,   u_{k+1} = S_k n_k + C_k u_k,   C_k = cos δ_k, S_k = sin δ_k
// (C_k = c_k c_{k+1} + s_k s_{k+1}, S_k = s_{k+1} c_k − c_{k+1} s_k: 2n sin/cos in all).
// The momentum of the sub-chain hanging at joint k is P_k = Σ_{j≥k} m_j v_j, and the
// canonical momenta are its components across the rods: p_k = ∂T/∂φ̇_k = l_k n_k·P_k, so
// q_k = p_k / l_k = n_k·P_k.
//
// Elimination from the tip. P_k is affine in the velocity v_{k−1} of the bob the sub-chain
// hangs from: P_k = r_k u_k (u_k·v_{k−1}) + b_k. The sub-chain can swing freely across rod k,
// so it resists the motion of its suspension only along u_k, with the articulated mass r_k;
// b_k is its momentum when the suspension is at rest. With r_{n+1} = 0, b_{n+1} = 0 and
// β_k = u_k·b_k (n_k·b_k = q_k by definition), the bob k plus the sub-chain below has the
// inertia m_k 1 + r_{k+1} u_{k+1}u_{k+1}ᵀ; its component across rod k and the Schur
// complement that removes that direction give
//   d_k = m_k + r_{k+1} S_k²,               r_k = m_k (m_k + r_{k+1}) / d_k,
//   a_k = (q_k − C_k q_{k+1} − S_k β_{k+1}) / d_k,
//   β_k = C_k β_{k+1} − S_k q_{k+1} + r_{k+1} S_k C_k a_k,     γ_k = r_{k+1} S_k C_k / d_k.
// From the pivot down, with the suspension velocity of rod k in its own frame,
// x_k = n_k·v_{k−1}, y_k = u_k·v_{k−1} (x_1 = y_1 = 0):
//   w_k = a_k − γ_k y_k        (n_k·v_k: the velocity of bob k across rod k)
//   ω_k = w_k − x_k,           φ̇_k = ω_k / l_k,
//   x_{k+1} = C_k w_k − S_k y_k,   y_{k+1} = S_k w_k + C_k y_k       (u_k·v_k = y_k: rigid rod)
//   U_k = u_k·P_k = r_k y_k + β_k,   ṗ_k = ∂L/∂φ_k = −ω_k U_k − ∂V/∂φ_k
// (∂v_j/∂φ_k = −ω_k u_k for j ≥ k, so ∂T/∂φ_k = −ω_k u_k·P_k; −U_k is the impulsive tension of
// rod k), T = ½ Σ m_k |v_k|² = ½ Σ m_k (w_k² + y_k²), and det A = Π l_k² d_k: the elimination
// is a U D Uᵀ factorisation of A (U unit upper triangular) with the pivots D_kk = l_k² d_k.
//
// Why this form: d_k, r_k, T and det A are sums and products of positive numbers, so they
// are accurate to a few roundings whatever the masses; the earlier formulation (a
// tridiagonal system for the rod tensions in the inverse masses, diagonal 1/m_i + 1/m_{i−1},
// and ω = Ẑq − Q̂τ) cancelled and lost accuracy in proportion to the mass ratio (4e-8
// relative in φ̇ at m = 1, 1e8). The outputs of this one are accurate to a small multiple
// of their componentwise condition number times ε for mass and length ratios up to 1e8
// (tests/generated/test_kernel_accuracy.cpp measures it against a binary128 reference).
//
// The Jacobian J = [[B, W], [C, D]] is the forward-mode derivative of this straight-line
// program (articulated_form.cpp writes the tangent out, with the shared factors ρ_k =
// C_k m_k / d_k and ξ_k = S_k (m_k + r_{k+1}) / d_k where a link has no source of its own):
// O(n) per direction, O(n²) in all. Along q_k it gives W = ∂φ̇/∂p = A⁻¹, only the entries
// i ≤ k (the pass stops at link k); along φ_k the columns of B = ∂φ̇/∂φ and C = ∂ṗ/∂φ. The
// Hamiltonian structure is imposed, not computed twice: W and C are symmetric and D = −Bᵀ.
// Of C each entry is taken as ∂ṗ_i/∂φ_k with i ≥ k (the lower link's force along the upper
// link's angle): the other member of the pair, differentiated through the whole
// elimination, loses up to 1e5 condition numbers at extreme ratios, this one at most ~20.
// Every step is exact algebra; `npend-gen --verify` checks the results against GiNaC's
// derivatives of the Lagrangian at exact rational points.
#pragma once

#include <vector>

#include "expr_graph.hpp"

namespace npend::gen {

/// The turn between rod k and rod k + 1 from their sines and cosines, C_k = cos(φ_{k+1} − φ_k)
/// and S_k = sin(φ_{k+1} − φ_k), through products, so that a kernel needs only 2n
/// trigonometric calls.
struct rod_turn {
  sx C, S;
};
rod_turn turn_between(sx s, sx c, sx s_next, sx c_next);

/// One link's step of the elimination from the tip (the file comment's d_k, 1/d_k, r_k,
/// r_{k+1} S_k C_k, γ_k, the numerator of a_k, a_k and β_k). The steps are shared by the
/// unrolled kernels (articulated_form) and the loop kernels (loop_kernels.hpp), so both run
/// the same algebra.
struct elimination_step {
  sx d, inv_d, r, rsc, gamma, num, a, beta;
};
/// The tip link, with nothing below it (γ, r S C and β are 0).
elimination_step eliminate_tip(sx mass, sx q);
/// Link k < n − 1, from link k + 1's r, β and q and the turn C_k, S_k between the rods.
elimination_step eliminate_link(sx mass, sx C, sx S, sx q, sx q_next, sx r_next, sx beta_next);

/// One link's step of the pass from the pivot: the velocity of bob k across rod k (w_k),
/// ω_k, U_k = u_k·P_k (axial), the kinetic part −ω_k U_k of ṗ_k, and the suspension
/// velocity (x_{k+1}, y_{k+1}) of the next rod (when C, S of the turn to it are given).
struct pivot_step {
  sx w, omega, axial, kinetic_force, x_next, y_next;
};
pivot_step pivot_link(sx a, sx gamma, sx r, sx beta, sx x, sx y);
pivot_step pivot_link(sx a, sx gamma, sx r, sx beta, sx x, sx y, sx C, sx S);

/// Graph nodes of the articulated-body formulation of one chain (see the file comment).
struct articulated_form {
  /// Builds the momentum-independent nodes from the angle, mass and length inputs of `graph`.
  articulated_form(int links, expr_graph& graph);

  int n;
  std::vector<sx> s, c;        ///< sin φ_k, cos φ_k (the only trigonometric calls)
  std::vector<sx> mass;        ///< m_k
  std::vector<sx> inv_length;  ///< 1/l_k
  std::vector<sx> cd, sd;  ///< C_k = cos(φ_{k+1} − φ_k), S_k = sin(φ_{k+1} − φ_k), k < n − 1

  /// The motion for momenta p (dim n): speeds ω_k = l_k φ̇_k, bob velocities (w_k, y_k) in
  /// the frame of rod k, and the kinetic part −ω_k U_k of ṗ_k.
  struct motion {
    std::vector<sx> omega, w, y, kinetic_force;
  };
  motion solve(const std::vector<sx>& p) const;

  /// T = ½ Σ m_k (w_k² + y_k²).
  sx kinetic_energy(const motion& m) const;

  /// det A = (Π l_k)² Π d_k.
  sx mass_matrix_determinant() const;

  /// Derivatives of ω_k and of the kinetic part of ṗ_k (each dim n) along one direction.
  struct tangent {
    std::vector<sx> omega, kinetic_force;
  };
  /// Along φ_k, at momenta p.
  tangent along_angle(const std::vector<sx>& p, int k) const;
  /// Along q_k = p_k / l_k (multiply by 1/l_k for ∂/∂p_k), at momenta p.
  tangent along_scaled_momentum(const std::vector<sx>& p, int k) const;

 private:
  struct values;
  values evaluate(const std::vector<sx>& p) const;
  tangent propagate(const values& v, const std::vector<sx>& dC, const std::vector<sx>& dS,
                    const std::vector<sx>& dq) const;
  expr_graph* m_graph;
};

}  // namespace npend::gen
