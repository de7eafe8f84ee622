// The paper's chain: point masses on massless rods, a fixed pivot, the unrolled kernels.
#include <fmt/format.h>

#include "kernel_sets/kernel_set_detail.hpp"

namespace npend::detail {

namespace {

class point_mass_kernel_set final : public kernel_set {
 public:
  point_mass_kernel_set(const chain_parameters& params, const chain_kernels& point,
                        const physical_kernels& physical)
      : kernel_set(params.links(), params.packed()),
        m_params(params),
        m_point(&point),
        m_physical(&physical),
        m_physical_packed(params.physical_packed()) {}

  int coordinates() const noexcept override { return links(); }
  int input_size() const noexcept override { return chain_layout::input_size(links()); }
  int points() const noexcept override { return links(); }
  const chain_kernels* unrolled() const noexcept override { return m_point; }
  const taylor_kernels* taylor() const noexcept override { return m_point->taylor; }

  void rhs(const double* x, double /*t*/, double* dxdt) const noexcept override {
    m_point->rhs(x, packed().data(), dxdt);
  }
  void jacobian(const double* x, double /*t*/, double* jac) const noexcept override {
    m_point->jacobian(x, packed().data(), jac);
  }
  // The physical chain with c = l and nothing else is this chain: its input kernels serve.
  void actuated_rhs(const double* x, double /*t*/, const double* actuation,
                    double* dxdt) const override {
    const input_buffer w = torque_inputs(actuation);
    m_physical->rhs(x, m_physical_packed.data(), w.data(), dxdt);
  }
  void actuated_jacobian(const double* x, double /*t*/, const double* actuation,
                         double* jac) const override {
    const input_buffer w = torque_inputs(actuation);
    m_physical->jacobian(x, m_physical_packed.data(), w.data(), jac);
  }
  void input_matrix(const double* q, double* dfdw) const override {
    m_physical->input_matrix(q, m_physical_packed.data(), dfdw);
  }

  double hamiltonian_closed_form(const double* x) const override {
    if (m_point->hamiltonian_closed_form == nullptr)
      throw std::invalid_argument(
          fmt::format("the closed-form Hamiltonian is emitted for up to 3 links, not {}", links()));
    return m_point->hamiltonian_closed_form(x, packed().data());
  }
  void velocities(const double* q, const double* p, double* dq) const noexcept override {
    m_point->velocities(q, p, packed().data(), dq);
  }
  void momenta(const double* q, const double* dq, double* p) const noexcept override {
    m_point->momenta(q, dq, packed().data(), p);
  }
  double kinetic_energy(const double* q, const double* dq) const noexcept override {
    return m_point->kinetic_energy(q, dq, packed().data());
  }
  double potential_energy(const double* q, double /*t*/) const noexcept override {
    return fixed_support_potential(m_params, q);
  }
  void mass_matrix(const double* q, double* A) const noexcept override {
    m_point->mass_matrix(q, packed().data(), A);
  }
  double det_mass_matrix(const double* q) const noexcept override {
    return m_point->det_mass_matrix(q, packed().data());
  }
  void potential_gradient(const double* q, double /*t*/, double* grad) const noexcept override {
    m_point->potential_gradient(q, packed().data(), grad);
  }
  void potential_hessian(const double* q, double /*t*/, double* hess) const noexcept override {
    m_point->potential_hessian(q, packed().data(), hess);
  }
  void positions(const double* q, double* xy) const noexcept override {
    m_point->positions(q, packed().data(), xy);
  }
  const char* equations_latex() const override { return m_point->equations_latex(); }

 protected:
  int first_actuator() const noexcept override { return chain_layout::torque_index(links(), 0); }

 private:
  input_buffer torque_inputs(const double* torques) const noexcept {
    input_buffer w{};
    for (int i = 0; i < links(); ++i) w[chain_layout::torque_index(links(), i)] = torques[i];
    return w;
  }

  chain_parameters m_params;
  const chain_kernels* m_point;
  const physical_kernels* m_physical;
  std::vector<double> m_physical_packed;
};

}  // namespace

std::shared_ptr<const kernel_set> make_point_mass_kernel_set(const chain_parameters& params,
                                                             const chain_kernels& point,
                                                             const physical_kernels& physical) {
  return std::make_shared<point_mass_kernel_set>(params, point, physical);
}

}  // namespace npend::detail
