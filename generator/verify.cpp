#include "verify.hpp"

#include <fmt/format.h>
#include <fmt/ostream.h>

#include <ostream>
#include <random>
#include <stdexcept>

#include "chain_functions.hpp"
#include "chain_model.hpp"
#include "polynomial.hpp"

namespace npend::gen {

namespace {

std::size_t u(int i) { return static_cast<std::size_t>(i); }
using num = GiNaC::numeric;

const emitted_function& find(const std::vector<emitted_function>& fs, const std::string& name) {
  for (const auto& f : fs)
    if (f.name == name) return f;
  throw std::logic_error("verify: no function " + name);
}

struct exact_matrix {
  int rows, cols;
  std::vector<num> v;
  num& operator()(int i, int j) { return v[u(i * cols + j)]; }
  const num& operator()(int i, int j) const { return v[u(i * cols + j)]; }
};

exact_matrix multiply(const exact_matrix& a, const exact_matrix& b) {
  exact_matrix c{a.rows, b.cols, std::vector<num>(u(a.rows * b.cols), 0)};
  for (int i = 0; i < a.rows; ++i)
    for (int k = 0; k < a.cols; ++k)
      for (int j = 0; j < b.cols; ++j) c(i, j) += a(i, k) * b(k, j);
  return c;
}

class checker {
 public:
  explicit checker(std::ostream& report) : m_report(report) {}
  void equal(const std::string& what, const num& got, const num& want) {
    ++m_checks;
    if (got == want) return;
    if (m_failures++ < 10)
      fmt::print(m_report, "  MISMATCH {}: emitted {} != derived {}\n", what, got.to_double(),
                 want.to_double());
  }
  int checks() const { return m_checks; }
  int failures() const { return m_failures; }

