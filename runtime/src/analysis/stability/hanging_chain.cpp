#include "npend/analysis/stability/hanging_chain.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <boost/math/special_functions/bessel.hpp>
#include <cmath>
#include <stdexcept>

namespace npend {

namespace {

void require_positive(std::span<const double> values, const char* what) {
  for (std::size_t i = 0; i < values.size(); ++i)
    if (!(values[i] > 0) || !std::isfinite(values[i]))
      throw std::invalid_argument(
          fmt::format("{} {} must be a positive number, got {}", what, i + 1, values[i]));
}

}  // namespace

std::vector<hanging_chain_mode> hanging_chain_modes(std::span<const double> masses,
                                                    std::span<const double> lengths, double g,
                                                    int count) {
  const auto n = static_cast<Eigen::Index>(masses.size());
  if (n == 0 || lengths.size() != masses.size())
    throw std::invalid_argument(
        fmt::format("hanging chain: need n >= 1 masses and as many lengths, got {} and {}",
                    masses.size(), lengths.size()));
  if (count < 1 || count > n)
    throw std::invalid_argument(
        fmt::format("hanging chain: the number of modes must be 1..{}, got {}", n, count));
  require_positive(masses, "mass");
  require_positive(lengths, "length");
  if (!(g > 0) || !std::isfinite(g))
    throw std::invalid_argument(fmt::format("hanging chain: g must be positive, got {}", g));

  // κ_j = g μ_j / l_j, from the free end up.
  Eigen::VectorXd kappa(n);
  double below = 0;
  for (Eigen::Index j = n - 1; j >= 0; --j) {
    below += masses[static_cast<std::size_t>(j)];
    kappa(j) = g * below / lengths[static_cast<std::size_t>(j)];
  }
  // M^{-1/2} K M^{-1/2}: diagonal (κ_i + κ_{i+1}) / m_i, off-diagonal −κ_{i+1} / √(m_i m_{i+1}).
  Eigen::VectorXd diagonal(n), off(n > 1 ? n - 1 : 0), root_mass(n);
  for (Eigen::Index i = 0; i < n; ++i)
    root_mass(i) = std::sqrt(masses[static_cast<std::size_t>(i)]);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double lower = i + 1 < n ? kappa(i + 1) : 0.0;
    diagonal(i) = (kappa(i) + lower) / (root_mass(i) * root_mass(i));
    if (i + 1 < n) off(i) = -kappa(i + 1) / (root_mass(i) * root_mass(i + 1));
  }
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver;
  solver.computeFromTridiagonal(diagonal, off, Eigen::ComputeEigenvectors);
  if (solver.info() != Eigen::Success)
    throw std::runtime_error("hanging chain: the tridiagonal eigensolver did not converge");
  std::vector<hanging_chain_mode> out;
  for (int k = 0; k < count; ++k) {
    hanging_chain_mode mode;
    mode.frequency = std::sqrt(std::max(0.0, solver.eigenvalues()(k)));
    const Eigen::VectorXd x = solver.eigenvectors().col(k).cwiseQuotient(root_mass);
    mode.displacement.assign(x.data(), x.data() + n);
    const double end = x(n - 1);  // never a node: the free end moves in every mode
    for (double& v : mode.displacement) v /= end;
    out.push_back(std::move(mode));
  }
  return out;
}

double rope_frequency(int k, double length, double g) {
  if (k < 1) throw std::invalid_argument(fmt::format("rope mode numbers start at 1, got {}", k));
  return boost::math::cyl_bessel_j_zero(0.0, k) / 2 * std::sqrt(g / length);
}

double rope_shape(int k, double s, double length) {
  if (k < 1) throw std::invalid_argument(fmt::format("rope mode numbers start at 1, got {}", k));
  return boost::math::cyl_bessel_j(
      0, boost::math::cyl_bessel_j_zero(0.0, k) * std::sqrt(std::max(0.0, s) / length));
}

double convergence_order(double error_a, int links_a, double error_b, int links_b) {
  if (links_a < 1 || links_b < 1 || links_a == links_b)
    throw std::invalid_argument(
        fmt::format("convergence_order: the link counts must be positive and differ, got {} and {}",
                    links_a, links_b));
  return std::log(std::fabs(error_a) / std::fabs(error_b)) /
         std::log(static_cast<double>(links_b) / links_a);
}

}  // namespace npend
