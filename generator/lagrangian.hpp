// The generic Lagrangian mechanics of any model with generalised coordinates q: everything a
// model's kinematics file does not say (docs/generator.md, "Adding a model").
//
// A model gives its kinetic energy T(q, q̇), potential V(q), Rayleigh function R(q̇) and the
// virtual work W = Σ w_j δ(…) of its inputs w as GiNaC expressions; from them this derives
// L = T − V, the momenta p = ∂L/∂q̇ (the Legendre transform), the mass matrix A = ∂p/∂q̇, the
// generalised forces Q = ∂W/∂q − ∂R/∂q̇ and the derivatives that Hamilton's equations,
// their exact Jacobian (general_form.hpp) and the verification (verify.hpp) need. Nothing
// here knows what the coordinates mean.
#pragma once

#include <ginac/ginac.h>

#include <vector>

namespace npend::gen {

/// Generalised coordinates q, their rates q̇ and accelerations q̈ (for Lagrange's equations),
/// and the conjugate momenta p, indexed 0..size()-1.
struct coordinates {
  std::vector<GiNaC::realsymbol> q, dq, ddq, p;
  int size() const { return static_cast<int>(q.size()); }
};

/// What a model's kinematics provides. T must be a quadratic form in q̇ (no terms linear in
/// q̇), so that H = ½ pᵀq̇ + V; R = ½ q̇ᵀ B q̇; W is linear in q (its gradient is the forces
/// of the inputs).
struct lagrangian_model {
  GiNaC::ex kinetic, potential, rayleigh, input_work;
};

/// The Lagrangian mechanics derived from a lagrangian_model (vectors dim N = number of
/// coordinates, matrices N × N). Field names follow the chain's φ for q.
struct lagrangian_mechanics {
  GiNaC::ex kinetic;                      ///< T(q, q̇), expanded
  GiNaC::ex potential;                    ///< V(q), expanded
  GiNaC::ex lagrangian;                   ///< L = T − V
  std::vector<GiNaC::ex> momenta;         ///< p_i = ∂L/∂q̇_i
  GiNaC::matrix mass_matrix;              ///< A_ij = ∂p_i/∂q̇_j
  std::vector<GiNaC::ex> dL_dphi;         ///< ∂L/∂q_i at fixed q̇; ṗ_i = ∂L/∂q_i + Q_i
  std::vector<GiNaC::ex> grad_potential;  ///< ∂V/∂q_i
  GiNaC::matrix hess_potential;           ///< ∂²V/∂q_i∂q_j
  /// The non-conservative generalised forces Q_i = ∂W/∂q_i − ∂R/∂q̇_i.
  std::vector<GiNaC::ex> force;
  GiNaC::ex rayleigh;  ///< R, expanded
};

/// Derives the mechanics of `model` in the coordinates `q` (see the file comment).
lagrangian_mechanics derive_lagrangian_mechanics(const coordinates& q,
                                                 const lagrangian_model& model);

/// The total time derivative d/dt of an expression in q, q̇ (q̈ appears as q.ddq).
GiNaC::ex time_derivative(const coordinates& q, const GiNaC::ex& e);

/// ∂/∂q_k of every entry of the mass matrix, k = 0..N-1.
std::vector<GiNaC::matrix> mass_matrix_derivatives(const coordinates& q,
                                                   const lagrangian_mechanics& mech);

/// Hessian blocks of L: ∂²L/∂q_i∂q_j and ∂²L/∂q_i∂q̇_j (both N × N), and ∂Q_i/∂q̇_j of the
/// generalised forces (zero without damping; Q does not depend on q).
struct lagrangian_hessians {
  GiNaC::matrix phi_phi, phi_dphi, force_dphi;
  bool has_damping = false;  ///< force_dphi is not identically zero
};
lagrangian_hessians derive_lagrangian_hessians(const coordinates& q,
                                               const lagrangian_mechanics& mech);

/// The closed-form Hamiltonian H = numerator / (2 det A) + V with numerator = pᵀ adj(A) p.
/// Only sensible for small N: the adjugate grows factorially.
struct closed_form_hamiltonian {
  GiNaC::ex numerator;  ///< pᵀ adj(A) p
  GiNaC::ex det;        ///< det A
  GiNaC::ex potential;  ///< V
};
closed_form_hamiltonian derive_closed_form_hamiltonian(const coordinates& q,
                                                       const lagrangian_mechanics& mech);

}  // namespace npend::gen
