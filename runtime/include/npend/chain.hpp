// A chain: the generated functions of one link count bound to its parameters.
#pragma once

#include <memory>
#include <span>
#include <vector>

#include "npend/chain_kernels.hpp"
#include "npend/kernel_set.hpp"
#include "npend/parameters.hpp"

namespace npend {

/// The link counts with unrolled kernels compiled into this build (ascending). A point-mass
/// chain of any other count runs on the loop kernels (generated/chain_loop.*).
std::vector<int> built_link_counts();

/// An n-link chain with fixed parameters, calling the generated kernels for n through its
/// kernel_set: the point-mass kernels for the paper's model, the physical kernels (rigid
/// links, joint springs and damping, a moving pivot; see chain_parameters) when the
/// parameters ask for any of it, the cart's kernels for a pendulum on a cart.
///
/// State layout everywhere: x = [q, p] with q = [φ_1..φ_n] (dim 2n), angles in rad from the
/// downward vertical, p the canonical momenta (kg m²/s); on a cart q = [x_c, φ_1..φ_n] (m,
/// rad) and p = [p_x, p_1..p_n], dim 2(n + 1) = 2·coordinates(). Matrices are row-major.
/// Every method checks the sizes of its arguments and throws std::invalid_argument on a
/// mismatch.
///
/// A moving pivot is taken in its own frame (docs/model.md): positions are relative to the
/// pivot, p = ∂L/∂φ̇ of the pivot-frame Lagrangian, and H(x, t) = T + V with V holding the
/// potential of the inertial force −m a(t). The functions that depend on time take t
/// (default 0); on a chain with a fixed pivot they do not depend on it.
class chain {
 public:
  /// Throws std::invalid_argument if the parameters are invalid (see
  /// chain_parameters::validate), or for a physical chain or cart of a link count that was
  /// not built (the message names the CMake option that adds it). A point-mass chain of a
  /// count not built runs on the loop kernels, which take any n.
  explicit chain(chain_parameters params);

  int links() const { return m_links; }
  /// The generalised coordinates q: n, or n + 1 on a cart.
  int coordinates() const { return m_coordinates; }
  int state_size() const { return 2 * m_coordinates; }
  /// Whether the chain hangs from a cart (q starts with the cart's position).
  bool has_cart() const { return m_params.has_cart(); }
  /// Where φ_i (0-based) sits in q and in x: i, or i + 1 after the cart's position.
  int angle_index(int i) const { return m_coordinates - m_links + i; }
  const chain_parameters& parameters() const { return m_params; }
  /// Whether this chain runs on the physical kernels (or the cart's).
  bool is_physical() const { return m_params.is_physical(); }
  /// Whether this chain runs on the loop kernels (a point-mass chain of a link count without
  /// unrolled kernels).
  bool runs_on_loops() const { return m_kernels->matrix_free(); }
  /// The kernels this chain evaluates, bound to its parameters.
  const kernel_set& kernels_in_use() const { return *m_kernels; }
  /// The packed parameters the kernels take: [m, l, g] for a point-mass chain, the physical
  /// layout (chain_layout::physical_param_size) for a physical one, that followed by
  /// [M, b_x] on a cart.
  const std::vector<double>& packed_parameters() const { return m_kernels->packed(); }
  /// The unrolled point-mass kernels behind this chain; throws std::logic_error for a
  /// physical chain or one on the loop kernels.
  const chain_kernels& kernels() const;
  /// The unrolled point-mass kernels, or nullptr (a physical chain, or one on the loops).
  const chain_kernels* unrolled_kernels() const noexcept { return m_kernels->unrolled(); }
  /// The physical kernels of this link count (the pivot's, also on a cart); throws
  /// std::invalid_argument for a link count without them.
  const physical_kernels& physical_table() const;
  /// The derived equations of this chain's model as LaTeX (npend-gen --latex).
  const char* equations_latex() const;

  /// The inputs w of input_matrix: [a_x, a_y, u_1..u_n] (dim n + 2) on a pivot, [F, u_1..u_n]
  /// (dim n + 1) on a cart.
  int input_size() const { return m_kernels->input_size(); }
  /// The actuators a controller drives: the joint torques u_1..u_n (N m; u_j acts on link j
  /// and its reaction on link j−1), and first the force F on the cart (N) where there is one.
  int actuators() const { return m_kernels->actuators(); }
  /// The column of input_matrix that belongs to actuator k (0-based).
  int actuator_input(int k) const { return m_kernels->actuator_input(k); }
  /// The points of positions(): the bobs, after the cart where there is one.
  int points() const { return m_kernels->points(); }

