// Forward-mode differentiation of an expression graph: the exact derivative of a straight-line
// program along one input, as new nodes of the same graph.
//
// Why: the Jacobian of a kernel whose right-hand side is an O(n) recursion (the rigid-link
// articulated form) follows from the recursion itself — every node's tangent from its
// operands' tangents, in construction order — instead of a hand-derived tangent per
// formulation. Only nodes that depend on the input get a tangent, so one direction through an
// O(n) recursion costs O(n) nodes and the full Jacobian O(n²). Hash-consing shares the
// tangents' common subexpressions with the values', and the results are exact algebra that
// `npend-gen --verify` checks like any other output.
#pragma once

#include <utility>
#include <vector>

#include "expr_graph.hpp"

namespace npend::gen {

/// d outputs / d input for an input node of `graph` (an angle, a momentum, ...): for each
/// output a node of `graph`, the constant 0 where the output does not depend on the input.
/// sin and cos are differentiated as functions of their argument.
std::vector<sx> directional_derivative(expr_graph& graph, const std::vector<sx>& outputs, sx input);

/// The tangent of `outputs` when input node seeds[k].first moves with the tangent
/// seeds[k].second (a node of `graph`): Σ_k ∂output/∂input_k · seed_k, forward mode. With
/// tangent-vector inputs as seeds this is a Jacobian–vector product J·w built from the
/// outputs' own program, O(its size) nodes whatever the number of inputs.
std::vector<sx> tangent_along(expr_graph& graph, const std::vector<sx>& outputs,
                              const std::vector<std::pair<sx, sx>>& seeds);

}  // namespace npend::gen
