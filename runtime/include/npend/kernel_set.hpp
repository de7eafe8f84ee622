// The kernels of one model bound to its parameters: what a chain evaluates.
#pragma once

#include <memory>
#include <vector>

#include "npend/chain_kernels.hpp"
#include "npend/parameters.hpp"

namespace npend {

/// One model's generated kernels bound to its packed parameters, behind one interface, so
/// that `chain` and everything generic over it (integrators, energies, equilibria, LQR)
/// never asks which table it runs on. The implementations (runtime/src/kernel_sets/) wrap
/// the point-mass kernels (chain_kernels), the physical ones (physical_kernels), the loop
/// kernels of any link count (loop_kernels) and the pendulum on a cart; a new model is a new
/// implementation and one line in make_kernel_set.
///
/// The coordinates q have dim coordinates(): q = [φ_1..φ_n] on a pivot, q = [x_c, φ_1..φ_n]
/// on a cart; the state is x = [q, p] (dim 2·coordinates()). The inputs w (dim input_size())
/// are what the kernels take besides x: w = [a_x, a_y, u_1..u_n] on a pivot, [F, u_1..u_n]
/// on a cart; the actuators (dim actuators()) are the entries of w a controller drives.
///
/// The functions are unchecked (`chain` checks sizes) and take t where the model depends
/// on time. Functions marked "throws" refuse with std::invalid_argument where the set has
/// no such kernel (the loop kernels have no input kernels, LaTeX or closed form).
class kernel_set {
 public:
  virtual ~kernel_set() = default;

  int links() const noexcept { return m_links; }
  /// The generalised coordinates q (n, or n + 1 with a cart).
  virtual int coordinates() const noexcept = 0;
  /// The inputs w of input_matrix.
  virtual int input_size() const noexcept = 0;
  /// The actuators: joint torques u_1..u_n on a pivot, [F, u_1..u_n] on a cart.
  int actuators() const noexcept { return input_size() - first_actuator(); }
  /// Where actuator k sits in w.
  int actuator_input(int k) const noexcept { return first_actuator() + k; }
  /// The points of positions(): the n bobs, and the cart first where there is one.
  virtual int points() const noexcept = 0;
  /// The packed parameters the kernels take.
  const std::vector<double>& packed() const noexcept { return m_packed; }
  /// Whether J·u runs without forming J (O(n) on the loop kernels).
  virtual bool matrix_free() const noexcept { return false; }
  /// The unrolled point-mass kernels behind this set, or nullptr (the lanes of the batch
  /// integrators run those directly).
  virtual const chain_kernels* unrolled() const noexcept { return nullptr; }

  /// The Taylor kernels of the unactuated equations (params packed()), or nullptr where
  /// the model has none (the loop kernels).
  virtual const taylor_kernels* taylor() const noexcept { return nullptr; }
  /// The Taylor series of the inputs w(t + τ) with no actuation, as the Taylor kernels take
  /// them: input_size() rows of order + 1 numbers, w[j·(order+1) + k] for k = 0..order
  /// (all zero but a moving pivot's acceleration). Throws std::invalid_argument where w has
  /// no series (a custom pivot path).
  virtual void input_series(double t, int order, double* w) const;
  virtual void input_series(double t, int order, long double* w) const;

  /// dxdt = f(x, t) with no actuation (x, dxdt: dim 2·coordinates()).
  virtual void rhs(const double* x, double t, double* dxdt) const noexcept = 0;
  /// ∂f/∂x, row-major.
  virtual void jacobian(const double* x, double t, double* jac) const noexcept = 0;
  /// J(x)·u: forms J unless matrix_free().
  virtual void jacobian_vector(const double* x, const double* u, double t, double* ju) const;
  /// f and ∂f/∂x with the actuators at `actuation` (dim actuators()). Throws.
  virtual void actuated_rhs(const double* x, double t, const double* actuation,
                            double* dxdt) const = 0;
  virtual void actuated_jacobian(const double* x, double t, const double* actuation,
                                 double* jac) const = 0;
  /// ∂f/∂w, row-major 2·coordinates() × input_size(). Throws.
  virtual void input_matrix(const double* q, double* dfdw) const = 0;
  /// ∂f/∂t (zero unless the model depends on time).
  virtual void time_derivative(const double* x, double t, double* dfdt) const;
  /// Whether f depends on t.
  virtual bool time_dependent() const noexcept { return false; }

  /// H(x, t) = T + V; V as potential_energy.
  virtual double hamiltonian(const double* x, double t) const;
  /// The closed-form H of the paper's chains (n ≤ 3). Throws.
  virtual double hamiltonian_closed_form(const double* x) const;
  /// q̇ = A⁻¹p and p = A q̇.
  virtual void velocities(const double* q, const double* p, double* dq) const noexcept = 0;
  virtual void momenta(const double* q, const double* dq, double* p) const noexcept = 0;
  /// L = T − V.
  virtual double lagrangian(const double* q, const double* dq, double t) const;
  virtual double kinetic_energy(const double* q, const double* dq) const noexcept = 0;
  /// V, zero at the hanging rest position; without cancellation near it where nothing
  /// moves the model in time (1 − cos φ as 2 sin²(φ/2)).
  virtual double potential_energy(const double* q, double t) const noexcept = 0;
  /// A(q), row-major coordinates()²; its determinant and logarithm.
  virtual void mass_matrix(const double* q, double* A) const noexcept = 0;
  virtual double det_mass_matrix(const double* q) const noexcept = 0;
  virtual double log_det_mass_matrix(const double* q) const noexcept;
  /// ∂V/∂q and ∂²V/∂q².
  virtual void potential_gradient(const double* q, double t, double* grad) const noexcept = 0;
  virtual void potential_hessian(const double* q, double t, double* hess) const noexcept = 0;
  /// [x_1, y_1, ...] of points() points.
  virtual void positions(const double* q, double* xy) const noexcept = 0;
  /// The derived equations as LaTeX. Throws.
  virtual const char* equations_latex() const = 0;

 protected:
  kernel_set(int links, std::vector<double> packed) : m_links(links), m_packed(std::move(packed)) {}
  /// The index in w of the first actuator.
  virtual int first_actuator() const noexcept = 0;

 private:
  int m_links;
  std::vector<double> m_packed;
};

/// The kernel set for `params` (validated): the cart's where it has one, the physical
/// kernels where it needs them, else the unrolled point-mass kernels, or the loop kernels
/// for a link count without them. Throws std::invalid_argument for a physical chain or cart
/// of a link count not built (naming the CMake option that adds it), std::logic_error where
/// the generated kernels disagree with chain_layout.
std::shared_ptr<const kernel_set> make_kernel_set(const chain_parameters& params);

}  // namespace npend
