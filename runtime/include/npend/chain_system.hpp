// The chain as something Boost.Odeint integrates: a System (x, dxdt, t) calling the
// generated right-hand side, and the (rhs, jacobian) pair that implicit steppers take.
#pragma once

#include <cstddef>
#include <span>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>

#include "npend/chain.hpp"

namespace npend {

namespace detail {

/// Checks that a state or derivative handed to a system has the chain's dimension.
inline void check_system_size(std::size_t got, int expected, const char* what) {
  if (got != static_cast<std::size_t>(expected))
    throw std::invalid_argument(std::string(what) + " has " + std::to_string(got) +
                                " entries; the system has dimension " + std::to_string(expected));
}

}  // namespace detail

/// Hamilton's equations of a chain as odeint's System concept: `sys(x, dxdt, t)` sets
/// dxdt = f(x, t) (both dim 2n; x = [φ_1..φ_n, p_1..p_n], or on a cart dim 2(n + 1)); t matters
/// only where the pivot moves. It works with any contiguous state type that has `size()` and
/// `operator[]` (std::vector<double>, std::span<double>, Eigen vectors).
///
/// A chain_system refers to the chain it was made from (its kernel set), so the chain must
/// outlive it; copying it is cheap, as odeint expects.
class chain_system {
 public:
  explicit chain_system(const chain& c) : m_kernels(&c.kernels_in_use()), m_size(c.state_size()) {}

  /// Throws std::invalid_argument if x or dxdt does not have dimension 2n.
  template <class State, class Deriv>
  void operator()(const State& x, Deriv& dxdt, double t) const {
    detail::check_system_size(x.size(), m_size, "state x");
    detail::check_system_size(dxdt.size(), m_size, "dxdt");
    m_kernels->rhs(&x[0], t, &dxdt[0]);
  }

  /// The state dimension 2n.
  int size() const { return m_size; }

 private:
  const kernel_set* m_kernels;
  int m_size;
};

/// The exact Jacobian of a chain's Hamilton equations in the form odeint's implicit
/// steppers call it: `jac(x, J, t, dfdt)` sets J = ∂f/∂x (dim 2n × 2n) and dfdt = ∂f/∂t
/// (dim 2n; zero unless the pivot moves). J is a row-major Eigen matrix (a column-major one is
/// rejected at compile time). Refers to its chain like chain_system.
///
/// (odeint's own rosenbrock4 takes ublas matrices, and Boost 1.74's ublas does not compile
/// as C++20; npend runs it through detail::rosenbrock4_dense_output, which hands this
/// functor an Eigen matrix.)
class chain_jacobian {
 public:
  explicit chain_jacobian(const chain& c) : m_chain(&c), m_size(c.state_size()) {}

  /// Throws std::invalid_argument if x, J or dfdt has the wrong dimension.
  template <class State, class Matrix, class Deriv>
  void operator()(const State& x, Matrix& J, double t, Deriv& dfdt) const {
    static_assert(Matrix::IsRowMajor, "chain_jacobian writes row-major matrices");
    detail::check_system_size(x.size(), m_size, "state x");
    detail::check_system_size(static_cast<std::size_t>(J.rows()), m_size, "jacobian (rows)");
    detail::check_system_size(static_cast<std::size_t>(J.cols()), m_size, "jacobian (columns)");
    detail::check_system_size(dfdt.size(), m_size, "dfdt");
    m_chain->evaluate_jacobian(&x[0], t, &J(0, 0));
    if (m_chain->parameters().pivot.moves()) {
      m_chain->time_derivative(std::span<const double>(&x[0], static_cast<std::size_t>(m_size)),
                               std::span<double>(&dfdt[0], static_cast<std::size_t>(m_size)), t);
      return;
    }
    for (int i = 0; i < m_size; ++i) dfdt[i] = 0.0;
  }

  int size() const { return m_size; }

 private:
  const chain* m_chain;
  int m_size;
};

/// The pair (rhs, jacobian) — odeint's form of an implicit system — that
/// npend::gauss_legendre, the rosenbrock4 of npend::integrate_system and
/// npend::integrate_system take. The chain must outlive the pair.
inline std::pair<chain_system, chain_jacobian> make_implicit_system(const chain& c) {
  return {chain_system(c), chain_jacobian(c)};
}

}  // namespace npend
