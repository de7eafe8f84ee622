#include "npend/analysis/chaos/toda_brumer.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "analysis/detail/dense_eigen.hpp"

namespace npend {

namespace {

// Whether V is a sum of one term per angle, V = Σ_k g s_k (1 − cos φ_k) with s_k the first
// moment of the mass at and below link k about its joint (s_k = μ_k l_k for point masses):
// gravity alone, no joint springs (which couple neighbours) and a fixed pivot.
bool separable_potential(const chain& c) {
  const auto& k = c.parameters().stiffness;
  return std::all_of(k.begin(), k.end(), [](double v) { return v == 0; }) &&
         !c.parameters().pivot.moves();
}

// g s_k for a separable V: its gradient g s_k sin φ_k at φ = π/2 everywhere. O(n) time and
// memory, where the Hessian of a long chain would be n² (80 GB for 100000 links).
std::vector<double> separable_curvatures(const chain& c) {
  const auto n = static_cast<std::size_t>(c.links());
  std::vector<double> quarter(n, std::numbers::pi / 2), grad(n);
  c.potential_gradient(quarter, grad);
  return grad;
}

}  // namespace

std::vector<double> toda_brumer_eigenvalues(const chain& c, std::span<const double> phi) {
  const int n = c.links();
  if (phi.size() != static_cast<std::size_t>(n))
    throw std::invalid_argument(
        fmt::format("phi has {} entries; the {}-link chain needs {}", phi.size(), n, n));
  if (separable_potential(c)) {  // the Hessian is diagonal, −g s_k cos φ_k on it
    std::vector<double> lambda = separable_curvatures(c);
    for (std::size_t k = 0; k < lambda.size(); ++k) lambda[k] *= -std::cos(phi[k]);
    std::sort(lambda.begin(), lambda.end());
    return lambda;
  }
  std::vector<double> hess(static_cast<std::size_t>(n) * static_cast<std::size_t>(n));
  c.potential_hessian(phi, hess);
  const Eigen::MatrixXd minus_hess =
      -Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
          hess.data(), n, n);
  const Eigen::VectorXd lambda = detail::symmetric_eigen_decomposition(minus_hess, false).values;
  return {lambda.data(), lambda.data() + n};
}

std::vector<toda_brumer_link> toda_brumer_links(const chain& c) {
  const int n = c.links();
  const auto nn = static_cast<std::size_t>(n);
  if (separable_potential(c)) {
    // The curvature at rest is g s_k, and V(φ_k = π/2, others 0) = g s_k (1 − cos π/2) too.
    const std::vector<double> curvature = separable_curvatures(c);
    std::vector<toda_brumer_link> out;
    for (int k = 0; k < n; ++k)
      out.push_back(
          {k + 1, curvature[static_cast<std::size_t>(k)], curvature[static_cast<std::size_t>(k)]});
    return out;
  }
  std::vector<double> zero(nn, 0.0), hess(nn * nn);
  c.potential_hessian(zero, hess);
  std::vector<toda_brumer_link> out;
  for (int k = 0; k < n; ++k) {
    // Λ_k = −∂²V/∂φ_k² turns positive at cos φ_k = 0; the cheapest such state from rest has
    // the other links hanging and φ_k = π/2.
    std::vector<double> phi(nn, 0.0);
    phi[static_cast<std::size_t>(k)] = std::numbers::pi / 2;
    out.push_back({k + 1, hess[static_cast<std::size_t>(k) * nn + static_cast<std::size_t>(k)],
                   c.potential_energy(phi)});
  }
  return out;
}

double toda_brumer_critical_energy(const chain& c, std::span<const int> fixed) {
  const int n = c.links();
  std::vector<bool> is_fixed(static_cast<std::size_t>(n), false);
  for (const int k : fixed) {
    if (k < 1 || k > n)
      throw std::invalid_argument(
          fmt::format("fixed link {} is out of range: links are numbered 1..{}", k, n));
    is_fixed[static_cast<std::size_t>(k - 1)] = true;
  }
  double best = std::numeric_limits<double>::infinity();
  for (const auto& link : toda_brumer_links(c))
    if (!is_fixed[static_cast<std::size_t>(link.link - 1)])
      best = std::min(best, link.critical_energy);
  if (best == std::numeric_limits<double>::infinity())
    throw std::invalid_argument("every link is fixed: no free link can reach the unstable region");
  return best;
}

}  // namespace npend
