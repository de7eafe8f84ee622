#include "emit_cpp.hpp"

#include <fmt/format.h>

#include <cmath>
#include <functional>
#include <map>
#include <npend/chain_kernels.hpp>
#include <stdexcept>

namespace npend::gen {

namespace {

std::size_t u(int i) { return static_cast<std::size_t>(i); }

// Expressions longer than this become named temporaries even when used once, so that
// lines stay readable and no expression nests without bound.
constexpr std::size_t max_inline_length = 64;

enum precedence : int { additive = 1, multiplicative = 2, unary = 3, atom = 4 };

struct printed {
  std::string text;
  int prec = atom;
};

std::string literal(const GiNaC::numeric& value) {
  const double d = value.to_double();
  if (!std::isfinite(d)) throw std::logic_error("emit: non-finite constant");
  if (d == std::floor(d) && std::fabs(d) < 9007199254740992.0) return fmt::format("{:.1f}", d);
  return fmt::format("{:.17g}", d);
}

std::vector<int> postorder(const expr_graph& g, const std::vector<sx>& outputs) {
  std::vector<int> order;
  std::vector<char> seen(u(g.size()), 0);
  // Iterative DFS: graphs for n = 20 are deep enough to make recursion a risk.
  for (const sx out : outputs) {
    std::vector<std::pair<int, int>> stack{{out.id, 0}};
    while (!stack.empty()) {
      auto& [id, stage] = stack.back();
      if (seen[u(id)]) {
        stack.pop_back();
        continue;
      }
      const node& n = g.at(id);
      if (stage == 0) {
        stage = 1;
        if (n.lhs >= 0 && !seen[u(n.lhs)]) stack.emplace_back(n.lhs, 0);
        continue;
      }
      if (stage == 1) {
        stage = 2;
        if (n.rhs >= 0 && !seen[u(n.rhs)]) stack.emplace_back(n.rhs, 0);
        continue;
      }
      seen[u(id)] = 1;
      order.push_back(id);
      stack.pop_back();
    }
  }
  return order;
}

std::string input_text(argument_layout layout, int n, const node& in) {
  switch (in.input) {
    case input_kind::phi:
      if (layout == argument_layout::state)
        return fmt::format("x[{}]", chain_layout::angle_index(n, in.index));
      return fmt::format("phi[{}]", in.index);
    case input_kind::p:
      if (layout == argument_layout::state)
        return fmt::format("x[{}]", chain_layout::momentum_index(n, in.index));
      return fmt::format("p[{}]", in.index);
    case input_kind::dphi:
      return fmt::format("dphi[{}]", in.index);
    case input_kind::mass:
      return fmt::format("params[{}]", chain_layout::mass_index(n, in.index));
    case input_kind::length:
      return fmt::format("params[{}]", chain_layout::length_index(n, in.index));
    case input_kind::gravity:
      return fmt::format("params[{}]", chain_layout::gravity_index(n));
    case input_kind::com:
      return fmt::format("params[{}]", chain_layout::com_index(n, in.index));
    case input_kind::inertia:
      return fmt::format("params[{}]", chain_layout::inertia_index(n, in.index));
    case input_kind::stiffness:
      return fmt::format("params[{}]", chain_layout::stiffness_index(n, in.index));
    case input_kind::rest_angle:
      return fmt::format("params[{}]", chain_layout::rest_angle_index(n, in.index));
    case input_kind::damping:
      return fmt::format("params[{}]", chain_layout::damping_index(n, in.index));
    case input_kind::drive:
      return fmt::format("inputs[{}]", chain_layout::pivot_acceleration_index(in.index));
    case input_kind::torque:
      return fmt::format("inputs[{}]", chain_layout::torque_index(n, in.index));
    case input_kind::local:
      break;  // a loop kernel's step names its own inputs
    case input_kind::tangent:
      break;  // only the batch kernels take a tangent vector (emit_batch.cpp)
  }
  throw std::logic_error("emit: unknown input");
}

bool layout_has(const emitted_function& f, input_kind kind) {
  const argument_layout layout = f.layout;
  switch (kind) {
    case input_kind::phi:
      return true;
    case input_kind::p:
      return layout == argument_layout::state || layout == argument_layout::phi_p;
    case input_kind::dphi:
      return layout == argument_layout::phi_dphi;
    case input_kind::drive:
    case input_kind::torque:
      return f.takes_inputs;
    default:
      return true;
  }
}

std::string wrap(const printed& p, int min_prec) {
  return p.prec < min_prec ? "(" + p.text + ")" : p.text;
}

std::string signature(const emitted_function& f) {
  std::string args;
  switch (f.layout) {
    case argument_layout::state:
      args = "const double* x";
      break;
    case argument_layout::phi_dphi:
      args = "const double* phi, const double* dphi";
      break;
    case argument_layout::phi_p:
      args = "const double* phi, const double* p";
      break;
    case argument_layout::phi:
      args = "const double* phi";
      break;
  }
  args += ", const double* params";
  if (f.takes_inputs) args += ", const double* inputs";
  if (!f.returns_scalar) args += ", double* " + f.output_name;
  return fmt::format("{} {}({}) noexcept", f.returns_scalar ? "double" : "void", f.name, args);
}

std::string body(int n, const emitted_function& f) {
  const auto leaf = [&](const node& in) {
    if (!layout_has(f, in.input))
      throw std::logic_error("emit: " + f.name + " uses an input it does not take");
    return input_text(f.layout, n, in);
  };
  const emitted_statements st = emit_statements(*f.graph, f.outputs, leaf, "  ");
  std::string text = st.text;
  if (f.returns_scalar) {
    text += fmt::format("  return {};\n", st.outputs.at(0));
  } else {
    for (std::size_t i = 0; i < st.outputs.size(); ++i)
      text += fmt::format("  {}[{}] = {};\n", f.output_name, i, st.outputs[i]);
  }
  return text;
}

std::string doc_comment(const emitted_function& f) {
  std::string out;
  for (const auto& line : f.doc) out += "/// " + line + "\n";
  return out;
}

}  // namespace

emitted_statements emit_statements(const expr_graph& g, const std::vector<sx>& outputs,
                                   const std::function<std::string(const node&)>& leaf,
                                   const std::string& indent) {
  const std::vector<int> order = postorder(g, outputs);
  std::vector<int> uses(u(g.size()), 0);
  for (const int id : order) {
    const node& nd = g.at(id);
    if (nd.lhs >= 0) ++uses[u(nd.lhs)];
    if (nd.rhs >= 0) ++uses[u(nd.rhs)];
  }
  for (const sx out : outputs) ++uses[u(out.id)];

  emitted_statements st;
  std::map<int, printed> done;
  int temporaries = 0;
  for (const int id : order) {
    const node& nd = g.at(id);
    printed p;
    auto child = [&](int c) -> const printed& { return done.at(c); };
    switch (nd.kind) {
      case op::constant:
        p = {literal(nd.value), nd.value < 0 ? int{unary} : int{atom}};
        break;
      case op::input:
        p = {leaf(nd), atom};
        break;
      case op::neg:
        p = {"-" + wrap(child(nd.lhs), unary), unary};
        break;
      case op::add:
      case op::sub: {
        // The right operand is bracketed at equal precedence: a + (b + c) must not be
        // re-associated, or the rounding would differ from the graph's.
        const char* sym = nd.kind == op::add ? " + " : " - ";
        p = {wrap(child(nd.lhs), additive) + sym + wrap(child(nd.rhs), additive + 1), additive};
        break;
      }
      case op::mul:
      case op::div: {
        const char* sym = nd.kind == op::mul ? " * " : " / ";
        p = {wrap(child(nd.lhs), multiplicative) + sym + wrap(child(nd.rhs), multiplicative + 1),
             multiplicative};
        break;
      }
      case op::sin:
        p = {"std::sin(" + child(nd.lhs).text + ")", atom};
        break;
      case op::cos:
        p = {"std::cos(" + child(nd.lhs).text + ")", atom};
        break;
    }
    const bool leaf_node = nd.kind == op::constant || nd.kind == op::input;
    const bool trig = nd.kind == op::sin || nd.kind == op::cos;
    if (!leaf_node && (uses[u(id)] > 1 || trig || p.text.size() > max_inline_length)) {
      const std::string name = fmt::format("t{}", temporaries++);
      st.text += fmt::format("{}const double {} = {};\n", indent, name, p.text);
      p = {name, atom};
    }
    done[id] = p;
  }
  for (const sx out : outputs) st.outputs.push_back(done.at(out.id).text);
  return st;
}

operation_count count_operations(const emitted_function& f) {
  operation_count c;
  for (const int id : postorder(*f.graph, f.outputs)) {
    switch (f.graph->at(id).kind) {
      case op::add:
      case op::sub:
        ++c.add;
        break;
      case op::mul:
        ++c.mul;
        break;
      case op::div:
        ++c.div;
        break;
      case op::neg:
        ++c.neg;
        break;
      case op::sin:
      case op::cos:
        ++c.trig;
        break;
      default:
        break;
    }
  }
  return c;
}

std::string generated_banner(const std::string& command) {
  return fmt::format(
      "// Generated by `{}`: do not edit. Regenerate with `cmake --build <build> --target "
      "npend_regenerate`.\n",
      command);
}

std::string chain_stem(int links, link_kind kind) {
  return fmt::format("{}_{}", kind == link_kind::physical ? "physical" : "chain", links);
}

namespace {

// The header's opening: what the chain is and how its arrays are laid out.
std::string header_preamble(int n, link_kind kind) {
  if (kind != link_kind::physical)
    return fmt::format(
        "#pragma once\n\n"
        "// The planar {0}-link pendulum: point masses m_i on massless rods l_i under "
        "gravity g.\n"
        "// State x = [phi_1..phi_n, p_1..p_n] (dim 2n = {1}); angles from the downward "
        "vertical.\n"
        "// Parameters params = [m_1..m_n, l_1..l_n, g] (dim 2n+1 = {2}).\n"
        "// (The layout is npend::chain_layout's, in <npend/chain_kernels.hpp>.)\n\n"
        "#include <npend/chain_kernels.hpp>\n\n"
        "namespace npend::generated::chain_{0} {{\n\n"
        "inline constexpr int links = {0};\n"
        "inline constexpr int state_size = {1};\n"
        "inline constexpr int param_size = {2};\n\n",
        n, chain_layout::state_size(n), chain_layout::param_size(n));
  return fmt::format(
      "#pragma once\n\n"
      "// The physical planar {0}-link pendulum: rigid links (mass m_i at its centre of mass c_i\n"
      "// down the link, inertia J_i about it), joint springs k_i with rest angles theta0_i,\n"
      "// joint damping b_i and joint torques u_i, the pivot moving with acceleration a.\n"
      "// State x = [phi_1..phi_n, p_1..p_n] (dim 2n = {1}); angles from the downward vertical;\n"
      "// everything in the pivot's frame (docs/model.md).\n"
      "// Parameters params = [m, l, g, c, J, k, theta0, b] (dim 7n+1 = {2}); inputs\n"
      "// w = [a_x, a_y, u_1..u_n] (dim n+2 = {3}).\n"
      "// (The layout is npend::chain_layout's, in <npend/chain_kernels.hpp>.)\n\n"
      "#include <npend/chain_kernels.hpp>\n\n"
      "namespace npend::generated::physical_{0} {{\n\n"
      "inline constexpr int links = {0};\n"
      "inline constexpr int state_size = {1};\n"
      "inline constexpr int param_size = {2};\n"
      "inline constexpr int input_size = {3};\n\n",
      n, chain_layout::state_size(n), chain_layout::physical_param_size(n),
      chain_layout::input_size(n));
}

}  // namespace

chain_sources emit_chain(int n, const std::vector<emitted_function>& functions,
                         const std::string& latex, const std::string& options, link_kind kind) {
  const bool physical = kind == link_kind::physical;
  const std::string stem = chain_stem(n, kind);
  const std::string banner = generated_banner(fmt::format("npend-gen --links {}{}{}{}", n,
                                                          physical ? " --model physical" : "",
                                                          options.empty() ? "" : " ", options));
  chain_sources out;
  out.header = banner + header_preamble(n, kind);
  out.source = banner + fmt::format("#include \"{}.hpp\"\n\n#include <cmath>\n\n", stem) +
               fmt::format("namespace npend::generated::{} {{\n", stem);
  for (const auto& f : functions) {
    out.header += doc_comment(f) + signature(f) + ";\n\n";
    out.source += "\n" + signature(f) + " {\n" + body(n, f) + "}\n";
  }
  const std::string latex_signature = "const char* equations_latex() noexcept";
  out.header += "/// The derived equations as LaTeX (the output of npend-gen --latex).\n" +
                latex_signature + ";\n\n";
  if (latex.find(")npend\"") != std::string::npos)
    throw std::logic_error("emit: the LaTeX text contains the raw-string delimiter");
  out.source += "\n" + latex_signature + " {\n  return R\"npend(" + latex + ")npend\";\n}\n";
  // The table entry, filled by field name from the functions just emitted: the runtime's
  // chain_kernels must have a field of the same name and type for each.
  const char* table = physical ? "physical_kernels" : "chain_kernels";
  out.header += fmt::format(
      "/// This link count's entry of the runtime's kernel table.\nextern const {} kernels;\n\n",
      table);
  out.source += fmt::format(
      "\nconst {} kernels = {{\n    .links = links,\n    .state_size = state_size,\n"
      "    .param_size = param_size,\n{}",
      table, physical ? "    .input_size = input_size,\n" : "");
  for (const auto& f : functions) out.source += fmt::format("    .{0} = &{0},\n", f.name);
  out.source += "    .equations_latex = &equations_latex,\n};\n";
  out.header += fmt::format("}}  // namespace npend::generated::{}\n", stem);
  out.source += fmt::format("\n}}  // namespace npend::generated::{}\n", stem);
  return out;
}

chain_sources emit_index(const std::vector<int>& links) {
  std::string list;
  for (const int n : links) list += (list.empty() ? "" : ",") + std::to_string(n);
  const std::string banner = generated_banner("npend-gen --index " + list);
  chain_sources out;
  out.header = banner + R"(#pragma once

// The table of generated chains, so that the runtime can look a link count up.

#include <npend/chain_kernels.hpp>

namespace npend::generated {

/// The kernels for `links` links, or nullptr when that link count was not built.
const chain_kernels* find_chain(int links) noexcept;

/// The physical chain's kernels for `links` links, or nullptr when not built.
const physical_kernels* find_physical(int links) noexcept;

/// The built link counts, ascending: a pointer to `*count` entries.
const int* built_links(int* count) noexcept;

}  // namespace npend::generated
)";
  out.source = banner + fmt::format("#include \"{}.hpp\"\n\n", index_stem);
  for (const int n : links) out.source += fmt::format("#include \"{}.hpp\"\n", chain_stem(n));
  for (const int n : links)
    out.source += fmt::format("#include \"{}.hpp\"\n", chain_stem(n, link_kind::physical));
  out.source +=
      "\nnamespace npend::generated {\n\nnamespace {\n\nconst chain_kernels* const table[] = {";
  for (std::size_t i = 0; i < links.size(); ++i)
    out.source += fmt::format("{}&chain_{}::kernels", i ? ", " : "", links[i]);
  out.source += "};\n\nconst physical_kernels* const physical_table[] = {";
  for (std::size_t i = 0; i < links.size(); ++i)
    out.source += fmt::format("{}&physical_{}::kernels", i ? ", " : "", links[i]);
  out.source += "};\n\nconst int links_built[] = {";
  for (std::size_t i = 0; i < links.size(); ++i)
    out.source += (i ? ", " : "") + std::to_string(links[i]);
  out.source += R"(};

}  // namespace

const chain_kernels* find_chain(int links) noexcept {
  for (const chain_kernels* k : table)
    if (k->links == links) return k;
  return nullptr;
}

const physical_kernels* find_physical(int links) noexcept {
  for (const physical_kernels* k : physical_table)
    if (k->links == links) return k;
  return nullptr;
}

const int* built_links(int* count) noexcept {
  *count = static_cast<int>(sizeof(links_built) / sizeof(links_built[0]));
  return links_built;
}

}  // namespace npend::generated
)";
  return out;
}

}  // namespace npend::gen

namespace npend::gen {

// For the other emitters (emit_batch.cpp): the same literals and the same order of nodes.
std::string constant_literal(const GiNaC::numeric& value) { return literal(value); }

std::vector<int> evaluation_order(const expr_graph& g, const std::vector<sx>& outputs) {
  return postorder(g, outputs);
}

}  // namespace npend::gen
