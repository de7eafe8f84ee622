#include "npend/analysis/motion/rod_tensions.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

namespace npend {

void rod_tensions(const chain& c, std::span<const double> x, std::span<double> tau) {
  if (c.is_physical())
    throw std::invalid_argument(
        "rod tensions are those of point masses on massless rods: rigid links, joint springs, "
        "damping, torques and a moving pivot load the joints with more than a tension");
  const auto n = static_cast<std::size_t>(c.links());
  if (x.size() != 2 * n || tau.size() != n)
    throw std::invalid_argument(fmt::format(
        "rod_tensions: the {}-link chain needs a state of {} and {} tensions, got {} and {}", n,
        2 * n, n, x.size(), tau.size()));
  const chain_parameters& p = c.parameters();
  const std::span<const double> phi = x.first(n);
  std::vector<double> dphi(n);
  c.velocities(phi, x.subspan(n), dphi);

  // Thomas algorithm on the tridiagonal system of the file comment: diagonal d_k,
  // off-diagonal e_k = −C_k/m_k between τ_k and τ_{k+1}.
  std::vector<double> diagonal(n), upper(n), rhs(n);
  for (std::size_t k = 0; k < n; ++k) {
    const double inv_m = 1.0 / p.masses[k];
    diagonal[k] = inv_m + (k > 0 ? 1.0 / p.masses[k - 1] : 0.0);
    upper[k] = k + 1 < n ? -std::cos(phi[k + 1] - phi[k]) * inv_m : 0.0;
    rhs[k] = p.lengths[k] * dphi[k] * dphi[k] + (k == 0 ? p.g * std::cos(phi[0]) : 0.0);
  }
  for (std::size_t k = 1; k < n; ++k) {
    const double factor = upper[k - 1] / diagonal[k - 1];
    diagonal[k] -= factor * upper[k - 1];
    rhs[k] -= factor * rhs[k - 1];
  }
  tau[n - 1] = rhs[n - 1] / diagonal[n - 1];
  for (std::size_t k = n - 1; k-- > 0;) tau[k] = (rhs[k] - upper[k] * tau[k + 1]) / diagonal[k];
}

std::vector<double> rod_tensions(const chain& c, std::span<const double> x) {
  std::vector<double> tau(static_cast<std::size_t>(c.links()));
  rod_tensions(c, x, tau);
  return tau;
}

}  // namespace npend
