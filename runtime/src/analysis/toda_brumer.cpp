#include "npend/analysis/toda_brumer.hpp"

#include <Eigen/Dense>
#include <fmt/format.h>

#include <limits>
#include <numbers>
#include <stdexcept>

namespace npend {

std::vector<double> toda_brumer_eigenvalues(const chain& c, std::span<const double> phi) {
  const int n = c.links();
  std::vector<double> hess(static_cast<std::size_t>(n * n));
  c.potential_hessian(phi, hess);
  const Eigen::MatrixXd minus_hess =
      -Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
          hess.data(), n, n);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(minus_hess,
                                                               Eigen::EigenvaluesOnly);
  const Eigen::VectorXd& lambda = solver.eigenvalues();
  return {lambda.data(), lambda.data() + n};
}

std::vector<toda_brumer_link> toda_brumer_links(const chain& c) {
  const int n = c.links();
  const auto nn = static_cast<std::size_t>(n);
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
