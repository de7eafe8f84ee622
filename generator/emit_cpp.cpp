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

// A cart's arguments (cart_layout): the coordinates q = [x, φ_1..φ_n] and their rates and
// momenta, so a link's entry sits one place on from the chain's in phi/dphi/p.

std::string cart_input_text(argument_layout layout, int n, const node& in) {
  const bool state = layout == argument_layout::state;
  switch (in.input) {
    case input_kind::cart_position:
      return state ? fmt::format("x[{}]", cart_layout::cart_position_index) : "phi[0]";
    case input_kind::phi:
      return state ? fmt::format("x[{}]", cart_layout::angle_index(n, in.index))
                   : fmt::format("phi[{}]", 1 + in.index);
    case input_kind::cart_momentum:
      return state ? fmt::format("x[{}]", cart_layout::cart_momentum_index(n)) : "p[0]";
    case input_kind::p:
      return state ? fmt::format("x[{}]", cart_layout::momentum_index(n, in.index))
                   : fmt::format("p[{}]", 1 + in.index);
    case input_kind::cart_velocity:
      return "dphi[0]";
    case input_kind::dphi:
      return fmt::format("dphi[{}]", 1 + in.index);
    case input_kind::cart_mass:
      return fmt::format("params[{}]", cart_layout::cart_mass_index(n));
    case input_kind::cart_damping:
      return fmt::format("params[{}]", cart_layout::cart_damping_index(n));
    case input_kind::cart_force:
      return fmt::format("inputs[{}]", cart_layout::force_index);
    case input_kind::torque:
      return fmt::format("inputs[{}]", cart_layout::torque_index(n, in.index));
    case input_kind::drive:
      throw std::logic_error("emit: a chain on a cart has no pivot drive");
    default:
      return {};  // the parameters of the physical chain, at their places
  }
}

}  // namespace

std::string input_text(argument_layout layout, int n, const node& in, link_kind kind) {
  if (on_cart(kind)) {
    std::string text = cart_input_text(layout, n, in);
    if (!text.empty()) return text;
  }
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
    default:
      break;  // a cart's own inputs (cart_input_text)
  }
  throw std::logic_error("emit: unknown input");
}

namespace {

bool layout_has(const emitted_function& f, input_kind kind) {
  const argument_layout layout = f.layout;
  switch (kind) {
    case input_kind::phi:
      return true;
    case input_kind::p:
    case input_kind::cart_momentum:
      return layout == argument_layout::state || layout == argument_layout::phi_p;
    case input_kind::dphi:
    case input_kind::cart_velocity:
      return layout == argument_layout::phi_dphi;
    case input_kind::drive:
    case input_kind::torque:
    case input_kind::cart_force:
      return f.takes_inputs;
    default:
      return true;
  }
}

std::string wrap(const printed& p, int min_prec) {
  return p.prec < min_prec ? "(" + p.text + ")" : p.text;
}

bool reads_time_inputs(const emitted_function& f) {
  for (const int id : postorder(*f.graph, f.outputs)) {
    const node& nd = f.graph->at(id);
    if (nd.kind == op::input && (nd.input == input_kind::drive || nd.input == input_kind::torque ||
                                 nd.input == input_kind::cart_force))
      return true;
  }
  return false;
}

std::string signature(const emitted_function& f, bool definition = false) {
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
  // The table's signature takes the inputs; the definition of a function that reads none of
  // them (the cart's energies: its force and torques act through Q alone) leaves the
  // parameter unnamed.
  if (f.takes_inputs)
    args += definition && !reads_time_inputs(f) ? ", const double* /*inputs*/"
                                                : ", const double* inputs";
  if (!f.returns_scalar) args += ", double* " + f.output_name;
  return fmt::format("{} {}({}) noexcept", f.returns_scalar ? "double" : "void", f.name, args);
}

std::string body(int n, const emitted_function& f, link_kind kind, const std::string& math) {
  const auto leaf = [&](const node& in) {
    if (!layout_has(f, in.input))
      throw std::logic_error("emit: " + f.name + " uses an input it does not take");
    return input_text(f.layout, n, in, kind);
  };
  const emitted_statements st = emit_statements(*f.graph, f.outputs, leaf, "  ", math);
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
                                   const std::string& indent, const std::string& math) {
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
        p = {math + "sin(" + child(nd.lhs).text + ")", atom};
        break;
      case op::cos:
        p = {math + "cos(" + child(nd.lhs).text + ")", atom};
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
      "npend_regenerate`.\n"
      "// This file is generated code, free to use under the terms of LICENSE-EXCEPTION.md (the "
      "output exception to npend's GPL).\n",
      command);
}

