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

}  // namespace

bool verify_chain(const chain_symbols& sym, int points, std::ostream& report,
                  kinetic_solver solver) {
  const int n = sym.n;
  const chain_mechanics mech = derive_mechanics(sym);
  const lagrangian_hessians hess = derive_lagrangian_hessians(sym, mech);
  const auto functions = build_chain_functions(sym, mech, solver);
  const polynomial_space space(sym);

  const bool physical = sym.kind == link_kind::physical;
  // ṗ = ∂L/∂φ + Q; F = ∂ṗ/∂φ̇ at fixed φ = L_φφ̇ + ∂Q/∂φ̇. And Lagrange's equations of the
  // second kind with the Rayleigh function and the torques, d/dt ∂L/∂φ̇ − ∂L/∂φ − Q = 0,
  // linear in φ̈: checked with φ̈ = d/dt φ̇ = (J f)_φ from the emitted rhs and Jacobian.
  std::vector<polynomial> a_poly, dl_poly, lpp_poly, lpd_poly, f_poly, el_poly;
  for (int i = 0; i < n; ++i) {
    dl_poly.push_back(space.canonical(mech.dL_dphi[u(i)] + mech.force[u(i)]));
    el_poly.push_back(space.canonical(time_derivative(sym, mech.momenta[u(i)]) -
                                      mech.dL_dphi[u(i)] - mech.force[u(i)]));
    for (int j = 0; j < n; ++j) {
      a_poly.push_back(space.canonical(mech.mass_matrix(u(i), u(j))));
      lpp_poly.push_back(space.canonical(hess.phi_phi(u(i), u(j))));
      lpd_poly.push_back(space.canonical(hess.phi_dphi(u(i), u(j))));
      f_poly.push_back(space.canonical(hess.phi_dphi(u(i), u(j)) + hess.force_dphi(u(i), u(j))));
    }
  }
  const polynomial t_poly = space.canonical(mech.kinetic);
  const polynomial v_poly = space.canonical(mech.potential);

  checker check(report);
  std::mt19937_64 rng(20261123u + static_cast<unsigned>(n));
  for (int point = 0; point < points; ++point) {
    expr_graph::exact_inputs in;
    for (int i = 0; i < n; ++i) {
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
      if (physical) {
        // φ itself (the springs read it) independent of (s, c): see exact_inputs.
        in.phi.push_back(random_rational(rng, -40, 40, 9));
        in.stiffness.push_back(random_rational(rng, 0, 30, 7));
        in.rest_angle.push_back(random_rational(rng, -20, 20, 11));
        in.damping.push_back(random_rational(rng, 0, 30, 13));
        in.torque.push_back(random_rational(rng, -30, 30, 7));
      }
    }
    if (physical) in.drive = {random_rational(rng, -50, 50, 7), random_rational(rng, -50, 50, 7)};
    in.gravity = num(981, 100);
    // The general path's graphs hold φ̇ input nodes that nothing reads (the computed φ̇
    // replaces them); evaluate() visits every node, so they need a value.
    in.dphi.assign(u(n), 0);

    const auto eval = [&](const std::string& name) {
      const auto& f = find(functions, name);
      return f.graph->evaluate(f.outputs, in);
    };
    const auto dphi = eval("velocities");
    in.dphi = dphi;

    std::vector<num> values(u(space.count()), 0);
    for (int id = 0; id < space.count(); ++id) {
      const variable& v = space.var(id);
      const auto k = u(v.index);
      switch (v.kind) {
        case var_kind::mu: {
          num mu = 0;
          for (int j = v.index; j < n; ++j) mu += in.mass[u(j)];
          values[u(id)] = mu;
          break;
        }
        case var_kind::length:
          values[u(id)] = in.length[k];
          break;
        case var_kind::gravity:
          values[u(id)] = in.gravity;
          break;
        case var_kind::sin:
          values[u(id)] = in.sin_phi[k];
          break;
        case var_kind::cos:
          values[u(id)] = in.cos_phi[k];
          break;
        case var_kind::dphi:
          values[u(id)] = dphi[k];
          break;
        case var_kind::p:
          values[u(id)] = in.p[k];
          break;
        case var_kind::ddphi:
          break;
        case var_kind::com:
          values[u(id)] = in.com[k];
          break;
        case var_kind::inertia:
          values[u(id)] = in.inertia[k];
          break;
        case var_kind::angle:
          values[u(id)] = in.phi[k];
          break;
        case var_kind::stiffness:
          values[u(id)] = in.stiffness[k];
          break;
        case var_kind::rest_angle:
          values[u(id)] = in.rest_angle[k];
          break;
        case var_kind::damping:
          values[u(id)] = in.damping[k];
          break;
        case var_kind::drive:
          values[u(id)] = in.drive[k];
          break;
        case var_kind::torque:
          values[u(id)] = in.torque[k];
          break;
      }
    }
    const auto matrix_of = [&](const std::vector<polynomial>& polys) {
      exact_matrix m{n, n, {}};
      for (const auto& poly : polys) m.v.push_back(evaluate(poly, values));
      return m;
    };
    const exact_matrix A = matrix_of(a_poly), Lpp = matrix_of(lpp_poly), Lpd = matrix_of(lpd_poly),
                       F = matrix_of(f_poly);

    // Legendre transform both ways.
    const auto p_emitted = eval("momenta");
    for (int i = 0; i < n; ++i) {
      num ap = 0;
      for (int j = 0; j < n; ++j) ap += A(i, j) * dphi[u(j)];
      check.equal(fmt::format("(A dphi)_{}", i + 1), ap, in.p[u(i)]);
      check.equal(fmt::format("momenta_{}", i + 1), p_emitted[u(i)], in.p[u(i)]);
    }

    // Hamilton's equations against the Lagrangian: p' = ∂L/∂φ at φ̇ = A⁻¹p.
    const auto f = eval("rhs");
    for (int i = 0; i < n; ++i) {
      check.equal(fmt::format("rhs dphi_{}", i + 1), f[u(i)], dphi[u(i)]);
      check.equal(fmt::format("rhs dp_{}", i + 1), f[u(n + i)], evaluate(dl_poly[u(i)], values));
    }
    const num energy = evaluate(t_poly, values) + evaluate(v_poly, values);
    check.equal("hamiltonian = T + V", eval("hamiltonian").at(0), energy);
    if (n <= closed_form_max_links && !physical)
      check.equal("closed-form hamiltonian", eval("hamiltonian_closed_form").at(0), energy);

    // The Jacobian by implicit differentiation of p = ∂L/∂φ̇(φ, φ̇) and ṗ = ∂L/∂φ(φ, φ̇).
    const auto J = eval("jacobian");
    const int dim = 2 * n;
    exact_matrix B{n, n, {}}, W{n, n, {}}, C{n, n, {}}, D{n, n, {}};
    for (int i = 0; i < n; ++i)
      for (int k = 0; k < n; ++k) {
        B.v.push_back(J[u(i * dim + k)]);
        W.v.push_back(J[u(i * dim + n + k)]);
        C.v.push_back(J[u((n + i) * dim + k)]);
        D.v.push_back(J[u((n + i) * dim + n + k)]);
      }
    const exact_matrix AW = multiply(A, W), AB = multiply(A, B), LB = multiply(F, B),
                       LW = multiply(F, W);
    for (int i = 0; i < n; ++i)
      for (int k = 0; k < n; ++k) {
        check.equal(fmt::format("(A dphi'/dp)_{}{}", i + 1, k + 1), AW(i, k), num(i == k ? 1 : 0));
        check.equal(fmt::format("(A dphi'/dphi)_{}{}", i + 1, k + 1), AB(i, k), -Lpd(k, i));
        check.equal(fmt::format("dp'_{}/dphi_{}", i + 1, k + 1), C(i, k), Lpp(i, k) + LB(i, k));
        check.equal(fmt::format("dp'_{}/dp_{}", i + 1, k + 1), D(i, k), LW(i, k));
      }

    // Lagrange's equations with φ̈ from the emitted flow: φ̈_i = Σ_j J_ij f_j.
    for (int i = 0; i < n; ++i) {
      num ddphi = 0;
      for (int j = 0; j < dim; ++j) ddphi += J[u(i * dim + j)] * f[u(j)];
      values[u(space.id(var_kind::ddphi, i))] = ddphi;
    }
    for (int i = 0; i < n; ++i)
      check.equal(fmt::format("Euler-Lagrange residual {}", i + 1), evaluate(el_poly[u(i)], values),
                  0);

    if (physical) {
      // f is affine in w = [a_x, a_y, u]: f(w + e_j) − f(w) is column j of df/dw exactly.
      const auto dfdw = eval("input_matrix");
      const int inputs = n + 2;
      for (int j = 0; j < inputs; ++j) {
        expr_graph::exact_inputs shifted = in;
        if (j < 2)
          shifted.drive[u(j)] += 1;
        else
          shifted.torque[u(j - 2)] += 1;
        const auto& rhs = find(functions, "rhs");
        const auto f1 = rhs.graph->evaluate(rhs.outputs, shifted);
        for (int i = 0; i < dim; ++i)
          check.equal(fmt::format("df_{}/dw_{}", i + 1, j + 1), dfdw[u(i * inputs + j)],
                      f1[u(i)] - f[u(i)]);
      }
    }

    // det A by fraction-free elimination of the exact matrix.
    GiNaC::matrix Am(u(n), u(n));
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) Am(u(i), u(j)) = A(i, j);
    check.equal("det A", eval("det_mass_matrix").at(0),
                GiNaC::ex_to<num>(Am.determinant(GiNaC::determinant_algo::bareiss)));
  }
  const bool ok = check.failures() == 0;
  fmt::print(report,
             "npend-gen --verify {} --model {} --solver {}: {} exact identities at {} rational "
             "points: {}\n",
             n, link_kind_name(sym.kind), solver_name(solver), check.checks(), points,
             ok ? "all hold" : fmt::format("{} FAILED", check.failures()));
  return ok;
}

}  // namespace npend::gen
