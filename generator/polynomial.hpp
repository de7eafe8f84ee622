// Canonical polynomials: the bridge from GiNaC's expressions to deterministic output.
//
// A GiNaC expression of the chain is a polynomial in sin φ_i, cos φ_i, the parameters and
// φ̇ or p. We rewrite it in fixed variables — s_i, c_i for the trigonometric functions, μ_j
// for the masses (m_j = μ_j − μ_{j+1}, which collapses the chain's mass sums), reduce
// s_i² → 1 − c_i² so the form is unique, and store it as a sorted map from monomials to
// exact rational coefficients. From there it goes into the expression graph (by Horner's
// scheme) or, through product-to-sum formulas, into the trigonometric form printed as LaTeX.
#pragma once

#include <ginac/ginac.h>

#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "chain_model.hpp"
#include "expr_graph.hpp"

namespace npend::gen {

/// Variable kinds in their canonical order (ties in Horner's scheme go to the earlier one).
/// (com and inertia, of rigid links only, and the joint and drive variables of physical chains
/// come last so that a point-mass chain's variables and so its emitted code are those of the
/// point-mass derivation. `angle` is φ itself, which the springs bring in. The cart's
/// variables, of chains on a cart only, come after all of them.)
enum class var_kind : std::uint8_t {
  mu,
  length,
  gravity,
  sin,
  cos,
  dphi,
  p,
  ddphi,
  com,
  inertia,
  angle,
  stiffness,
  rest_angle,
  damping,
  drive,
  torque,
  cart_position,
  cart_velocity,
  cart_momentum,
  cart_acceleration,
  cart_mass,
  cart_damping,
  cart_force
};

struct variable {
  var_kind kind;
  int index;  ///< 0-based link index (0 for g; for the drive 0 = a_x, 1 = a_y)
};

/// (variable id, exponent > 0), sorted by id.
using monomial = std::vector<std::pair<int, int>>;
/// Monomial → exact coefficient; std::map keeps a fixed, address-independent order.
using polynomial = std::map<monomial, GiNaC::numeric>;

/// The variables of one chain and the rewriting of GiNaC expressions into polynomials.
class polynomial_space {
 public:
  explicit polynomial_space(const chain_symbols& sym);

  int links() const { return m_sym.n; }
  int count() const { return static_cast<int>(m_vars.size()); }
  const variable& var(int id) const { return m_vars.at(static_cast<std::size_t>(id)); }
  int id(var_kind kind, int index = 0) const;

  /// The number of generalised coordinates (links, plus one on a cart).
  int coordinates() const { return m_sym.coords.size(); }
  /// The variable of coordinate k's rate (dphi), momentum (p) or acceleration (ddphi): the
  /// cart's for k = 0 on a cart, else link k's (k − 1 on a cart).
  int coordinate_id(var_kind kind, int k) const;

  /// The canonical polynomial of e (see the file comment). Throws std::invalid_argument if
  /// e is not a polynomial in those variables (an angle outside sin/cos, a division, ...).
  polynomial canonical(const GiNaC::ex& e) const;

 private:
  const chain_symbols& m_sym;
  std::vector<variable> m_vars;
  std::map<std::string, int> m_id_by_name;
  GiNaC::lst m_to_variables;  ///< sin φ → s, cos φ → c, m → μ differences
  GiNaC::lst m_reduce;        ///< s² → 1 − c²
};

/// Graph nodes standing for each variable of a polynomial_space (μ as suffix sums of the
/// mass inputs, s/c as sin/cos of the angle inputs). φ̈ has no node.
std::vector<sx> variable_nodes(const polynomial_space& space, expr_graph& graph);

/// The input node of coordinate k's momentum (kind p) or rate (kind dphi), numbered as
/// polynomial_space::coordinate_id numbers them.
sx coordinate_input(const polynomial_space& space, input_kind kind, int k, expr_graph& graph);

/// The polynomial as a straight-line program: Horner's scheme, factoring out the variable
/// that occurs in most terms first, so shared factors are computed once.
sx to_graph(const polynomial& poly, const std::vector<sx>& vars, expr_graph& graph);

/// Exact value of a polynomial at exact values of its variables (indexed by variable id).
GiNaC::numeric evaluate(const polynomial& poly, const std::vector<GiNaC::numeric>& values);

/// A trigonometric factor cos(k·φ) or sin(k·φ), k an integer vector with first non-zero
/// entry positive; k = 0 with is_sin = false is the constant 1.
struct trig_term {
  bool is_sin = false;
  std::vector<int> k;
  auto operator<=>(const trig_term&) const = default;
};

/// A polynomial in the non-trigonometric variables times trigonometric factors: the
/// product-to-sum ("Fourier") form used for printing, as the paper writes cos(φ1 − φ2).
using trig_polynomial = std::map<std::pair<monomial, trig_term>, GiNaC::numeric>;

trig_polynomial to_trig_form(const polynomial& poly, const polynomial_space& space);

}  // namespace npend::gen
