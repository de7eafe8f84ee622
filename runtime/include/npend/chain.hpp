// A chain: the generated functions of one link count bound to its parameters.
#pragma once

#include "npend/chain_kernels.hpp"
#include "npend/parameters.hpp"

#include <span>
#include <vector>

namespace npend {

/// The link counts compiled into this build (ascending).
std::vector<int> built_link_counts();

/// An n-link chain with fixed parameters, calling the generated kernels for n.
///
/// State layout everywhere: x = [φ_1..φ_n, p_1..p_n] (dim 2n), angles in rad from the
/// downward vertical, p the canonical momenta (kg m²/s). Matrices are row-major. Every
/// method checks the sizes of its arguments and throws std::invalid_argument on a mismatch.
class chain {
 public:
  /// Throws std::invalid_argument if the parameters are invalid (see
  /// chain_parameters::validate) or if this link count was not built — the message names
  /// the CMake option that adds it.
  explicit chain(chain_parameters params);

  int links() const { return m_links; }
  int state_size() const { return chain_layout::state_size(m_links); }
  const chain_parameters& parameters() const { return m_params; }
  /// [m_1..m_n, l_1..l_n, g] as the kernels take it.
  const std::vector<double>& packed_parameters() const { return m_packed; }
  /// The generated functions behind this chain (the contract of chain_kernels.hpp).
  const chain_kernels& kernels() const { return *m_kernels; }
  /// The derived equations of this link count as LaTeX (npend-gen --latex).
  const char* equations_latex() const { return m_kernels->equations_latex(); }

  /// Hamilton's equations: dxdt = f(x) (both dim 2n).
  void rhs(std::span<const double> x, std::span<double> dxdt) const;
  /// Exact Jacobian ∂f/∂x, row-major (dim 2n × 2n).
  void jacobian(std::span<const double> x, std::span<double> jac) const;
  /// H(φ, p) = T + V (J).
  double hamiltonian(std::span<const double> x) const;
  /// Closed-form H, available for n ≤ 3 (throws std::invalid_argument otherwise).
  double hamiltonian_closed_form(std::span<const double> x) const;

  /// φ̇ = A⁻¹ p (phi, p, dphi: dim n).
  void velocities(std::span<const double> phi, std::span<const double> p,
                  std::span<double> dphi) const;
  /// p = A φ̇ = ∂L/∂φ̇ (dim n).
  void momenta(std::span<const double> phi, std::span<const double> dphi,
               std::span<double> p) const;
  /// L(φ, φ̇) = T − V.
  double lagrangian(std::span<const double> phi, std::span<const double> dphi) const;
  double kinetic_energy(std::span<const double> phi, std::span<const double> dphi) const;
  double potential_energy(std::span<const double> phi) const;
  /// Mass matrix A(φ), row-major (dim n × n).
  void mass_matrix(std::span<const double> phi, std::span<double> A) const;
  double det_mass_matrix(std::span<const double> phi) const;
  /// ∂V/∂φ (dim n) and ∂²V/∂φ² (row-major n × n).
  void potential_gradient(std::span<const double> phi, std::span<double> grad) const;
  void potential_hessian(std::span<const double> phi, std::span<double> hess) const;
  /// Bob positions [x_1, y_1, ..., x_n, y_n] (dim 2n; m, y pointing down).
  void positions(std::span<const double> phi, std::span<double> xy) const;

  /// Convenience forms returning vectors.
  std::vector<double> rhs(std::span<const double> x) const;
  std::vector<double> jacobian(std::span<const double> x) const;
  /// The state [φ, A(φ) φ̇] for angles φ and angular velocities φ̇ (dim n each).
  std::vector<double> state_from_velocities(std::span<const double> phi,
                                            std::span<const double> dphi) const;

 private:
  void check_size(std::span<const double> v, int expected, const char* what) const;
  void check_size(std::span<double> v, int expected, const char* what) const;

  chain_parameters m_params;
  std::vector<double> m_packed;
  const chain_kernels* m_kernels = nullptr;
  int m_links = 0;
};

/// An angle on the circle: φ reduced to [−π, π] (the state carries angles unwrapped).
double wrapped_angle(double phi);

}  // namespace npend
