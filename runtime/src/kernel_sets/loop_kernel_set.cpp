// The paper's chain of a link count without unrolled kernels: the loop kernels, any n.
#include <fmt/format.h>

#include <chain_loop.hpp>

#include "kernel_sets/kernel_set_detail.hpp"

namespace npend::detail {

namespace {

class loop_kernel_set final : public kernel_set {
 public:
  explicit loop_kernel_set(const chain_parameters& params)
      : kernel_set(params.links(), params.packed()),
        m_params(params),
        m_k(&generated::chain_loop::kernels) {}

  int coordinates() const noexcept override { return links(); }
  int input_size() const noexcept override { return chain_layout::input_size(links()); }
  int points() const noexcept override { return links(); }
  bool matrix_free() const noexcept override { return true; }

  void rhs(const double* x, double /*t*/, double* dxdt) const noexcept override {
    m_k->rhs(links(), x, packed().data(), dxdt, workspace());
  }
  void jacobian(const double* x, double /*t*/, double* jac) const noexcept override {
    m_k->jacobian(links(), x, packed().data(), jac, workspace(true));
  }
  void jacobian_vector(const double* x, const double* u, double /*t*/, double* ju) const override {
    m_k->jacobian_vector(links(), x, packed().data(), u, ju, workspace());
  }
  void actuated_rhs(const double*, double, const double*, double*) const override {
    throw no_physical_kernels(links(), "this computation");
  }
  void actuated_jacobian(const double*, double, const double*, double*) const override {
    throw no_physical_kernels(links(), "this computation");
  }
  void input_matrix(const double*, double*) const override {
    throw no_physical_kernels(links(), "this computation");
  }

  void velocities(const double* q, const double* p, double* dq) const noexcept override {
    m_k->velocities(links(), q, p, packed().data(), dq, workspace());
  }
  void momenta(const double* q, const double* dq, double* p) const noexcept override {
    m_k->momenta(links(), q, dq, packed().data(), p, workspace());
  }
  double kinetic_energy(const double* q, const double* dq) const noexcept override {
    return m_k->kinetic_energy(links(), q, dq, packed().data(), workspace());
  }
  double potential_energy(const double* q, double /*t*/) const noexcept override {
    return fixed_support_potential(m_params, q);
  }
  void mass_matrix(const double* q, double* A) const noexcept override {
    m_k->mass_matrix(links(), q, packed().data(), A, workspace());
  }
  double det_mass_matrix(const double* q) const noexcept override {
    return m_k->det_mass_matrix(links(), q, packed().data(), workspace());
  }
  double log_det_mass_matrix(const double* q) const noexcept override {
    return m_k->log_det_mass_matrix(links(), q, packed().data(), workspace());
  }
  void potential_gradient(const double* q, double /*t*/, double* grad) const noexcept override {
    m_k->potential_gradient(links(), q, packed().data(), grad, workspace());
  }
  void potential_hessian(const double* q, double /*t*/, double* hess) const noexcept override {
    m_k->potential_hessian(links(), q, packed().data(), hess, workspace());
  }
  void positions(const double* q, double* xy) const noexcept override {
    m_k->positions(links(), q, packed().data(), xy, workspace());
  }
  const char* equations_latex() const override {
    throw std::invalid_argument(fmt::format(
        "the equations of {} links are not derived in this build (it runs them on the loop "
        "kernels); npend-gen --latex {} prints them",
        links(), links()));
  }

 protected:
  int first_actuator() const noexcept override { return chain_layout::torque_index(links(), 0); }

 private:
  // The workspace of the loop kernels, one per thread (a chain is shared by threads); the
  // Jacobian's is O(n²), the others' O(n).
  double* workspace(bool jacobian = false) const {
    thread_local std::vector<double> work;
    const std::size_t size = jacobian ? m_k->jacobian_workspace_size(links())
                                      : static_cast<std::size_t>(m_k->workspace_size(links()));
    if (work.size() < size) work.resize(size);
    return work.data();
  }

  chain_parameters m_params;
  const loop_kernels* m_k;
};

}  // namespace

std::shared_ptr<const kernel_set> make_loop_kernel_set(const chain_parameters& params) {
  return std::make_shared<loop_kernel_set>(params);
}

}  // namespace npend::detail
