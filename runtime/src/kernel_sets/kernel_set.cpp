#include "npend/kernel_set.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <array>
#include <chain_index.hpp>
#include <cmath>
#include <vector>

#include "kernel_sets/kernel_set_detail.hpp"
#include "npend/chain.hpp"

namespace npend {

void kernel_set::jacobian_vector(const double* x, const double* u, double t, double* ju) const {
  const auto dim = static_cast<std::size_t>(2 * coordinates());
  std::vector<double> jac(dim * dim);
  jacobian(x, t, jac.data());
  for (std::size_t i = 0; i < dim; ++i) {
    double sum = 0;
    for (std::size_t j = 0; j < dim; ++j) sum += jac[i * dim + j] * u[j];
    ju[i] = sum;
  }
}

void kernel_set::input_series(double /*t*/, int order, double* w) const {
  std::fill(w, w + static_cast<std::ptrdiff_t>(input_size()) * (order + 1), 0.0);
}

void kernel_set::input_series(double /*t*/, int order, long double* w) const {
  std::fill(w, w + static_cast<std::ptrdiff_t>(input_size()) * (order + 1), 0.0L);
}

void kernel_set::time_derivative(const double* /*x*/, double /*t*/, double* dfdt) const {
  for (int i = 0; i < 2 * coordinates(); ++i) dfdt[i] = 0.0;
}

double kernel_set::hamiltonian(const double* x, double t) const {
  // T = ½ pᵀq̇ with q̇ = A⁻¹p, and V as potential_energy.
  // On the stack for the short chains, whose H a map asks for once per cell.
  const int c = coordinates();
  std::array<double, 16> short_chain;
  std::vector<double> long_chain(c > 16 ? static_cast<std::size_t>(c) : 0);
  double* dq = c > 16 ? long_chain.data() : short_chain.data();
  velocities(x, x + c, dq);
  double kinetic = 0;
  for (int i = 0; i < c; ++i) kinetic += x[c + i] * dq[i];
  return 0.5 * kinetic + potential_energy(x, t);
}

double kernel_set::hamiltonian_closed_form(const double* /*x*/) const {
  throw std::invalid_argument("the closed-form Hamiltonian is emitted for point-mass chains only");
}

double kernel_set::lagrangian(const double* q, const double* dq, double t) const {
  return kinetic_energy(q, dq) - potential_energy(q, t);
}

double kernel_set::log_det_mass_matrix(const double* q) const noexcept {
  return std::log(det_mass_matrix(q));
}

namespace {

std::string not_built_message(int n, const char* model) {
  const std::string list = fmt::format("{}", fmt::join(built_link_counts(), ";"));
  return fmt::format(
      "the {} of {} links is not built into this program (built: {}; point-mass chains take "
      "any count); add it with cmake -DNPEND_LINKS=\"{};{}\" and rebuild",
      model, n, list, list, n);
}

}  // namespace

std::shared_ptr<const kernel_set> make_kernel_set(const chain_parameters& params) {
  const int n = params.links();
  if (params.has_cart()) {
    const physical_kernels* cart = generated::cart_kernels_for(n);
    if (cart == nullptr) throw std::invalid_argument(not_built_message(n, "pendulum on a cart"));
    return detail::make_cart_kernel_set(params, *cart);
  }
  const chain_kernels* point = generated::find_chain(n);
  const physical_kernels* physical = generated::find_physical(n);
  if (point == nullptr || physical == nullptr) {
    if (params.is_physical()) throw std::invalid_argument(not_built_message(n, "physical chain"));
    return detail::make_loop_kernel_set(params);
  }
  detail::check_generated_sizes(n, point->state_size, point->param_size,
                                chain_layout::input_size(n), chain_layout::state_size(n),
                                chain_layout::param_size(n), chain_layout::input_size(n));
  detail::check_generated_sizes(n, physical->state_size, physical->param_size, physical->input_size,
                                chain_layout::state_size(n), chain_layout::physical_param_size(n),
                                chain_layout::input_size(n));
  if (params.is_physical()) return detail::make_physical_kernel_set(params, *physical);
  return detail::make_point_mass_kernel_set(params, *point, *physical);
}

namespace detail {

double fixed_support_potential(const chain_parameters& p, const double* phi) {
  const std::size_t n = p.masses.size();
  double gravity = 0, below = 0;  // below: the mass hanging under link k
  for (std::size_t k = n; k-- > 0;) {
    const double c = p.com.empty() ? p.lengths[k] : p.com[k];
    const double s = std::sin(0.5 * phi[k]);
    gravity += (p.masses[k] * c + p.lengths[k] * below) * (2 * s * s);
    below += p.masses[k];
  }
  double springs = 0;
  for (std::size_t j = 0; j < p.stiffness.size(); ++j) {
    if (p.stiffness[j] == 0) continue;
    const double rest = p.rest_angles.empty() ? 0 : p.rest_angles[j];
    const double bend = phi[j] - (j == 0 ? 0 : phi[j - 1]) - rest;
    springs += 0.5 * p.stiffness[j] * bend * bend;
  }
  return p.g * gravity + springs;
}

std::invalid_argument no_physical_kernels(int n, const char* what) {
  return std::invalid_argument(fmt::format(
      "{} needs the physical kernels, which are built for {} links only, not {}; add {} with "
      "cmake -DNPEND_LINKS",
      what, fmt::join(built_link_counts(), ", "), n, n));
}

void check_generated_sizes(int links, int state, int param, int inputs, int want_state,
                           int want_param, int want_inputs) {
  // Where generated code meets the runtime: the kernels must index the arrays as packed.
  if (state != want_state || param != want_param || inputs != want_inputs)
    throw std::logic_error(fmt::format(
        "the generated kernels for {} links take {} state, {} parameter and {} input entries, "
        "the runtime packs {}, {} and {}: regenerate them (cmake --build <build> --target "
        "npend_regenerate)",
        links, state, param, inputs, want_state, want_param, want_inputs));
}

}  // namespace detail

}  // namespace npend
