#include "forward_diff.hpp"

#include <algorithm>
#include <stdexcept>

namespace npend::gen {

namespace {

std::size_t u(int i) { return static_cast<std::size_t>(i); }

// Marks the nodes the outputs are computed from (node ids are topological: operands first).
std::vector<char> needed_nodes(const expr_graph& graph, const std::vector<sx>& outputs) {
  std::vector<char> needed(u(graph.size()), 0);
  for (const sx out : outputs) needed[u(out.id)] = 1;
  for (int id = graph.size() - 1; id >= 0; --id) {
    if (!needed[u(id)]) continue;
    const node& n = graph.at(id);
    if (n.lhs >= 0) needed[u(n.lhs)] = 1;
    if (n.rhs >= 0) needed[u(n.rhs)] = 1;
  }
  return needed;
}

}  // namespace

std::vector<sx> directional_derivative(expr_graph& graph, const std::vector<sx>& outputs,
                                       sx input) {
  return tangent_along(graph, outputs, {{input, graph.constant(1)}});
}

std::vector<sx> tangent_along(expr_graph& graph, const std::vector<sx>& outputs,
                              const std::vector<std::pair<sx, sx>>& seeds) {
  const int size = graph.size();  // the tangents' own nodes are appended past this
  const std::vector<char> needed = needed_nodes(graph, outputs);
  // tangent[id] = -1: the node does not depend on the seeded inputs.
  std::vector<int> tangent(u(size), -1);
  int first = size;
  for (const auto& [input, seed] : seeds) {
    if (graph.at(input.id).kind != op::input)
      throw std::logic_error("tangent_along: a direction must be an input node");
    tangent[u(input.id)] = seed.id;
    first = std::min(first, input.id);
  }
  const auto d = [&](int id) { return sx{&graph, tangent[u(id)]}; };
  const auto has = [&](int id) { return id >= 0 && tangent[u(id)] >= 0; };
  for (int id = first + 1; id < size; ++id) {
    if (!needed[u(id)]) continue;
    const node n = graph.at(id);  // a copy: creating nodes may reallocate the node storage
    if (!has(n.lhs) && !has(n.rhs)) continue;
    const sx a{&graph, n.lhs}, b{&graph, n.rhs}, self{&graph, id};
    sx t;
    switch (n.kind) {
      case op::neg:
        t = -d(n.lhs);
        break;
      case op::add:
        t = has(n.lhs) && has(n.rhs) ? d(n.lhs) + d(n.rhs) : has(n.lhs) ? d(n.lhs) : d(n.rhs);
        break;
      case op::sub:
        t = has(n.lhs) && has(n.rhs) ? d(n.lhs) - d(n.rhs) : has(n.lhs) ? d(n.lhs) : -d(n.rhs);
        break;
      case op::mul:
        if (has(n.lhs) && has(n.rhs))
          t = d(n.lhs) * b + a * d(n.rhs);
        else
          t = has(n.lhs) ? d(n.lhs) * b : a * d(n.rhs);
        break;
      case op::div:
        // (a/b)' = (a' − (a/b) b') / b: the quotient is a node already.
        if (has(n.lhs) && has(n.rhs))
          t = (d(n.lhs) - self * d(n.rhs)) / b;
        else
          t = has(n.lhs) ? d(n.lhs) / b : -(self * d(n.rhs) / b);
        break;
      case op::sin:
        t = graph.cos(a) * d(n.lhs);
        break;
      case op::cos:
        t = -(graph.sin(a) * d(n.lhs));
        break;
      case op::constant:
      case op::input:
        continue;
    }
    tangent[u(id)] = t.id;
  }
  std::vector<sx> out;
  out.reserve(outputs.size());
  for (const sx o : outputs) out.push_back(has(o.id) ? d(o.id) : graph.constant(0));
  return out;
}

}  // namespace npend::gen
