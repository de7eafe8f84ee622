#include "emit_taylor.hpp"

#include <fmt/format.h>

#include <map>
#include <npend/chain_kernels.hpp>
#include <set>
#include <stdexcept>
#include <utility>
#include <vector>

namespace npend::gen {

namespace {

std::size_t u(int i) { return static_cast<std::size_t>(i); }

// Where an input node's series or value lives: a row of the state series, a row of the
// inputs' series, or a parameter (a constant of the recurrences).
struct input_place {
  enum kind { state, input, parameter } where;
  int index = 0;     // the row (state, input)
  std::string text;  // params[i] (parameter)
};

input_place place_of(int n, const node& nd, link_kind kind) {
  const std::string text = input_text(argument_layout::state, n, nd, kind);
  // stoi reads the index up to the closing bracket.
  const auto row = [&](std::size_t prefix) { return std::stoi(text.substr(prefix)); };
  if (text.rfind("x[", 0) == 0) return {input_place::state, row(2), {}};
  if (text.rfind("inputs[", 0) == 0) return {input_place::input, row(7), {}};
  if (text.rfind("params[", 0) == 0) return {input_place::parameter, 0, text};
  throw std::logic_error("emit_taylor: an input that is neither state, input nor parameter: " +
                         text);
}

// A rational constant in the number type T, exact where T can hold it.
std::string constant_text(const GiNaC::numeric& value) {
  if (!value.is_rational()) throw std::logic_error("emit_taylor: a constant that is not rational");
  const GiNaC::numeric num = value.numer(), den = value.denom();
  if (den == 1) return "T(" + constant_literal(num) + ")";
  return "(T(" + constant_literal(num) + ") / T(" + constant_literal(den) + "))";
}

// Prints the recurrences of one graph: first the nodes that read only parameters (scalars,
// once), then, inside the loop over the orders k, the k-th coefficient of every series node.
class taylor_printer {
 public:
  taylor_printer(int n, const emitted_function& rhs, link_kind kind)
      : m_n(n), m_g(*rhs.graph), m_kind(kind), m_order(evaluation_order(m_g, rhs.outputs)) {
    m_series.assign(u(m_g.size()), 0);
    m_text.assign(u(m_g.size()), {});
    for (const int id : m_order) classify(id);
    pair_sines_and_cosines();
    plan_mirrors();
    for (const sx out : rhs.outputs) m_outputs.push_back(out.id);
  }

  std::string body() {
    std::string constants, pointers, loop;
    const auto slot = [&](const std::string& name) {
      pointers += fmt::format("  T* const {} = work + {} * P;\n", name, m_slots++);
    };
    for (const int id : m_order) {
      const node& nd = m_g.at(id);
      if (!m_series[u(id)]) {
        if (nd.kind != op::constant && nd.kind != op::input)
          constants += fmt::format("  const T {} = {};\n", m_text[u(id)], scalar_expression(nd));
        continue;
      }
      if (m_mirror[u(id)]) slot(mirror_name(id));
      if (m_weighted[u(id)]) slot(weighted_name(id));
      if (nd.kind == op::input) continue;
      slot(m_text[u(id)]);
      if ((nd.kind == op::sin || nd.kind == op::cos) && !has_partner(id)) slot(partner_name(id));
      loop += recurrence(id);
    }
    for (std::size_t i = 0; i < m_outputs.size(); ++i) loop += output(static_cast<int>(i));
    std::string text =
        "  using std::cos;\n  using std::sin;\n  const int P = order + 1;\n  const int M = "
        "order;\n";
    text += constants + m_rows + pointers;
    text += "  for (int k = 0; k < order; ++k) {\n    const T next = T(1) / T(k + 1);\n" +
            input_mirrors() + loop + "  }\n";
    return text;
  }

  int slots() const { return m_slots; }
  bool reads_inputs() const { return m_reads_inputs; }

