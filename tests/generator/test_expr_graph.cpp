// The expression graph the emitted kernels are built in: identical subexpressions stored
// once, commutative operands in a fixed order, exact constant folding, and exact evaluation
// at rational points (what npend-gen --verify relies on).
#include <doctest/doctest.h>

#include <stdexcept>

#include "expr_graph.hpp"

using namespace npend::gen;
using GiNaC::numeric;

TEST_CASE("expr_graph: an expression built twice is one node") {
  expr_graph g;
  const sx m = g.input(input_kind::mass, 0), l = g.input(input_kind::length, 1);
  const sx a = m * l + sin(g.input(input_kind::phi, 2));
  const int size = g.size();
  const sx b = m * l + sin(g.input(input_kind::phi, 2));
  CHECK(a.id == b.id);
  CHECK(g.size() == size);
  // Commutative operands are ordered: l·m and m·l, l + m and m + l are the same node.
  CHECK((l * m).id == (m * l).id);
  CHECK((l + m).id == (m + l).id);
  CHECK((m - l).id != (l - m).id);
}

TEST_CASE("expr_graph: constants fold exactly and identities vanish") {
  expr_graph g;
  const sx x = g.input(input_kind::p, 0);
  const sx third = g.constant(numeric(1, 3));
  CHECK(g.is_constant(third + third + third, 1));  // exact: 1/3 three times is 1
  CHECK((x * g.constant(1)).id == x.id);
  CHECK((x + g.constant(0)).id == x.id);
  CHECK(g.is_constant(x * g.constant(0), 0));
  CHECK(g.is_constant(x - x, 0));
  CHECK((-(-x)).id == x.id);
  CHECK(g.is_constant(cos(g.constant(0)), 1));
  // Signs are pulled out of products: x·(−y) and (−x)·y share the node x·y.
  const sx y = g.input(input_kind::p, 1);
  CHECK((x * (-y)).id == ((-x) * y).id);
  // Division by a power of two becomes an exact product; by 3 it stays a division.
  CHECK(g.at((x / g.constant(4)).id).kind == op::mul);
  CHECK(g.at((x / g.constant(3)).id).kind == op::div);
  CHECK_THROWS_AS(x / g.constant(0), std::logic_error);
  CHECK_THROWS_AS(g.constant(numeric("0.5") * GiNaC::ex_to<numeric>(GiNaC::Pi.evalf())),
                  std::logic_error);
}

TEST_CASE("expr_graph: evaluate is exact at rational points of the unit circle") {
  expr_graph g;
  const sx phi = g.input(input_kind::phi, 0), p = g.input(input_kind::p, 0);
  const sx m = g.input(input_kind::mass, 0), l = g.input(input_kind::length, 0);
  const sx grav = g.input(input_kind::gravity);
  // The single pendulum: φ̇ = p/(m l²), ṗ = −m g l sin φ.
  const sx dphi = p / (m * l * l), dp = -(m * grav * l * sin(phi));
  expr_graph::exact_inputs in;
  in.sin_phi = {numeric(3, 5)};
  in.cos_phi = {numeric(4, 5)};
  in.p = {numeric(-2, 7)};
  in.mass = {numeric(3, 2)};
  in.length = {numeric(5, 4)};
  in.gravity = numeric(981, 100);
  const auto v = g.evaluate({dphi, dp, cos(phi)}, in);
  REQUIRE(v.size() == 3);
  CHECK(v[0] == numeric(-2, 7) / (numeric(3, 2) * numeric(25, 16)));
  CHECK(v[1] == -numeric(3, 2) * numeric(981, 100) * numeric(5, 4) * numeric(3, 5));
  CHECK(v[2] == numeric(4, 5));
  // An angle read outside sin/cos has no rational value.
  CHECK_THROWS_AS(g.evaluate({phi + p}, in), std::logic_error);
}