const std::vector<emitted_model>& emitted_models() {
  static const std::vector<emitted_model> models{
      {link_kind::point_mass, "chain", "chain_kernels", "find_chain", "table",
       "The kernels for `links` links, or nullptr when that link count was not built."},
      {link_kind::physical, "physical", "physical_kernels", "find_physical", "physical_table",
       "The physical chain's kernels for `links` links, or nullptr when not built."},
      {link_kind::cart, "cart", "physical_kernels", "cart_kernels_for", "cart_table",
       "The kernels of the chain of `links` links on a cart (cart_layout), or nullptr when not "
       "built."},
  };
  return models;
}

const emitted_model& emitted_model_of(link_kind kind) {
  for (const auto& m : emitted_models())
    if (m.kind == kind) return m;
  throw std::invalid_argument(
      fmt::format("npend-gen writes no kernels for the {} model", link_kind_name(kind)));
}

std::string chain_stem(int links, link_kind kind) {
  return fmt::format("{}_{}", emitted_model_of(kind).stem, links);
}

namespace {

// The header's opening: what the chain is and how its arrays are laid out.
std::string header_preamble(int n, link_kind kind) {
  if (kind == link_kind::cart)
    return fmt::format(
        "#pragma once\n\n"
        "// The physical planar {0}-link pendulum on a cart: a cart of mass M on a horizontal "
        "rail\n"
        "// (viscous damping b_x, pushed by a force F) carries the pivot of rigid links (mass "
        "m_i at\n"
        "// its centre of mass c_i down the link, inertia J_i about it) with joint springs k_i "
        "at\n"
        "// rest angles theta0_i, joint damping b_i and joint torques u_i.\n"
        "// Coordinates q = [x, phi_1..phi_n] (dim n+1 = {4}); state x = [x, phi_1..phi_n, "
        "p_x, p_1..p_n]\n"
        "// (dim 2(n+1) = {1}); angles from the downward vertical, x to the right.\n"
        "// Parameters params = [m, l, g, c, J, k, theta0, b, M, b_x] (dim 7n+3 = {2}); inputs\n"
        "// w = [F, u_1..u_n] (dim n+1 = {3}).\n"
        "// (The layout is npend::cart_layout's, in <npend/chain_kernels.hpp>.)\n\n"
        "#include <npend/chain_kernels.hpp>\n\n"
        "namespace npend::generated::cart_{0} {{\n\n"
        "inline constexpr int links = {0};\n"
        "inline constexpr int state_size = {1};\n"
        "inline constexpr int param_size = {2};\n"
        "inline constexpr int input_size = {3};\n\n",
        n, cart_layout::state_size(n), cart_layout::param_size(n), cart_layout::input_size(n),
        cart_layout::coordinate_count(n));
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

std::string chain_command(int n, const std::string& options, link_kind kind) {
  return fmt::format(
      "npend-gen --links {}{}{}{}", n,
      kind == link_kind::point_mass ? "" : fmt::format(" --model {}", link_kind_name(kind)),
      options.empty() ? "" : " ", options);
}

std::string function_definition(int n, const emitted_function& f, link_kind kind,
                                const std::string& math) {
  return signature(f, true) + " {\n" + body(n, f, kind, math) + "}\n";
}

chain_sources emit_chain(int n, const std::vector<emitted_function>& functions,
                         const std::string& latex, const std::string& options, link_kind kind) {
  const emitted_model& model = emitted_model_of(kind);
  const bool inputs = has_joint_forces(kind);
  const std::string stem = chain_stem(n, kind);
  const std::string banner = generated_banner(chain_command(n, options, kind));
  chain_sources out;
  out.header = banner + header_preamble(n, kind);
  out.source =
      banner +
      fmt::format("#include \"{}.hpp\"\n\n#include <cmath>\n\n#include \"taylor_{}.hpp\"\n\n", stem,
                  stem) +
      fmt::format("namespace npend::generated::{} {{\n", stem);
  for (const auto& f : functions) {
    out.header += doc_comment(f) + signature(f) + ";\n\n";
    out.source += "\n" + function_definition(n, f, kind);
  }
  const std::string latex_signature = "const char* equations_latex() noexcept";
  out.header += "/// The derived equations as LaTeX (the output of npend-gen --latex).\n" +
                latex_signature + ";\n\n";
  if (latex.find(")npend\"") != std::string::npos)
    throw std::logic_error("emit: the LaTeX text contains the raw-string delimiter");
  out.source += "\n" + latex_signature + " {\n  return R\"npend(" + latex + ")npend\";\n}\n";
  // The table entry, filled by field name from the functions just emitted: the runtime's
  // kernel table must have a field of the same name and type for each.
  out.header += fmt::format(
      "/// This link count's entry of the runtime's kernel table.\nextern const {} kernels;\n\n",
      model.table);
  out.source += fmt::format(
      "\nconst {} kernels = {{\n    .links = links,\n    .state_size = state_size,\n"
      "    .param_size = param_size,\n{}",
      model.table, inputs ? "    .input_size = input_size,\n" : "");
  for (const auto& f : functions) out.source += fmt::format("    .{0} = &{0},\n", f.name);
  out.source += fmt::format(
      "    .equations_latex = &equations_latex,\n    .taylor = &taylor_{}::kernels,\n}};\n", stem);
  out.header += fmt::format("}}  // namespace npend::generated::{}\n", stem);
  out.source += fmt::format("\n}}  // namespace npend::generated::{}\n", stem);
  return out;
}

chain_sources emit_lookup_index(const lookup_index& index, const std::vector<int>& links) {
  std::string list;
  for (const int n : links) list += (list.empty() ? "" : ",") + std::to_string(n);
  const std::string banner = generated_banner("npend-gen --index " + list);
  const std::string open_inline =
      index.inline_namespace.empty() ? "" : "inline namespace " + index.inline_namespace + " {\n\n";
  const std::string close_inline =
      index.inline_namespace.empty() ? "" : "}  // namespace " + index.inline_namespace + "\n";
  chain_sources out;
  out.header = banner + "#pragma once\n\n" + index.intro + "\n#include <" + index.include +
               ">\n\nnamespace npend::generated {\n\n" + open_inline;
  for (const auto& t : index.tables)
    out.header +=
        fmt::format("/// {}\nconst {}* {}(int links) noexcept;\n\n", t.doc, t.type, t.lookup);
  if (index.built_links)
    out.header +=
        "/// The built link counts, ascending: a pointer to `*count` entries.\n"
        "const int* built_links(int* count) noexcept;\n\n";
  out.header += close_inline + "}  // namespace npend::generated\n";

  out.source = banner + fmt::format("#include \"{}.hpp\"\n\n", index.stem);
  for (const auto& t : index.tables)
    for (const int n : links) out.source += fmt::format("#include \"{}_{}.hpp\"\n", t.stem, n);
  out.source += "\nnamespace npend::generated {\n\n" + open_inline + "namespace {\n";
  for (const auto& t : index.tables) {
    out.source += fmt::format("\nconst {}* const {}[] = {{", t.type, t.array);
    for (std::size_t i = 0; i < links.size(); ++i)
      out.source += fmt::format("{}&{}_{}::kernels", i ? ", " : "", t.stem, links[i]);
    out.source += "};\n";
  }
  if (index.built_links) {
    out.source += "\nconst int links_built[] = {";
    for (std::size_t i = 0; i < links.size(); ++i)
      out.source += (i ? ", " : "") + std::to_string(links[i]);
    out.source += "};\n";
  }
  out.source += "\n}  // namespace\n";
  for (const auto& t : index.tables)
    out.source += fmt::format(
        "\nconst {0}* {1}(int links) noexcept {{\n  for (const {0}* k : {2})\n"
        "    if (k->links == links) return k;\n  return nullptr;\n}}\n",
        t.type, t.lookup, t.array);
  if (index.built_links)
    out.source +=
        "\nconst int* built_links(int* count) noexcept {\n"
        "  *count = static_cast<int>(sizeof(links_built) / sizeof(links_built[0]));\n"
        "  return links_built;\n}\n";
  out.source += "\n" + close_inline + "}  // namespace npend::generated\n";
  return out;
}

chain_sources emit_index(const std::vector<int>& links) {
  lookup_index index{index_stem,
                     "// The table of generated chains, so that the runtime can look a link "
                     "count up.\n",
                     "npend/chain_kernels.hpp",
                     {},
                     true};
  for (const auto& m : emitted_models())
    index.tables.push_back({m.table, m.lookup, m.doc, m.array, m.stem});
  return emit_lookup_index(index, links);
}

}  // namespace npend::gen

namespace npend::gen {

// For the other emitters (emit_batch.cpp): the same literals and the same order of nodes.
std::string constant_literal(const GiNaC::numeric& value) { return literal(value); }

std::vector<int> evaluation_order(const expr_graph& g, const std::vector<sx>& outputs) {
  return postorder(g, outputs);
}

}  // namespace npend::gen