 private:
  void classify(int id) {
    const node& nd = m_g.at(id);
    switch (nd.kind) {
      case op::constant:
        m_text[u(id)] = constant_text(nd.value);
        return;
      case op::input: {
        const input_place place = place_of(m_n, nd, m_kind);
        if (place.where == input_place::parameter) {
          m_text[u(id)] = place.text;
          return;
        }
        // x_i's series is the row series[i·P .. i·P + order]; an input's row likewise.
        m_series[u(id)] = 1;
        const bool state = place.where == input_place::state;
        m_text[u(id)] = fmt::format("{}{}", state ? "x" : "w", place.index);
        m_rows += fmt::format("  const T* const {} = {} + {} * P;\n", m_text[u(id)],
                              state ? "series" : "inputs", place.index);
        m_reads_inputs = m_reads_inputs || !state;
        return;
      }
      default:
        m_series[u(id)] =
            (nd.lhs >= 0 && m_series[u(nd.lhs)]) || (nd.rhs >= 0 && m_series[u(nd.rhs)]);
        m_text[u(id)] = fmt::format("{}{}", m_series[u(id)] ? "s" : "c", id);
    }
  }

  // sin u and cos u of the same u are one recurrence; a lone one gets a partner series.
  void pair_sines_and_cosines() {
    std::map<int, int> sine_of, cosine_of;
    for (const int id : m_order) {
      const node& nd = m_g.at(id);
      if (!m_series[u(id)]) continue;
      if (nd.kind == op::sin) sine_of[nd.lhs] = id;
      if (nd.kind == op::cos) cosine_of[nd.lhs] = id;
    }
    for (const auto& [arg, s] : sine_of) {
      const auto c = cosine_of.find(arg);
      if (c == cosine_of.end()) continue;
      m_partner[s] = c->second;
      m_partner[c->second] = s;
    }
  }

  // The sums of products, quotients and sine/cosine pairs run over one series forwards and
  // another backwards; each series read backwards is also kept mirrored (m[M − j] = s[j]),
  // so that both run forwards in memory and the sums vectorise. The argument u of a
  // sine/cosine pair is read as j·u[j], kept mirrored too (its "weighted" series).
  void plan_mirrors() {
    m_mirror.assign(u(m_g.size()), 0);
    m_weighted.assign(u(m_g.size()), 0);
    for (const int id : m_order) {
      const node& nd = m_g.at(id);
      if (!m_series[u(id)]) continue;
      if (nd.kind == op::mul && m_series[u(nd.lhs)] && m_series[u(nd.rhs)]) {
        // Read backwards the operand that is already mirrored, if one is.
        const int backwards = m_mirror[u(nd.lhs)] && !m_mirror[u(nd.rhs)] ? nd.lhs : nd.rhs;
        m_backwards[id] = backwards;
        m_mirror[u(backwards)] = 1;
      }
      if (nd.kind == op::div && m_series[u(nd.rhs)]) m_mirror[u(nd.rhs)] = 1;
      if (nd.kind == op::sin || nd.kind == op::cos) m_weighted[u(nd.lhs)] = 1;
    }
  }

  std::string mirror_name(int id) const { return m_text[u(id)] + "_m"; }
  std::string weighted_name(int id) const { return m_text[u(id)] + "_w"; }
  // The statement that mirrors coefficient k of node id, if it is read backwards.
  std::string mirror(int id) const {
    if (!m_mirror[u(id)]) return {};
    return fmt::format("    {}[M - k] = {}[k];\n", mirror_name(id), m_text[u(id)]);
  }

  // The state's and the inputs' coefficient k, known when the order starts, mirrored.
  std::string input_mirrors() const {
    std::string text;
    for (const int id : m_order)
      if (m_g.at(id).kind == op::input && m_series[u(id)]) text += mirror(id);
    return text;
  }

  bool has_partner(int id) const { return m_partner.count(id) != 0; }
  std::string partner_name(int id) const {
    return has_partner(id) ? m_text[u(m_partner.at(id))] : m_text[u(id)] + "_pair";
  }

  std::string scalar_expression(const node& nd) const {
    const auto a = [&] { return m_text[u(nd.lhs)]; };
    const auto b = [&] { return m_text[u(nd.rhs)]; };
    switch (nd.kind) {
      case op::neg:
        return "-" + a();
      case op::add:
        return a() + " + " + b();
      case op::sub:
        return a() + " - " + b();
      case op::mul:
        return a() + " * " + b();
      case op::div:
        return a() + " / " + b();
      case op::sin:
        return "sin(" + a() + ")";
      case op::cos:
        return "cos(" + a() + ")";
      default:
        throw std::logic_error("emit_taylor: not an operation");
    }
  }

