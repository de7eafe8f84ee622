// Canonical polynomials: the bridge from GiNaC's expressions (whose printed form is not
// deterministic) to a unique, ordered form — s² reduced to 1 − c², masses as differences
// of the sums μ — and from there to the expression graph and the LaTeX trigonometric form.
#include <doctest/doctest.h>

#include <stdexcept>

#include "polynomial.hpp"

using namespace npend::gen;
using GiNaC::ex;
using GiNaC::numeric;

namespace {

// Values of every variable of `space` (by id): μ, l, g, s, c, φ̇, p, φ̈, with s² + c² = 1.
std::vector<numeric> sample_values(const polynomial_space& space) {
  std::vector<numeric> v(static_cast<std::size_t>(space.count()));
  for (int id = 0; id < space.count(); ++id) {
    const variable& x = space.var(id);
    const int k = x.index + 1;
    switch (x.kind) {
      case var_kind::mu:
        v[static_cast<std::size_t>(id)] = numeric(10 - 3 * x.index);
        break;
      case var_kind::length:
        v[static_cast<std::size_t>(id)] = numeric(k + 1, k);
        break;
      case var_kind::gravity:
        v[static_cast<std::size_t>(id)] = numeric(981, 100);
        break;
      case var_kind::sin:
        v[static_cast<std::size_t>(id)] = k % 2 ? numeric(3, 5) : numeric(5, 13);
        break;
      case var_kind::cos:
        v[static_cast<std::size_t>(id)] = k % 2 ? numeric(-4, 5) : numeric(12, 13);
        break;
      default:
        v[static_cast<std::size_t>(id)] = numeric(k, 7);
        break;
    }
  }
  return v;
}

}  // namespace

TEST_CASE("polynomial_space: sin^2 + cos^2 is the polynomial 1") {
  const chain_symbols sym(2);
  const polynomial_space space(sym);
  const polynomial one = space.canonical(GiNaC::pow(GiNaC::sin(sym.phi[1]), 2) +
                                         GiNaC::pow(GiNaC::cos(sym.phi[1]), 2));
  REQUIRE(one.size() == 1);
  CHECK(one.begin()->first.empty());
  CHECK(one.begin()->second == 1);
}

TEST_CASE("polynomial_space: one expression written two ways has one canonical form") {
  const chain_symbols sym(3);
  const polynomial_space space(sym);
  // cos²φ1 · p1 and (1 − sin²φ1) · p1, factors in another order.
  const ex a = GiNaC::pow(GiNaC::cos(sym.phi[0]), 2) * sym.p[0];
  const ex b = sym.p[0] - sym.p[0] * GiNaC::sin(sym.phi[0]) * GiNaC::sin(sym.phi[0]);
  CHECK(space.canonical(a) == space.canonical(b));
  // The masses as written and as differences of sums: m1 = (m1 + m2 + m3) − (m2 + m3).
  const ex m1 = sym.mass[0] * sym.length[0];
  const ex m1_by_sums =
      (sym.mass[0] + sym.mass[1] + sym.mass[2] - sym.mass[1] - sym.mass[2]) * sym.length[0];
  CHECK(space.canonical(m1) == space.canonical(m1_by_sums));
  // m_1 = μ_1 − μ_2: two monomials.
  CHECK(space.canonical(sym.mass[0]).size() == 2);
}

TEST_CASE("polynomial_space: what is not a polynomial in its variables is refused") {
  const chain_symbols sym(2);
  const polynomial_space space(sym);
  CHECK_THROWS_AS(space.canonical(sym.phi[0] * sym.p[0]), std::invalid_argument);
  CHECK_THROWS_AS(space.canonical(sym.p[0] / sym.mass[1]), std::invalid_argument);
}

TEST_CASE("to_graph: Horner's scheme evaluates to the polynomial's exact value") {
  const chain_symbols sym(2);
  const polynomial_space space(sym);
  const ex e = sym.mass[1] * sym.length[0] * sym.length[1] * GiNaC::cos(sym.phi[0]) *
                   GiNaC::cos(sym.phi[1]) * sym.p[0] * sym.p[1] +
               3 * sym.g * sym.mass[0] * GiNaC::pow(GiNaC::sin(sym.phi[1]), 2) - sym.p[1];
  const polynomial poly = space.canonical(e);
  expr_graph graph;
  const std::vector<sx> vars = variable_nodes(space, graph);
  const sx node = to_graph(poly, vars, graph);
  const std::vector<numeric> values = sample_values(space);
  // The graph's inputs: masses from μ (m_1 = μ_1 − μ_2, m_2 = μ_2), angles by sin/cos.
  expr_graph::exact_inputs in;
  const auto value_of = [&](var_kind kind, int index) {
    return values[static_cast<std::size_t>(space.id(kind, index))];
  };
  in.mass = {value_of(var_kind::mu, 0) - value_of(var_kind::mu, 1), value_of(var_kind::mu, 1)};
  in.length = {value_of(var_kind::length, 0), value_of(var_kind::length, 1)};
  in.gravity = value_of(var_kind::gravity, 0);
  in.sin_phi = {value_of(var_kind::sin, 0), value_of(var_kind::sin, 1)};
  in.cos_phi = {value_of(var_kind::cos, 0), value_of(var_kind::cos, 1)};
  in.p = {value_of(var_kind::p, 0), value_of(var_kind::p, 1)};
  in.dphi = {value_of(var_kind::dphi, 0), value_of(var_kind::dphi, 1)};
  CHECK(graph.evaluate({node}, in).at(0) == evaluate(poly, values));
  // And the same value straight from GiNaC's expression at that point.
  GiNaC::exmap point{{sym.mass[0], in.mass[0]},
                     {sym.mass[1], in.mass[1]},
                     {sym.length[0], in.length[0]},
                     {sym.length[1], in.length[1]},
                     {sym.g, in.gravity},
                     {sym.p[0], in.p[0]},
                     {sym.p[1], in.p[1]},
                     {GiNaC::sin(sym.phi[0]), in.sin_phi[0]},
                     {GiNaC::sin(sym.phi[1]), in.sin_phi[1]},
                     {GiNaC::cos(sym.phi[0]), in.cos_phi[0]},
                     {GiNaC::cos(sym.phi[1]), in.cos_phi[1]}};
  CHECK(GiNaC::ex_to<numeric>(e.subs(point)) == evaluate(poly, values));
}

TEST_CASE("to_trig_form: products of sines and cosines become cosines of angle sums") {
  const chain_symbols sym(2);
  const polynomial_space space(sym);
  // cos φ1 cos φ2 + sin φ1 sin φ2 = cos(φ1 − φ2): one term, k = (1, −1).
  const trig_polynomial t =
      to_trig_form(space.canonical(GiNaC::cos(sym.phi[0]) * GiNaC::cos(sym.phi[1]) +
                                   GiNaC::sin(sym.phi[0]) * GiNaC::sin(sym.phi[1])),
                   space);
  REQUIRE(t.size() == 1);
  const auto& [key, coefficient] = *t.begin();
  CHECK(key.first.empty());
  CHECK_FALSE(key.second.is_sin);
  CHECK(key.second.k == std::vector<int>{1, -1});
  CHECK(coefficient == 1);
}
