#include "loop_kernels.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <memory>
#include <stdexcept>
#include <utility>

#include "articulated_form.hpp"
#include "forward_diff.hpp"

namespace npend::gen {

namespace {

// One link's step of a loop: a small graph over inputs its caller names (array elements,
// parameters, running sums) and the places its outputs are assigned to.
class loop_step {
 public:
  loop_step() : m_graph(std::make_unique<expr_graph>()) {}

  sx in(std::string text) {
    m_inputs.push_back(std::move(text));
    return m_graph->input(input_kind::local, static_cast<int>(m_inputs.size()) - 1);
  }
  sx constant(const GiNaC::numeric& value) { return m_graph->constant(value); }
  void out(std::string target, sx value) {
    m_targets.push_back(std::move(target));
    m_outputs.push_back(value);
  }

  // Σ_i ∂value/∂input_i · tangent_i for each value: the step's forward-mode derivative, each
  // seed pairing an input with the input that holds its tangent.
  std::vector<sx> tangents(const std::vector<sx>& values,
                           const std::vector<std::pair<sx, sx>>& seeds) {
    std::vector<sx> out(values.size(), constant(0));
    for (const auto& [input, tangent] : seeds) {
      const std::vector<sx> d = directional_derivative(*m_graph, values, input);
      for (std::size_t i = 0; i < values.size(); ++i) out[i] = out[i] + d[i] * tangent;
    }
    return out;
  }

  // d value / d input for each value (0 where a value does not depend on the input).
  std::vector<sx> partials(const std::vector<sx>& values, sx input) {
    return directional_derivative(*m_graph, values, input);
  }
  bool is_zero(sx value) const { return m_graph->is_constant(value, 0); }

  // The step's statements. An output assigned to a name the step also reads (a value carried
  // to the next link) is assigned last, after every output has been computed from the old
  // value.
  std::string emit(const std::string& indent) const {
    const auto leaf = [&](const node& nd) -> std::string {
      if (nd.input != input_kind::local) throw std::logic_error("loop step: a non-local input");
      return m_inputs.at(static_cast<std::size_t>(nd.index));
    };
    const emitted_statements st = emit_statements(*m_graph, m_outputs, leaf, indent);
    std::string text = st.text, carried;
    for (std::size_t i = 0; i < m_outputs.size(); ++i) {
      const bool read = std::find(m_inputs.begin(), m_inputs.end(), m_targets[i]) != m_inputs.end();
      if (!read) {
        text += fmt::format("{}{} = {};\n", indent, m_targets[i], st.outputs[i]);
        continue;
      }
      text += fmt::format("{}const double out{} = {};\n", indent, i, st.outputs[i]);
      carried += fmt::format("{}{} = out{};\n", indent, m_targets[i], i);
    }
    return text + carried;
  }