  // The statement that computes coefficient k of series node id.
  std::string recurrence(int id) {
    const node& nd = m_g.at(id);
    const std::string& v = m_text[u(id)];
    const auto name = [&](int operand) { return m_text[u(operand)]; };
    const auto series = [&](int operand) { return m_series[u(operand)] != 0; };
    switch (nd.kind) {
      case op::neg:
        return fmt::format("    {}[k] = -{}[k];\n", v, name(nd.lhs)) + mirror(id);
      case op::add:
      case op::sub: {
        const char* sign = nd.kind == op::add ? "+" : "-";
        if (series(nd.lhs) && series(nd.rhs))
          return fmt::format("    {}[k] = {}[k] {} {}[k];\n", v, name(nd.lhs), sign, name(nd.rhs)) +
                 mirror(id);
        if (series(nd.lhs))
          return fmt::format("    {0}[k] = k == 0 ? {1}[0] {2} {3} : {1}[k];\n", v, name(nd.lhs),
                             sign, name(nd.rhs)) +
                 mirror(id);
        return fmt::format("    {0}[k] = k == 0 ? {1} {2} {3}[0] : {4}{3}[k];\n", v, name(nd.lhs),
                           sign, name(nd.rhs), nd.kind == op::add ? "" : "-") +
               mirror(id);
      }
      case op::mul: {
        if (series(nd.lhs) && series(nd.rhs)) {
          const int backwards = m_backwards.at(id);
          const int forwards = backwards == nd.rhs ? nd.lhs : nd.rhs;
          return fmt::format("    {}[k] = taylor::product({}, {}, M, k);\n", v, name(forwards),
                             mirror_name(backwards)) +
                 mirror(id);
        }
        const int factor = series(nd.lhs) ? nd.rhs : nd.lhs;
        return fmt::format("    {}[k] = {} * {}[k];\n", v, name(factor),
                           name(factor == nd.lhs ? nd.rhs : nd.lhs)) +
               mirror(id);
      }
      case op::div:
        if (!series(nd.rhs))
          return fmt::format("    {}[k] = {}[k] / {};\n", v, name(nd.lhs), name(nd.rhs)) +
                 mirror(id);
        return fmt::format("    {0}[k] = taylor::quotient({1}, {2}, {0}, M, k);\n", v,
                           series(nd.lhs) ? name(nd.lhs) + "[k]"
                                          : fmt::format("k == 0 ? {} : T(0)", name(nd.lhs)),
                           mirror_name(nd.rhs)) +
               mirror(id);
      case op::sin:
      case op::cos: {
        // The pair is computed where its first member comes.
        if (has_partner(id) && m_paired.count(m_partner.at(id)) != 0) return {};
        m_paired.insert(id);
        const std::string other = partner_name(id);
        const std::string& s = nd.kind == op::sin ? v : other;
        const std::string& c = nd.kind == op::sin ? other : v;
        std::string text = fmt::format(
            "    {0}[M - k] = T(k) * {1}[k];\n    taylor::sin_cos({1}[0], {0}, {2}, {3}, M, k);\n",
            weighted_name(nd.lhs), name(nd.lhs), s, c);
        text += mirror(id);
        if (has_partner(id)) text += mirror(m_partner.at(id));
        return text;
      }
      default:
        throw std::logic_error("emit_taylor: a series node that is no operation");
    }
  }

  // x_i[k+1] = f_i[k] / (k + 1): output i is Hamilton's equation for state entry i.
  std::string output(int i) const {
    const int id = m_outputs[u(i)];
    if (m_series[u(id)])
      return fmt::format("    series[{} * P + k + 1] = {}[k] * next;\n", i, m_text[u(id)]);
    return fmt::format("    series[{} * P + k + 1] = k == 0 ? {} : T(0);\n", i, m_text[u(id)]);
  }

