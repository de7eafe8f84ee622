#include "chain_functions.hpp"

#include <fmt/format.h>

#include <map>
#include <stdexcept>
#include <string>

#include "articulated_form.hpp"
#include "forward_diff.hpp"
#include "general_form.hpp"
#include "polynomial.hpp"
#include "rigid_articulated_form.hpp"

namespace npend::gen {

namespace {

std::size_t u(int i) { return static_cast<std::size_t>(i); }

emitted_function make(std::string name, argument_layout layout, std::vector<std::string> doc,
                      std::string output_name = {}) {
  emitted_function f;
  f.name = std::move(name);
  f.layout = layout;
  f.doc = std::move(doc);
  f.returns_scalar = output_name.empty();
  f.output_name = std::move(output_name);
  f.graph = std::make_unique<expr_graph>();
  return f;
}

std::vector<sx> inputs(expr_graph& g, input_kind kind, int n) {
  std::vector<sx> out;
  for (int i = 0; i < n; ++i) out.push_back(g.input(kind, i));
  return out;
}

// A function whose outputs are GiNaC expressions, emitted through canonical polynomials.
emitted_function from_expressions(const polynomial_space& space, std::string name,
                                  argument_layout layout, std::vector<std::string> doc,
                                  const std::vector<GiNaC::ex>& values,
                                  std::string output_name = {}) {
  emitted_function f = make(std::move(name), layout, std::move(doc), std::move(output_name));
  const std::vector<sx> vars = variable_nodes(space, *f.graph);
  for (const auto& v : values) f.outputs.push_back(to_graph(space.canonical(v), vars, *f.graph));
  return f;
}

std::vector<GiNaC::ex> entries(const GiNaC::matrix& m) {
  std::vector<GiNaC::ex> out;
  for (unsigned i = 0; i < m.rows(); ++i)
    for (unsigned j = 0; j < m.cols(); ++j) out.push_back(m(i, j));
  return out;
}

// −∂V/∂φ_i from the derived potential, as nodes of `graph`.
std::vector<sx> potential_force(const polynomial_space& space, const chain_mechanics& mech,
                                expr_graph& graph) {
  const std::vector<sx> vars = variable_nodes(space, graph);
  std::vector<sx> out;
  for (const auto& dv : mech.grad_potential)
    out.push_back(-to_graph(space.canonical(dv), vars, graph));
  return out;
}

emitted_function rhs_function(int n, const polynomial_space& space, const chain_mechanics& mech) {
  emitted_function f =
      make("rhs", argument_layout::state,
           {"Hamilton's equations f(x): dxdt = [dphi/dt (dim n), dp/dt (dim n)].",
            "phi' = A^-1 p by an O(n) articulated-body elimination (no inverse masses), "
            "p' = -dH/dphi."},
           "dxdt");
  expr_graph& g = *f.graph;
  const articulated_form form(n, g);
  const auto motion = form.solve(inputs(g, input_kind::p, n));
  const auto force = potential_force(space, mech, g);
  for (int i = 0; i < n; ++i) f.outputs.push_back(motion.omega[u(i)] * form.inv_length[u(i)]);
  for (int i = 0; i < n; ++i) f.outputs.push_back(motion.kinetic_force[u(i)] + force[u(i)]);
  return f;
}

emitted_function jacobian_function(int n, const polynomial_space& space,
                                   const chain_mechanics& mech) {
  emitted_function f =
      make("jacobian", argument_layout::state,
           {"Exact Jacobian J = df/dx of rhs, row-major (2n x 2n): J[i*2n + j] = df_i/dx_j.",
            "Hamiltonian structure: J = [[B, A^-1], [C, -B^T]] with C symmetric."},
           "jac");
  expr_graph& g = *f.graph;
  const articulated_form form(n, g);
  const auto p = inputs(g, input_kind::p, n);
  const std::vector<sx> vars = variable_nodes(space, g);
  const int dim = 2 * n;
  f.outputs.assign(u(dim * dim), sx{});
  auto out = [&](int row, int col) -> sx& { return f.outputs[u(row * dim + col)]; };

  // Along q_k = p_k / l_k: W_ik = ∂φ̇_i/∂p_k for i ≤ k (mirrored), which needs the pass
  // from the pivot only down to link k.
  for (int k = 0; k < n; ++k) {
    const auto t = form.along_scaled_momentum(p, k);
    for (int i = 0; i <= k; ++i)
      out(i, n + k) = out(k, n + i) =
          t.omega[u(i)] * (form.inv_length[u(i)] * form.inv_length[u(k)]);
  }
  // Along φ_k: B_ik = ∂φ̇_i/∂φ_k, D = −Bᵀ, and C_ik = ∂ṗ_i/∂φ_k for i ≥ k (mirrored), the
  // kinetic part plus −∂²V/∂φ_i∂φ_k (see articulated_form.hpp for why these entries).
  for (int k = 0; k < n; ++k) {
    const auto t = form.along_angle(p, k);
    for (int i = 0; i < n; ++i) {
      const sx b = t.omega[u(i)] * form.inv_length[u(i)];
      out(i, k) = b;
      out(n + k, n + i) = -b;
    }
    for (int i = k; i < n; ++i) {
      sx cik = t.kinetic_force[u(i)];
      const auto hess = space.canonical(mech.hess_potential(u(i), u(k)));
      if (!hess.empty()) cik = cik - to_graph(hess, vars, g);
      out(n + i, k) = out(n + k, i) = cik;
    }
  }
  return f;
}

emitted_function hamiltonian_function(int n, const polynomial_space& space,
                                      const chain_mechanics& mech) {
  emitted_function f = make("hamiltonian", argument_layout::state,
                            {"Hamiltonian H(phi, p) = 1/2 p^T A^-1 p + V (total energy)."});
  expr_graph& g = *f.graph;
  const articulated_form form(n, g);
  const auto motion = form.solve(inputs(g, input_kind::p, n));
  // T = ½ Σ m_k |v_k|²: a sum of positive terms, so H = T + V does not cancel.
  const std::vector<sx> vars = variable_nodes(space, g);
  f.outputs.push_back(form.kinetic_energy(motion) +
                      to_graph(space.canonical(mech.potential), vars, g));
  return f;
}

emitted_function velocities_function(int n) {
  emitted_function f = make("velocities", argument_layout::phi_p,
                            {"Inverse Legendre transform: dphi = A^-1 p (dim n)."}, "dphi");
  expr_graph& g = *f.graph;
  const articulated_form form(n, g);
  const auto motion = form.solve(inputs(g, input_kind::p, n));
  for (int i = 0; i < n; ++i) f.outputs.push_back(motion.omega[u(i)] * form.inv_length[u(i)]);
  return f;
}

emitted_function det_function(int n) {
  emitted_function f = make("det_mass_matrix", argument_layout::phi,
                            {"det A(phi) = (prod l_i)^2 prod d_i, d_i the pivots of the "
                             "articulated-body elimination."});
  expr_graph& g = *f.graph;
  const articulated_form form(n, g);
  f.outputs.push_back(form.mass_matrix_determinant());
  return f;
}

emitted_function closed_form_function(const chain_symbols& sym, const polynomial_space& space,
                                      const chain_mechanics& mech) {
  emitted_function f = make(
      "hamiltonian_closed_form", argument_layout::state,
      {"Closed-form Hamiltonian p^T adj(A) p / (2 det A) + V, as printed by npend-gen --latex.",
       "For checking against the paper; hamiltonian() is the faster way to the same value."});
  const auto closed = derive_closed_form_hamiltonian(sym.coords, mech);
  expr_graph& g = *f.graph;
  const std::vector<sx> vars = variable_nodes(space, g);
  const sx num = to_graph(space.canonical(closed.numerator), vars, g);
  const sx det = to_graph(space.canonical(closed.det), vars, g);
  f.outputs.push_back(num / (g.constant(2) * det) +
                      to_graph(space.canonical(closed.potential), vars, g));
  return f;
}

// ∂f/∂w of a chain with inputs (physical_kernels::input_matrix): f is affine in w and
// q̇ = A⁻¹p does not depend on it, so only ṗ = ∂L/∂q + Q has entries, functions of q alone.
emitted_function input_matrix_function(const chain_symbols& sym, const polynomial_space& space,
                                       const chain_mechanics& mech) {
  const int n = sym.coords.size();
  const std::vector<GiNaC::realsymbol> w = input_symbols(sym);
  std::vector<GiNaC::ex> entries_rowmajor;
  for (int i = 0; i < n; ++i)
    for (std::size_t j = 0; j < w.size(); ++j) entries_rowmajor.push_back(0);
  for (int i = 0; i < n; ++i) {
    const GiNaC::ex rate = mech.dL_dphi[u(i)] + mech.force[u(i)];
    for (const auto& wj : w) entries_rowmajor.push_back(rate.diff(wj).expand());
  }
  std::vector<std::string> doc =
      on_cart(sym.kind)
          ? std::vector<std::string>{"Input matrix df/dw, row-major (2(n+1) x (n+1)), for the "
                                     "inputs w = [F, u_1..u_n]:",
                                     "the force on the cart and the joint torques. df/dt = "
                                     "(df/dw) dw/dt."}
          : std::vector<std::string>{
                "Input matrix df/dw, row-major (2n x (n+2)), for the inputs w = [a_x, a_y, "
                "u_1..u_n]:",
                "the pivot's acceleration and the joint torques. Its last n columns are B = "
                "df/du; df/dt = (df/dw) dw/dt."};
  return from_expressions(space, "input_matrix", argument_layout::phi, std::move(doc),
                          entries_rowmajor, "dfdw");
}

// The exact Jacobian of a rigid-link chain's rhs, from forward-mode derivatives of the
// elimination. ṗ = ṗ_H + Q splits into the Hamiltonian part ṗ_H = ∂T/∂φ − ∂V/∂φ = −∂H/∂φ
// and the joint forces Q = Q_φ̇ φ̇ + Q_0, linear in φ̇ (damping) with the constant matrix
// Q_φ̇ (tridiagonal) and Q_0 the torques. With B = ∂φ̇/∂φ, W = ∂φ̇/∂p = A⁻¹ and C = ∂ṗ_H/∂φ:
//   J = [[B, W], [C + Q_φ̇ B, −Bᵀ + Q_φ̇ W]],
// W and C symmetric (second derivatives of H). So only B, the half i ≤ k of W and the half
// i ≥ k of C are differentiated — about half the work of the whole rhs along all 2n
// directions — and the lower link's force along the upper link's angle is the member of each
// pair of C taken, as in the point-mass form (articulated_form.hpp).
std::vector<sx> rigid_jacobian(const rigid_articulated_form& form,
                               const rigid_articulated_form::motion& motion,
                               const std::vector<sx>& p, expr_graph& g) {
  const int n = static_cast<int>(p.size()), dim = 2 * n;
  const std::vector<sx> potential = form.potential_force();
  std::vector<sx> hamiltonian_rate;
  for (int i = 0; i < n; ++i)
    hamiltonian_rate.push_back(motion.kinetic_force[u(i)] + potential[u(i)]);
  // Q at the rate inputs, to differentiate along them.
  const std::vector<sx> joint_force = form.joint_force(inputs(g, input_kind::dphi, n));
  std::vector<std::vector<sx>> q_rate(u(n));  // q_rate[j][i] = ∂Q_i/∂φ̇_j: parameters only
  for (int j = 0; j < n; ++j)
    q_rate[u(j)] = directional_derivative(g, joint_force, g.input(input_kind::dphi, j));
  std::vector<std::vector<sx>> b(u(n)), w(u(n), std::vector<sx>(u(n))), c = w;  // b[k][i] = B_ik
  std::vector<sx> out(u(dim * dim));
  const auto at = [&](int row, int col) -> sx& { return out[u(row * dim + col)]; };
  for (int k = 0; k < n; ++k) {
    // Along φ_k: B's column k and C_ik for i ≥ k.
    std::vector<sx> outputs = motion.dphi;
    outputs.insert(outputs.end(), hamiltonian_rate.begin() + k, hamiltonian_rate.end());
    const auto d = directional_derivative(g, outputs, g.input(input_kind::phi, k));
    b[u(k)].assign(d.begin(), d.begin() + n);
    for (int i = k; i < n; ++i) c[u(i)][u(k)] = c[u(k)][u(i)] = d[u(n + i - k)];
    // Along p_k: W_ik for i ≤ k; the rates of the links below k are not needed.
    const std::vector<sx> upper(motion.dphi.begin(), motion.dphi.begin() + k + 1);
    const auto dw = directional_derivative(g, upper, p[u(k)]);
    for (int i = 0; i <= k; ++i) w[u(i)][u(k)] = w[u(k)][u(i)] = dw[u(i)];
  }
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < n; ++k) {
      at(i, k) = b[u(k)][u(i)];
      at(i, n + k) = w[u(i)][u(k)];
      sx force_phi = c[u(i)][u(k)], force_p = -b[u(i)][u(k)];
      for (int j = 0; j < n; ++j) {
        const sx qij = q_rate[u(j)][u(i)];
        if (g.is_constant(qij, 0)) continue;
        force_phi = force_phi + qij * b[u(k)][u(j)];
        force_p = force_p + qij * w[u(j)][u(k)];
      }
      at(n + i, k) = force_phi;
      at(n + i, n + k) = force_p;
    }
  return out;
}

// The kinetic functions of a rigid-link chain by the O(n) articulated-body elimination
// (rigid_articulated_form.hpp): rhs, jacobian (its forward-mode derivative), hamiltonian,
// velocities and det_mass_matrix, each over its own graph. ṗ = ∂T/∂φ − ∂V/∂φ + Q with V and Q
// from the derivation's polynomials at the computed φ̇.
std::vector<emitted_function> rigid_articulated_functions(const chain_symbols& sym,
                                                          const polynomial_space& space,
                                                          const chain_mechanics& mech) {
  const int n = sym.n;
  const bool physical = sym.kind == link_kind::physical;
  std::vector<emitted_function> out;
  out.push_back(make("rhs", argument_layout::state,
                     {"Hamilton's equations f(x): dxdt = [dphi/dt (dim n), dp/dt (dim n)].",
                      "phi' = A^-1 p by an O(n) articulated-body elimination for rigid links, "
                      "p' = dL/dphi"},
                     "dxdt"));
  out.push_back(make("jacobian", argument_layout::state,
                     {"Exact Jacobian J = df/dx of rhs, row-major (2n x 2n): J[i*2n + j] = "
                      "df_i/dx_j,",
                      "the forward-mode derivative of rhs's recursion."},
                     "jac"));
  out.push_back(make("hamiltonian", argument_layout::state,
                     {"Hamiltonian H(phi, p) = T + V (total energy)."}));
  out.push_back(make("velocities", argument_layout::phi_p,
                     {"Inverse Legendre transform: dphi = A^-1 p (dim n)."}, "dphi"));
  out.push_back(make("det_mass_matrix", argument_layout::phi,
                     {"det A(phi) = prod D_k, the pivots of the articulated-body elimination."}));
  if (physical) {
    out[0].doc[1] += " + Q, Q the joint torques and damping forces.";
    out[1].doc[1] += " With damping the flow is not Hamiltonian.";
    out[2].doc[0] =
        "H(phi, p) = T + V: the energy in the pivot's frame, V with the springs and the "
        "inertial potential of the pivot's acceleration.";
  } else {
    out[0].doc[1] += ".";
  }
  for (auto& f : out) {
    expr_graph& g = *f.graph;
    const rigid_articulated_form form(n, physical, g);
    if (f.name == "det_mass_matrix") {
      f.outputs = {form.mass_matrix_determinant()};
      continue;
    }
    const auto p = inputs(g, input_kind::p, n);
    const auto motion = form.solve(p);
    if (f.name == "velocities") {
      f.outputs = motion.dphi;
      continue;
    }
    if (f.name == "hamiltonian") {
      // V from the derivation: a sum of terms, not needed differentiated.
      f.outputs = {motion.kinetic_energy +
                   to_graph(space.canonical(mech.potential), variable_nodes(space, g), g)};
      continue;
    }
    if (f.name == "rhs") {
      const std::vector<sx> potential = form.potential_force();
      const std::vector<sx> joint = form.joint_force(motion.dphi);
      f.outputs = motion.dphi;
      for (int i = 0; i < n; ++i)
        f.outputs.push_back(motion.kinetic_force[u(i)] + (potential[u(i)] + joint[u(i)]));
      continue;
    }
    f.outputs = rigid_jacobian(form, motion, p, g);
  }
  return out;
}

// The kinetic functions by the general path: rhs, jacobian, hamiltonian, velocities and
// det_mass_matrix, each from its own general_form over its own graph.
std::vector<emitted_function> general_functions(const polynomial_space& space,
                                                const chain_mechanics& mech,
                                                const lagrangian_hessians& hessians) {
  std::vector<emitted_function> out;
  out.push_back(make("rhs", argument_layout::state,
                     {"Hamilton's equations f(x): dxdt = [dphi/dt (dim n), dp/dt (dim n)].",
                      "phi' = A^-1 p with A = L D L^T factored here (general path), "
                      "p' = dL/dphi at phi'."},
                     "dxdt"));
  out.push_back(make("jacobian", argument_layout::state,
                     {"Exact Jacobian J = df/dx of rhs, row-major (2n x 2n): J[i*2n + j] = "
                      "df_i/dx_j.",
                      "Hamiltonian structure: J = [[B, A^-1], [C, -B^T]] with C symmetric."},
                     "jac"));
  out.push_back(make("hamiltonian", argument_layout::state,
                     {"Hamiltonian H(phi, p) = 1/2 p^T A^-1 p + V (total energy)."}));
  out.push_back(make("velocities", argument_layout::phi_p,
                     {"Inverse Legendre transform: dphi = A^-1 p (dim n)."}, "dphi"));
  out.push_back(make("det_mass_matrix", argument_layout::phi,
                     {"det A(phi) = prod D_i, the pivots of A = L D L^T."}));
  if (hessians.has_damping) {
    out[0].doc[1] += " + Q, Q the joint torques, springs aside, and damping forces.";
    out[1].doc[1] = "With damping the flow is not Hamiltonian: no symmetry of J is assumed.";
    out[2].doc[0] =
        "H(phi, p) = 1/2 p^T A^-1 p + V: the energy in the pivot's frame, V with the springs "
        "and the inertial potential of the pivot's acceleration.";
  }
  for (auto& f : out) {
    const general_form form(space, mech, hessians, *f.graph);
    if (f.name == "rhs") {
      f.outputs = form.velocities();
      for (const sx rate : form.momentum_rates()) f.outputs.push_back(rate);
    } else if (f.name == "jacobian") {
      f.outputs = form.jacobian();
    } else if (f.name == "hamiltonian") {
      f.outputs = {form.hamiltonian()};
    } else if (f.name == "velocities") {
      f.outputs = form.velocities();
    } else {
      f.outputs = {form.mass_matrix_determinant()};
    }
  }
  return out;
}

// The cart's functions say what their arrays hold: the coordinates are q = [x, phi_1..phi_n]
// (cart_layout), and the energy is the lab frame's.
void describe_cart(std::vector<emitted_function>& functions) {
  const std::map<std::string, std::vector<std::string>> docs{
      {"rhs",
       {"Hamilton's equations f(x): dxdt = [dq/dt (dim n+1), dp/dt (dim n+1)], q = [x, "
        "phi_1..phi_n];",
        "q' = A^-1 p with A = L D L^T factored here, p' = dL/dq at q' + Q (the force on the "
        "cart, the joint torques and the damping forces)."}},
      {"jacobian",
       {"Exact Jacobian J = df/dx of rhs, row-major (2(n+1) x 2(n+1)): J[i*2(n+1) + j] = "
        "df_i/dx_j.",
        "With damping the flow is not Hamiltonian: no symmetry of J is assumed."}},
      {"hamiltonian", {"Hamiltonian H(q, p) = 1/2 p^T A^-1 p + V (total energy, T + V)."}},
      {"velocities", {"Inverse Legendre transform: dq = A^-1 p (dim n+1)."}},
      {"momenta", {"Legendre transform: p = dL/d(dq) = A dq (dim n+1)."}},
      {"kinetic_energy", {"Kinetic energy T = M/2 dx^2 + sum of the links' kinetic energies."}},
      {"mass_matrix", {"Mass matrix A = d^2T/d(dq)^2, row-major ((n+1) x (n+1))."}},
      {"potential_gradient", {"Gradient dV/dq (dim n+1)."}},
      {"potential_hessian", {"Hessian d^2V/dq^2, row-major ((n+1) x (n+1))."}},
      {"positions",
       {"The cart's position and the bobs': [x, 0, x_1, y_1, ..., x_n, y_n] (dim 2(n+1)), y "
        "down."}}};
  for (auto& f : functions) {
    const auto it = docs.find(f.name);
    if (it != docs.end()) f.doc = it->second;
  }
}

}  // namespace