 private:
  std::ostream& m_report;
  int m_checks = 0, m_failures = 0;
};

num random_rational(std::mt19937_64& rng, int lo_num, int hi_num, int den) {
  std::uniform_int_distribution<int> dist(lo_num, hi_num);
  return num(dist(rng), den);
}

// A random exact point: angles at rational points of the unit circle, rational parameters,
// momenta and inputs.
expr_graph::exact_inputs random_inputs(const chain_symbols& sym, std::mt19937_64& rng) {
  expr_graph::exact_inputs in;
  const bool joints = has_joint_forces(sym.kind);
  for (int i = 0; i < sym.n; ++i) {
    // (s, c) = (2t, 1 − t²)/(1 + t²) lies exactly on the unit circle.
    const num t = random_rational(rng, -40, 40, 13);
    in.sin_phi.push_back(2 * t / (1 + t * t));
    in.cos_phi.push_back((1 - t * t) / (1 + t * t));
    in.mass.push_back(random_rational(rng, 4, 30, 7));
    in.length.push_back(random_rational(rng, 4, 30, 11));
    in.p.push_back(random_rational(rng, -30, 30, 9));
    if (has_rigid_links(sym.kind)) {
      in.com.push_back(random_rational(rng, 1, 40, 17));
      in.inertia.push_back(random_rational(rng, 0, 30, 19));
    }
    if (joints) {
      // φ itself (the springs read it) independent of (s, c): see exact_inputs.
      in.phi.push_back(random_rational(rng, -40, 40, 9));
      in.stiffness.push_back(random_rational(rng, 0, 30, 7));
      in.rest_angle.push_back(random_rational(rng, -20, 20, 11));
      in.damping.push_back(random_rational(rng, 0, 30, 13));
      in.torque.push_back(random_rational(rng, -30, 30, 7));
    }
  }
  if (has_pivot_drive(sym.kind))
    in.drive = {random_rational(rng, -50, 50, 7), random_rational(rng, -50, 50, 7)};
  if (on_cart(sym.kind)) {
    in.cart_position = random_rational(rng, -40, 40, 9);
    in.cart_momentum = random_rational(rng, -30, 30, 9);
    in.cart_mass = random_rational(rng, 4, 30, 7);
    in.cart_damping = random_rational(rng, 0, 30, 13);
    in.cart_force = random_rational(rng, -30, 30, 7);
  }
  in.gravity = num(981, 100);
  // The general path's graphs hold φ̇ input nodes that nothing reads (the computed φ̇
  // replaces them); evaluate() visits every node, so they need a value.
  in.dphi.assign(u(sym.n), 0);
  return in;
}

// The momenta of the coordinates q (the cart's first on a cart).
std::vector<num> coordinate_momenta(const chain_symbols& sym, const expr_graph::exact_inputs& in) {
  std::vector<num> p;
  if (on_cart(sym.kind)) p.push_back(in.cart_momentum);
  p.insert(p.end(), in.p.begin(), in.p.end());
  return p;
}

// Sets the rate inputs of the graphs from the coordinates' rates dq.
void set_rates(const chain_symbols& sym, const std::vector<num>& dq, expr_graph::exact_inputs& in) {
  const std::size_t first = on_cart(sym.kind) ? 1 : 0;
  if (first) in.cart_velocity = dq[0];
  in.dphi.assign(dq.begin() + static_cast<std::ptrdiff_t>(first), dq.end());
}

// Adds 1 to input j of the layout's w (chain_functions.hpp, input_symbols).
void shift_input(const chain_symbols& sym, int j, expr_graph::exact_inputs& in) {
  const int first_torque = has_pivot_drive(sym.kind) ? 2 : on_cart(sym.kind) ? 1 : 0;
  if (j >= first_torque)
    in.torque[u(j - first_torque)] += 1;
  else if (on_cart(sym.kind))
    in.cart_force += 1;
  else
    in.drive[u(j)] += 1;
}

// The value of every variable of `space` at the point (rates dq; accelerations left 0).
std::vector<num> variable_values(const polynomial_space& space, const chain_symbols& sym,
                                 const expr_graph::exact_inputs& in, const std::vector<num>& dq) {
  const int n = sym.n;
  const std::size_t first = on_cart(sym.kind) ? 1 : 0;
  std::vector<num> values(u(space.count()), 0);
  for (int id = 0; id < space.count(); ++id) {
    const variable& v = space.var(id);
    const auto k = u(v.index);
    num& value = values[u(id)];
    switch (v.kind) {
      case var_kind::mu:
        for (int j = v.index; j < n; ++j) value += in.mass[u(j)];
        break;
      case var_kind::length:
        value = in.length[k];
        break;
      case var_kind::gravity:
        value = in.gravity;
        break;
      case var_kind::sin:
        value = in.sin_phi[k];
        break;
      case var_kind::cos:
        value = in.cos_phi[k];
        break;
      case var_kind::dphi:
        value = dq[first + k];
        break;
      case var_kind::p:
        value = in.p[k];
        break;
      case var_kind::ddphi:
      case var_kind::cart_acceleration:
        break;
      case var_kind::com:
        value = in.com[k];
        break;
      case var_kind::inertia:
        value = in.inertia[k];
        break;
      case var_kind::angle:
        value = in.phi[k];
        break;
      case var_kind::stiffness:
        value = in.stiffness[k];
        break;
      case var_kind::rest_angle:
        value = in.rest_angle[k];
        break;
      case var_kind::damping:
        value = in.damping[k];
        break;
      case var_kind::drive:
        value = in.drive[k];
        break;
      case var_kind::torque:
        value = in.torque[k];
        break;
      case var_kind::cart_position:
        value = in.cart_position;
        break;
      case var_kind::cart_velocity:
        value = dq[0];
        break;
      case var_kind::cart_momentum:
        value = in.cart_momentum;
        break;
      case var_kind::cart_mass:
        value = in.cart_mass;
        break;
      case var_kind::cart_damping:
        value = in.cart_damping;
        break;
      case var_kind::cart_force:
        value = in.cart_force;
        break;
    }
  }
  return values;
}

// The emitted functions of one chain against its derivation, one identity family per step.
// With N coordinates: ṗ = ∂L/∂q + Q; F = ∂ṗ/∂q̇ at fixed q = L_qq̇ + ∂Q/∂q̇. And Lagrange's
// equations of the second kind with the Rayleigh function and the inputs,
// d/dt ∂L/∂q̇ − ∂L/∂q − Q = 0, linear in q̈: checked with q̈ = d/dt q̇ = (J f)_q from the
// emitted rhs and Jacobian.
class chain_verifier {
 public:
  chain_verifier(const chain_symbols& sym, kinetic_solver solver, std::ostream& report)
      : m_sym(sym),
        m_mech(derive_mechanics(sym)),
        m_space(sym),
        m_functions(build_chain_functions(sym, m_mech, solver)),
        m_n(sym.coords.size()),
        m_check(report) {
    const lagrangian_hessians hess = derive_lagrangian_hessians(sym.coords, m_mech);
    for (int i = 0; i < m_n; ++i) {
      m_rate.push_back(m_space.canonical(m_mech.dL_dphi[u(i)] + m_mech.force[u(i)]));
      m_euler_lagrange.push_back(m_space.canonical(time_derivative(sym, m_mech.momenta[u(i)]) -
                                                   m_mech.dL_dphi[u(i)] - m_mech.force[u(i)]));
      for (int j = 0; j < m_n; ++j) {
        m_a.push_back(m_space.canonical(m_mech.mass_matrix(u(i), u(j))));
        m_lpp.push_back(m_space.canonical(hess.phi_phi(u(i), u(j))));
        m_lpd.push_back(m_space.canonical(hess.phi_dphi(u(i), u(j))));
        m_f.push_back(m_space.canonical(hess.phi_dphi(u(i), u(j)) + hess.force_dphi(u(i), u(j))));
      }
    }
    m_kinetic = m_space.canonical(m_mech.kinetic);
    m_potential = m_space.canonical(m_mech.potential);
  }

