#include "npend/chain.hpp"

#include <chain_index.hpp>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace npend {

std::vector<int> built_link_counts() {
  int count = 0;
  const int* links = generated::built_links(&count);
  return {links, links + count};
}

namespace {

std::string not_built_message(int n) {
  const std::string list = fmt::format("{}", fmt::join(built_link_counts(), ";"));
  return fmt::format(
      "{} links are not built into this program (built: {}); add them with cmake "
      "-DNPEND_LINKS=\"{};{}\" and rebuild",
      n, list, list, n);
}

}  // namespace

chain::chain(chain_parameters params) : m_params(std::move(params)) {
  m_params.validate();
  m_links = m_params.links();
  m_kernels = generated::find_chain(m_links);
  if (m_kernels == nullptr) throw std::invalid_argument(not_built_message(m_links));
  // Where generated code meets the runtime: the kernels must index the arrays as packed().
  if (m_kernels->state_size != chain_layout::state_size(m_links) ||
      m_kernels->param_size != chain_layout::param_size(m_links))
    throw std::logic_error(fmt::format(
        "the generated kernels for {} links take {} state and {} parameter entries, the runtime "
        "packs {} and {}: regenerate them (cmake --build <build> --target npend_regenerate)",
        m_links, m_kernels->state_size, m_kernels->param_size, chain_layout::state_size(m_links),
        chain_layout::param_size(m_links)));
  m_packed = m_params.packed();
}

void chain::check_size(std::span<const double> v, int expected, const char* what) const {
  if (v.size() != static_cast<std::size_t>(expected))
    throw std::invalid_argument(fmt::format("{} has {} entries; the {}-link chain needs {}", what,
                                            v.size(), m_links, expected));
}

void chain::check_size(std::span<double> v, int expected, const char* what) const {
  check_size(std::span<const double>(v.data(), v.size()), expected, what);
}

void chain::rhs(std::span<const double> x, std::span<double> dxdt) const {
  check_size(x, state_size(), "state x");
  check_size(dxdt, state_size(), "dxdt");
  m_kernels->rhs(x.data(), m_packed.data(), dxdt.data());
}

void chain::jacobian(std::span<const double> x, std::span<double> jac) const {
  check_size(x, state_size(), "state x");
  check_size(jac, state_size() * state_size(), "jacobian");
  m_kernels->jacobian(x.data(), m_packed.data(), jac.data());
}

double chain::hamiltonian(std::span<const double> x) const {
  check_size(x, state_size(), "state x");
  return m_kernels->hamiltonian(x.data(), m_packed.data());
}

double chain::hamiltonian_closed_form(std::span<const double> x) const {
  check_size(x, state_size(), "state x");
  if (m_kernels->hamiltonian_closed_form == nullptr)
    throw std::invalid_argument(
        fmt::format("the closed-form Hamiltonian is emitted for up to 3 links, not {}", m_links));
  return m_kernels->hamiltonian_closed_form(x.data(), m_packed.data());
}

void chain::velocities(std::span<const double> phi, std::span<const double> p,
                       std::span<double> dphi) const {
  check_size(phi, m_links, "phi");
  check_size(p, m_links, "p");
  check_size(dphi, m_links, "dphi");
  m_kernels->velocities(phi.data(), p.data(), m_packed.data(), dphi.data());
}

void chain::momenta(std::span<const double> phi, std::span<const double> dphi,
                    std::span<double> p) const {
  check_size(phi, m_links, "phi");
  check_size(dphi, m_links, "dphi");
  check_size(p, m_links, "p");
  m_kernels->momenta(phi.data(), dphi.data(), m_packed.data(), p.data());
}

double chain::lagrangian(std::span<const double> phi, std::span<const double> dphi) const {
  check_size(phi, m_links, "phi");
  check_size(dphi, m_links, "dphi");
  return m_kernels->lagrangian(phi.data(), dphi.data(), m_packed.data());
}

double chain::kinetic_energy(std::span<const double> phi, std::span<const double> dphi) const {
  check_size(phi, m_links, "phi");
  check_size(dphi, m_links, "dphi");
  return m_kernels->kinetic_energy(phi.data(), dphi.data(), m_packed.data());
}

double chain::potential_energy(std::span<const double> phi) const {
  check_size(phi, m_links, "phi");
  return m_kernels->potential_energy(phi.data(), m_packed.data());
}

void chain::mass_matrix(std::span<const double> phi, std::span<double> A) const {
  check_size(phi, m_links, "phi");
  check_size(A, m_links * m_links, "mass matrix");
  m_kernels->mass_matrix(phi.data(), m_packed.data(), A.data());
}

double chain::det_mass_matrix(std::span<const double> phi) const {
  check_size(phi, m_links, "phi");
  return m_kernels->det_mass_matrix(phi.data(), m_packed.data());
}

void chain::potential_gradient(std::span<const double> phi, std::span<double> grad) const {
  check_size(phi, m_links, "phi");
  check_size(grad, m_links, "gradient");
  m_kernels->potential_gradient(phi.data(), m_packed.data(), grad.data());
}

void chain::potential_hessian(std::span<const double> phi, std::span<double> hess) const {
  check_size(phi, m_links, "phi");
  check_size(hess, m_links * m_links, "hessian");
  m_kernels->potential_hessian(phi.data(), m_packed.data(), hess.data());
}

void chain::positions(std::span<const double> phi, std::span<double> xy) const {
  check_size(phi, m_links, "phi");
  check_size(xy, 2 * m_links, "positions");
  m_kernels->positions(phi.data(), m_packed.data(), xy.data());
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

std::vector<double> chain::state_from_velocities(std::span<const double> phi,
                                                 std::span<const double> dphi) const {
  std::vector<double> x(phi.begin(), phi.end());
  x.resize(static_cast<std::size_t>(state_size()));
  momenta(phi, dphi, std::span<double>(x).subspan(static_cast<std::size_t>(m_links)));
  return x;
}

double wrapped_angle(double phi) { return std::remainder(phi, 2 * std::numbers::pi); }

}  // namespace npend
