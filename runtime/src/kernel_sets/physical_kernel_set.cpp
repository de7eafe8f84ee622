// The physical chain: rigid links, joint springs, damping and torques, a moving pivot.
#include <algorithm>

#include "kernel_sets/kernel_set_detail.hpp"

namespace npend::detail {

namespace {

class physical_kernel_set final : public kernel_set {
 public:
  physical_kernel_set(const chain_parameters& params, const physical_kernels& kernels)
      : kernel_set(params.links(), params.physical_packed()), m_params(params), m_k(&kernels) {}

  int coordinates() const noexcept override { return links(); }
  int input_size() const noexcept override { return chain_layout::input_size(links()); }
  int points() const noexcept override { return links(); }
  bool time_dependent() const noexcept override { return m_params.pivot.moves(); }
  const taylor_kernels* taylor() const noexcept override { return m_k->taylor; }
  void input_series(double t, int order, double* w) const override { pivot_series(t, order, w); }
  void input_series(double t, int order, long double* w) const override {
    pivot_series(t, order, w);
  }

  void rhs(const double* x, double t, double* dxdt) const noexcept override {
    const input_buffer w = inputs(t);
    m_k->rhs(x, packed().data(), w.data(), dxdt);
  }
  void jacobian(const double* x, double t, double* jac) const noexcept override {
    const input_buffer w = inputs(t);
    m_k->jacobian(x, packed().data(), w.data(), jac);
  }
  void actuated_rhs(const double* x, double t, const double* actuation,
                    double* dxdt) const override {
    const input_buffer w = inputs(t, actuation);
    m_k->rhs(x, packed().data(), w.data(), dxdt);
  }
  void actuated_jacobian(const double* x, double t, const double* actuation,
                         double* jac) const override {
    const input_buffer w = inputs(t, actuation);
    m_k->jacobian(x, packed().data(), w.data(), jac);
  }
  void input_matrix(const double* q, double* dfdw) const override {
    m_k->input_matrix(q, packed().data(), dfdw);
  }
  void time_derivative(const double* x, double t, double* dfdt) const override {
    const int dim = 2 * links();
    for (int i = 0; i < dim; ++i) dfdt[i] = 0.0;
    if (!m_params.pivot.moves()) return;
    // f is affine in w and w depends on t through the pivot's acceleration only.
    const int width = input_size();
    std::vector<double> dfdw(static_cast<std::size_t>(dim * width));
    input_matrix(x, dfdw.data());
    const auto jerk = m_params.pivot.jerk_at(t);
    for (int i = 0; i < dim; ++i)
      dfdt[i] =
          dfdw[static_cast<std::size_t>(i * width + chain_layout::pivot_acceleration_index(0))] *
              jerk[0] +
          dfdw[static_cast<std::size_t>(i * width + chain_layout::pivot_acceleration_index(1))] *
              jerk[1];
  }

  double hamiltonian(const double* x, double t) const override {
    if (!m_params.pivot.moves()) return kernel_set::hamiltonian(x, t);
    const input_buffer w = inputs(t);
    return m_k->hamiltonian(x, packed().data(), w.data());
  }
  double lagrangian(const double* q, const double* dq, double t) const override {
    if (!m_params.pivot.moves()) return kernel_set::lagrangian(q, dq, t);
    const input_buffer w = inputs(t);
    return m_k->lagrangian(q, dq, packed().data(), w.data());
  }
  void velocities(const double* q, const double* p, double* dq) const noexcept override {
    m_k->velocities(q, p, packed().data(), dq);
  }
  void momenta(const double* q, const double* dq, double* p) const noexcept override {
    m_k->momenta(q, dq, packed().data(), p);
  }
  double kinetic_energy(const double* q, const double* dq) const noexcept override {
    return m_k->kinetic_energy(q, dq, packed().data());
  }
  double potential_energy(const double* q, double t) const noexcept override {
    if (!m_params.pivot.moves()) return fixed_support_potential(m_params, q);
    const input_buffer w = inputs(t);
    return m_k->potential_energy(q, packed().data(), w.data());
  }
  void mass_matrix(const double* q, double* A) const noexcept override {
    m_k->mass_matrix(q, packed().data(), A);
  }
  double det_mass_matrix(const double* q) const noexcept override {
    return m_k->det_mass_matrix(q, packed().data());
  }
  void potential_gradient(const double* q, double t, double* grad) const noexcept override {
    const input_buffer w = inputs(t);
    m_k->potential_gradient(q, packed().data(), w.data(), grad);
  }
  void potential_hessian(const double* q, double t, double* hess) const noexcept override {
    const input_buffer w = inputs(t);
    m_k->potential_hessian(q, packed().data(), w.data(), hess);
  }
  void positions(const double* q, double* xy) const noexcept override {
    m_k->positions(q, packed().data(), xy);
  }
  const char* equations_latex() const override { return m_k->equations_latex(); }

 protected:
  int first_actuator() const noexcept override { return chain_layout::torque_index(links(), 0); }

 private:
  // w(t) = [a_x, a_y, u_1..u_n]: the pivot's acceleration and the torques (none: zero).
  input_buffer inputs(double t, const double* torques = nullptr) const noexcept {
    input_buffer w;
    const auto a = m_params.pivot.acceleration_at(t);
    w[chain_layout::pivot_acceleration_index(0)] = a[0];
    w[chain_layout::pivot_acceleration_index(1)] = a[1];
    for (int i = 0; i < links(); ++i)
      w[chain_layout::torque_index(links(), i)] = torques != nullptr ? torques[i] : 0.0;
    return w;
  }

  // The pivot's acceleration as a series; the torques (none) zero.
  template <class T>
  void pivot_series(double t, int order, T* w) const {
    const int stride = order + 1;
    std::fill(w, w + static_cast<std::ptrdiff_t>(input_size()) * stride, T(0));
    m_params.pivot.acceleration_series(t, order,
                                       w + chain_layout::pivot_acceleration_index(0) * stride,
                                       w + chain_layout::pivot_acceleration_index(1) * stride);
  }

  chain_parameters m_params;
  const physical_kernels* m_k;
};

}  // namespace

std::shared_ptr<const kernel_set> make_physical_kernel_set(const chain_parameters& params,
                                                           const physical_kernels& kernels) {
  return std::make_shared<physical_kernel_set>(params, kernels);
}

}  // namespace npend::detail