 private:
  std::unique_ptr<expr_graph> m_graph;
  std::vector<std::string> m_inputs, m_targets;
  std::vector<sx> m_outputs;
};

// The parameters of link k (and g) as the emitted code reads them.
const char* const mass_k = "params[chain_layout::mass_index(n, k)]";
const char* const length_k = "params[chain_layout::length_index(n, k)]";
const char* const gravity = "params[chain_layout::gravity_index(n)]";

// g μ_k l_k t: the gravity moment on the links from k down, times sin φ_k (−∂V/∂φ_k's
// negative) or cos φ_k (∂²V/∂φ_k², and −V's term).
sx gravity_moment(sx g, sx mu, sx l, sx trig) { return g * mu * l * trig; }

std::string loop(const std::string& head, const std::string& body) {
  return fmt::format("  for ({}) {{\n{}  }}\n", head, body);
}
std::string block(const std::string& comment, const std::string& body) {
  return fmt::format("  {{  // {}\n{}  }}\n", comment, body);
}
const char* const in_loop = "    ";

// s_k, c_k of every φ_k (the generated sines_and_cosines).
std::string angle_step() { return "  sines_and_cosines(n, phi, v);\n"; }

// The inputs of link k's elimination step, as the tangent step reads them.
struct elimination_inputs {
  sx mass, C, S, q, q_next, r_next, beta_next;
};
elimination_inputs read_elimination(loop_step& st) {
  return {st.in(mass_k),       st.in("v.cd[k]"),    st.in("v.sd[k]"),      st.in("v.q[k]"),
          st.in("v.q[k + 1]"), st.in("v.r[k + 1]"), st.in("v.beta[k + 1]")};
}
elimination_step eliminate(const elimination_inputs& e) {
  return eliminate_link(e.mass, e.C, e.S, e.q, e.q_next, e.r_next, e.beta_next);
}

// q = p / l: a link's momentum per length, for the link whose length `length` names.
sx momentum_per_length(loop_step& st, sx p, const std::string& length) {
  return p * (st.constant(1) / st.in(length));
}

// Link k's sine and cosine (from sines_and_cosines) and q_k = p_k / l_k, stored.
struct link_angle {
  sx s, c, q;
};
link_angle read_angle(loop_step& st) {
  const link_angle a{st.in("v.s[k]"), st.in("v.c[k]"),
                     momentum_per_length(st, st.in("p[k]"), length_k)};
  st.out("v.q[k]", a.q);
  return a;
}

// Stores link k's elimination (and μ_k) and carries what link k − 1 reads in locals.
void store_elimination(loop_step& st, const link_angle& a, sx mu, const elimination_step& e) {
  st.out("v.mu[k]", mu);
  st.out("v.d[k]", e.d);
  st.out("v.r[k]", e.r);
  st.out("v.gamma[k]", e.gamma);
  st.out("v.a[k]", e.a);
  st.out("v.beta[k]", e.beta);
  st.out("s1", a.s);
  st.out("c1", a.c);
  st.out("q1", a.q);
  st.out("mu1", mu);
  st.out("r1", e.r);
  st.out("beta1", e.beta);
}

// The elimination from the tip: μ_k, d_k, r_k, γ_k, a_k, β_k, with each link's q_k and turn
// C_k, S_k in the same pass. What link k reads of link k + 1 comes from registers (the locals
// s1 .. beta1), not from a store just made, which would lengthen the pass's chain of
// divisions.
std::string elimination_pass() {
  std::string text = angle_step() + "  double s1, c1, q1, mu1, r1, beta1;\n";
  loop_step tip;
  const link_angle ta = read_angle(tip);
  const sx m = tip.in(mass_k);
  store_elimination(tip, ta, m, eliminate_tip(m, ta.q));
  text += block("the tip", "    const int k = n - 1;\n" + tip.emit(in_loop));

  loop_step st;
  const link_angle a = read_angle(st);
  const rod_turn t = turn_between(a.s, a.c, st.in("s1"), st.in("c1"));
  st.out("v.cd[k]", t.C);
  st.out("v.sd[k]", t.S);
  const sx mass = st.in(mass_k);
  const elimination_step e =
      eliminate_link(mass, t.C, t.S, a.q, st.in("q1"), st.in("r1"), st.in("beta1"));
  store_elimination(st, a, mass + st.in("mu1"), e);
  return text + loop("int k = n - 2; k >= 0; --k", st.emit(in_loop));
}

// The inputs of link k's step from the pivot; the suspension's velocity (x, y) comes from
// the locals `vx`, `vy` when `running` (the passes), else from v.x, v.y (the tangent).
struct pivot_inputs {
  sx a, gamma, r, beta, x, y, C, S;
};
pivot_inputs read_pivot(loop_step& st, bool last, bool running = false) {
  pivot_inputs p{st.in("v.a[k]"),
                 st.in("v.gamma[k]"),
                 st.in("v.r[k]"),
                 st.in("v.beta[k]"),
                 st.in(running ? "vx" : "v.x[k]"),
                 st.in(running ? "vy" : "v.y[k]"),
                 {},
                 {}};
  if (!last) {
    p.C = st.in("v.cd[k]");
    p.S = st.in("v.sd[k]");
  }
  return p;
}
pivot_step step_from_pivot(const pivot_inputs& p, bool last) {
  return last ? pivot_link(p.a, p.gamma, p.r, p.beta, p.x, p.y)
              : pivot_link(p.a, p.gamma, p.r, p.beta, p.x, p.y, p.C, p.S);
}

// f_k = φ̇_k = ω_k / l_k and f_{n+k} = ṗ_k = −ω_k U_k − g μ_k l_k sin φ_k from the passes'
// ω, kinetic force and sine (nodes of `st`).
std::pair<sx, sx> hamilton_equations(loop_step& st, sx omega, sx kinetic_force, sx s) {
  const sx l = st.in(length_k);
  const sx dphi = omega * (st.constant(1) / l);
  const sx dp = kinetic_force - gravity_moment(st.in(gravity), st.in("v.mu[k]"), l, s);
  return {dphi, dp};
}

// The pass from the pivot, the suspension's velocity (x, y) carried in locals (vx, vy). With `f`
// empty: w_k, ω_k, the kinetic part of ṗ_k and (x_k, y_k) stored for the later passes; else
// only Hamilton's equations, into f (rhs needs nothing else, and stores nothing else).
std::string pivot_pass(const std::string& f = "") {
  std::string text = "  double vx = 0.0, vy = 0.0;\n";
  if (f.empty()) text += "  v.x[0] = 0.0;\n  v.y[0] = 0.0;\n";
  for (const bool last : {false, true}) {
    loop_step st;
    const pivot_step p = step_from_pivot(read_pivot(st, last, true), last);
    if (f.empty()) {
      st.out("v.w[k]", p.w);
      st.out("v.omega[k]", p.omega);
      st.out("v.force[k]", p.kinetic_force);
    } else {
      const auto [dphi, dp] = hamilton_equations(st, p.omega, p.kinetic_force, st.in("v.s[k]"));
      st.out(f + "[k]", dphi);
      st.out(f + "[n + k]", dp);
    }
    if (!last) {
      if (f.empty()) {
        st.out("v.x[k + 1]", p.x_next);
        st.out("v.y[k + 1]", p.y_next);
      }
      st.out("vx", p.x_next);
      st.out("vy", p.y_next);
    }
    text += last ? block("the tip", "    const int k = n - 1;\n" + st.emit(in_loop))
                 : loop("int k = 0; k + 1 < n; ++k", st.emit(in_loop));
  }
  return text;
}

// The tangent pass: along the direction (dphi, dp), the derivative of every step in turn.
std::string tangent_pass() {
  std::string text;
  {
    loop_step st;
    const sx s = st.in("v.s[k]"), c = st.in("v.c[k]"), dphi = st.in("dphi[k]");
    st.out("v.ds[k]", c * dphi);
    st.out("v.dc[k]", -(s * dphi));
    const sx p = st.in("p_unused");
    st.out("v.dq[k]",
           st.tangents({momentum_per_length(st, p, length_k)}, {{p, st.in("dp[k]")}})[0]);
    text += loop("int k = 0; k < n; ++k", st.emit(in_loop));
  }
  {
    loop_step st;
    const sx s = st.in("v.s[k]"), c = st.in("v.c[k]"), s1 = st.in("v.s[k + 1]"),
             c1 = st.in("v.c[k + 1]");
    const rod_turn t = turn_between(s, c, s1, c1);
    const auto d = st.tangents({t.C, t.S}, {{s, st.in("v.ds[k]")},
                                            {c, st.in("v.dc[k]")},
                                            {s1, st.in("v.ds[k + 1]")},
                                            {c1, st.in("v.dc[k + 1]")}});
    st.out("v.dcd[k]", d[0]);
    st.out("v.dsd[k]", d[1]);
    text += loop("int k = 0; k + 1 < n; ++k", st.emit(in_loop));
  }
  {
    loop_step tip;
    const sx q = tip.in("v.q[k]");
    const elimination_step t = eliminate_tip(tip.in(mass_k), q);
    const auto d = tip.tangents({t.r, t.gamma, t.a, t.beta}, {{q, tip.in("v.dq[k]")}});
    tip.out("v.dr[k]", d[0]);
    tip.out("v.dgamma[k]", d[1]);
    tip.out("v.da[k]", d[2]);
    tip.out("v.dbeta[k]", d[3]);
    text += block("the tip", "    const int k = n - 1;\n" + tip.emit(in_loop));

    loop_step st;
    const elimination_inputs in = read_elimination(st);
    const elimination_step e = eliminate(in);
    const auto de =
        st.tangents({e.r, e.gamma, e.a, e.beta}, {{in.C, st.in("v.dcd[k]")},
                                                  {in.S, st.in("v.dsd[k]")},
                                                  {in.q, st.in("v.dq[k]")},
                                                  {in.q_next, st.in("v.dq[k + 1]")},
                                                  {in.r_next, st.in("v.dr[k + 1]")},
                                                  {in.beta_next, st.in("v.dbeta[k + 1]")}});
    st.out("v.dr[k]", de[0]);
    st.out("v.dgamma[k]", de[1]);
    st.out("v.da[k]", de[2]);
    st.out("v.dbeta[k]", de[3]);
    text += loop("int k = n - 2; k >= 0; --k", st.emit(in_loop));
  }
  text += "  v.dx[0] = 0.0;\n  v.dy[0] = 0.0;\n";
  for (const bool last : {false, true}) {
    loop_step st;
    const pivot_inputs in = read_pivot(st, last);
    const pivot_step p = step_from_pivot(in, last);
    const sx s = st.in("v.s[k]");
    const auto [dphi, dp] = hamilton_equations(st, p.omega, p.kinetic_force, s);
    std::vector<sx> values{dphi, dp};
    if (!last) {
      values.push_back(p.x_next);
      values.push_back(p.y_next);
    }
    std::vector<std::pair<sx, sx>> seeds{{in.a, st.in("v.da[k]")}, {in.gamma, st.in("v.dgamma[k]")},
                                         {in.r, st.in("v.dr[k]")}, {in.beta, st.in("v.dbeta[k]")},
                                         {in.x, st.in("v.dx[k]")}, {in.y, st.in("v.dy[k]")},
                                         {s, st.in("v.ds[k]")}};
    if (!last) {
      seeds.emplace_back(in.C, st.in("v.dcd[k]"));
      seeds.emplace_back(in.S, st.in("v.dsd[k]"));
    }
    const auto d = st.tangents(values, seeds);
    st.out("df[k]", d[0]);
    st.out("df[n + k]", d[1]);
    if (!last) {
      st.out("v.dx[k + 1]", d[2]);
      st.out("v.dy[k + 1]", d[3]);
    }
    text += last ? block("the tip", "    const int k = n - 1;\n" + st.emit(in_loop))
                 : loop("int k = 0; k + 1 < n; ++k", st.emit(in_loop));
  }
  return text;
}

// One link's step of the vector forward mode (the Jacobian: all 2n directions at once). Along
// every direction, an output's tangent is the same linear combination of the input tangents,
// with the step's partial derivatives as coefficients: those are computed once per link (as
// outputs of the step's graph), and the loops over the directions are multiply-adds over rows
// of tangents, with no divisions or libm calls, which the compiler vectorises. Where the step
// reads a quantity that depends on one angle or momentum only (a turn, q_k), its direct
// contribution is a seed added at that one direction.
class vector_step {
 public:
  /// A value node of the step and the row (a pointer of the emitted code) holding its tangent.
  using row = std::pair<sx, std::string>;