const char* solver_name(kinetic_solver solver) {
  return solver == kinetic_solver::articulated ? "articulated" : "ldlt";
}

bool reads_inputs(const std::string& function_name) {
  for (const char* name : {"rhs", "jacobian", "hamiltonian", "lagrangian", "potential_energy",
                           "potential_gradient", "potential_hessian"})
    if (function_name == name) return true;
  return false;
}

kinetic_solver default_solver(const chain_symbols& sym) {
  return fits_articulated(sym) ? kinetic_solver::articulated : kinetic_solver::ldlt;
}

bool fits_articulated(const chain_symbols& sym) { return !on_cart(sym.kind); }

std::vector<GiNaC::realsymbol> input_symbols(const chain_symbols& sym) {
  std::vector<GiNaC::realsymbol> w;
  if (has_pivot_drive(sym.kind)) w = {sym.drive_x, sym.drive_y};
  if (on_cart(sym.kind)) w = {sym.cart_force};
  if (has_joint_forces(sym.kind)) w.insert(w.end(), sym.torque.begin(), sym.torque.end());
  return w;
}

std::vector<emitted_function> build_chain_functions(const chain_symbols& sym,
                                                    const chain_mechanics& mech,
                                                    kinetic_solver solver) {
  const int n = sym.n;
  if (solver == kinetic_solver::articulated && !fits_articulated(sym))
    throw std::invalid_argument(
        fmt::format("the articulated-body solver does not fit the {} model: use --solver ldlt",
                    link_kind_name(sym.kind)));
  const polynomial_space space(sym);
  std::vector<emitted_function> out;
  std::vector<emitted_function> precomputed;  // the kinetic functions of the rigid or general path
  if (solver == kinetic_solver::ldlt)
    precomputed = general_functions(space, mech, derive_lagrangian_hessians(sym.coords, mech));
  else if (has_rigid_links(sym.kind))
    precomputed = rigid_articulated_functions(sym, space, mech);
  // The kinetic functions in their place of the file's order, from either path.
  const auto take = [&](const char* name, auto&& point_mass) {
    if (precomputed.empty()) {
      out.push_back(point_mass());
      return;
    }
    for (auto& f : precomputed)
      if (f.name == name) out.push_back(std::move(f));
  };
  take("rhs", [&] { return rhs_function(n, space, mech); });
  take("jacobian", [&] { return jacobian_function(n, space, mech); });
  take("hamiltonian", [&] { return hamiltonian_function(n, space, mech); });
  take("velocities", [&] { return velocities_function(n); });
  out.push_back(from_expressions(space, "momenta", argument_layout::phi_dphi,
                                 {"Legendre transform: p = dL/d(dphi) = A dphi (dim n)."},
                                 mech.momenta, "p"));
  out.push_back(from_expressions(space, "lagrangian", argument_layout::phi_dphi,
                                 {"Lagrangian L = T - V."}, {mech.lagrangian}));
  out.push_back(from_expressions(space, "kinetic_energy", argument_layout::phi_dphi,
                                 {"Kinetic energy T = sum m_k/2 |dr_k/dt|^2."}, {mech.kinetic}));
  out.push_back(from_expressions(space, "potential_energy", argument_layout::phi,
                                 {"Potential energy V, zero at the hanging rest position."},
                                 {mech.potential}));
  out.push_back(from_expressions(space, "mass_matrix", argument_layout::phi,
                                 {"Mass matrix A = d^2T/d(dphi)^2, row-major (n x n)."},
                                 entries(mech.mass_matrix), "A"));
  take("det_mass_matrix", [&] { return det_function(n); });
  out.push_back(from_expressions(space, "potential_gradient", argument_layout::phi,
                                 {"Gradient dV/dphi (dim n)."}, mech.grad_potential, "grad"));
  out.push_back(from_expressions(space, "potential_hessian", argument_layout::phi,
                                 {"Hessian d^2V/dphi^2, row-major (n x n)."},
                                 entries(mech.hess_potential), "hess"));
  std::vector<GiNaC::ex> xy;
  if (on_cart(sym.kind)) xy = {sym.cart_x, 0};
  for (int k = 0; k < n; ++k) {
    xy.push_back(mech.x[u(k)]);
    xy.push_back(mech.y[u(k)]);
  }
  out.push_back(from_expressions(space, "positions", argument_layout::phi,
                                 {"Bob positions [x_1, y_1, ..., x_n, y_n] (dim 2n), y down."}, xy,
                                 "xy"));
  if (!has_joint_forces(sym.kind)) {
    if (n <= closed_form_max_links) out.push_back(closed_form_function(sym, space, mech));
    return out;
  }
  out.push_back(input_matrix_function(sym, space, mech));
  for (auto& f : out) f.takes_inputs = reads_inputs(f.name);
  if (on_cart(sym.kind)) describe_cart(out);
  return out;
}

}  // namespace npend::gen
