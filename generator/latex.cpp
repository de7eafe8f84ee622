#include "latex.hpp"

#include <fmt/format.h>
#include <fmt/ostream.h>

#include <algorithm>
#include <map>
#include <ostream>
#include <sstream>

#include "chain_functions.hpp"
#include "chain_model.hpp"
#include "polynomial.hpp"

namespace npend::gen {

namespace {

std::size_t u(int i) { return static_cast<std::size_t>(i); }

bool is_dynamic(var_kind k) {
  return k == var_kind::dphi || k == var_kind::p || k == var_kind::ddphi ||
         k == var_kind::cart_velocity || k == var_kind::cart_momentum ||
         k == var_kind::cart_acceleration;
}

std::string variable_latex(const variable& v) {
  const int i = v.index + 1;
  switch (v.kind) {
    case var_kind::mu:
      return fmt::format("\\mu_{{{}}}", i);
    case var_kind::length:
      return fmt::format("l_{{{}}}", i);
    case var_kind::gravity:
      return "g";
    case var_kind::sin:
      return fmt::format("\\sin\\varphi_{{{}}}", i);
    case var_kind::cos:
      return fmt::format("\\cos\\varphi_{{{}}}", i);
    case var_kind::dphi:
      return fmt::format("\\dot\\varphi_{{{}}}", i);
    case var_kind::p:
      return fmt::format("p_{{{}}}", i);
    case var_kind::ddphi:
      return fmt::format("\\ddot\\varphi_{{{}}}", i);
    case var_kind::com:
      return fmt::format("c_{{{}}}", i);
    case var_kind::inertia:
      return fmt::format("J_{{{}}}", i);
    case var_kind::angle:
      return fmt::format("\\varphi_{{{}}}", i);
    case var_kind::stiffness:
      return fmt::format("k_{{{}}}", i);
    case var_kind::rest_angle:
      return fmt::format("\\bar\\theta_{{{}}}", i);
    case var_kind::damping:
      return fmt::format("b_{{{}}}", i);
    case var_kind::drive:
      return i == 1 ? "a_x" : "a_y";
    case var_kind::torque:
      return fmt::format("u_{{{}}}", i);
    case var_kind::cart_position:
      return "x";
    case var_kind::cart_velocity:
      return "\\dot x";
    case var_kind::cart_momentum:
      return "p_{x}";
    case var_kind::cart_acceleration:
      return "\\ddot x";
    case var_kind::cart_mass:
      return "M";
    case var_kind::cart_damping:
      return "b_x";
    case var_kind::cart_force:
      return "F";
  }
  return "?";
}

std::string monomial_latex(const monomial& m, const polynomial_space& space) {
  std::string out;
  for (const auto& [var, exponent] : m) {
    if (!out.empty()) out += " ";
    out += variable_latex(space.var(var));
    if (exponent > 1) out += fmt::format("^{{{}}}", exponent);
  }
  return out;
}

std::string angle_latex(const std::vector<int>& k) {
  std::string out;
  for (std::size_t i = 0; i < k.size(); ++i) {
    if (k[i] == 0) continue;
    const int a = k[i] < 0 ? -k[i] : k[i];
    if (!out.empty() || k[i] < 0) out += k[i] < 0 ? " - " : " + ";
    if (a != 1) out += std::to_string(a);
    out += fmt::format("\\varphi_{{{}}}", i + 1);
  }
  return out;
}

std::string trig_latex(const trig_term& t) {
  bool constant = true;
  int nonzero = 0;
  for (int v : t.k) {
    if (v != 0) constant = false;
    if (v != 0) ++nonzero;
  }
  if (constant) return "";
  const std::string angle = angle_latex(t.k);
  // "\sin\varphi_{1}" needs no parentheses; "\sin(2\varphi_{1})" and sums do.
  const bool simple = nonzero == 1 && angle.rfind("\\varphi", 0) == 0;
  const std::string fn = t.is_sin ? "\\sin" : "\\cos";
  return simple ? fn + angle : fn + "(" + angle + ")";
}

std::string integer_text(const GiNaC::numeric& k) {
  std::ostringstream s;
  s << k;
  return s.str();
}

std::string rational_latex(const GiNaC::numeric& q) {
  if (q.is_integer()) return integer_text(q);
  return fmt::format("\\tfrac{{{}}}{{{}}}", integer_text(q.numer()), integer_text(q.denom()));
}

// Σ coeff · monomial, with signs: "a - b + \tfrac{1}{2} c".
std::string sum_latex(const std::vector<std::pair<std::string, GiNaC::numeric>>& terms) {
  std::string out;
  for (const auto& [body, coeff] : terms) {
    const GiNaC::numeric mag = GiNaC::abs(coeff);
    const bool negative = coeff < 0;
    if (out.empty())
      out += negative ? "-" : "";
    else
      out += negative ? " - " : " + ";
    if (body.empty())
      out += rational_latex(mag);
    else
      out += (mag == 1 ? "" : rational_latex(mag) + " ") + body;
  }
  return out.empty() ? "0" : out;
}

// A trig polynomial in the parameters (no dynamic variables): grouped by trigonometric
// factor, each factor's parameter polynomial in parentheses when it has several terms.
std::string coefficient_latex(const std::map<trig_term, polynomial>& by_trig,
                              const polynomial_space& space) {
  std::vector<std::pair<std::string, GiNaC::numeric>> terms;
  for (const auto& [t, poly] : by_trig) {
    const std::string trig = trig_latex(t);
    if (poly.size() == 1) {
      const auto& [mono, coeff] = *poly.begin();
      std::string body = monomial_latex(mono, space);
      if (!trig.empty()) body += (body.empty() ? "" : " ") + trig;
      terms.emplace_back(body, coeff);
    } else {
      // Factor out the monomial common to all terms: l_1^2 l_2^2 (μ_1 − μ_2).
      monomial common = poly.begin()->first;
      for (const auto& [mono, coeff] : poly) {
        monomial kept;
        for (const auto& [v, e] : common)
          for (const auto& [w, f] : mono)
            if (v == w) kept.emplace_back(v, std::min(e, f));
        common = kept;
      }
      std::vector<std::pair<std::string, GiNaC::numeric>> inner;
      for (const auto& [mono, coeff] : poly) {
        monomial rest;
        for (const auto& [v, e] : mono) {
          int left = e;
          for (const auto& [w, f] : common)
            if (v == w) left -= f;
          if (left > 0) rest.emplace_back(v, left);
        }
        inner.emplace_back(monomial_latex(rest, space), coeff);
      }
      std::string prefix = monomial_latex(common, space);
      if (!prefix.empty()) prefix += " ";
      terms.emplace_back(
          prefix + "\\left(" + sum_latex(inner) + "\\right)" + (trig.empty() ? "" : " " + trig), 1);
    }
  }
  std::string out;
  for (const auto& [body, coeff] : terms) {
    std::vector<std::pair<std::string, GiNaC::numeric>> one{{body, coeff}};
    const std::string s = sum_latex(one);
    if (out.empty())
      out = s;
    else
      out += s[0] == '-' ? " - " + s.substr(1) : " + " + s;
  }
  return out.empty() ? "0" : out;
}

// The dynamic-variable monomials (φ̇, p, φ̈) in the order p_1², p_1 p_2, …, p_2², … .
struct dynamic_order {
  const polynomial_space* space;
  bool operator()(const monomial& a, const monomial& b) const {
    std::vector<int> ea(u(space->count()), 0), eb(u(space->count()), 0);
    for (const auto& [v, e] : a) ea[u(v)] = e;
    for (const auto& [v, e] : b) eb[u(v)] = e;
    return ea > eb;
  }
};

// A polynomial printed as Σ_{dynamic monomials} [coefficient] · monomial, one per line.
std::string grouped_latex(const polynomial& poly, const polynomial_space& space,
                          const std::string& line_break = " \\\\\n  &\\quad ") {
  std::map<monomial, std::map<trig_term, polynomial>, dynamic_order> groups(dynamic_order{&space});
  for (const auto& [key, coeff] : to_trig_form(poly, space)) {
    monomial dyn, rest;
    for (const auto& [v, e] : key.first)
      (is_dynamic(space.var(v).kind) ? dyn : rest).emplace_back(v, e);
    groups[dyn][key.second][rest] += coeff;
  }
  std::string out;
  for (const auto& [dyn, by_trig] : groups) {
    std::string coeff = coefficient_latex(by_trig, space);
    const std::string mono = monomial_latex(dyn, space);
    const bool several = by_trig.size() > 1 || by_trig.begin()->second.size() > 1;
    std::string term;
    if (mono.empty())
      term = coeff;
    else if (several)
      term = "\\left[" + coeff + "\\right] " + mono;
    else if (coeff == "1")
      term = mono;
    else if (coeff == "-1")
      term = "-" + mono;
    else
      term = coeff + " " + mono;
    if (out.empty())
      out = term;
    else
      out += line_break + (term[0] == '-' ? "- " + term.substr(1) : "+ " + term);
  }
  return out.empty() ? "0" : out;
}

}  // namespace

void print_latex(const chain_symbols& sym, const chain_mechanics& mech, std::ostream& out) {
  const int n = sym.n, dim = sym.coords.size();
  const polynomial_space space(sym);
  const auto tex = [&](const GiNaC::ex& e) { return grouped_latex(space.canonical(e), space); };

  // Coordinate i's subscript and symbols: φ_{i+1}, or on a cart x for i = 0 and φ_i after.
  const bool cart = on_cart(sym.kind);
  const auto label = [&](int i) {
    return cart ? (i == 0 ? "x" : std::to_string(i)) : std::to_string(i + 1);
  };
  const auto q = [&](int i) {
    return label(i) == "x" ? std::string("x") : fmt::format("\\varphi_{{{}}}", label(i));
  };
  const auto dq = [&](int i) { return "\\dot" + std::string(label(i) == "x" ? " " : "") + q(i); };
  const auto mom = [&](int i) { return fmt::format("p_{{{}}}", label(i)); };

  const bool joints = has_joint_forces(sym.kind);
  if (cart)
    fmt::print(out,
               "% The planar {0}-link pendulum on a cart, derived by `npend-gen --latex {0} "
               "--model cart` (GiNaC).\n"
               "% A cart of mass M at x on a horizontal rail (damping b_x, force F) carries the "
               "pivot of\n"
               "% rigid links (centre of mass c_i down link i, inertia J_i about it) with joint "
               "springs k_i\n"
               "% at rest angles bar theta_i, joint damping b_i (Rayleigh function R) and joint "
               "torques u_i;\n"
               "% angles from the downward vertical, y pointing down, V = 0 at the hanging rest "
               "position;\n"
               "% mu_j = m_j + ... + m_{0}.\n",
               n);
  else if (joints)
    fmt::print(out,
               "% The planar {0}-link pendulum, derived by `npend-gen --latex {0} --model "
               "physical` (GiNaC).\n"
               "% Rigid links (centre of mass c_i down link i, inertia J_i about it), joint "
               "springs k_i\n"
               "% with rest angles bar theta_i, joint damping b_i (Rayleigh function R), joint "
               "torques u_i,\n"
               "% pivot acceleration (a_x, a_y) taken in the pivot's frame; angles from the "
               "downward\n"
               "% vertical, y pointing down, V = 0 at the hanging rest position; mu_j = m_j + "
               "... + m_{0}.\n",
               n);
  else
    fmt::print(out,
               "% The planar {0}-link pendulum, derived by `npend-gen --latex {0}` (GiNaC).\n"
               "% Point masses m_i on massless rods l_i, angles from the downward vertical,\n"
               "% y pointing down, V = 0 at the hanging rest position; mu_j = m_j + ... + "
               "m_{0}.\n",
               n);
  out << "\\begin{align*}\n";
  for (int k = 0; k < n; ++k)
    fmt::print(out, "x_{{{0}}} &= {1}, & y_{{{0}}} &= {2} \\\\\n", k + 1, tex(mech.x[u(k)]),
               tex(mech.y[u(k)]));
  fmt::print(out, "T &= {} \\\\\n", tex(mech.kinetic));
  fmt::print(out, "V &= {} \\\\\n", tex(mech.potential));
  out << "L &= T - V \\\\\n";
  for (int i = 0; i < dim; ++i)
    for (int j = i; j < dim; ++j)
      fmt::print(out, "A_{{{}{}}} &= {} \\\\\n", label(i), label(j),
                 tex(mech.mass_matrix(u(i), u(j))));
  for (int i = 0; i < dim; ++i)
    fmt::print(out, "{} &= \\frac{{\\partial L}}{{\\partial{}}} = {} \\\\\n", mom(i), dq(i),
               tex(mech.momenta[u(i)]));

  if (dim <= closed_form_max_links) {
    const auto closed = derive_closed_form_hamiltonian(sym.coords, mech);
    fmt::print(out, "\\det A &= {} \\\\\n", tex(closed.det));
    fmt::print(out, "H &= \\frac{{1}}{{2\\det A}} \\Big[ {} \\Big] + V \\\\\n",
               tex(closed.numerator));
    for (int i = 0; i < dim; ++i)
      fmt::print(out,
                 "{} &= \\frac{{\\partial H}}{{\\partial {}}} = "
                 "\\frac{{1}}{{\\det A}} \\Big[ {} \\Big] \\\\\n",
                 dq(i), mom(i), tex(closed.numerator.diff(sym.coords.p[u(i)]) / 2));
  } else {
    fmt::print(out,
               "H &= \\tfrac{{1}}{{2}} p^\\top A^{{-1}} p + V, \\qquad \\dot{} = A^{{-1}} p \\\\\n",
               cart ? " q" : "\\varphi");
  }
  for (int i = 0; i < dim; ++i)
    fmt::print(out,
               "\\dot {} &= -\\frac{{\\partial H}}{{\\partial{}}} = "
               "\\frac{{\\partial L}}{{\\partial{}}}\\Big|_{{\\dot{} = A^{{-1}}p}}"
               " = {} \\\\\n",
               mom(i), q(i) == "x" ? " x" : q(i), q(i) == "x" ? " x" : q(i),
               cart ? " q" : "\\varphi", tex(mech.dL_dphi[u(i)]));
  if (joints) {
    fmt::print(out, "R &= {} \\\\\n", tex(mech.rayleigh));
    for (int i = 0; i < dim; ++i)
      fmt::print(out, "Q_{{{}}} &= {} \\qquad (\\dot {} \\mathrel{{+}}= Q_{{{}}}) \\\\\n", label(i),
                 tex(mech.force[u(i)]), mom(i), label(i));
  }
  for (int i = 0; i < dim; ++i) {
    const GiNaC::ex el =
        time_derivative(sym, mech.momenta[u(i)]) - mech.dL_dphi[u(i)] - mech.force[u(i)];
    fmt::print(out,
               "0 &= \\frac{{d}}{{dt}}\\frac{{\\partial L}}{{\\partial{}}} - "
               "\\frac{{\\partial L}}{{\\partial{}}}{} = {}{}\n",
               dq(i), q(i) == "x" ? " x" : q(i), joints ? fmt::format(" - Q_{{{}}}", label(i)) : "",
               tex(el), i + 1 < dim ? " \\\\" : "");
  }
  out << "\\end{align*}\n";
}

}  // namespace npend::gen
