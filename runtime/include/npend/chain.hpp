// A chain: the generated functions of one link count bound to its parameters.
#pragma once

#include <span>
#include <vector>

#include "npend/chain_kernels.hpp"
#include "npend/parameters.hpp"

namespace npend {

/// The link counts with unrolled kernels compiled into this build (ascending). A point-mass
/// chain of any other count runs on the loop kernels (generated/chain_loop.*).
std::vector<int> built_link_counts();

/// An n-link chain with fixed parameters, calling the generated kernels for n: the
/// point-mass kernels for the paper's model, the physical kernels (rigid links, joint springs
/// and damping, a moving pivot; see chain_parameters) when the parameters ask for any of it.
///
/// State layout everywhere: x = [φ_1..φ_n, p_1..p_n] (dim 2n), angles in rad from the
/// downward vertical, p the canonical momenta (kg m²/s). Matrices are row-major. Every
/// method checks the sizes of its arguments and throws std::invalid_argument on a mismatch.
///
/// A moving pivot is taken in its own frame (docs/model.md): positions are relative to the
/// pivot, p = ∂L/∂φ̇ of the pivot-frame Lagrangian, and H(x, t) = T + V with V holding the
/// potential of the inertial force −m a(t). The functions that depend on time take t
/// (default 0); on a chain with a fixed pivot they do not depend on it.
class chain {
 public:
  /// Throws std::invalid_argument if the parameters are invalid (see
  /// chain_parameters::validate), or for a physical chain of a link count that was not built
  /// (the message names the CMake option that adds it). A point-mass chain of a count not
  /// built runs on the loop kernels, which take any n.
  explicit chain(chain_parameters params);

  int links() const { return m_links; }
  int state_size() const { return chain_layout::state_size(m_links); }
  const chain_parameters& parameters() const { return m_params; }
  /// Whether this chain runs on the physical kernels.
  bool is_physical() const { return m_physical; }
  /// Whether this chain runs on the loop kernels (a point-mass chain of a link count without
  /// unrolled kernels).
  bool runs_on_loops() const { return m_loop != nullptr; }
  /// The packed parameters the kernels take: [m, l, g] for a point-mass chain, the physical
  /// layout (chain_layout::physical_param_size) for a physical one.
  const std::vector<double>& packed_parameters() const { return m_packed; }
  /// The unrolled point-mass kernels behind this chain; throws std::logic_error for a
  /// physical chain or one on the loop kernels.
  const chain_kernels& kernels() const;
  /// The unrolled point-mass kernels, or nullptr (a physical chain, or one on the loops).
  const chain_kernels* unrolled_kernels() const noexcept {
    return m_physical || m_loop != nullptr ? nullptr : m_kernels;
  }
  /// The physical kernels of this link count (used by every chain for input_matrix); throws
  /// std::invalid_argument for a chain on the loop kernels, which have none.
  const physical_kernels& physical_table() const;
  /// The derived equations of this link count as LaTeX (npend-gen --latex).
  const char* equations_latex() const;

  /// Hamilton's equations: dxdt = f(x, t) (both dim 2n).
  void rhs(std::span<const double> x, std::span<double> dxdt, double t = 0) const;
  /// Exact Jacobian ∂f/∂x, row-major (dim 2n × 2n).
  void jacobian(std::span<const double> x, std::span<double> jac, double t = 0) const;
  /// J(x)·u (dim 2n) without forming J: O(n) on the loop kernels, J then a product otherwise.
  void jacobian_vector(std::span<const double> x, std::span<const double> u, std::span<double> ju,
                       double t = 0) const;
  /// f and ∂f/∂x with motor torques u_j at the joints (dim n, N m; u_j acts on link j and
  /// its reaction on link j−1) — on any chain: a point-mass chain runs them on the physical
  /// kernels with c = l.
  void rhs(std::span<const double> x, std::span<double> dxdt, double t,
           std::span<const double> torques) const;
  void jacobian(std::span<const double> x, std::span<double> jac, double t,
                std::span<const double> torques) const;
  /// ∂f/∂t (dim 2n): zero unless the pivot moves.
  void time_derivative(std::span<const double> x, std::span<double> dfdt, double t = 0) const;
  /// ∂f/∂w for the inputs w = [a_x, a_y, u_1..u_n] (pivot acceleration, joint torques),
  /// row-major 2n × (n + 2); its last n columns are the input matrix B = ∂f/∂u.
  void input_matrix(std::span<const double> phi, std::span<double> dfdw) const;
  /// H(φ, p, t) = T + V (J). On a fixed pivot T = ½ pᵀA⁻¹p and V are summed from terms
  /// that keep their relative precision near the rest position (1 − cos φ as 2 sin²(φ/2)),
  /// so that small energies and their drift are measured to rounding, not to 1e-16 J.
  double hamiltonian(std::span<const double> x, double t = 0) const;
  /// Closed-form H, available for point-mass chains of n ≤ 3 (throws std::invalid_argument
  /// otherwise).
  double hamiltonian_closed_form(std::span<const double> x) const;

