#include "emit_batch.hpp"

#include <fmt/format.h>

#include <map>
#include <npend/chain_kernels.hpp>
#include <stdexcept>
#include <utility>

#include "forward_diff.hpp"

namespace npend::gen {

namespace {

std::size_t u(int i) { return static_cast<std::size_t>(i); }

// As emit_cpp.cpp: long expressions become named temporaries.
constexpr std::size_t max_inline_length = 64;

enum precedence : int { additive = 1, multiplicative = 2, unary = 3, atom = 4 };

struct printed {
  std::string text;
  int prec = atom;
};

std::string wrap(const printed& p, int min_prec) {
  return p.prec < min_prec ? "(" + p.text + ")" : p.text;
}

// Coordinate i of lane l in a structure-of-arrays array.
std::string lane(const char* array, int i) { return fmt::format("{}[{} * W + l]", array, i); }

std::string input_text(int n, const node& in) {
  switch (in.input) {
    case input_kind::phi:
      return lane("x", chain_layout::angle_index(n, in.index));
    case input_kind::p:
      return lane("x", chain_layout::momentum_index(n, in.index));
    case input_kind::mass:
      return fmt::format("params[{}]", chain_layout::mass_index(n, in.index));
    case input_kind::length:
      return fmt::format("params[{}]", chain_layout::length_index(n, in.index));
    case input_kind::gravity:
      return fmt::format("params[{}]", chain_layout::gravity_index(n));
    case input_kind::tangent:
      return lane("w", in.index);
    default:
      throw std::logic_error("emit_batch: the point-mass rhs reads only phi, p, m, l and g");
  }
}

// The angle index of sin(φ_i)/cos(φ_i); anything else is an error.
int trig_angle(const expr_graph& g, const node& nd) {
  const node& arg = g.at(nd.lhs);
  if (arg.kind != op::input || arg.input != input_kind::phi)
    throw std::logic_error("emit_batch: a sine or cosine of something other than an angle");
  return arg.index;
}

// Which nodes of `order` read nothing but the parameters and constants: the same in every
// lane and every block, so computed once per call, before the loop over the blocks. (A
// division by a mass or length costs as much as the lanes' one true division; repeated per
// block, they kept the divider busy for 37 % of rhs_batch's time, measured with perf.)
std::vector<char> parameters_only(const expr_graph& g, const std::vector<int>& order) {
  std::vector<char> only(u(g.size()), 0);
  for (const int id : order) {
    const node& nd = g.at(id);
    switch (nd.kind) {
      case op::constant:
        only[u(id)] = 1;
        break;
      case op::input:
        only[u(id)] = nd.input == input_kind::mass || nd.input == input_kind::length ||
                      nd.input == input_kind::gravity;
        break;
      case op::sin:
      case op::cos:
        break;
      default:
        only[u(id)] = (nd.lhs < 0 || only[u(nd.lhs)]) && (nd.rhs < 0 || only[u(nd.rhs)]);
    }
  }
  return only;
}

// The nodes of parameters_only that the rest of the program (or an output) reads: each
// becomes a named temporary before the loop over the blocks, the rest of their expression
// inlined into it.
std::vector<char> hoisted_nodes(const expr_graph& g, const std::vector<int>& order,
                                const std::vector<char>& only, const std::vector<sx>& outputs) {
  std::vector<char> hoisted(u(g.size()), 0);
  for (const int id : order) {
    const node& nd = g.at(id);
    if (only[u(id)]) continue;
    for (const int operand : {nd.lhs, nd.rhs})
      if (operand >= 0 && only[u(operand)]) hoisted[u(operand)] = 1;
  }
  for (const sx out : outputs)
    if (only[u(out.id)]) hoisted[u(out.id)] = 1;
  return hoisted;
}

// Prints the nodes of a straight-line program over lanes, one statement at a time: the state,
// the tangent vector w and the parameters as inputs, the sines and cosines read from the
// arrays s and c. A node used more than once, or too long to inline, becomes a temporary.
class lane_printer {
 public:
  lane_printer(int n, const expr_graph& g, const std::vector<int>& order,
               const std::vector<sx>& outputs)
      : m_n(n), m_g(g), m_uses(u(g.size()), 0) {
    for (const int id : order) {
      const node& nd = g.at(id);
      if (nd.lhs >= 0) ++m_uses[u(nd.lhs)];
      if (nd.rhs >= 0) ++m_uses[u(nd.rhs)];
    }
    for (const sx out : outputs) ++m_uses[u(out.id)];
  }

