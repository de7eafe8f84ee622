#include "polynomial.hpp"

#include <algorithm>
#include <stdexcept>

namespace npend::gen {

namespace {

std::size_t u(int i) { return static_cast<std::size_t>(i); }

void multiply_into(monomial& m, int var, int exponent) {
  auto it = std::lower_bound(m.begin(), m.end(), std::make_pair(var, 0));
  if (it != m.end() && it->first == var)
    it->second += exponent;
  else
    m.insert(it, {var, exponent});
}

}  // namespace

polynomial_space::polynomial_space(const chain_symbols& sym) : m_sym(sym) {
  const int n = sym.n;
  auto add = [&](var_kind kind, int index, const GiNaC::realsymbol& s) {
    m_id_by_name.emplace(s.get_name(), count());
    m_vars.push_back({kind, index});
  };
  for (int i = 0; i < n; ++i) add(var_kind::mu, i, sym.mu[u(i)]);
  for (int i = 0; i < n; ++i) add(var_kind::length, i, sym.length[u(i)]);
  add(var_kind::gravity, 0, sym.g);
  for (int i = 0; i < n; ++i) add(var_kind::sin, i, sym.s[u(i)]);
  for (int i = 0; i < n; ++i) add(var_kind::cos, i, sym.c[u(i)]);
  for (int i = 0; i < n; ++i) add(var_kind::dphi, i, sym.dphi[u(i)]);
  for (int i = 0; i < n; ++i) add(var_kind::p, i, sym.p[u(i)]);
  for (int i = 0; i < n; ++i) add(var_kind::ddphi, i, sym.ddphi[u(i)]);
  if (has_rigid_links(sym.kind)) {
    for (int i = 0; i < n; ++i) add(var_kind::com, i, sym.com[u(i)]);
    for (int i = 0; i < n; ++i) add(var_kind::inertia, i, sym.inertia[u(i)]);
  }
  if (has_joint_forces(sym.kind)) {
    for (int i = 0; i < n; ++i) add(var_kind::angle, i, sym.phi[u(i)]);
    for (int i = 0; i < n; ++i) add(var_kind::stiffness, i, sym.stiffness[u(i)]);
    for (int i = 0; i < n; ++i) add(var_kind::rest_angle, i, sym.rest_angle[u(i)]);
    for (int i = 0; i < n; ++i) add(var_kind::damping, i, sym.damping[u(i)]);
    if (has_pivot_drive(sym.kind)) {
      add(var_kind::drive, 0, sym.drive_x);
      add(var_kind::drive, 1, sym.drive_y);
    }
    for (int i = 0; i < n; ++i) add(var_kind::torque, i, sym.torque[u(i)]);
  }
  if (on_cart(sym.kind)) {
    add(var_kind::cart_position, 0, sym.cart_x);
    add(var_kind::cart_velocity, 0, sym.cart_dx);
    add(var_kind::cart_momentum, 0, sym.cart_p);
    add(var_kind::cart_acceleration, 0, sym.cart_ddx);
    add(var_kind::cart_mass, 0, sym.cart_mass);
    add(var_kind::cart_damping, 0, sym.cart_damping);
    add(var_kind::cart_force, 0, sym.cart_force);
  }

  for (int i = 0; i < n; ++i) {
    m_to_variables.append(GiNaC::sin(sym.phi[u(i)]) == sym.s[u(i)]);
    m_to_variables.append(GiNaC::cos(sym.phi[u(i)]) == sym.c[u(i)]);
    const GiNaC::ex below = (i + 1 < n) ? GiNaC::ex(sym.mu[u(i + 1)]) : GiNaC::ex(0);
    m_to_variables.append(sym.mass[u(i)] == sym.mu[u(i)] - below);
    m_reduce.append(GiNaC::pow(sym.s[u(i)], 2) == 1 - GiNaC::pow(sym.c[u(i)], 2));
  }
}

int polynomial_space::id(var_kind kind, int index) const {
  for (std::size_t i = 0; i < m_vars.size(); ++i)
    if (m_vars[i].kind == kind && m_vars[i].index == index) return static_cast<int>(i);
  throw std::out_of_range("polynomial_space: no such variable");
}

int polynomial_space::coordinate_id(var_kind kind, int k) const {
  if (!on_cart(m_sym.kind)) return id(kind, k);
  if (k > 0) return id(kind, k - 1);
  switch (kind) {
    case var_kind::dphi:
      return id(var_kind::cart_velocity);
    case var_kind::p:
      return id(var_kind::cart_momentum);
    case var_kind::ddphi:
      return id(var_kind::cart_acceleration);
    default:
      throw std::out_of_range("polynomial_space: no such coordinate variable");
  }
}

sx coordinate_input(const polynomial_space& space, input_kind kind, int k, expr_graph& graph) {
  if (space.coordinates() == space.links()) return graph.input(kind, k);
  if (k > 0) return graph.input(kind, k - 1);
  if (kind == input_kind::p) return graph.input(input_kind::cart_momentum);
  if (kind == input_kind::dphi) return graph.input(input_kind::cart_velocity);
  throw std::logic_error("coordinate_input: not a rate or momentum");
}

polynomial polynomial_space::canonical(const GiNaC::ex& e) const {
  GiNaC::ex x = e.subs(m_to_variables).expand();
  // algebraic substitution also rewrites s³ = s·s², so the result has s-degree ≤ 1.
  x = x.subs(m_reduce, GiNaC::subs_options::algebraic).expand();

  polynomial poly;
  auto add_term = [&](const GiNaC::ex& term) {
    GiNaC::numeric coeff = 1;
    monomial mono;
    auto factor = [&](const GiNaC::ex& f) {
      if (GiNaC::is_a<GiNaC::numeric>(f)) {
        coeff *= GiNaC::ex_to<GiNaC::numeric>(f);
        return;
      }
      GiNaC::ex base = f;
      int exponent = 1;
      if (GiNaC::is_a<GiNaC::power>(f)) {
        base = f.op(0);
        const GiNaC::ex ex = f.op(1);
        if (!GiNaC::is_a<GiNaC::numeric>(ex) || !GiNaC::ex_to<GiNaC::numeric>(ex).is_pos_integer())
          throw std::invalid_argument("canonical: not a polynomial (negative or fractional power)");
        exponent = GiNaC::ex_to<GiNaC::numeric>(ex).to_int();
      }
      if (!GiNaC::is_a<GiNaC::symbol>(base))
        throw std::invalid_argument("canonical: not a polynomial in the chain's variables");
      const auto it = m_id_by_name.find(GiNaC::ex_to<GiNaC::symbol>(base).get_name());
      if (it == m_id_by_name.end())
        throw std::invalid_argument("canonical: unexpected symbol " +
                                    GiNaC::ex_to<GiNaC::symbol>(base).get_name());
      multiply_into(mono, it->second, exponent);
    };
    if (GiNaC::is_a<GiNaC::mul>(term))
      for (const auto& f : term) factor(f);
    else
      factor(term);
    if (coeff.is_zero()) return;
    auto [it, inserted] = poly.emplace(std::move(mono), coeff);
    if (!inserted) {
      it->second += coeff;
      if (it->second.is_zero()) poly.erase(it);
    }
  };
  if (GiNaC::is_a<GiNaC::add>(x))
    for (const auto& term : x) add_term(term);
  else if (!x.is_zero())
    add_term(x);
  return poly;
}

std::vector<sx> variable_nodes(const polynomial_space& space, expr_graph& graph) {
  const int n = space.links();
  std::vector<sx> nodes(u(space.count()));
  // μ_j = m_j + μ_{j+1}: one addition per link instead of a sum per use.
  std::vector<sx> mu(u(n));
  for (int j = n - 1; j >= 0; --j) {
    const sx m = graph.input(input_kind::mass, j);
    mu[u(j)] = (j == n - 1) ? m : m + mu[u(j + 1)];
  }
  for (int id = 0; id < space.count(); ++id) {
    const variable& v = space.var(id);
    switch (v.kind) {
      case var_kind::mu:
        nodes[u(id)] = mu[u(v.index)];
        break;
      case var_kind::length:
        nodes[u(id)] = graph.input(input_kind::length, v.index);
        break;
      case var_kind::gravity:
        nodes[u(id)] = graph.input(input_kind::gravity);
        break;
      case var_kind::sin:
        nodes[u(id)] = sin(graph.input(input_kind::phi, v.index));
        break;
      case var_kind::cos:
        nodes[u(id)] = cos(graph.input(input_kind::phi, v.index));
        break;
      case var_kind::dphi:
        nodes[u(id)] = graph.input(input_kind::dphi, v.index);
        break;
      case var_kind::p:
        nodes[u(id)] = graph.input(input_kind::p, v.index);
        break;
      case var_kind::ddphi:
        break;  // only printed, never emitted
      case var_kind::com:
        nodes[u(id)] = graph.input(input_kind::com, v.index);
        break;
      case var_kind::inertia:
        nodes[u(id)] = graph.input(input_kind::inertia, v.index);
        break;
      case var_kind::angle:
        nodes[u(id)] = graph.input(input_kind::phi, v.index);
        break;
      case var_kind::stiffness:
        nodes[u(id)] = graph.input(input_kind::stiffness, v.index);
        break;
      case var_kind::rest_angle:
        nodes[u(id)] = graph.input(input_kind::rest_angle, v.index);
        break;
      case var_kind::damping:
        nodes[u(id)] = graph.input(input_kind::damping, v.index);
        break;
      case var_kind::drive:
        nodes[u(id)] = graph.input(input_kind::drive, v.index);
        break;
      case var_kind::torque:
        nodes[u(id)] = graph.input(input_kind::torque, v.index);
        break;
      case var_kind::cart_position:
        nodes[u(id)] = graph.input(input_kind::cart_position);
        break;
      case var_kind::cart_velocity:
        nodes[u(id)] = graph.input(input_kind::cart_velocity);
        break;
      case var_kind::cart_momentum:
        nodes[u(id)] = graph.input(input_kind::cart_momentum);
        break;
      case var_kind::cart_acceleration:
        break;  // only printed, never emitted
      case var_kind::cart_mass:
        nodes[u(id)] = graph.input(input_kind::cart_mass);
        break;
      case var_kind::cart_damping:
        nodes[u(id)] = graph.input(input_kind::cart_damping);
        break;
      case var_kind::cart_force:
        nodes[u(id)] = graph.input(input_kind::cart_force);
        break;
    }
  }
  return nodes;
}

namespace {

using term_list = std::vector<std::pair<monomial, GiNaC::numeric>>;

sx power_node(sx base, int exponent) {
  sx result = base;
  for (int e = 1; e < exponent; ++e) result = result * base;
  return result;
}

sx monomial_node(const monomial& mono, const std::vector<sx>& vars, expr_graph& graph) {
  sx result = graph.constant(1);
  for (const auto& [var, exponent] : mono) {
    const sx v = vars.at(u(var));
    if (v.graph == nullptr) throw std::logic_error("to_graph: variable without a graph node");
    result = result * power_node(v, exponent);
  }
  return result;
}

// The rational "content" of the coefficients (gcd of numerators over lcm of denominators),
// with the sign of the first term, so that ½x + ½y becomes ½(x + y).
GiNaC::numeric content(const term_list& terms) {
  GiNaC::numeric num = 0, den = 1;
  for (const auto& [mono, coeff] : terms) {
    num = GiNaC::gcd(num, coeff.numer());
    den = GiNaC::lcm(den, coeff.denom());
  }
  GiNaC::numeric c = num / den;
  if (terms.front().second < 0) c = -c;
  return c;
}

sx horner(term_list terms, const std::vector<sx>& vars, expr_graph& graph) {
  if (terms.empty()) return graph.constant(0);
  if (terms.size() == 1)
    return graph.constant(terms[0].second) * monomial_node(terms[0].first, vars, graph);

  const GiNaC::numeric factor = content(terms);
  if (factor != 1) {
    for (auto& t : terms) t.second = t.second / factor;
    return graph.constant(factor) * horner(std::move(terms), vars, graph);
  }

  std::map<int, int> occurrences;
  for (const auto& [mono, coeff] : terms)
    for (const auto& [var, exponent] : mono) ++occurrences[var];
  int best = -1, best_count = 1;
  for (const auto& [var, count] : occurrences)
    if (count > best_count) best = var, best_count = count;

  if (best < 0) {  // no variable is shared: a plain sum, in canonical term order
    sx sum = graph.constant(0);
    for (auto& t : terms) sum = sum + horner({t}, vars, graph);
    return sum;
  }
  term_list with, without;
  for (auto& [mono, coeff] : terms) {
    auto it = std::lower_bound(mono.begin(), mono.end(), std::make_pair(best, 0));
    if (it != mono.end() && it->first == best) {
      monomial reduced = mono;
      auto r = reduced.begin() + (it - mono.begin());
      if (--r->second == 0) reduced.erase(r);
      with.emplace_back(std::move(reduced), coeff);
    } else {
      without.emplace_back(mono, coeff);
    }
  }
  std::sort(with.begin(), with.end());
  const sx factored = vars.at(u(best)) * horner(std::move(with), vars, graph);
  return without.empty() ? factored : factored + horner(std::move(without), vars, graph);
}

}  // namespace

sx to_graph(const polynomial& poly, const std::vector<sx>& vars, expr_graph& graph) {
  return horner(term_list(poly.begin(), poly.end()), vars, graph);
}

GiNaC::numeric evaluate(const polynomial& poly, const std::vector<GiNaC::numeric>& values) {
  GiNaC::numeric sum = 0;
  for (const auto& [mono, coeff] : poly) {
    GiNaC::numeric term = coeff;
    for (const auto& [var, exponent] : mono)
      for (int e = 0; e < exponent; ++e) term *= values.at(u(var));
    sum += term;
  }
  return sum;
}

namespace {

using trig_sum = std::map<trig_term, GiNaC::numeric>;

void accumulate(trig_sum& sum, trig_term t, GiNaC::numeric coeff) {
  // Normalise the sign of k: cos(−x) = cos x, sin(−x) = −sin x; sin 0 = 0.
  const auto first = std::find_if(t.k.begin(), t.k.end(), [](int v) { return v != 0; });
  if (first == t.k.end()) {
    if (t.is_sin) return;
  } else if (*first < 0) {
    for (int& v : t.k) v = -v;
    if (t.is_sin) coeff = -coeff;
  }
  auto [it, inserted] = sum.emplace(t, coeff);
  if (!inserted) {
    it->second += coeff;
    if (it->second.is_zero()) sum.erase(it);
  }
}

// Multiplies every term by sin φ_i or cos φ_i with the product-to-sum formulas.
trig_sum times_trig(const trig_sum& in, bool by_sin, int i) {
  trig_sum out;
  for (const auto& [t, coeff] : in) {
    trig_term plus = t, minus = t;
    plus.k[u(i)] += 1;
    minus.k[u(i)] -= 1;
    const GiNaC::numeric half = coeff / 2;
    if (!t.is_sin && !by_sin) {  // cos a cos b = ½[cos(a+b) + cos(a−b)]
      accumulate(out, plus, half);
      accumulate(out, minus, half);
    } else if (!t.is_sin && by_sin) {  // cos a sin b = ½[sin(a+b) − sin(a−b)]
      plus.is_sin = minus.is_sin = true;
      accumulate(out, plus, half);
      accumulate(out, minus, -half);
    } else if (t.is_sin && !by_sin) {  // sin a cos b = ½[sin(a+b) + sin(a−b)]
      accumulate(out, plus, half);
      accumulate(out, minus, half);
    } else {  // sin a sin b = ½[cos(a−b) − cos(a+b)]
      plus.is_sin = minus.is_sin = false;
      accumulate(out, minus, half);
      accumulate(out, plus, -half);
    }
  }
  return out;
}

}  // namespace

trig_polynomial to_trig_form(const polynomial& poly, const polynomial_space& space) {
  trig_polynomial out;
  for (const auto& [mono, coeff] : poly) {
    monomial rest;
    trig_sum trig;
    trig.emplace(trig_term{false, std::vector<int>(u(space.links()), 0)}, 1);
    for (const auto& [var, exponent] : mono) {
      const variable& v = space.var(var);
      if (v.kind == var_kind::sin || v.kind == var_kind::cos) {
        for (int e = 0; e < exponent; ++e)
          trig = times_trig(trig, v.kind == var_kind::sin, v.index);
      } else {
        rest.emplace_back(var, exponent);
      }
    }
    for (const auto& [t, tc] : trig) {
      auto [it, inserted] = out.emplace(std::make_pair(rest, t), coeff * tc);
      if (!inserted) {
        it->second += coeff * tc;
        if (it->second.is_zero()) out.erase(it);
      }
    }
  }
  return out;
}

}  // namespace npend::gen
