// The planar n-link pendulum as GiNaC sees it: symbols, kinematics, energies, and the
// Lagrangian mechanics derived from them (paper §6.2–6.3; docs/paper.md, "Conventions").
//
// Everything here is *derived*: positions from the chain's geometry (eq. 6.1), T and V from
// the positions, L = T − V, p = ∂L/∂φ̇ (the Legendre transform), A = ∂p/∂φ̇. Nothing is
// typed in from the known closed form of the mass matrix. Point masses on massless rods
// under gravity are the paper's model; rigid links, joint springs and generalised forces
// enter as further terms of T, V and Q in derive_mechanics.
#pragma once

#include <ginac/ginac.h>

#include <string>
#include <vector>

namespace npend::gen {

/// What the links are. Point masses on massless rods is the paper's model. Rigid links put
/// link k's mass m_k at its centre of mass, a distance c_k from its upper joint along the
/// link, with a moment of inertia J_k about it (a uniform rod: c = l/2, J = m l²/12; c = l,
/// J = 0 is the point mass again) — the physical pendulum of the paper's §6.2 remark.
///
/// The physical chain is the general planar chain: rigid links, a torsion spring k_i with
/// rest angle θ_i⁰ and viscous damping b_i at every joint, a motor torque u_i at every joint
/// and a moving pivot. Joint i joins link i−1 to link i, θ_i = φ_i − φ_{i−1} (φ_0 ≡ 0). The
/// pivot's motion enters in the pivot's frame, through its acceleration (a_x, a_y) (x right,
/// y down) and the inertial force −m_k a on every mass point (docs/model.md).
enum class link_kind { point_mass, rigid, physical };

/// "point", "rigid" or "physical".
const char* link_kind_name(link_kind kind);

/// Whether links carry a centre of mass and an inertia (rigid and physical chains).
inline bool has_rigid_links(link_kind kind) { return kind != link_kind::point_mass; }

/// The GiNaC symbols of an n-link chain. Vectors are indexed 0..n-1; printed names are
/// 1-based as in the paper (phi1, m1, ...).
struct chain_symbols {
  explicit chain_symbols(int links, link_kind kind = link_kind::point_mass);

  int n;
  link_kind kind;
  std::vector<GiNaC::realsymbol> phi, dphi, ddphi, p;  ///< angles, their rates, momenta
  std::vector<GiNaC::realsymbol> mass, length;         ///< run-time parameters m_i, l_i
  std::vector<GiNaC::realsymbol> com, inertia;  ///< c_i, J_i of rigid links (unused otherwise)
  /// Joint spring k_i, its rest angle θ_i⁰, joint damping b_i and motor torque u_i, and the
  /// pivot's acceleration (a_x, a_y): physical chains only.
  std::vector<GiNaC::realsymbol> stiffness, rest_angle, damping, torque;
  GiNaC::realsymbol drive_x, drive_y;
  std::vector<GiNaC::realsymbol> mu;  ///< μ_j = m_j + … + m_n, the mass at and below joint j
  GiNaC::realsymbol g;
  std::vector<GiNaC::realsymbol> s, c;  ///< stand-ins for sin φ_i, cos φ_i in polynomials
};

/// The Lagrangian mechanics of the chain.
struct chain_mechanics {
  std::vector<GiNaC::ex> x, y;            ///< link-end (bob) positions, y pointing down (eq. 6.1)
  GiNaC::ex kinetic;                      ///< T(φ, φ̇)
  GiNaC::ex potential;                    ///< V(φ), zero at the hanging rest position (eq. 6.12)
  GiNaC::ex lagrangian;                   ///< L = T − V
  std::vector<GiNaC::ex> momenta;         ///< p_i = ∂L/∂φ̇_i
  GiNaC::matrix mass_matrix;              ///< A_ij = ∂p_i/∂φ̇_j (n × n)
  std::vector<GiNaC::ex> dL_dphi;         ///< ∂L/∂φ_i at fixed φ̇; equals ṗ_i on the flow
  std::vector<GiNaC::ex> grad_potential;  ///< ∂V/∂φ_i
  GiNaC::matrix hess_potential;           ///< ∂²V/∂φ_i∂φ_j (n × n)
  /// The non-conservative generalised forces Q_i = −∂R/∂φ̇_i + Σ_j u_j ∂θ_j/∂φ_i, R the
  /// Rayleigh function ½ Σ b_j θ̇_j² (zero but for physical chains): ṗ_i = ∂L/∂φ_i + Q_i.
  std::vector<GiNaC::ex> force;
  GiNaC::ex rayleigh;  ///< R
  /// The joint angles θ_j = φ_j − φ_{j−1}.
  std::vector<GiNaC::ex> joint_angle;
};

/// Derives the mechanics of the n-link chain of sym.kind: point masses m_i on massless rods
/// l_i, or rigid links (masses at their centres c_i, moments of inertia J_i). x, y are the
/// positions of the link ends (the bobs of point masses).
chain_mechanics derive_mechanics(const chain_symbols& sym);

/// ∂/∂φ_k of every entry of the mass matrix, k = 0..n-1 (used to check the Jacobian).
std::vector<GiNaC::matrix> mass_matrix_derivatives(const chain_symbols& sym,
                                                   const chain_mechanics& mech);

/// Hessian blocks of L: ∂²L/∂φ_i∂φ_j and ∂²L/∂φ_i∂φ̇_j (both n × n), and ∂Q_i/∂φ̇_j of the
/// generalised forces (zero without damping; Q does not depend on φ).
struct lagrangian_hessians {
  GiNaC::matrix phi_phi, phi_dphi, force_dphi;
  bool has_damping = false;  ///< force_dphi is not identically zero
};
lagrangian_hessians derive_lagrangian_hessians(const chain_symbols& sym,
                                               const chain_mechanics& mech);

/// The closed-form Hamiltonian H = numerator / (2 det A) + V with numerator = pᵀ adj(A) p.
/// Only sensible for small n: the adjugate grows factorially.
struct closed_form_hamiltonian {
  GiNaC::ex numerator;  ///< pᵀ adj(A) p
  GiNaC::ex det;        ///< det A
  GiNaC::ex potential;  ///< V
};
closed_form_hamiltonian derive_closed_form_hamiltonian(const chain_symbols& sym,
                                                       const chain_mechanics& mech);

/// The total time derivative d/dt of an expression in φ, φ̇ (φ̈ appears as ddphi).
GiNaC::ex time_derivative(const chain_symbols& sym, const GiNaC::ex& e);

}  // namespace npend::gen