  explicit vector_step(loop_step& st) : m_st(st) {}

  /// for j in [from, to): output rows[j] = Σ ∂output/∂input · input rows[j].
  void directions(const std::string& from, const std::string& to, const std::vector<row>& outputs,
                  const std::vector<row>& inputs) {
    std::string reads, writes;
    for (std::size_t i = 0; i < inputs.size(); ++i)
      reads += fmt::format("{}e{} = {}[j]", i == 0 ? "const double " : ", ", i, inputs[i].second);
    std::vector<sx> values;
    for (const auto& [value, name] : outputs) values.push_back(value);
    std::vector<std::string> sums(outputs.size());
    for (std::size_t i = 0; i < inputs.size(); ++i) {
      const std::vector<sx> d = m_st.partials(values, inputs[i].first);
      for (std::size_t o = 0; o < outputs.size(); ++o) {
        if (m_st.is_zero(d[o])) continue;
        sums[o] += fmt::format("{}{} * e{}", sums[o].empty() ? "" : " + ", scalar(d[o]), i);
      }
    }
    for (std::size_t o = 0; o < outputs.size(); ++o)
      writes +=
          fmt::format("      {}[j] = {};\n", outputs[o].second, sums[o].empty() ? "0.0" : sums[o]);
    if (!reads.empty()) reads = "      " + reads + ";\n";
    m_loops +=
        fmt::format("    for (int j = {}; j < {}; ++j) {{\n{}{}    }}\n", from, to, reads, writes);
  }

  /// The outputs' direct dependence on one direction: Σ ∂output/∂input · seed over the
  /// (input, seed) pairs, added to the output rows at `direction`.
  void seed(const std::string& direction, const std::vector<row>& outputs,
            const std::vector<std::pair<sx, sx>>& seeds) {
    std::vector<sx> values;
    for (const auto& [value, name] : outputs) values.push_back(value);
    const std::vector<sx> d = m_st.tangents(values, seeds);
    for (std::size_t o = 0; o < outputs.size(); ++o)
      if (!m_st.is_zero(d[o]))
        m_seeds += fmt::format("    {}[{}] += {};\n", outputs[o].second, direction, scalar(d[o]));
  }

