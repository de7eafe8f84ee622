#include "npend/chain.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chain_index.hpp>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "kernel_sets/kernel_set_detail.hpp"

namespace npend {

std::vector<int> built_link_counts() {
  int count = 0;
  const int* links = generated::built_links(&count);
  return {links, links + count};
}

chain::chain(chain_parameters params) : m_params(std::move(params)) {
  m_params.validate();
  m_kernels = make_kernel_set(m_params);
  m_links = m_kernels->links();
  m_coordinates = m_kernels->coordinates();
}

const chain_kernels& chain::kernels() const {
  if (m_kernels->unrolled() == nullptr)
    throw std::logic_error(is_physical()
                               ? "chain::kernels(): a physical chain runs on physical_table()"
                               : "chain::kernels(): this chain runs on the loop kernels");
  return *m_kernels->unrolled();
}

const physical_kernels& chain::physical_table() const {
  const physical_kernels* table = generated::find_physical(m_links);
  if (table == nullptr) throw detail::no_physical_kernels(m_links, "this computation");
  return *table;
}

const char* chain::equations_latex() const { return m_kernels->equations_latex(); }

void chain::check_size(std::span<const double> v, int expected, const char* what) const {
  if (v.size() != static_cast<std::size_t>(expected))
    throw std::invalid_argument(fmt::format("{} has {} entries; the {}-link chain{} needs {}", what,
                                            v.size(), m_links, has_cart() ? " on a cart" : "",
                                            expected));
}

void chain::check_size(std::span<double> v, int expected, const char* what) const {
  check_size(std::span<const double>(v.data(), v.size()), expected, what);
}

void chain::rhs(std::span<const double> x, std::span<double> dxdt, double t) const {
  check_size(x, state_size(), "state x");
  check_size(dxdt, state_size(), "dxdt");
  evaluate_rhs(x.data(), t, dxdt.data());
}

void chain::jacobian(std::span<const double> x, std::span<double> jac, double t) const {
  check_size(x, state_size(), "state x");
  check_size(jac, state_size() * state_size(), "jacobian");
  evaluate_jacobian(x.data(), t, jac.data());
}

void chain::input_matrix(std::span<const double> q, std::span<double> dfdw) const {
  check_size(q, m_coordinates, "phi");
  check_size(dfdw, state_size() * input_size(), "input matrix");
  m_kernels->input_matrix(q.data(), dfdw.data());
}

void chain::rhs(std::span<const double> x, std::span<double> dxdt, double t,
                std::span<const double> actuation) const {
  check_size(x, state_size(), "state x");
  check_size(dxdt, state_size(), "dxdt");
  check_size(actuation, actuators(), has_cart() ? "actuation" : "torques");
  m_kernels->actuated_rhs(x.data(), t, actuation.data(), dxdt.data());
}

void chain::jacobian(std::span<const double> x, std::span<double> jac, double t,
                     std::span<const double> actuation) const {
  check_size(x, state_size(), "state x");
  check_size(jac, state_size() * state_size(), "jacobian");
  check_size(actuation, actuators(), has_cart() ? "actuation" : "torques");
  m_kernels->actuated_jacobian(x.data(), t, actuation.data(), jac.data());
}

void chain::time_derivative(std::span<const double> x, std::span<double> dfdt, double t) const {
  check_size(x, state_size(), "state x");
  check_size(dfdt, state_size(), "dfdt");
  m_kernels->time_derivative(x.data(), t, dfdt.data());
}

double chain::hamiltonian(std::span<const double> x, double t) const {
  check_size(x, state_size(), "state x");
  return m_kernels->hamiltonian(x.data(), t);
}

double chain::hamiltonian_closed_form(std::span<const double> x) const {
  check_size(x, state_size(), "state x");
  return m_kernels->hamiltonian_closed_form(x.data());
}

void chain::velocities(std::span<const double> q, std::span<const double> p,
                       std::span<double> dq) const {
  check_size(q, m_coordinates, "phi");
  check_size(p, m_coordinates, "p");
  check_size(dq, m_coordinates, "dphi");
  m_kernels->velocities(q.data(), p.data(), dq.data());
}

void chain::momenta(std::span<const double> q, std::span<const double> dq,
                    std::span<double> p) const {
  check_size(q, m_coordinates, "phi");
  check_size(dq, m_coordinates, "dphi");
  check_size(p, m_coordinates, "p");
  m_kernels->momenta(q.data(), dq.data(), p.data());
}

double chain::lagrangian(std::span<const double> q, std::span<const double> dq, double t) const {
  check_size(q, m_coordinates, "phi");
  check_size(dq, m_coordinates, "dphi");
  return m_kernels->lagrangian(q.data(), dq.data(), t);
}

double chain::kinetic_energy(std::span<const double> q, std::span<const double> dq) const {
  check_size(q, m_coordinates, "phi");
  check_size(dq, m_coordinates, "dphi");
  return m_kernels->kinetic_energy(q.data(), dq.data());
}

double chain::potential_energy(std::span<const double> q, double t) const {
  check_size(q, m_coordinates, "phi");
  return m_kernels->potential_energy(q.data(), t);
}

void chain::mass_matrix(std::span<const double> q, std::span<double> A) const {
  check_size(q, m_coordinates, "phi");
  check_size(A, m_coordinates * m_coordinates, "mass matrix");
  m_kernels->mass_matrix(q.data(), A.data());
}

double chain::det_mass_matrix(std::span<const double> q) const {
  check_size(q, m_coordinates, "phi");
  return m_kernels->det_mass_matrix(q.data());
}

double chain::log_det_mass_matrix(std::span<const double> q) const {
  check_size(q, m_coordinates, "phi");
  return m_kernels->log_det_mass_matrix(q.data());
}

void chain::potential_gradient(std::span<const double> q, std::span<double> grad, double t) const {
  check_size(q, m_coordinates, "phi");
  check_size(grad, m_coordinates, "gradient");
  m_kernels->potential_gradient(q.data(), t, grad.data());
}

void chain::potential_hessian(std::span<const double> q, std::span<double> hess, double t) const {
  check_size(q, m_coordinates, "phi");
  check_size(hess, m_coordinates * m_coordinates, "hessian");
  m_kernels->potential_hessian(q.data(), t, hess.data());
}

void chain::positions(std::span<const double> q, std::span<double> xy) const {
  check_size(q, m_coordinates, "phi");
  check_size(xy, 2 * points(), "positions");
  m_kernels->positions(q.data(), xy.data());
}

void chain::jacobian_vector(std::span<const double> x, std::span<const double> u,
                            std::span<double> ju, double t) const {
  check_size(x, state_size(), "state x");
  check_size(u, state_size(), "direction u");
  check_size(ju, state_size(), "J u");
  m_kernels->jacobian_vector(x.data(), u.data(), t, ju.data());
}

std::vector<double> chain::rhs(std::span<const double> x) const {
  std::vector<double> out(static_cast<std::size_t>(state_size()));
  rhs(x, out);
  return out;
}

std::vector<double> chain::jacobian(std::span<const double> x) const {
  std::vector<double> out(static_cast<std::size_t>(state_size() * state_size()));
  jacobian(x, out);
  return out;
}

std::vector<double> chain::state_from_velocities(std::span<const double> q,
                                                 std::span<const double> dq) const {
  std::vector<double> x(q.begin(), q.end());
  x.resize(static_cast<std::size_t>(state_size()));
  momenta(q, dq, std::span<double>(x).subspan(static_cast<std::size_t>(m_coordinates)));
  return x;
}

double wrapped_angle(double phi) { return std::remainder(phi, 2 * std::numbers::pi); }

}  // namespace npend