  int m_n;
  const expr_graph& m_g;
  link_kind m_kind;
  std::vector<int> m_order;
  std::vector<char> m_series;  // whether a node varies along the solution
  std::vector<std::string> m_text;
  std::map<int, int> m_partner;
  std::vector<char> m_mirror, m_weighted;  // series kept mirrored, and j·u[j] mirrored
  std::map<int, int> m_backwards;          // the operand a product reads backwards
  std::set<int> m_paired;                  // sine/cosine nodes whose pair is computed
  std::vector<int> m_outputs;
  int m_slots = 0;
  std::string m_rows;  // the declarations of the state's and the inputs' rows
  bool m_reads_inputs = false;
};

int input_count(int n, link_kind kind) {
  if (kind == link_kind::physical) return chain_layout::input_size(n);
  if (kind == link_kind::cart) return cart_layout::input_size(n);
  return 0;
}

int param_count(int n, link_kind kind) {
  if (kind == link_kind::physical) return chain_layout::physical_param_size(n);
  if (kind == link_kind::cart) return cart_layout::param_size(n);
  return chain_layout::param_size(n);
}

int state_count(int n, link_kind kind) {
  return kind == link_kind::cart ? cart_layout::state_size(n) : chain_layout::state_size(n);
}

std::string signature(const char* type) {
  return fmt::format(
      "void coefficients(const {0}* params, const {0}* inputs, int order, {0}* series, {0}* work) "
      "noexcept",
      type);
}

}  // namespace

std::string taylor_stem(int links, link_kind kind) { return "taylor_" + chain_stem(links, kind); }

chain_sources emit_taylor(int n, const emitted_function& rhs, const std::string& options,
                          link_kind kind) {
  if (rhs.name != "rhs" || rhs.layout != argument_layout::state)
    throw std::logic_error("emit_taylor: needs the chain's rhs");
  const std::string stem = taylor_stem(n, kind);
  const std::string banner = generated_banner(chain_command(n, options, kind));
  taylor_printer printer(n, rhs, kind);
  const std::string body = printer.body();
  const int states = state_count(n, kind), inputs = input_count(n, kind);

  chain_sources out;
  out.header = banner + fmt::format(
                            "#pragma once\n\n"
                            "// The Taylor coefficients of the solution of {0}'s Hamilton's "
                            "equations through a\n"
                            "// state, by the recurrences of automatic differentiation over "
                            "the nodes of its rhs\n"
                            "// (the layouts of {0}.hpp).\n\n"
                            "#include <npend/chain_kernels.hpp>\n\n"
                            "namespace npend::generated::{1} {{\n\n",
                            chain_stem(n, kind), stem);
  out.header += fmt::format(
      "/// The series the recurrences keep: the workspace holds work_slots·(order + 1) numbers.\n"
      "inline constexpr int work_slots = {};\n\n",
      printer.slots());
  out.header +=
      "/// series[i·(order+1) + k] is the coefficient of τ^k in x_i(t + τ) (dim " +
      std::to_string(states) +
      " rows): the caller\n"
      "/// sets k = 0 to the state, and this fills k = 1..order. " +
      (inputs > 0
           ? fmt::format("inputs[j·(order+1) + k] are the\n/// coefficients of the inputs w_j (dim "
                         "{} rows), k = 0..order−1, which the caller computes\n/// from their "
                         "time dependence.",
                         inputs)
           : std::string("inputs is not read (the chain has no\n/// inputs).")) +
      "\n" + signature("double") + ";\n" + signature("long double") + ";\n" +
      "/// The same on dual numbers: with x_i's derivative set to w_i in k = 0, the derivatives\n"
      "/// of series are the coefficients of the tangent vector w(t), w' = J(x(t)) w.\n" +
      signature("npend::taylor::dual") + ";\n\n";
  out.header +=
      "/// This link count's entry of the runtime's Taylor table.\nextern const taylor_kernels "
      "kernels;\n\n";
  out.header += fmt::format("}}  // namespace npend::generated::{}\n", stem);

  out.source =
      banner +
      fmt::format(
          "#include \"{0}.hpp\"\n\n#include <cmath>\n#include "
          "<npend/integrators/taylor_recurrences.hpp>\n\nnamespace npend::generated::{0} {{\n\n"
          "namespace {{\n\n",
          stem) +
      fmt::format(
          "template <class T>\nvoid recurrences(const T* params, {}const T* inputs, int order, "
          "T* series, T* work) noexcept {{\n",
          printer.reads_inputs() ? "" : "[[maybe_unused]] ") +
      body + "}\n\n}  // namespace\n\n";
  for (const char* type : {"double", "long double", "npend::taylor::dual"})
    out.source +=
        signature(type) + " {\n  recurrences(params, inputs, order, series, work);\n}\n\n";
  out.source += fmt::format(
      "const taylor_kernels kernels = {{\n    .state_size = {},\n    .param_size = {},\n"
      "    .input_size = {},\n    .work_slots = work_slots,\n    .coefficients = &coefficients,\n"
      "    .coefficients_long = &coefficients,\n    .coefficients_dual = &coefficients,\n}};\n\n",
      states, param_count(n, kind), inputs);
  out.source += fmt::format("}}  // namespace npend::generated::{}\n", stem);
  return out;
}

}  // namespace npend::gen
