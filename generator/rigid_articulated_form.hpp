// The rigid-link chain's kinetic structure in O(n): φ̇ = A⁻¹p, the kinetic part ∂T/∂φ of ṗ,
// T and det A by an articulated-body elimination from the tip to the pivot — the point-mass
// form (articulated_form.hpp) generalised to links with a centre of mass c_k and a moment of
// inertia J_k. The Jacobian is the forward-mode derivative of this program
// (forward_diff.hpp).
//
// Kinematics (pivot frame: the pivot is at rest). Link k has u_k = (sin φ_k, cos φ_k) along
// it and n_k = (cos φ_k, −sin φ_k) = ∂u_k/∂φ_k across it; its upper joint moves with v_{k−1}
// (v_0 = 0), its centre of mass with v_{c,k} = v_{k−1} + c_k φ̇_k n_k and its lower joint with
// v_k = v_{k−1} + l_k φ̇_k n_k. T = ½ Σ (m_k |v_{c,k}|² + J_k φ̇_k²). Vectors are written in the
// frame (n_k, u_k) of the link at hand; neighbouring frames turn by δ_k = φ_{k+1} − φ_k with
// C_k = cos δ_k, S_k = sin δ_k formed from products of sin φ, cos φ (2n calls in all).
//
// Momenta. With P_{k+1} = Σ_{j>k} m_j v_{c,j}, the momentum of the sub-chain below joint k+1,
//   p_k = ∂T/∂φ̇_k = n_k·(c_k m_k v_{c,k} + l_k P_{k+1}) + J_k φ̇_k.
//
// Elimination from the tip. For given momenta, P_{k+1} is affine in the velocity of the joint
// it hangs from: P_{k+1} = R_{k+1} v_k + b_{k+1}. R is the sub-chain's articulated mass, a
// symmetric positive semi-definite 2 × 2 matrix. For point masses it has rank one: the
// sub-chain swings freely across its top rod. A rigid link also resists across it, through
// its inertia. b is the sub-chain's momentum when its joint is at rest. With R, b of the
// sub-chain below turned into link k's frame (entries R_nn, R_nu, R_uu, b_n, b_u; det R and
// tr R do not depend on the frame), and v_{k−1} = (x_k, y_k) in that frame,
//   p_k = D_k φ̇_k + g_n x_k + g_u y_k + l_k b_n,
//   D_k = m_k c_k² + J_k + l_k² R_nn,   g_n = c_k m_k + l_k R_nn,   g_u = l_k R_nu.
// Solving for φ̇_k and putting it into P_k = m_k v_{c,k} + P_{k+1} gives R_k = m_k 1 + R −
// g gᵀ/D_k and b_k = b + g a_k with a_k = (p_k − l_k b_n)/D_k. Multiplied out (e_k = l_k − c_k,
// the distance from the centre of mass to the lower joint), every entry but the off-diagonal
// one is a sum of positive terms, so no cancellation at any mass or inertia ratio:
//   D_k R_k,nn = J_k (R_nn + m_k) + m_k e_k² R_nn,
//   D_k R_k,nu = (J_k − m_k c_k e_k) R_nu,
//   D_k R_k,uu = J_k (R_uu + m_k) + l_k² det R + l_k² m_k R_nn + m_k c_k² (R_uu + m_k),
//   D_k det R_k = (J_k + m_k e_k²) det R + J_k m_k (tr R + m_k) + m_k² e_k² R_nn.
// (For c = l, J = 0 these reduce to R_k = r_k u_k u_kᵀ, D_k = l_k² d_k of the point-mass form.)
//
// From the pivot down: φ̇_k = a_k − (g_n x_k + g_u y_k)/D_k, v_k = (x_k + l_k φ̇_k, y_k), turned
// into the next link's frame. The kinetic part of ṗ is, since ∂v_{c,j}/∂φ_k = −φ̇_k c_k u_k for
// j = k and −φ̇_k l_k u_k for j > k,
//   ∂T/∂φ_k = −φ̇_k (c_k m_k y_k + l_k u_k·P_{k+1}),  u_k·P_{k+1} = R_nu (x_k + l_k φ̇_k) + R_uu y_k
//   + b_u,
// and det A = Π D_k: the elimination is a U D Uᵀ factorisation of A with the pivots D_k.
//
// The applied forces, O(1) per link as well (written out here rather than taken from the
// derivation's polynomials, which spell the moments through differences of the μ_j): in the
// pivot's frame gravity g − a_y and the horizontal field a_x act on the moments
// G_k = m_k c_k + l_k μ_{k+1} (μ_j = m_j + … + m_n), and the springs on the joint angles
// θ_k = φ_k − φ_{k−1}:
//   ∂V/∂φ_k = G_k ((g − a_y) sin φ_k + a_x cos φ_k) + k_k (θ_k − θ̄_k) − k_{k+1} (θ_{k+1} −
//   θ̄_{k+1});
// the joint torques τ_j = u_j − b_j θ̇_j act on link j and, reversed, on link j − 1:
// Q_k = τ_k − τ_{k+1}. A rigid chain without joints' features has gravity alone.
// `npend-gen --verify` checks all of it in exact arithmetic against GiNaC's derivation.
#pragma once

#include <vector>

#include "expr_graph.hpp"

namespace npend::gen {

/// Graph nodes of the rigid-link articulated-body formulation (see the file comment).
class rigid_articulated_form {
 public:
  /// Builds the momentum-independent nodes from the angle, mass, length, centre-of-mass and
  /// inertia inputs of `graph`.
  /// `joint_features`: the physical chain's springs, damping, torques and moving pivot.
  rigid_articulated_form(int links, bool joint_features, expr_graph& graph);

  /// The motion for momenta p (dim n): the rates φ̇_k, the kinetic part ∂T/∂φ_k of ṗ_k and T.
  struct motion {
    std::vector<sx> dphi, kinetic_force;
    sx kinetic_energy;
  };
  motion solve(const std::vector<sx>& p) const;

  /// det A = Π D_k.
  sx mass_matrix_determinant() const;

  /// −∂V/∂φ_k (dim n).
  std::vector<sx> potential_force() const;
  /// The joint forces Q_k at the rates `dphi` (dim n; zero without joint features).
  std::vector<sx> joint_force(const std::vector<sx>& dphi) const;

 private:
  // The momentum-independent part of the elimination of link k: D_k, 1/D_k, g, and the
  // articulated mass R of the sub-chain below, turned into link k's frame.
  struct pivot_step {
    sx D, inv_D, gn, gu, Rnu, Ruu;
  };
  int m_n;
  bool m_joint_features;
  expr_graph* m_graph;
  std::vector<sx> m_sin, m_cos;
  std::vector<sx> m_mass, m_length, m_com, m_inertia, m_cd, m_sd;
  std::vector<pivot_step> m_steps;
};

}  // namespace npend::gen