  /// Hamilton's equations: dxdt = f(x, t) (both dim state_size()).
  void rhs(std::span<const double> x, std::span<double> dxdt, double t = 0) const;
  /// Exact Jacobian ∂f/∂x, row-major (dim state_size()²).
  void jacobian(std::span<const double> x, std::span<double> jac, double t = 0) const;
  /// J(x)·u (dim state_size()) without forming J: O(n) on the loop kernels, J then a
  /// product otherwise.
  void jacobian_vector(std::span<const double> x, std::span<const double> u, std::span<double> ju,
                       double t = 0) const;
  /// f and ∂f/∂x with the actuators at `actuation` (dim actuators()) — on any chain with
  /// input kernels: a point-mass chain runs them on the physical kernels with c = l.
  void rhs(std::span<const double> x, std::span<double> dxdt, double t,
           std::span<const double> actuation) const;
  void jacobian(std::span<const double> x, std::span<double> jac, double t,
                std::span<const double> actuation) const;
  /// ∂f/∂t (dim state_size()): zero unless the pivot moves.
  void time_derivative(std::span<const double> x, std::span<double> dfdt, double t = 0) const;
  /// ∂f/∂w for the inputs w (see input_size), row-major state_size() × input_size(); the
  /// columns actuator_input(k) are the input matrix B = ∂f/∂u of the actuators.
  void input_matrix(std::span<const double> q, std::span<double> dfdw) const;
  /// H(q, p, t) = T + V (J). On a fixed pivot or a cart T = ½ pᵀA⁻¹p and V are summed from
  /// terms that keep their relative precision near the rest position (1 − cos φ as
  /// 2 sin²(φ/2)), so that small energies and their drift are measured to rounding, not to
  /// 1e-16 J.
  double hamiltonian(std::span<const double> x, double t = 0) const;
  /// Closed-form H, available for point-mass chains of n ≤ 3 (throws std::invalid_argument
  /// otherwise).
  double hamiltonian_closed_form(std::span<const double> x) const;

  /// q̇ = A⁻¹ p (q, p, dq: dim coordinates()).
  void velocities(std::span<const double> q, std::span<const double> p, std::span<double> dq) const;
  /// p = A q̇ = ∂L/∂q̇ (dim coordinates()).
  void momenta(std::span<const double> q, std::span<const double> dq, std::span<double> p) const;
  /// L(q, q̇, t) = T − V.
  double lagrangian(std::span<const double> q, std::span<const double> dq, double t = 0) const;
  double kinetic_energy(std::span<const double> q, std::span<const double> dq) const;
  /// V (J), zero at the hanging rest position (without cancellation on a fixed pivot or a
  /// cart, as hamiltonian).
  double potential_energy(std::span<const double> q, double t = 0) const;
  /// Mass matrix A(q), row-major (dim coordinates()²).
  void mass_matrix(std::span<const double> q, std::span<double> A) const;
  double det_mass_matrix(std::span<const double> q) const;
  /// ln det A: for long chains, where det A under- or overflows (l^(2n)).
  double log_det_mass_matrix(std::span<const double> q) const;
  /// ∂V/∂q (dim coordinates()) and ∂²V/∂q² (row-major coordinates()²).
  void potential_gradient(std::span<const double> q, std::span<double> grad, double t = 0) const;
  void potential_hessian(std::span<const double> q, std::span<double> hess, double t = 0) const;
  /// Positions [x_1, y_1, ...] of the points() points (m, y pointing down): the link ends
  /// (bobs) relative to the pivot, or on a cart the cart (x_c, 0) and then the bobs.
  void positions(std::span<const double> q, std::span<double> xy) const;

  /// Unchecked forms for integrators: x, dxdt dim state_size(), jac state_size()².
  void evaluate_rhs(const double* x, double t, double* dxdt) const noexcept {
    m_kernels->rhs(x, t, dxdt);
  }
  void evaluate_jacobian(const double* x, double t, double* jac) const noexcept {
    m_kernels->jacobian(x, t, jac);
  }

  /// Convenience forms returning vectors.
  std::vector<double> rhs(std::span<const double> x) const;
  std::vector<double> jacobian(std::span<const double> x) const;
  /// The state [q, A(q) q̇] for coordinates q and their velocities q̇ (dim coordinates()
  /// each).
  std::vector<double> state_from_velocities(std::span<const double> q,
                                            std::span<const double> dq) const;

 private:
  void check_size(std::span<const double> v, int expected, const char* what) const;
  void check_size(std::span<double> v, int expected, const char* what) const;

  chain_parameters m_params;
  // Shared by the copies of a chain: it is immutable.
  std::shared_ptr<const kernel_set> m_kernels;
  int m_links = 0;
  int m_coordinates = 0;
};

/// An angle on the circle: φ reduced to [−π, π] (the state carries angles unwrapped).
double wrapped_angle(double phi);

}  // namespace npend
