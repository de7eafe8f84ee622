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

#include "lagrangian.hpp"

namespace npend::gen {

/// What the links are, and what they hang from. Point masses on massless rods is the paper's
/// model. Rigid links put link k's mass m_k at its centre of mass, a distance c_k from its
/// upper joint along the link, with a moment of inertia J_k about it (a uniform rod: c = l/2,
/// J = m l²/12; c = l, J = 0 is the point mass again) — the physical pendulum of the paper's
/// §6.2 remark.
///
/// The physical chain is the general planar chain: rigid links, a torsion spring k_i with
/// rest angle θ_i⁰ and viscous damping b_i at every joint, a motor torque u_i at every joint
/// and a moving pivot. Joint i joins link i−1 to link i, θ_i = φ_i − φ_{i−1} (φ_0 ≡ 0). The
/// pivot's motion enters in the pivot's frame, through its acceleration (a_x, a_y) (x right,
/// y down) and the inertial force −m_k a on every mass point (docs/model.md).
///
/// The cart is the physical chain's links hung from a cart of mass M on a horizontal rail:
/// one more coordinate, the cart's position x, with viscous damping b_x and a horizontal force
/// F on the cart (cart_model.cpp); the pivot is the cart, so there is no prescribed drive.
enum class link_kind { point_mass, rigid, physical, cart };

/// "point", "rigid", "physical" or "cart".
const char* link_kind_name(link_kind kind);

/// Whether links carry a centre of mass and an inertia (rigid, physical and cart chains).
inline bool has_rigid_links(link_kind kind) { return kind != link_kind::point_mass; }
/// Whether the joints carry springs, damping and torques (physical and cart chains).
inline bool has_joint_forces(link_kind kind) {
  return kind == link_kind::physical || kind == link_kind::cart;
}
/// Whether the pivot moves with a prescribed acceleration (the physical chain's drive).
inline bool has_pivot_drive(link_kind kind) { return kind == link_kind::physical; }
/// Whether the chain hangs from a cart (the coordinates start with the cart's position).
inline bool on_cart(link_kind kind) { return kind == link_kind::cart; }

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
  /// The cart's position x, its rate, acceleration and momentum p_x, its mass M, damping b_x
  /// and the force F on it: chains on a cart only.
  GiNaC::realsymbol cart_x, cart_dx, cart_ddx, cart_p, cart_mass, cart_damping, cart_force;
  /// The generalised coordinates: q = φ, or q = [x, φ] on a cart.
  coordinates coords;
};

/// The Lagrangian mechanics of the chain: the generic derivation plus the chain's geometry.
struct chain_mechanics : lagrangian_mechanics {
  std::vector<GiNaC::ex> x, y;  ///< link-end (bob) positions, y pointing down (eq. 6.1)
  /// The joint angles θ_j = φ_j − φ_{j−1}.
  std::vector<GiNaC::ex> joint_angle;
};

/// The planar chain's kinematics hung from a pivot at (pivot_x, 0): fills mech.x, mech.y and
/// mech.joint_angle, and returns T, V, R and the inputs' work of the links (point masses m_i
/// on massless rods l_i, or rigid links with masses at their centres c_i and inertias J_i,
/// and the joint forces of sym.kind).
lagrangian_model chain_kinematics(const chain_symbols& sym, const GiNaC::ex& pivot_x,
                                  chain_mechanics& mech);

/// Derives the mechanics of the n-link chain of sym.kind (the chain's kinematics, or the
/// cart's for link_kind::cart, then derive_lagrangian_mechanics).
chain_mechanics derive_mechanics(const chain_symbols& sym);

/// The chain on a cart (cart_model.cpp): the chain's links from a pivot at (x, 0), plus the
/// cart's kinetic energy ½ M ẋ², its damping ½ b_x ẋ² in R and the force's work F x.
chain_mechanics derive_cart_mechanics(const chain_symbols& sym);

/// The chain's coordinates in the generic functions of lagrangian.hpp.
inline GiNaC::ex time_derivative(const chain_symbols& sym, const GiNaC::ex& e) {
  return time_derivative(sym.coords, e);
}

}  // namespace npend::gen
