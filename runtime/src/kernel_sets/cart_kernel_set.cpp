// The pendulum on a cart: the physical chain hung from a cart that rolls along x.
#include "kernel_sets/kernel_set_detail.hpp"

namespace npend::detail {

namespace {

class cart_kernel_set final : public kernel_set {
 public:
  cart_kernel_set(const chain_parameters& params, const physical_kernels& kernels)
      : kernel_set(params.links(), params.cart_packed()), m_params(params), m_k(&kernels) {}

  const taylor_kernels* taylor() const noexcept override { return m_k->taylor; }

  // q = [x_c, φ_1..φ_n]; w = [F, u_1..u_n], all of them actuators.
  int coordinates() const noexcept override { return cart_layout::coordinate_count(links()); }
  int input_size() const noexcept override { return cart_layout::input_size(links()); }
  int points() const noexcept override { return links() + 1; }

  void rhs(const double* x, double /*t*/, double* dxdt) const noexcept override {
    m_k->rhs(x, packed().data(), no_inputs.data(), dxdt);
  }
  void jacobian(const double* x, double /*t*/, double* jac) const noexcept override {
    m_k->jacobian(x, packed().data(), no_inputs.data(), jac);
  }
  void actuated_rhs(const double* x, double /*t*/, const double* actuation,
                    double* dxdt) const override {
    m_k->rhs(x, packed().data(), actuation, dxdt);
  }
  void actuated_jacobian(const double* x, double /*t*/, const double* actuation,
                         double* jac) const override {
    m_k->jacobian(x, packed().data(), actuation, jac);
  }
  void input_matrix(const double* q, double* dfdw) const override {
    m_k->input_matrix(q, packed().data(), dfdw);
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
  // The cart moves horizontally: V is the links' alone, a function of the angles.
  double potential_energy(const double* q, double /*t*/) const noexcept override {
    return fixed_support_potential(m_params, q + 1);
  }
  void mass_matrix(const double* q, double* A) const noexcept override {
    m_k->mass_matrix(q, packed().data(), A);
  }
  double det_mass_matrix(const double* q) const noexcept override {
    return m_k->det_mass_matrix(q, packed().data());
  }
  void potential_gradient(const double* q, double /*t*/, double* grad) const noexcept override {
    m_k->potential_gradient(q, packed().data(), no_inputs.data(), grad);
  }
  void potential_hessian(const double* q, double /*t*/, double* hess) const noexcept override {
    m_k->potential_hessian(q, packed().data(), no_inputs.data(), hess);
  }
  void positions(const double* q, double* xy) const noexcept override {
    m_k->positions(q, packed().data(), xy);
  }
  const char* equations_latex() const override {
    if (m_k->equations_latex == nullptr)
      throw std::invalid_argument("the equations of the pendulum on a cart are not emitted");
    return m_k->equations_latex();
  }

 protected:
  int first_actuator() const noexcept override { return cart_layout::force_index; }

 private:
  chain_parameters m_params;
  const physical_kernels* m_k;
};

}  // namespace

std::shared_ptr<const kernel_set> make_cart_kernel_set(const chain_parameters& params,
                                                       const physical_kernels& kernels) {
  const int n = params.links();
  check_generated_sizes(n, kernels.state_size, kernels.param_size, kernels.input_size,
                        cart_layout::state_size(n), cart_layout::param_size(n),
                        cart_layout::input_size(n));
  return std::make_shared<cart_kernel_set>(params, kernels);
}

}  // namespace npend::detail
