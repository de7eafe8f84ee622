// The functions emitted for one link count: each one a small expression graph with its
// outputs, built from the GiNaC derivation (energies, momenta, mass matrix, positions,
// potential derivatives, closed-form H) or from the articulated-body formulation (Hamilton's
// equations, their Jacobian, velocities, H, det A; see articulated_form.hpp).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "chain_model.hpp"
#include "expr_graph.hpp"

namespace npend::gen {

/// How the angle/rate/momentum inputs of a function are passed.
enum class argument_layout {
  state,     ///< (const double* x, ...) with x = [φ_1..φ_n, p_1..p_n]
  phi_dphi,  ///< (const double* phi, const double* dphi, ...)
  phi_p,     ///< (const double* phi, const double* p, ...)
  phi,       ///< (const double* phi, ...)
};

struct emitted_function {
  std::string name;
  std::vector<std::string> doc;  ///< lines of the /// comment
  argument_layout layout = argument_layout::state;
  bool returns_scalar = false;  ///< `double f(...)`; otherwise `void f(..., double* out)`
  std::string output_name;      ///< name of the output array of a void function
  /// Takes the time-dependent inputs w of a physical chain or a chain on a cart
  /// (input_symbols) as `const double* inputs` after params.
  bool takes_inputs = false;
  std::unique_ptr<expr_graph> graph;
  std::vector<sx> outputs;
};

/// How Hamilton's equations, their Jacobian, H, φ̇ and det A are formed.
enum class kinetic_solver {
  articulated,  ///< the O(n) articulated-body elimination (articulated_form.hpp for point
                ///< masses, rigid_articulated_form.hpp for rigid links)
  ldlt,         ///< the general path: A from the derivation, factored L D Lᵀ (general_form.hpp)
};

/// "articulated" or "ldlt".
const char* solver_name(kinetic_solver solver);

/// The solver for a chain: the articulated-body form where it fits (every chain from a fixed
/// or driven pivot), the general path otherwise (the chain on a cart); the general path also
/// serves as a cross-check (`npend-gen --verify N --solver ldlt`).
kinetic_solver default_solver(const chain_symbols& sym);

/// Whether the articulated-body elimination fits the chain (not on a cart: its recursion
/// starts from a pivot whose motion is given).
bool fits_articulated(const chain_symbols& sym);

/// The time-dependent inputs w of a chain, in the order of its layout: [a_x, a_y, u_1..u_n]
/// for the physical chain, [F, u_1..u_n] on a cart, none otherwise.
std::vector<GiNaC::realsymbol> input_symbols(const chain_symbols& sym);

/// The functions of a physical chain that read its time-dependent inputs (the drive enters V,
/// the torques Q): rhs, jacobian, hamiltonian, lagrangian, potential_energy,
/// potential_gradient, potential_hessian.
bool reads_inputs(const std::string& function_name);

/// Every emitted function of the n-link chain, in the order they are written; the kinetic
/// functions (rhs, jacobian, hamiltonian, velocities, det_mass_matrix) by `solver`. A chain
/// with inputs (physical, cart) also gets input_matrix, ∂f/∂w for its inputs w. Throws
/// std::invalid_argument if `solver` does not fit the chain.
std::vector<emitted_function> build_chain_functions(const chain_symbols& sym,
                                                    const chain_mechanics& mech,
                                                    kinetic_solver solver);

/// Largest link count for which the closed-form Hamiltonian is emitted and printed.
inline constexpr int closed_form_max_links = 3;

}  // namespace npend::gen
