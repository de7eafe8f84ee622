// The rigid-link chain the generator derives (link k: mass m_k at its centre of mass c_k down
// the link, moment of inertia J_k about it) against rigid-body mechanics written out by hand:
// the compound pendulum, the two-link mass matrix and potential, and the point-mass limit
// c = l, J = 0.
#include <doctest/doctest.h>

#include <vector>

#include "chain_model.hpp"
#include "polynomial.hpp"

using namespace npend::gen;
using GiNaC::numeric;

namespace {

// Exact values of every variable of `space` at angles (s_k, c_k) on the unit circle, with
// masses m (through μ), lengths l, c, J and g given.
struct point {
  std::vector<numeric> s, c, m, l, com, inertia;
  numeric g = numeric(981, 100);
};

std::vector<numeric> values_at(const polynomial_space& space, const point& x) {
  std::vector<numeric> v(static_cast<std::size_t>(space.count()), 0);
  for (int id = 0; id < space.count(); ++id) {
    const variable& var = space.var(id);
    const auto k = static_cast<std::size_t>(var.index);
    numeric& out = v[static_cast<std::size_t>(id)];
    switch (var.kind) {
      case var_kind::mu:
        for (std::size_t j = k; j < x.m.size(); ++j) out += x.m[j];
        break;
      case var_kind::length:
        out = x.l[k];
        break;
      case var_kind::gravity:
        out = x.g;
        break;
      case var_kind::sin:
        out = x.s[k];
        break;
      case var_kind::cos:
        out = x.c[k];
        break;
      case var_kind::com:
        out = x.com[k];
        break;
      case var_kind::inertia:
        out = x.inertia[k];
        break;
      default:
        break;
    }
  }
  return v;
}

numeric value(const polynomial_space& space, const GiNaC::ex& e, const point& x) {
  return evaluate(space.canonical(e), values_at(space, x));
}

}  // namespace

TEST_CASE("rigid links: the compound pendulum's inertia J + m c^2 and stiffness m g c") {
  const chain_symbols sym(1, link_kind::rigid);
  const chain_mechanics mech = derive_mechanics(sym);
  const polynomial_space space(sym);
  point x{{numeric(3, 5)}, {numeric(4, 5)},  {numeric(3, 2)},
          {numeric(2)},    {numeric(7, 10)}, {numeric(1, 4)}};
  const numeric m = x.m[0], c = x.com[0], J = x.inertia[0];
  CHECK(value(space, mech.mass_matrix(0, 0), x) == J + m * c * c);
  // At the hanging position the potential's curvature is m g c: ω² = m g c / (J + m c²).
  point rest = x;
  rest.s = {0};
  rest.c = {1};
  CHECK(value(space, mech.hess_potential(0, 0), rest) == m * x.g * c);
  CHECK(value(space, mech.potential, rest) == 0);
  // V = m g c (1 − cos φ) anywhere.
  CHECK(value(space, mech.potential, x) == m * x.g * c * (1 - x.c[0]));
}

TEST_CASE("rigid links: the two-link mass matrix and potential of rigid-body mechanics") {
  const chain_symbols sym(2, link_kind::rigid);
  const chain_mechanics mech = derive_mechanics(sym);
  const polynomial_space space(sym);
  const point x{{numeric(3, 5), numeric(-5, 13)}, {numeric(4, 5), numeric(12, 13)},
                {numeric(3, 2), numeric(5, 7)},   {numeric(2), numeric(6, 5)},
                {numeric(9, 10), numeric(2, 3)},  {numeric(1, 4), numeric(2, 9)}};
  const auto& [s, c, m, l, com, J, g] = x;
  // Link 1 turns about the pivot carrying link 2's joint at l_1; link 2's centre moves with
  // the joint and turns about it (König): A₁₁ = J₁ + m₁c₁² + m₂l₁², A₁₂ = m₂ l₁ c₂ cos(φ₁ − φ₂),
  // A₂₂ = J₂ + m₂c₂².
  const numeric cos12 = c[0] * c[1] + s[0] * s[1];
  CHECK(value(space, mech.mass_matrix(0, 0), x) ==
        J[0] + m[0] * com[0] * com[0] + m[1] * l[0] * l[0]);
  CHECK(value(space, mech.mass_matrix(0, 1), x) == m[1] * l[0] * com[1] * cos12);
  CHECK(value(space, mech.mass_matrix(1, 0), x) == m[1] * l[0] * com[1] * cos12);
  CHECK(value(space, mech.mass_matrix(1, 1), x) == J[1] + m[1] * com[1] * com[1]);
  // V = g [m₁c₁(1 − cos φ₁) + m₂(l₁(1 − cos φ₁) + c₂(1 − cos φ₂))].
  CHECK(value(space, mech.potential, x) ==
        g * (m[0] * com[0] * (1 - c[0]) + m[1] * (l[0] * (1 - c[0]) + com[1] * (1 - c[1]))));
}

TEST_CASE("rigid links: c = l and J = 0 are the point masses of the paper") {
  const chain_symbols rigid(3, link_kind::rigid), points(3);
  const chain_mechanics a = derive_mechanics(rigid), b = derive_mechanics(points);
  const polynomial_space ra(rigid), pb(points);
  point x{{numeric(3, 5), numeric(-5, 13), numeric(8, 17)},
          {numeric(4, 5), numeric(12, 13), numeric(-15, 17)},
          {numeric(3, 2), numeric(5, 7), numeric(2)},
          {numeric(2), numeric(6, 5), numeric(1, 3)},
          {},
          {numeric(0), numeric(0), numeric(0)}};
  x.com = x.l;
  for (std::size_t i = 0; i < 3; ++i) {
    for (std::size_t j = 0; j < 3; ++j)
      CHECK(value(ra, a.mass_matrix(i, j), x) == value(pb, b.mass_matrix(i, j), x));
    CHECK(value(ra, a.grad_potential[i], x) == value(pb, b.grad_potential[i], x));
  }
  CHECK(value(ra, a.potential, x) == value(pb, b.potential, x));
}