  // Every step at one exact point.
  void check_at(const expr_graph::exact_inputs& point) {
    m_in = point;
    m_p = coordinate_momenta(m_sym, m_in);
    m_dq = eval("velocities");
    set_rates(m_sym, m_dq, m_in);
    m_values = variable_values(m_space, m_sym, m_in, m_dq);
    m_A = matrix_of(m_a);
    check_legendre();
    check_mass_matrix();
    m_rhs = eval("rhs");
    check_hamilton();
    check_energy();
    m_jac = eval("jacobian");
    check_jacobian();
    check_euler_lagrange();
    if (has_joint_forces(m_sym.kind)) check_input_matrix();
    check_determinant();
  }

  int checks() const { return m_check.checks(); }
  int failures() const { return m_check.failures(); }

 private:
  std::vector<num> eval(const std::string& name) const { return eval(name, m_in); }
  std::vector<num> eval(const std::string& name, const expr_graph::exact_inputs& in) const {
    const auto& f = find(m_functions, name);
    return f.graph->evaluate(f.outputs, in);
  }
  exact_matrix matrix_of(const std::vector<polynomial>& polys) const {
    exact_matrix m{m_n, m_n, {}};
    for (const auto& poly : polys) m.v.push_back(evaluate(poly, m_values));
    return m;
  }

  // The Legendre transform both ways: A q̇ = p and momenta(q̇) = p.
  void check_legendre() {
    const auto p_emitted = eval("momenta");
    for (int i = 0; i < m_n; ++i) {
      num ap = 0;
      for (int j = 0; j < m_n; ++j) ap += m_A(i, j) * m_dq[u(j)];
      m_check.equal(fmt::format("(A dq)_{}", i + 1), ap, m_p[u(i)]);
      m_check.equal(fmt::format("momenta_{}", i + 1), p_emitted[u(i)], m_p[u(i)]);
    }
  }

  // The emitted mass matrix is the derived A, and symmetric.
  void check_mass_matrix() {
    const auto a = eval("mass_matrix");
    for (int i = 0; i < m_n; ++i)
      for (int j = 0; j < m_n; ++j) {
        m_check.equal(fmt::format("mass_matrix_{}{}", i + 1, j + 1), a[u(i * m_n + j)], m_A(i, j));
        m_check.equal(fmt::format("mass_matrix_{}{} = _{}{}", i + 1, j + 1, j + 1, i + 1),
                      a[u(i * m_n + j)], a[u(j * m_n + i)]);
      }
  }

  // Hamilton's equations against the Lagrangian: ṗ = ∂L/∂q + Q at q̇ = A⁻¹p.
  void check_hamilton() {
    for (int i = 0; i < m_n; ++i) {
      m_check.equal(fmt::format("rhs dq_{}", i + 1), m_rhs[u(i)], m_dq[u(i)]);
      m_check.equal(fmt::format("rhs dp_{}", i + 1), m_rhs[u(m_n + i)],
                    evaluate(m_rate[u(i)], m_values));
    }
  }

  // H = T + V (and the closed form of small point-mass and rigid chains).
  void check_energy() {
    const num energy = evaluate(m_kinetic, m_values) + evaluate(m_potential, m_values);
    m_check.equal("hamiltonian = T + V", eval("hamiltonian").at(0), energy);
    if (m_sym.n <= closed_form_max_links && !has_joint_forces(m_sym.kind))
      m_check.equal("closed-form hamiltonian", eval("hamiltonian_closed_form").at(0), energy);
  }