  /// φ̇ = A⁻¹ p (phi, p, dphi: dim n).
  void velocities(std::span<const double> phi, std::span<const double> p,
                  std::span<double> dphi) const;
  /// p = A φ̇ = ∂L/∂φ̇ (dim n).
  void momenta(std::span<const double> phi, std::span<const double> dphi,
               std::span<double> p) const;
  /// L(φ, φ̇, t) = T − V.
  double lagrangian(std::span<const double> phi, std::span<const double> dphi, double t = 0) const;
  double kinetic_energy(std::span<const double> phi, std::span<const double> dphi) const;
  /// V (J), zero at the hanging rest position (without cancellation on a fixed pivot, as
  /// hamiltonian).
  double potential_energy(std::span<const double> phi, double t = 0) const;
  /// Mass matrix A(φ), row-major (dim n × n).
  void mass_matrix(std::span<const double> phi, std::span<double> A) const;
  double det_mass_matrix(std::span<const double> phi) const;
  /// ln det A: for long chains, where det A under- or overflows (l^(2n)).
  double log_det_mass_matrix(std::span<const double> phi) const;
  /// ∂V/∂φ (dim n) and ∂²V/∂φ² (row-major n × n).
  void potential_gradient(std::span<const double> phi, std::span<double> grad, double t = 0) const;
  void potential_hessian(std::span<const double> phi, std::span<double> hess, double t = 0) const;
  /// Link-end (bob) positions [x_1, y_1, ..., x_n, y_n] (dim 2n; m, y pointing down),
  /// relative to the pivot.
  void positions(std::span<const double> phi, std::span<double> xy) const;

  /// The inputs w(t) = [a_x, a_y, u_1..u_n] the physical kernels get at time t (the
  /// torques are zero here; a controller adds its own).
  std::vector<double> inputs_at(double t) const;

  /// Unchecked forms for integrators: x, dxdt dim 2n, jac 2n × 2n.
  void evaluate_rhs(const double* x, double t, double* dxdt) const noexcept;
  void evaluate_jacobian(const double* x, double t, double* jac) const noexcept;

  /// Convenience forms returning vectors.
  std::vector<double> rhs(std::span<const double> x) const;
  std::vector<double> jacobian(std::span<const double> x) const;
  /// The state [φ, A(φ) φ̇] for angles φ and angular velocities φ̇ (dim n each).
  std::vector<double> state_from_velocities(std::span<const double> phi,
                                            std::span<const double> dphi) const;

 private:
  void check_size(std::span<const double> v, int expected, const char* what) const;
  void check_size(std::span<double> v, int expected, const char* what) const;
  // The inputs at t into w (dim n + 2): the pivot's acceleration and the joint torques
  // (dim n; none: zero).
  void fill_inputs(double t, double* w, const double* torques = nullptr) const noexcept;

  chain_parameters m_params;
  std::vector<double> m_packed;
  std::vector<double> m_physical_packed;  ///< the physical layout, also for point-mass chains
  // The workspace of the loop kernels, one per thread (a chain is shared by threads); the
  // Jacobian's is O(n²), the others' O(n).
  double* loop_workspace(bool jacobian = false) const;

  const chain_kernels* m_kernels = nullptr;
  const physical_kernels* m_physical_kernels = nullptr;
  const loop_kernels* m_loop = nullptr;
  int m_links = 0;
  bool m_physical = false;
};

/// An angle on the circle: φ reduced to [−π, π] (the state carries angles unwrapped).
double wrapped_angle(double phi);

}  // namespace npend
