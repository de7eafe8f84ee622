// The implementations of the chain's Hamilton equations that the benchmarks compare, behind
// one interface, so that every one is timed through the same kind of call and checked
// against the generated kernels by the same code.
#pragma once

#include <array>
#include <memory>
#include <string_view>

#include "npend/parameters.hpp"

namespace npend::bench {

/// Table order: npend's generated kernels, its loop kernels for any n (generated/chain_loop.*),
/// the hand-written O(n) recursion
/// (tests/reference/include/reference/chain_recursion.hpp), the hand-written dense Eigen
/// implementation (tests/reference/include/reference/dense_chain.hpp), SymPy's generated C
/// (bench/sympy_peer.py) and npend's physical kernels (generated/physical_<n>: the general chain,
/// run here on the same point masses with c = l, no springs, damping or drive, so that it computes
/// the same f) and the hand-written O(n) recursion of the physical chain
/// (tests/reference/include/reference/physical_recursion.hpp), on the same chain: the physical
/// kernels' lower limit.
inline constexpr std::array<std::string_view, 7> implementation_names{
    "generated", "loop", "recursion", "eigen", "sympy", "physical", "physical-recursion"};

/// One implementation for one chain (its parameters fixed). Not thread-safe: the
/// hand-written ones keep a workspace.
class chain_implementation {
 public:
  virtual ~chain_implementation() = default;

  /// Hamilton's equations: dxdt = f(x), x = [φ_1..φ_n, p_1..p_n], both dim 2n.
  virtual void rhs(const double* x, double* dxdt) = 0;

  /// Whether jacobian() exists (the recursion only computes the right-hand side).
  virtual bool has_jacobian() const = 0;

  /// ∂f/∂x, row-major 2n × 2n. Throws std::logic_error when !has_jacobian().
  virtual void jacobian(const double* x, double* jac) = 0;
};

/// The implementation `name` (one of implementation_names) for a chain with these
/// parameters, or nullptr when this build has none for its link count (generated: n not in
/// NPEND_LINKS; sympy: n not in NPEND_SYMPY_LINKS). Throws std::invalid_argument for an
/// unknown name or invalid parameters.
std::unique_ptr<chain_implementation> make_implementation(std::string_view name,
                                                          const chain_parameters& params);

}  // namespace npend::bench
