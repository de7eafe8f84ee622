#include "npend/analysis/stability/normal_modes.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <cmath>
#include <stdexcept>

namespace npend {

namespace {

using row_major = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

void require_equilibrium(const chain& c, std::span<const double> angles) {
  const auto n = static_cast<std::size_t>(c.links());
  std::vector<double> grad(n);
  c.potential_gradient(angles, grad);
  // Compare with the potential's own scale (its curvature at rest, g μ_k l_k for gravity),
  // so that π typed as 3.14159265358979 still counts and 0.1 does not.
  std::vector<double> zero(n, 0.0), hess(n * n);
  c.potential_hessian(zero, hess);
  double scale = 0;
  for (std::size_t k = 0; k < n; ++k) scale = std::max(scale, std::fabs(hess[k * n + k]));
  for (std::size_t k = 0; k < n; ++k)
    if (std::fabs(grad[k]) > 1e-9 * scale)
      throw std::invalid_argument(fmt::format(
          "angles are not an equilibrium: dV/dphi_{} = {:.3g} (each angle must be 0 or pi)", k + 1,
          grad[k]));
}

}  // namespace

linearisation normal_modes(const chain& c, std::span<const double> angles) {
  const int n = c.links();
  // The cart's free coordinate adds a zero mode that the 0/π classification would misread.
  if (c.has_cart())
    throw std::invalid_argument(
        "normal_modes: the chain is on a cart; its modes are those of a chain on a fixed pivot "
        "(the cart adds a free coordinate; see lqr_design for the chain on a cart)");
  if (angles.size() != static_cast<std::size_t>(n))
    throw std::invalid_argument(
        fmt::format("angles has {} entries; the {}-link chain needs {}", angles.size(), n, n));
  require_equilibrium(c, angles);

  linearisation lin;
  lin.angles.assign(angles.begin(), angles.end());
  lin.mass_matrix.resize(static_cast<std::size_t>(n * n));
  lin.stiffness_matrix.resize(static_cast<std::size_t>(n * n));
  c.mass_matrix(angles, lin.mass_matrix);
  c.potential_hessian(angles, lin.stiffness_matrix);

  const Eigen::MatrixXd M = Eigen::Map<const row_major>(lin.mass_matrix.data(), n, n);
  const Eigen::MatrixXd K = Eigen::Map<const row_major>(lin.stiffness_matrix.data(), n, n);
  // M is positive definite, so K v = ω² M v is a symmetric-definite problem with real ω²
  // and M-orthonormal eigenvectors, ascending.
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> solver(K, M);
  if (solver.info() != Eigen::Success)
    throw std::runtime_error("normal_modes: the generalised eigensolver did not converge");
  for (int k = 0; k < n; ++k) {
    normal_mode mode;
    mode.omega_squared = solver.eigenvalues()(k);
    if (mode.omega_squared > 0)
      mode.frequency = std::sqrt(mode.omega_squared);
    else
      mode.growth_rate = std::sqrt(-mode.omega_squared);
    Eigen::VectorXd v = solver.eigenvectors().col(k);
    Eigen::Index largest = 0;
    v.cwiseAbs().maxCoeff(&largest);
    if (v(largest) < 0) v = -v;
    mode.shape.assign(v.data(), v.data() + n);
    lin.modes.push_back(std::move(mode));
  }
  return lin;
}

}  // namespace npend
