#include "expr_graph.hpp"

#include <stdexcept>
#include <utility>

namespace npend::gen {

namespace {

std::string numeric_key(const GiNaC::numeric& v) {
  std::ostringstream out;
  out << v;  // exact rational text: a numeric prints canonically, unlike a sum
  return out.str();
}

bool is_power_of_two(const GiNaC::numeric& v) {
  if (!v.is_rational() || v.is_zero()) return false;
  const auto check = [](const GiNaC::numeric& k) {
    GiNaC::numeric x = GiNaC::abs(k);
    if (!x.is_integer()) return false;
    while (x > 1) {
      if (!GiNaC::irem(x, 2).is_zero()) return false;
      x = x / 2;
    }
    return x == 1;
  };
  return check(v.numer()) && check(v.denom());
}

}  // namespace

sx expr_graph::intern(node n) {
  key k{n.kind,  n.lhs,   n.rhs,
        n.input, n.index, n.kind == op::constant ? numeric_key(n.value) : std::string{}};
  if (auto it = m_index.find(k); it != m_index.end()) return {this, it->second};
  m_nodes.push_back(std::move(n));
  const int id = static_cast<int>(m_nodes.size()) - 1;
  m_index.emplace(std::move(k), id);
  return {this, id};
}

sx expr_graph::constant(const GiNaC::numeric& value) {
  if (!value.is_rational()) throw std::logic_error("expr_graph: constants must be rational");
  node n;
  n.kind = op::constant;
  n.value = value;
  return intern(std::move(n));
}

sx expr_graph::input(input_kind kind, int index) {
  node n;
  n.kind = op::input;
  n.input = kind;
  n.index = index;
  return intern(std::move(n));
}

bool expr_graph::is_constant(sx a, const GiNaC::numeric& value) const {
  const node& n = at(a.id);
  return n.kind == op::constant && n.value == value;
}

sx expr_graph::neg(sx a) {
  const node& n = at(a.id);
  if (n.kind == op::constant) return constant(-n.value);
  if (n.kind == op::neg) return {this, n.lhs};
  if (n.kind == op::sub) return sub({this, n.rhs}, {this, n.lhs});
  return intern(node{op::neg, a.id});
}

sx expr_graph::add(sx a, sx b) {
  if (is_constant(a) && is_constant(b)) return constant(at(a.id).value + at(b.id).value);
  if (is_constant(a, 0)) return b;
  if (is_constant(b, 0)) return a;
  if (at(b.id).kind == op::neg) return sub(a, {this, at(b.id).lhs});
  if (at(a.id).kind == op::neg) return sub(b, {this, at(a.id).lhs});
  if (a.id > b.id) std::swap(a, b);
  return intern(node{op::add, a.id, b.id});
}

sx expr_graph::sub(sx a, sx b) {
  if (is_constant(a) && is_constant(b)) return constant(at(a.id).value - at(b.id).value);
  if (is_constant(b, 0)) return a;
  if (is_constant(a, 0)) return neg(b);
  if (a.id == b.id) return constant(0);
  if (at(b.id).kind == op::neg) return add(a, {this, at(b.id).lhs});
  return intern(node{op::sub, a.id, b.id});
}

sx expr_graph::mul(sx a, sx b) {
  if (is_constant(a) && is_constant(b)) return constant(at(a.id).value * at(b.id).value);
  if (is_constant(a, 0) || is_constant(b, 0)) return constant(0);
  if (is_constant(a, 1)) return b;
  if (is_constant(b, 1)) return a;
  if (is_constant(a, -1)) return neg(b);
  if (is_constant(b, -1)) return neg(a);
  // Pull signs out of products so that x*(-y) and (-x)*y share the node x*y.
  if (at(a.id).kind == op::neg) return neg(mul({this, at(a.id).lhs}, b));
  if (at(b.id).kind == op::neg) return neg(mul(a, {this, at(b.id).lhs}));
  if (is_constant(a) && at(a.id).value < 0) return neg(mul(constant(-at(a.id).value), b));
  if (is_constant(b) && at(b.id).value < 0) return neg(mul(a, constant(-at(b.id).value)));
  if (a.id > b.id) std::swap(a, b);
  return intern(node{op::mul, a.id, b.id});
}

sx expr_graph::div(sx a, sx b) {
  if (is_constant(b, 0)) throw std::logic_error("expr_graph: division by the constant 0");
  if (is_constant(a) && is_constant(b)) return constant(at(a.id).value / at(b.id).value);
  if (is_constant(a, 0)) return constant(0);
  if (is_constant(b, 1)) return a;
  // Division by a power of two is exact as a product; other constants stay divisions so
  // that the rounding is the one a reader of the formula expects.
  if (is_constant(b) && is_power_of_two(at(b.id).value))
    return mul(a, constant(GiNaC::numeric(1) / at(b.id).value));
  // a / (1 / x) = a * x: the first pivot of a tridiagonal solve is often a reciprocal.
  if (at(b.id).kind == op::div && is_constant({this, at(b.id).lhs}, 1))
    return mul(a, {this, at(b.id).rhs});
  if (at(a.id).kind == op::neg) return neg(div({this, at(a.id).lhs}, b));
  if (at(b.id).kind == op::neg) return neg(div(a, {this, at(b.id).lhs}));
  return intern(node{op::div, a.id, b.id});
}

sx expr_graph::sin(sx a) {
  if (is_constant(a, 0)) return constant(0);
  return intern(node{op::sin, a.id});
}

sx expr_graph::cos(sx a) {
  if (is_constant(a, 0)) return constant(1);
  return intern(node{op::cos, a.id});
}

std::vector<GiNaC::numeric> expr_graph::evaluate(const std::vector<sx>& outputs,
                                                 const exact_inputs& in) const {
  // Nodes are created after their operands, so one pass in id order suffices.
  std::vector<GiNaC::numeric> value(m_nodes.size());
  // An angle itself has no rational value; it may only be read through sin/cos.
  std::vector<bool> angle_dependent(m_nodes.size(), false);
  auto angle_index = [&](int id) {
    const node& a = at(id);
    if (a.kind != op::input || a.input != input_kind::phi)
      throw std::logic_error("evaluate: sin/cos of something other than an angle");
    return static_cast<std::size_t>(a.index);
  };
  for (std::size_t i = 0; i < m_nodes.size(); ++i) {
    const node& n = m_nodes[i];
    const auto L = [&] { return value[static_cast<std::size_t>(n.lhs)]; };
    const auto R = [&] { return value[static_cast<std::size_t>(n.rhs)]; };
    const bool binary =
        n.kind == op::add || n.kind == op::sub || n.kind == op::mul || n.kind == op::div;
    if (n.kind == op::neg || binary)
      angle_dependent[i] = angle_dependent[static_cast<std::size_t>(n.lhs)] ||
                           (binary && angle_dependent[static_cast<std::size_t>(n.rhs)]);
    switch (n.kind) {
      case op::constant:
        value[i] = n.value;
        break;
      case op::input: {
        const auto k = static_cast<std::size_t>(n.index);
        switch (n.input) {
          case input_kind::phi:
            if (k < in.phi.size())
              value[i] = in.phi[k];
            else
              angle_dependent[i] = true;
            break;
          case input_kind::dphi:
            value[i] = in.dphi.at(k);
            break;
          case input_kind::p:
            value[i] = in.p.at(k);
            break;
          case input_kind::mass:
            value[i] = in.mass.at(k);
            break;
          case input_kind::length:
            value[i] = in.length.at(k);
            break;
          case input_kind::gravity:
            value[i] = in.gravity;
            break;
          case input_kind::com:
            value[i] = in.com.at(k);
            break;
          case input_kind::inertia:
            value[i] = in.inertia.at(k);
            break;
          case input_kind::stiffness:
            value[i] = in.stiffness.at(k);
            break;
          case input_kind::rest_angle:
            value[i] = in.rest_angle.at(k);
            break;
          case input_kind::damping:
            value[i] = in.damping.at(k);
            break;
          case input_kind::drive:
            value[i] = in.drive.at(k);
            break;
          case input_kind::torque:
            value[i] = in.torque.at(k);
            break;
          case input_kind::local:
            value[i] = in.local.at(k);
            break;
          case input_kind::tangent:
            value[i] = in.tangent.at(k);
            break;
          case input_kind::cart_position:
            value[i] = in.cart_position;
            break;
          case input_kind::cart_velocity:
            value[i] = in.cart_velocity;
            break;
          case input_kind::cart_momentum:
            value[i] = in.cart_momentum;
            break;
          case input_kind::cart_mass:
            value[i] = in.cart_mass;
            break;
          case input_kind::cart_damping:
            value[i] = in.cart_damping;
            break;
          case input_kind::cart_force:
            value[i] = in.cart_force;
            break;
        }
        break;
      }
      case op::neg:
        value[i] = -L();
        break;
      case op::add:
        value[i] = L() + R();
        break;
      case op::sub:
        value[i] = L() - R();
        break;
      case op::mul:
        value[i] = L() * R();
        break;
      case op::div:
        value[i] = L() / R();
        break;
      case op::sin:
        value[i] = in.sin_phi.at(angle_index(n.lhs));
        break;
      case op::cos:
        value[i] = in.cos_phi.at(angle_index(n.lhs));
        break;
    }
  }
  std::vector<GiNaC::numeric> out;
  out.reserve(outputs.size());
  for (sx o : outputs) {
    if (angle_dependent.at(static_cast<std::size_t>(o.id)))
      throw std::logic_error("evaluate: an output uses an angle outside sin/cos");
    out.push_back(value.at(static_cast<std::size_t>(o.id)));
  }
  return out;
}

sx operator-(sx a) { return a.graph->neg(a); }
sx operator+(sx a, sx b) { return a.graph->add(a, b); }
sx operator-(sx a, sx b) { return a.graph->sub(a, b); }
sx operator*(sx a, sx b) { return a.graph->mul(a, b); }
sx operator/(sx a, sx b) { return a.graph->div(a, b); }
sx operator*(long k, sx a) { return a.graph->mul(a.graph->constant(k), a); }
sx operator+(sx a, long k) { return a.graph->add(a, a.graph->constant(k)); }
sx sin(sx a) { return a.graph->sin(a); }
sx cos(sx a) { return a.graph->cos(a); }

}  // namespace npend::gen