  /// The coefficients, then the loops over the directions, then the seeds.
  std::string emit() const { return m_st.emit(in_loop_body) + m_loops + m_seeds; }

 private:
  static constexpr const char* in_loop_body = "    ";
  // A coefficient as a named scalar of the link's step.
  std::string scalar(sx value) {
    const std::string name = fmt::format("c{}", m_count++);
    m_st.out("const double " + name, value);
    return name;
  }
  loop_step& m_st;
  std::string m_loops, m_seeds;
  int m_count = 0;
};

// Throws unless none of `values` depends on any of `inputs`: the Jacobian's momentum
// directions leave out the rows of quantities that depend on the angles only.
void require_independent(loop_step& st, const std::vector<sx>& values,
                         const std::vector<sx>& inputs, const char* what) {
  for (const sx input : inputs)
    for (const sx d : st.partials(values, input))
      if (!st.is_zero(d)) throw std::logic_error(std::string("loop Jacobian: ") + what);
}

// ∂C/∂φ and ∂S/∂φ of the turn between rods k and k + 1, for φ_k (`first`) or φ_{k+1}.
std::pair<sx, sx> turn_derivative(loop_step& st, bool first) {
  const sx s = st.in("v.s[k]"), c = st.in("v.c[k]"), s1 = st.in("v.s[k + 1]"),
           c1 = st.in("v.c[k + 1]");
  const rod_turn t = turn_between(s, c, s1, c1);
  const auto d = first ? st.tangents({t.C, t.S}, {{s, c}, {c, -s}})
                       : st.tangents({t.C, t.S}, {{s1, c1}, {c1, -s1}});
  return {d[0], d[1]};
}

// ∂q/∂p = 1/l for the link whose length `length` names.
sx momentum_derivative(loop_step& st, const std::string& length) {
  const sx p = st.in("p_unused");
  return st.tangents({momentum_per_length(st, p, length)}, {{p, st.constant(1)}})[0];
}

// The rows of link k's tangents in the Jacobian's workspace: r_k and γ_k over the n angle
// directions (they do not depend on the momenta), a_k and β_k over all 2n.
std::string link_rows(const std::string& k, const std::string& suffix, bool constant) {
  const char* type = constant ? "const double* const" : "double* const";
  return fmt::format(
      "    {0} dr{1} = rows + 6 * std::ptrdiff_t{{n}} * ({2});\n    {0} dgamma{1} = dr{1} + n;\n"
      "    {0} da{1} = dgamma{1} + n;\n    {0} dbeta{1} = da{1} + dim;\n",
      type, suffix, k);
}

// The elimination from the tip, along all directions: rows of r_k, γ_k, a_k, β_k.
std::string jacobian_backward() {
  std::string text;
  {
    loop_step tip;
    vector_step vs(tip);
    const sx q = tip.in("v.q[k]");
    const elimination_step t = eliminate_tip(tip.in(mass_k), q);
    require_independent(tip, {t.r, t.gamma}, {q}, "r and gamma of the tip depend on p");
    vs.directions("0", "n", {{t.r, "dr"}, {t.gamma, "dgamma"}}, {});
    vs.directions("0", "dim", {{t.a, "da"}, {t.beta, "dbeta"}}, {});
    vs.seed("n + k", {{t.a, "da"}, {t.beta, "dbeta"}}, {{q, momentum_derivative(tip, length_k)}});
    text += block("the tip", "    const int k = n - 1;\n" + link_rows("k", "", false) + vs.emit());
  }
  loop_step st;
  vector_step vs(st);
  const elimination_inputs in = read_elimination(st);
  const elimination_step e = eliminate(in);
  require_independent(st, {e.r, e.gamma}, {in.q, in.q_next, in.beta_next},
                      "r and gamma depend on p");
  const std::vector<vector_step::row> angle_out{
      {e.r, "dr"}, {e.gamma, "dgamma"}, {e.a, "da"}, {e.beta, "dbeta"}};
  const std::vector<vector_step::row> momentum_out{{e.a, "da"}, {e.beta, "dbeta"}};
  vs.directions("0", "n", angle_out, {{in.r_next, "dr1"}, {in.beta_next, "dbeta1"}});
  vs.directions("n", "dim", momentum_out, {{in.beta_next, "dbeta1"}});
  for (const bool first : {true, false}) {
    const auto [dC, dS] = turn_derivative(st, first);
    vs.seed(first ? "k" : "k + 1", angle_out, {{in.C, dC}, {in.S, dS}});
  }
  vs.seed("n + k", momentum_out, {{in.q, momentum_derivative(st, length_k)}});
  vs.seed("n + k + 1", momentum_out,
          {{in.q_next, momentum_derivative(st, "params[chain_layout::length_index(n, k + 1)]")}});
  text += loop("int k = n - 2; k >= 0; --k",
               link_rows("k", "", false) + link_rows("k + 1", "1", true) + vs.emit());
  return text;
}

// The pass from the pivot, along all directions: rows k (φ̇_k) and n + k (ṗ_k) of the
// Jacobian, and the running rows of the suspension's velocity (x, y).
std::string jacobian_forward() {
  std::string text = "  for (int j = 0; j < dim; ++j) {\n    dx[j] = 0.0;\n    dy[j] = 0.0;\n  }\n";
  for (const bool last : {false, true}) {
    loop_step st;
    vector_step vs(st);
    const pivot_inputs in = read_pivot(st, last);
    const pivot_step p = step_from_pivot(in, last);
    const sx s = st.in("v.s[k]"), c = st.in("v.c[k]");
    const auto [dphi, dp] = hamilton_equations(st, p.omega, p.kinetic_force, s);
    std::vector<vector_step::row> out{{dphi, "f"}, {dp, "g"}};
    if (!last) {
      out.emplace_back(p.x_next, "dx");
      out.emplace_back(p.y_next, "dy");
    }
    vs.directions("0", "n", out,
                  {{in.a, "da"},
                   {in.gamma, "dgamma"},
                   {in.r, "dr"},
                   {in.beta, "dbeta"},
                   {in.x, "dx"},
                   {in.y, "dy"}});
    vs.directions("n", "dim", out, {{in.a, "da"}, {in.beta, "dbeta"}, {in.x, "dx"}, {in.y, "dy"}});
    if (last) {
      vs.seed("k", out, {{s, c}});
    } else {
      for (const bool first : {true, false}) {
        const auto [dC, dS] = turn_derivative(st, first);
        std::vector<std::pair<sx, sx>> seeds{{in.C, dC}, {in.S, dS}};
        if (first) seeds.emplace_back(s, c);
        vs.seed(first ? "k" : "k + 1", out, seeds);
      }
    }
    const std::string rows = link_rows("k", "", true) +
                             "    double* const f = jac + std::ptrdiff_t{k} * dim;\n"
                             "    double* const g = jac + std::ptrdiff_t{n + k} * dim;\n";
    text += last ? block("the tip", "    const int k = n - 1;\n" + rows + vs.emit())
                 : loop("int k = 0; k + 1 < n; ++k", rows + vs.emit());
  }
  return text;
}

// φ̇ = f_k (k < n) from the value pass.
std::string velocity_step(const std::string& target) {
  loop_step st;
  const auto [dphi, dp] =
      hamilton_equations(st, st.in("v.omega[k]"), st.in("v.force[k]"), st.in("v.s[k]"));
  st.out(target + "[k]", dphi);
  return loop("int k = 0; k < n; ++k", st.emit(in_loop));
}

// μ_k = Σ_{j≥k} m_j, from the tip.
std::string mass_below_step() {
  loop_step st;
  st.out("v.mu[k]", st.in(mass_k) + st.in("(k + 1 < n ? v.mu[k + 1] : 0.0)"));
  return loop("int k = n - 1; k >= 0; --k", st.emit(in_loop));
}

// potential += g μ_k l_k (1 − cos φ_k) (from the pivot): V is zero where the chain hangs, as
// the unrolled kernels' V.
std::string potential_step() {
  loop_step st;
  st.out("potential",
         st.in("potential") + gravity_moment(st.in(gravity), st.in("v.mu[k]"), st.in(length_k),
                                             st.constant(1) - st.in("v.c[k]")));
  return loop("int k = 0; k < n; ++k", st.emit(in_loop));
}

// twice_t += m_k |v_k|² for the velocity (vx, vy) of bob k.
std::string kinetic_step(const char* vx, const char* vy) {
  loop_step st;
  const sx x = st.in(vx), y = st.in(vy);
  st.out("twice_t", st.in("twice_t") + st.in(mass_k) * (x * x + y * y));
  return loop("int k = 0; k < n; ++k", st.emit(in_loop));
}

// The bob velocities v_k = v_{k−1} + l_k φ̇_k (cos φ_k, −sin φ_k) into v.x, v.y.
std::string bob_velocity_step() {
  loop_step st;
  const sx ldphi = st.in(length_k)*st.in("dphi[k]");
  st.out("v.x[k]", st.in("(k > 0 ? v.x[k - 1] : 0.0)") + ldphi * st.in("v.c[k]"));
  st.out("v.y[k]", st.in("(k > 0 ? v.y[k - 1] : 0.0)") - ldphi * st.in("v.s[k]"));
  return loop("int k = 0; k < n; ++k", st.emit(in_loop));
}

struct function_text {
  std::string doc, signature, body;
};

std::vector<function_text> loop_functions() {
  const std::string values_call = "  const passes v = cut(n, work);\n";
  std::vector<function_text> fs;
  fs.push_back(
      {"Hamilton's equations f(x) (dim 2n), as the unrolled rhs.",
       "void rhs(int n, const double* x, const double* params, double* dxdt, "
       "double* work) noexcept",
       values_call + "  eliminate_from_tip(n, x, x + n, params, v);\n" + pivot_pass("dxdt")});
  fs.push_back({"J(x) u for a direction u (dim 2n): the forward-mode derivative of rhs, O(n).",
                "void jacobian_vector(int n, const double* x, const double* params, "
                "const double* u, double* ju, double* work) noexcept",
                values_call + "  evaluate(n, x, x + n, params, v);\n" +
                    "  tangent(n, params, v, u, u + n, ju);\n"});
  fs.push_back(
      {"The Jacobian df/dx, row-major 2n x 2n, in O(n^2): the forward mode along all 2n "
       "directions at once. Its workspace is jacobian_workspace_size(n) doubles.",
       "void jacobian(int n, const double* x, const double* params, double* jac, "
       "double* work) noexcept",
       values_call + "  evaluate(n, x, x + n, params, v);\n" +
           "  const int dim = 2 * n;\n"
           "  double* const rows = work + workspace_size(n);\n"
           "  double* const dx = rows + 6 * std::ptrdiff_t{n} * n;\n"
           "  double* const dy = dx + dim;\n" +
           jacobian_backward() + jacobian_forward()});
  fs.push_back({"H = T + V with T = 1/2 sum m_k |v_k|^2 from the elimination.",
                "double hamiltonian(int n, const double* x, const double* params, double* work) "
                "noexcept",
                values_call + "  evaluate(n, x, x + n, params, v);\n" +
                    "  double twice_t = 0.0, potential = 0.0;\n" +
                    kinetic_step("v.w[k]", "v.y[k]") + potential_step() +
                    "  return 0.5 * twice_t + potential;\n"});
  fs.push_back({"phi' = A^-1 p.",
                "void velocities(int n, const double* phi, const double* p, const double* params, "
                "double* dphi, double* work) noexcept",
                values_call + "  evaluate(n, phi, p, params, v);\n" + velocity_step("dphi")});
  {
    loop_step st;
    const sx px = st.in("px") + st.in(mass_k)*st.in("v.x[k]");
    const sx py = st.in("py") + st.in(mass_k)*st.in("v.y[k]");
    st.out("px", px);
    st.out("py", py);
    st.out("p[k]", st.in(length_k) * (st.in("v.c[k]") * px - st.in("v.s[k]") * py));
    fs.push_back(
        {"p = A phi' = dL/dphi': p_k = l_k n_k . P_k, P_k the momentum of the links "
         "from k down.",
         "void momenta(int n, const double* phi, const double* dphi, const double* "
         "params, double* p, double* work) noexcept",
         "  const passes v = cut(n, work);\n" + angle_step() + bob_velocity_step() +
             "  double px = 0.0, py = 0.0;\n" +
             loop("int k = n - 1; k >= 0; --k", st.emit(in_loop))});
  }
  fs.push_back({"T = 1/2 sum m_k |v_k|^2.",
                "double kinetic_energy(int n, const double* phi, const double* dphi, "
                "const double* params, double* work) noexcept",
                "  const passes v = cut(n, work);\n" + angle_step() + bob_velocity_step() +
                    "  double twice_t = 0.0;\n" + kinetic_step("v.x[k]", "v.y[k]") +
                    "  return 0.5 * twice_t;\n"});
  fs.push_back({"V = g sum mu_k l_k (1 - cos phi_k), zero at the hanging rest position.",
                "double potential_energy(int n, const double* phi, const double* params, "
                "double* work) noexcept",
                "  const passes v = cut(n, work);\n" + angle_step() + mass_below_step() +
                    "  double potential = 0.0;\n" + potential_step() + "  return potential;\n"});
  fs.push_back({"L = T - V.",
                "double lagrangian(int n, const double* phi, const double* dphi, const double* "
                "params, double* work) noexcept",
                "  return kinetic_energy(n, phi, dphi, params, work) - potential_energy(n, phi, "
                "params, work);\n"});
  {
    loop_step diag;
    const sx l = diag.in(length_k);
    diag.out("A[k * n + k]", l * l * diag.in("v.mu[k]"));
    loop_step off;
    const sx li = off.in("params[chain_layout::length_index(n, i)]"),
             lj = off.in("params[chain_layout::length_index(n, j)]");
    const sx cosine = off.in("v.c[i]") * off.in("v.c[j]") + off.in("v.s[i]") * off.in("v.s[j]");
    off.out("A[i * n + j]", li * lj * off.in("v.mu[i]") * cosine);
    fs.push_back({"The mass matrix A_ij = l_i l_j mu_max(i,j) cos(phi_i - phi_j), row-major n x n.",
                  "void mass_matrix(int n, const double* phi, const double* params, double* A, "
                  "double* work) noexcept",
                  "  const passes v = cut(n, work);\n" + angle_step() + mass_below_step() +
                      loop("int k = 0; k < n; ++k", diag.emit(in_loop)) +
                      "  for (int i = 0; i < n; ++i) {\n    for (int j = 0; j < i; ++j) {\n" +
                      off.emit("      ") + "      A[j * n + i] = A[i * n + j];\n    }\n  }\n"});
  }
  {
    loop_step st;
    const sx l = st.in(length_k);
    st.out("det", st.in("det") * (l * l * st.in("v.d[k]")));
    fs.push_back(
        {"det A = prod l_k^2 d_k, the pivots of the elimination (it under- or overflows "
         "a double for long chains of short links: l^(2n)).",
         "double det_mass_matrix(int n, const double* phi, const double* params, "
         "double* work) noexcept",
         "  const passes v = cut(n, work);\n"
         "  for (int k = 0; k < n; ++k) v.no_momenta[k] = 0.0;\n"
         "  evaluate(n, phi, v.no_momenta, params, v);\n"
         "  double det = 1.0;\n" +
             loop("int k = 0; k < n; ++k", st.emit(in_loop)) + "  return det;\n"});
  }
  {
    loop_step st;
    const sx l = st.in(length_k);
    st.out("const double pivot", l * l * st.in("v.d[k]"));
    fs.push_back(
        {"ln det A = sum ln(l_k^2 d_k): det A without under- or overflow, for long "
         "chains.",
         "double log_det_mass_matrix(int n, const double* phi, const double* params, "
         "double* work) noexcept",
         "  const passes v = cut(n, work);\n"
         "  for (int k = 0; k < n; ++k) v.no_momenta[k] = 0.0;\n"
         "  evaluate(n, phi, v.no_momenta, params, v);\n"
         "  double log_det = 0.0;\n" +
             loop("int k = 0; k < n; ++k",
                  st.emit(in_loop) + in_loop + "log_det += std::log(pivot);\n") +
             "  return log_det;\n"});
  }
  {
    loop_step st;
    st.out("grad[k]",
           gravity_moment(st.in(gravity), st.in("v.mu[k]"), st.in(length_k), st.in("v.s[k]")));
    fs.push_back({"dV/dphi_k = g mu_k l_k sin phi_k.",
                  "void potential_gradient(int n, const double* phi, const double* params, "
                  "double* grad, double* work) noexcept",
                  "  const passes v = cut(n, work);\n" + angle_step() + mass_below_step() +
                      loop("int k = 0; k < n; ++k", st.emit(in_loop))});
  }
  {
    loop_step st;
    st.out("hess[k * n + k]",
           gravity_moment(st.in(gravity), st.in("v.mu[k]"), st.in(length_k), st.in("v.c[k]")));
    fs.push_back({"d2V/dphi^2: diagonal, g mu_k l_k cos phi_k; row-major n x n.",
                  "void potential_hessian(int n, const double* phi, const double* params, "
                  "double* hess, double* work) noexcept",
                  "  const passes v = cut(n, work);\n" + angle_step() + mass_below_step() +
                      "  for (int i = 0; i < n * n; ++i) hess[i] = 0.0;\n" +
                      loop("int k = 0; k < n; ++k", st.emit(in_loop))});
  }
  {
    loop_step st;
    const sx phi = st.in("phi[k]"), l = st.in(length_k);
    st.out("xy[2 * k]", st.in("(k > 0 ? xy[2 * k - 2] : 0.0)") + l * sin(phi));
    st.out("xy[2 * k + 1]", st.in("(k > 0 ? xy[2 * k - 1] : 0.0)") + l * cos(phi));
    fs.push_back({"Bob positions [x_1, y_1, ..., x_n, y_n] relative to the pivot (y down).",
                  "void positions(int n, const double* phi, const double* params, double* xy, "
                  "double* /*work*/) noexcept",
                  loop("int k = 0; k < n; ++k", st.emit(in_loop))});
  }
  return fs;
}

// The per-link arrays of the passes, in the order they are cut from the workspace.
const char* const value_arrays[] = {"s",    "c", "cd",    "sd", "q", "mu", "d",     "r",
                                    "beta", "a", "gamma", "x",  "y", "w",  "omega", "force"};
const char* const tangent_arrays[] = {"ds",    "dc", "dcd",    "dsd", "dq", "dr",
                                      "dbeta", "da", "dgamma", "dx",  "dy"};

// How the helpers are printed for one compiler: the host's (chain_loop.cpp) or the GPU maps'
// device code (gpu_chain_loop.cuh).
struct dialect {
  std::string qualifier;  // before every function definition
  bool zero_momenta;      // the workspace ends with n zero momenta (det A, host only)
};
const dialect host_dialect{"", true};
// The device file has rhs, jacobian_vector and hamiltonian only: no det A, so no zero momenta.
const dialect device_dialect{"NPEND_GPU_FUNCTION ", false};

// The number of n-double arrays cut from the workspace: workspace_size(n) / n.
int workspace_arrays(const dialect& d) {
  return static_cast<int>(std::size(value_arrays) + std::size(tangent_arrays)) +
         (d.zero_momenta ? 1 : 0);
}

std::string passes_struct(const dialect& d) {
  std::string names, cuts;
  for (const char* a : value_arrays) names += fmt::format("{}*{}", names.empty() ? "" : ", ", a);
  std::string tnames;
  for (const char* a : tangent_arrays)
    tnames += fmt::format("{}*{}", tnames.empty() ? "" : ", ", a);
  for (const char* a : value_arrays) cuts += fmt::format("  v.{} = work + n * i++;\n", a);
  for (const char* a : tangent_arrays) cuts += fmt::format("  v.{} = work + n * i++;\n", a);
  const char* const what = d.zero_momenta
                               ? "// The per-link arrays of the passes (n each), and n zero "
                                 "momenta for det A, cut from the\n// caller's workspace.\n"
                               : "// The per-link arrays of the passes (n each), cut from the "
                                 "caller's workspace.\n";
  return fmt::format(
      "{}struct passes {{\n  double {};\n  double {};\n{}}};\n\n"
      "{}passes cut(int n, double* work) noexcept {{\n  passes v;\n  int i = 0;\n{}{}"
      "  return v;\n}}\n",
      what, names, tnames, d.zero_momenta ? "  double *no_momenta;\n" : "", d.qualifier, cuts,
      d.zero_momenta ? "  v.no_momenta = work + n * i;\n" : "");
}

// The passes every function starts from (the elimination, the value pass, the tangent pass),
// each definition after `d`'s qualifier.
std::string pass_functions(const dialect& d) {
  std::string text =
      "\n// The elimination from the tip at (phi, p) (articulated_form.hpp of the generator).\n" +
      d.qualifier +
      "void eliminate_from_tip(int n, const double* phi, const double* p, const double* params, "
      "const passes& v) noexcept {\n" +
      elimination_pass() + "}\n";
  text += "\n// The value pass at (phi, p): the elimination and the pass from the pivot.\n" +
          d.qualifier +
          "void evaluate(int n, const double* phi, const double* p, const double* params, "
          "const passes& v) noexcept {\n"
          "  eliminate_from_tip(n, phi, p, params, v);\n" +
          pivot_pass() + "}\n";
  text +=
      "\n// The derivative of f along (dphi, dp) into df (dim 2n), from evaluate's values: each "
      "step's\n// forward-mode derivative in the order of the steps.\n" +
      d.qualifier +
      "void tangent(int n, const double* params, const passes& v, const double* dphi, "
      "const double* dp, double* df) noexcept {\n" +
      tangent_pass() + "}\n";
  return text;
}

// The device functions: those of gpu_chain_<n>.cuh, with J·u in place of the Jacobian (a
// deviation vector's derivative is one product, O(n), where the Jacobian's tangent rows take
// O(n^2) doubles of workspace per call).
constexpr const char* device_functions[] = {"rhs", "jacobian_vector", "hamiltonian"};

std::string function_name(const function_text& f) {
  const auto open = f.signature.find('(');
  const auto start = f.signature.rfind(' ', open) + 1;
  return f.signature.substr(start, open - start);
}

}  // namespace

chain_sources emit_loop_kernels() {
  const int arrays = workspace_arrays(host_dialect);
  const std::string banner = generated_banner("npend-gen --loop");
  const auto fs = loop_functions();
  chain_sources out;
  out.header = banner + fmt::format(R"(#pragma once

// The planar n-link pendulum of point masses for any n: the functions of chain_<n>.hpp as
// loops over the links (the articulated-body elimination's steps, one loop per pass), for
// link counts without unrolled kernels. Layouts as npend::chain_layout's; every function takes
// the link count n first and a workspace of workspace_size(n) doubles last (none allocates,
// so a caller keeps one workspace per thread).

#include <npend/chain_kernels.hpp>

namespace npend::generated::chain_loop {{

/// Doubles of workspace the functions need for n links.
inline constexpr int workspace_size(int n) noexcept {{ return {} * n; }}

/// Doubles of workspace the Jacobian needs: workspace_size(n) and the tangent rows of every
/// link (O(n^2), as the Jacobian itself).
inline constexpr std::size_t jacobian_workspace_size(int n) noexcept {{
  const auto links = static_cast<std::size_t>(n);
  return static_cast<std::size_t>(workspace_size(n)) + 6 * links * links + 4 * links;
}}

)",
                                    arrays);
  out.source = banner +
               fmt::format(
                   "#include \"{}.hpp\"\n\n#include <cmath>\n#include <cstddef>\n#include "
                   "<npend/batch_math.hpp>\n\n",
                   loop_stem) +
               "namespace npend::generated::chain_loop {\n\nnamespace {\n\n" +
               passes_struct(host_dialect);
  out.source +=
      "\n// s_k, c_k of every phi_k by SLEEF's vectorised sincos (1 ulp, <npend/batch_math.hpp>), "
      "batch_width\n// angles at a time, the last partial batch through a padded copy: the "
      "libm calls, one at a time,\n// took most of the right-hand side's time.\n"
      "void sines_and_cosines(int n, const double* phi, const passes& v) noexcept {\n"
      "  int k = 0;\n"
      "  for (; k + batch_width <= n; k += batch_width) batch_sincos(phi + k, v.s + k, v.c + k);\n"
      "  if (k == n) return;\n"
      "  double x[batch_width] = {}, s[batch_width], c[batch_width];\n"
      "  for (int i = 0; k + i < n; ++i) x[i] = phi[k + i];\n"
      "  batch_sincos(x, s, c);\n"
      "  for (int i = 0; k + i < n; ++i) {\n"
      "    v.s[k + i] = s[i];\n"
      "    v.c[k + i] = c[i];\n"
      "  }\n"
      "}\n";
  out.source += pass_functions(host_dialect) + "\n}  // namespace\n";
  for (const auto& f : fs) {
    out.header += fmt::format("/// {}\n{};\n\n", f.doc, f.signature);
    out.source += fmt::format("\n{} {{\n{}}}\n", f.signature, f.body);
  }
  out.header +=
      "/// The loop kernels' entry of the runtime's kernel table.\n"
      "extern const loop_kernels kernels;\n\n}  // namespace npend::generated::chain_loop\n";
  out.source +=
      "\nconst loop_kernels kernels = {\n    .workspace_size = &workspace_size,\n"
      "    .jacobian_workspace_size = &jacobian_workspace_size,\n";
  for (const auto& f : fs) out.source += fmt::format("    .{0} = &{0},\n", function_name(f));
  out.source += "};\n\n}  // namespace npend::generated::chain_loop\n";
  return out;
}

std::string emit_gpu_loop_kernels() {
  std::string out = generated_banner("npend-gen --loop");
  out += fmt::format(
      R"(// The device functions of the planar n-link pendulum (point masses on massless rods) for
// npend's GPU maps, for link counts without unrolled device functions (gpu_chain_<n>.cuh):
// rhs, jacobian_vector and hamiltonian of chain_loop.hpp, the same loops and statements, as
// plain functions of doubles that CUDA device code and host C++ both compile. The includer
// defines NPEND_GPU_FUNCTION (`__device__ inline` for CUDA, `inline` on the host) and makes
// sin and cos visible (CUDA's device maths; <cmath> on the host). Layouts as
// npend::chain_layout's; every function takes the link count n first and a workspace of
// workspace_size(n) doubles last, per call.

namespace npend::gpu::chain_loop {{

// Doubles of workspace the functions need for n links.
NPEND_GPU_FUNCTION constexpr int workspace_size(int n) noexcept {{ return {} * n; }}

// The parameter layout of npend::chain_layout (<npend/chain_kernels.hpp>, which device code
// cannot include): params = [m_1..m_n, l_1..l_n, g].
namespace chain_layout {{
NPEND_GPU_FUNCTION constexpr int mass_index(int /*n*/, int i) noexcept {{ return i; }}
NPEND_GPU_FUNCTION constexpr int length_index(int n, int i) noexcept {{ return n + i; }}
NPEND_GPU_FUNCTION constexpr int gravity_index(int n) noexcept {{ return 2 * n; }}
}}  // namespace chain_layout

)",
      workspace_arrays(device_dialect));
  out += passes_struct(device_dialect);
  out +=
      "\n// s_k, c_k of every phi_k, one sin and one cos per link (the host's batch sincos has "
      "no\n// device version).\n" +
      device_dialect.qualifier +
      "void sines_and_cosines(int n, const double* phi, const passes& v) noexcept {\n"
      "  for (int k = 0; k < n; ++k) {\n"
      "    v.s[k] = sin(phi[k]);\n"
      "    v.c[k] = cos(phi[k]);\n"
      "  }\n"
      "}\n";
  out += pass_functions(device_dialect);
  const auto fs = loop_functions();
  for (const char* name : device_functions) {
    const auto f = std::find_if(fs.begin(), fs.end(),
                                [&](const function_text& t) { return function_name(t) == name; });
    if (f == fs.end()) throw std::logic_error(fmt::format("emit_gpu_loop_kernels: no {}", name));
    out += fmt::format("\n// {}\n{}{} {{\n{}}}\n", f->doc, device_dialect.qualifier, f->signature,
                       f->body);
  }
  out += "\n}  // namespace npend::gpu::chain_loop\n";
  return out;
}
}  // namespace npend::gen