  // The Jacobian by implicit differentiation of p = ∂L/∂q̇(q, q̇) and ṗ = ∂L/∂q(q, q̇) + Q.
  void check_jacobian() {
    const int n = m_n, dim = 2 * n;
    exact_matrix B{n, n, {}}, W{n, n, {}}, C{n, n, {}}, D{n, n, {}};
    for (int i = 0; i < n; ++i)
      for (int k = 0; k < n; ++k) {
        B.v.push_back(m_jac[u(i * dim + k)]);
        W.v.push_back(m_jac[u(i * dim + n + k)]);
        C.v.push_back(m_jac[u((n + i) * dim + k)]);
        D.v.push_back(m_jac[u((n + i) * dim + n + k)]);
      }
    const exact_matrix Lpp = matrix_of(m_lpp), Lpd = matrix_of(m_lpd), F = matrix_of(m_f);
    const exact_matrix AW = multiply(m_A, W), AB = multiply(m_A, B), FB = multiply(F, B),
                       FW = multiply(F, W);
    for (int i = 0; i < n; ++i)
      for (int k = 0; k < n; ++k) {
        m_check.equal(fmt::format("(A dq'/dp)_{}{}", i + 1, k + 1), AW(i, k), num(i == k ? 1 : 0));
        m_check.equal(fmt::format("(A dq'/dq)_{}{}", i + 1, k + 1), AB(i, k), -Lpd(k, i));
        m_check.equal(fmt::format("dp'_{}/dq_{}", i + 1, k + 1), C(i, k), Lpp(i, k) + FB(i, k));
        m_check.equal(fmt::format("dp'_{}/dp_{}", i + 1, k + 1), D(i, k), FW(i, k));
      }
  }

  // Lagrange's equations with q̈ from the emitted flow: q̈_i = Σ_j J_ij f_j.
  void check_euler_lagrange() {
    const int dim = 2 * m_n;
    for (int i = 0; i < m_n; ++i) {
      num ddq = 0;
      for (int j = 0; j < dim; ++j) ddq += m_jac[u(i * dim + j)] * m_rhs[u(j)];
      m_values[u(m_space.coordinate_id(var_kind::ddphi, i))] = ddq;
    }
    for (int i = 0; i < m_n; ++i)
      m_check.equal(fmt::format("Euler-Lagrange residual {}", i + 1),
                    evaluate(m_euler_lagrange[u(i)], m_values), 0);
  }

  // f is affine in w: f(w + e_j) − f(w) is column j of df/dw exactly.
  void check_input_matrix() {
    const auto dfdw = eval("input_matrix");
    const int inputs = static_cast<int>(input_symbols(m_sym).size()), dim = 2 * m_n;
    for (int j = 0; j < inputs; ++j) {
      expr_graph::exact_inputs shifted = m_in;
      shift_input(m_sym, j, shifted);
      const auto f1 = eval("rhs", shifted);
      for (int i = 0; i < dim; ++i)
        m_check.equal(fmt::format("df_{}/dw_{}", i + 1, j + 1), dfdw[u(i * inputs + j)],
                      f1[u(i)] - m_rhs[u(i)]);
    }
  }

  // det A by fraction-free elimination of the exact matrix.
  void check_determinant() {
    GiNaC::matrix Am(u(m_n), u(m_n));
    for (int i = 0; i < m_n; ++i)
      for (int j = 0; j < m_n; ++j) Am(u(i), u(j)) = m_A(i, j);
    m_check.equal("det A", eval("det_mass_matrix").at(0),
                  GiNaC::ex_to<num>(Am.determinant(GiNaC::determinant_algo::bareiss)));
  }

  const chain_symbols& m_sym;
  chain_mechanics m_mech;
  polynomial_space m_space;
  std::vector<emitted_function> m_functions;
  int m_n;  ///< the number of coordinates
  checker m_check;
  std::vector<polynomial> m_a, m_rate, m_lpp, m_lpd, m_f, m_euler_lagrange;
  polynomial m_kinetic, m_potential;
  // The point being checked.
  expr_graph::exact_inputs m_in;
  std::vector<num> m_p, m_dq, m_values, m_rhs, m_jac;
  exact_matrix m_A{0, 0, {}};
};

}  // namespace

bool verify_chain(const chain_symbols& sym, int points, std::ostream& report,
                  kinetic_solver solver) {
  chain_verifier verifier(sym, solver, report);
  std::mt19937_64 rng(20261123u + static_cast<unsigned>(sym.n));
  for (int point = 0; point < points; ++point) verifier.check_at(random_inputs(sym, rng));
  const bool ok = verifier.failures() == 0;
  fmt::print(report,
             "npend-gen --verify {} --model {} --solver {}: {} exact identities at {} rational "
             "points: {}\n",
             sym.n, link_kind_name(sym.kind), solver_name(solver), verifier.checks(), points,
             ok ? "all hold" : fmt::format("{} FAILED", verifier.failures()));
  return ok;
}

}  // namespace npend::gen