  // Prints node id (its operands printed before) into text; `temporary` forces a named one.
  void print(int id, std::string& text, bool temporary = false) {
    const node& nd = m_g.at(id);
    printed p;
    auto child = [&](int c) -> const printed& { return m_done.at(c); };
    switch (nd.kind) {
      case op::constant:
        p = {constant_literal(nd.value), nd.value < 0 ? int{unary} : int{atom}};
        break;
      case op::input:
        p = {input_text(m_n, nd), atom};
        break;
      case op::neg:
        p = {"-" + wrap(child(nd.lhs), unary), unary};
        break;
      case op::add:
      case op::sub: {
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
        p = {lane("s", trig_angle(m_g, nd)), atom};
        break;
      case op::cos:
        p = {lane("c", trig_angle(m_g, nd)), atom};
        break;
    }
    if (!is_leaf(id) && (temporary || m_uses[u(id)] > 1 || p.text.size() > max_inline_length)) {
      const std::string name = fmt::format("t{}", m_temporaries++);
      text += fmt::format("    const double {} = {};\n", name, p.text);
      p = {name, atom};
    }
    m_done[id] = p;
  }

  // What node id prints as from now on (a value the tangent loop reads back from v).
  void rename(int id, std::string text) { m_done[id] = {std::move(text), atom}; }
  const std::string& text_of(int id) const { return m_done.at(id).text; }
  bool is_leaf(int id) const {
    const op k = m_g.at(id).kind;
    return k == op::constant || k == op::input || k == op::sin || k == op::cos;
  }

 private:
  int m_n;
  const expr_graph& m_g;
  std::vector<int> m_uses;
  std::map<int, printed> m_done;
  int m_temporaries = 0;
};

// Output k of a lane body: lane("dxdt", k), then lane("dwdt", k - 2n).
std::string output_target(int n, int k) {
  const int d = chain_layout::state_size(n);
  return k < d ? lane("dxdt", k) : lane("dwdt", k - d);
}

// A kernel's program: what it computes once per call from the parameters (`prelude`), and
// the loop body over a block's lanes (`body`), both as printed by lane_printer (statements
// indented for the lane loop).
struct lane_program {
  std::string prelude, body;
};

// The program of the state (the scalar rhs's, or it with its tangent), with output k written
// to output_target(n, k).
lane_program lane_body(int n, const expr_graph& g, const std::vector<sx>& outputs) {
  const std::vector<int> order = evaluation_order(g, outputs);
  const std::vector<char> only = parameters_only(g, order);
  const std::vector<char> hoisted = hoisted_nodes(g, order, only, outputs);
  lane_printer printer(n, g, order, outputs);
  lane_program out;
  for (const int id : order)
    if (only[u(id)])
      printer.print(id, out.prelude, hoisted[u(id)] != 0);
    else
      printer.print(id, out.body);
  for (std::size_t i = 0; i < outputs.size(); ++i)
    out.body += fmt::format("    {} = {};\n", output_target(n, static_cast<int>(i)),
                            printer.text_of(outputs[i].id));
  return out;
}

// The rhs's outputs followed by its tangent along w: J(x) w by forward mode through the same
// straight-line program (forward_diff.hpp), added to g (a copy of the rhs's graph).
std::vector<sx> with_tangent(int n, expr_graph& g, const emitted_function& rhs) {
  std::vector<sx> outputs;
  for (const sx out : rhs.outputs) outputs.push_back(sx{&g, out.id});
  std::vector<std::pair<sx, sx>> seeds;
  for (int i = 0; i < n; ++i)
    seeds.emplace_back(g.input(input_kind::phi, i), g.input(input_kind::tangent, i));
  for (int i = 0; i < n; ++i)
    seeds.emplace_back(g.input(input_kind::p, i), g.input(input_kind::tangent, n + i));
  const std::vector<sx> tangents = tangent_along(g, outputs, seeds);
  outputs.insert(outputs.end(), tangents.begin(), tangents.end());
  return outputs;
}

lane_program tangent_lane_body(int n, const emitted_function& rhs) {
  expr_graph g = *rhs.graph;
  const std::vector<sx> outputs = with_tangent(n, g, rhs);
  return lane_body(n, g, outputs);
}

// Every line of text `by` spaces further in (by > 0) or out (by < 0), but pragmas.
std::string reindent(const std::string& text, int by) {
  std::string out;
  std::size_t start = 0;
  while (start < text.size()) {
    const std::size_t end = text.find('\n', start);
    const std::string line = text.substr(start, end - start + 1);
    if (line.front() == '#')  // a pragma stays at the line's start
      out += line;
    else
      out += by >= 0 ? std::string(u(by), ' ') + line : line.substr(u(-by));
    start = end + 1;
  }
  return out;
}

// A kernel's text: the prelude, then the loop over `blocks` blocks of W lanes, the arrays
// `advanced` moving on by `stride` doubles from block to block; `block` (indented for the
// block loop) reads the block's sines and cosines of the n angles from s and c, and has a
// buffer v of `kept` values per lane when kept > 0. The sines of up to batch_blocks blocks
// are taken first, then their arithmetic, block after block, so that the processor overlaps
// the blocks' divisions (taken block by block, each block's arithmetic waited for its own).
std::string block_kernel(int n, const std::string& prelude, const std::string& advanced,
                         std::size_t kept, const std::string& block) {
  const std::string buffer = kept > 0 ? fmt::format("      double v[{} * W];\n", kept) : "";
  return fmt::format(
      "  constexpr int W = batch_width;\n{0}"
      "  for (int first = 0; first < blocks; first += batch_blocks) {{\n"
      "    const int chunk = blocks - first < batch_blocks ? blocks - first : batch_blocks;\n"
      "    double sines[batch_blocks * {2} * W], cosines[batch_blocks * {2} * W];\n"
      "    for (int b = 0; b < chunk; ++b)\n"
      "      for (int i = 0; i < {2}; ++i)\n"
      "        batch_sincos(x + b * stride + i * W, sines + (b * {2} + i) * W,\n"
      "                     cosines + (b * {2} + i) * W);\n"
      "    for (int b = 0; b < chunk; ++b, {1}) {{\n"
      "      const double* s = sines + b * {2} * W;\n"
      "      const double* c = cosines + b * {2} * W;\n"
      "{3}{4}"
      "    }}\n"
      "  }}\n",
      reindent(prelude, -2), advanced, n, buffer, reindent(block, 2));
}

// One lane loop over `body` (statements printed for the lane loop), inside the block loop.
std::string lane_loop(const std::string& body) {
  return "#pragma omp simd\n    for (int l = 0; l < W; ++l) {\n" + reindent(body, 2) + "    }\n";
}

// The body of tangents_batch: tangent_batch's program split in two. The statements that do
// not read w run once — they give dxdt, and the values the tangent statements read are kept
// per lane in v — and the statements that read w run once per vector, in their own lane
// loop. Each vector's arithmetic is tangent_batch's, in the same order.
std::string tangents_body(int n, const emitted_function& rhs) {
  expr_graph g = *rhs.graph;
  const std::vector<sx> outputs = with_tangent(n, g, rhs);
  const std::vector<int> order = evaluation_order(g, outputs);
  const std::vector<char> only = parameters_only(g, order);
  const std::vector<char> hoisted = hoisted_nodes(g, order, only, outputs);
  std::vector<char> reads_w(u(g.size()), 0), kept(u(g.size()), 0);
  for (const int id : order) {
    const node& nd = g.at(id);
    reads_w[u(id)] = (nd.kind == op::input && nd.input == input_kind::tangent) ||
                     (nd.lhs >= 0 && reads_w[u(nd.lhs)]) || (nd.rhs >= 0 && reads_w[u(nd.rhs)]);
  }
  lane_printer printer(n, g, order, outputs);
  // A value the tangent statements read goes through v, unless it is computed once per call.
  const auto keep = [&](int id) {
    if (!reads_w[u(id)] && !only[u(id)] && !printer.is_leaf(id)) kept[u(id)] = 1;
  };
  for (const int id : order) {
    const node& nd = g.at(id);
    if (!reads_w[u(id)]) continue;
    for (const int operand : {nd.lhs, nd.rhs})
      if (operand >= 0) keep(operand);
  }
  const int d = chain_layout::state_size(n);
  for (std::size_t i = u(d); i < outputs.size(); ++i) keep(outputs[i].id);  // reads no w
  std::string prelude, values, stores, tangents;
  std::vector<int> slots;
  for (const int id : order) {
    if (reads_w[u(id)]) continue;
    if (only[u(id)])
      printer.print(id, prelude, hoisted[u(id)] != 0);
    else
      printer.print(id, values, kept[u(id)] != 0);
  }
  for (int k = 0; k < d; ++k)
    values += fmt::format("    {} = {};\n", output_target(n, k), printer.text_of(outputs[u(k)].id));
  for (const int id : order)
    if (kept[u(id)]) {
      const int slot = static_cast<int>(slots.size());
      slots.push_back(id);
      stores += fmt::format("    v[{} * W + l] = {};\n", slot, printer.text_of(id));
      printer.rename(id, fmt::format("v[{} * W + l]", slot));
    }
  for (const int id : order)
    if (reads_w[u(id)]) printer.print(id, tangents);
  for (std::size_t i = u(d); i < outputs.size(); ++i)
    tangents += fmt::format("    {} = {};\n", output_target(n, static_cast<int>(i)),
                            printer.text_of(outputs[i].id));
  const std::string per_vector = fmt::format(
      "    for (int j = 0; j < count; ++j) {{\n"
      "      const double* w = ws + j * {0} * W;\n"
      "      double* dwdt = dws + j * {0} * W;\n"
      "{1}"
      "    }}\n",
      d, reindent(lane_loop(tangents), 2));
  return block_kernel(n, prelude, "x += stride, ws += stride, dxdt += stride, dws += stride",
                      slots.size(), lane_loop(values + stores) + per_vector);
}

const char* batch_signature =
    "void rhs_batch(const double* x, const double* params, double* dxdt, int blocks,\n"
    "               std::size_t stride) noexcept";
const char* tangent_signature =
    "void tangent_batch(const double* x, const double* w, const double* params, double* dxdt,\n"
    "                   double* dwdt, int blocks, std::size_t stride) noexcept";
const char* tangents_signature =
    "void tangents_batch(const double* x, const double* ws, int count, const double* params,\n"
    "                    double* dxdt, double* dws, int blocks, std::size_t stride) noexcept";

}  // namespace

std::string batch_stem(int links) { return fmt::format("batch_{}", links); }

namespace {

// The batch kernels' definitions sit in the inline namespace of the ISA they are compiled for
// (npend/batch_math.hpp), so that one program holds them for several ISAs, picked at run
// time (the map's lanes, runtime/src/analysis/chaos/map_lanes.hpp).
constexpr const char* isa_namespace_open = "inline namespace NPEND_BATCH_ISA_NAMESPACE {\n";
constexpr const char* isa_namespace_close = "}  // namespace NPEND_BATCH_ISA_NAMESPACE\n";

}  // namespace

chain_sources emit_batch(int n, const emitted_function& rhs) {
  if (rhs.layout != argument_layout::state || rhs.returns_scalar || rhs.takes_inputs)
    throw std::logic_error("emit_batch: expects the point-mass chain's rhs");
  const std::string stem = batch_stem(n);
  const std::string banner = generated_banner(fmt::format("npend-gen --links {}", n));
  chain_sources out;
  out.header = banner + fmt::format(
                            "#pragma once\n\n"
                            "// The batch kernels of the planar {0}-link pendulum (point masses): "
                            "the rhs of chain_{0}.hpp\n"
                            "// on W = npend::batch_width states at once, structure-of-arrays: "
                            "coordinate i of lane l\n"
                            "// at [i*W + l]. Parameters params = [m_1..m_n, l_1..l_n, g] "
                            "(dim 2n+1 = {1}), shared by the lanes.\n\n"
                            "#include <npend/batch_kernels.hpp>\n\n"
                            "namespace npend::generated::{2} {{\n{3}\n"
                            "inline constexpr int links = {0};\n\n",
                            n, chain_layout::param_size(n), stem, isa_namespace_open);
  out.header += fmt::format(
      "/// Hamilton's equations on `blocks` blocks of W lanes, block b at x + b*stride and\n"
      "/// dxdt + b*stride (each block dim 2n*W = {}*W); each lane as chain_{}::rhs, with\n"
      "/// SLEEF's 1-ulp sines and cosines. What depends on the parameters alone is computed\n"
      "/// once per call.\n{};\n\n",
      chain_layout::state_size(n), n, batch_signature);
  out.header += fmt::format(
      "/// Hamilton's equations and their tangent on W lanes: dxdt = f(x) as rhs_batch, and\n"
      "/// dwdt = J(x) w, the Jacobian–vector product for the tangent vectors w (dim 2n*W),\n"
      "/// forward mode through rhs_batch's program; blocks as rhs_batch's (w and dwdt\n"
      "/// advance by stride too).\n{};\n\n",
      tangent_signature);
  out.header += fmt::format(
      "/// tangent_batch for `count` tangent vectors at once: ws and dws hold them one after\n"
      "/// another (vector j at ws + j*2n*W); f(x) and the values the tangents share are\n"
      "/// computed once, each vector's J(x) w as tangent_batch computes it; blocks as\n"
      "/// rhs_batch's (ws and dws advance by stride too).\n{};\n\n",
      tangents_signature);
  out.header += fmt::format(
      "/// This link count's entry of the runtime's batch kernel table.\n"
      "extern const batch_kernels kernels;\n\n{}}}  // namespace npend::generated::{}\n",
      isa_namespace_close, stem);

  out.source = banner + fmt::format("#include \"{}.hpp\"\n\n", stem) +
               fmt::format("namespace npend::generated::{} {{\n{}\n", stem, isa_namespace_open);
  const lane_program plain = lane_body(n, *rhs.graph, rhs.outputs);
  out.source +=
      fmt::format("{} {{\n", batch_signature) +
      block_kernel(n, plain.prelude, "x += stride, dxdt += stride", 0, lane_loop(plain.body)) +
      "}\n";
  const lane_program tangent = tangent_lane_body(n, rhs);
  out.source +=
      fmt::format("\n{} {{\n", tangent_signature) +
      block_kernel(n, tangent.prelude, "x += stride, w += stride, dxdt += stride, dwdt += stride",
                   0, lane_loop(tangent.body)) +
      "}\n";
  out.source += fmt::format("\n{} {{\n", tangents_signature) + tangents_body(n, rhs) + "}\n";
  out.source += fmt::format(
      "\nconst batch_kernels kernels = {{\n    .links = links,\n    .width = batch_width,\n"
      "    .rhs_batch = &rhs_batch,\n    .tangent_batch = &tangent_batch,\n"
      "    .tangents_batch = &tangents_batch,\n}};\n\n"
      "{}}}  // namespace npend::generated::{}\n",
      isa_namespace_close, stem);
  return out;
}

chain_sources emit_batch_index(const std::vector<int>& links) {
  return emit_lookup_index(
      {batch_index_stem,
       "// The table of generated batch kernels (point-mass chains), so that the runtime can "
       "look a\n// link count up.\n",
       "npend/batch_kernels.hpp",
       {{"batch_kernels", "find_batch",
         "The batch kernels for `links` links, or nullptr when that link count was not built.",
         "table", "batch"}},
       false,
       "NPEND_BATCH_ISA_NAMESPACE"},
      links);
}

}  // namespace npend::gen
