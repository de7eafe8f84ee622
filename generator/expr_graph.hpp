// A hash-consed expression DAG (a straight-line program) for the emitted kernels.
//
// Every value the generator wants in C++ is a node here. Identical subexpressions are
// stored once (common-subexpression elimination by construction), commutative operands
// are ordered by node id, and constants are exact rationals, folded as they are built.
// Node ids follow construction order, and construction is deterministic, so the emitted
// text is too — unlike GiNaC's own printing, whose term order depends on addresses.
#pragma once

#include <ginac/ginac.h>

#include <cstdint>
#include <map>
#include <string>
#include <tuple>
#include <vector>

namespace npend::gen {

enum class op : std::uint8_t { constant, input, neg, add, sub, mul, div, sin, cos };

/// What an input node stands for; the emitter maps each to an argument array. drive (index 0
/// a_x, 1 a_y) and torque are the time-dependent inputs of physical chains. local is an input
/// of one link's step of a loop kernel (loop_kernels.hpp): a value its caller names. tangent
/// (index 0..2n-1) is a tangent vector w of the state, the direction of a batch kernel's
/// Jacobian–vector product (emit_batch.hpp). The cart_ inputs are those of a chain on a cart:
/// its position x, rate ẋ, momentum p_x, mass M, damping b_x and the force F on it.
enum class input_kind : std::uint8_t {
  phi,
  dphi,
  p,
  mass,
  length,
  gravity,
  com,
  inertia,
  stiffness,
  rest_angle,
  damping,
  drive,
  torque,
  local,
  tangent,
  cart_position,
  cart_velocity,
  cart_momentum,
  cart_mass,
  cart_damping,
  cart_force
};

struct node {
  op kind = op::constant;
  int lhs = -1;  ///< first operand (unary ops use lhs only)
  int rhs = -1;
  input_kind input = input_kind::phi;
  int index = 0;         ///< 0-based link index of an input
  GiNaC::numeric value;  ///< exact value of a constant
};

class expr_graph;

/// A symbolic scalar: a handle to a node, with the arithmetic operators of a double.
struct sx {
  expr_graph* graph = nullptr;
  int id = -1;
};

class expr_graph {
 public:
  sx constant(const GiNaC::numeric& value);
  sx input(input_kind kind, int index = 0);

  sx neg(sx a);
  sx add(sx a, sx b);
  sx sub(sx a, sx b);
  sx mul(sx a, sx b);
  sx div(sx a, sx b);
  sx sin(sx a);
  sx cos(sx a);

  const node& at(int id) const { return m_nodes.at(static_cast<std::size_t>(id)); }
  int size() const { return static_cast<int>(m_nodes.size()); }

  bool is_constant(sx a, const GiNaC::numeric& value) const;
  bool is_constant(sx a) const { return at(a.id).kind == op::constant; }

  /// Exact value of a node, given exact values for the inputs and for the sin/cos of each
  /// angle (the verifier evaluates at rational points of the unit circle). An angle read
  /// other than through sin/cos (a spring's θ) takes its value from `phi`; without one such
  /// a read is an error. (sin/cos never see `phi`: a rational angle has no rational sine,
  /// and the identities checked hold for independent values of both.)
  struct exact_inputs {
    std::vector<GiNaC::numeric> sin_phi, cos_phi, dphi, p, mass, length;
    std::vector<GiNaC::numeric> com, inertia;  ///< of rigid links
    std::vector<GiNaC::numeric> phi, stiffness, rest_angle, damping, drive, torque;  ///< physical
    std::vector<GiNaC::numeric> local;    ///< the inputs of a loop kernel's step
    std::vector<GiNaC::numeric> tangent;  ///< w of a Jacobian–vector product
    GiNaC::numeric gravity;
    /// x, ẋ, p_x, M, b_x and F of a chain on a cart.
    GiNaC::numeric cart_position, cart_velocity, cart_momentum, cart_mass, cart_damping, cart_force;
  };
  std::vector<GiNaC::numeric> evaluate(const std::vector<sx>& outputs,
                                       const exact_inputs& in) const;

 private:
  using key = std::tuple<op, int, int, input_kind, int, std::string>;
  sx intern(node n);
  std::vector<node> m_nodes;
  std::map<key, int> m_index;
};

sx operator-(sx a);
sx operator+(sx a, sx b);
sx operator-(sx a, sx b);
sx operator*(sx a, sx b);
sx operator/(sx a, sx b);
sx operator*(long k, sx a);
sx operator+(sx a, long k);
sx sin(sx a);
sx cos(sx a);

}  // namespace npend::gen
