#include "npend/chain.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <array>
#include <chain_index.hpp>
#include <chain_loop.hpp>
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
      "the physical chain of {} links is not built into this program (built: {}; point-mass "
      "chains take any count); add it with cmake -DNPEND_LINKS=\"{};{}\" and rebuild",
      n, list, list, n);
}

std::invalid_argument no_physical_kernels(int n, const char* what) {
  return std::invalid_argument(fmt::format(
      "{} needs the physical kernels, which are built for {} links only, not {}; add {} with "
      "cmake -DNPEND_LINKS",
      what, fmt::join(built_link_counts(), ", "), n, n));
}

// V on a fixed pivot: gravity g Σ_k a_k (1 − cos φ_k) with a_k = m_k c_k + l_k Σ_{j>k} m_j
// (c_k = l_k for a point mass) and the joint springs ½ k_j (φ_j − φ_{j−1} − θ⁰_j)² (φ_0 = 0),
// the kernels' V term for term, but with 1 − cos φ written 2 sin²(φ/2): near the rest
// position 1 − cos φ cancels to one rounding unit of 1 (an energy of 1e-12 J came out with a
// relative error of 1e-3), its half-angle form keeps the relative precision of φ².
double fixed_pivot_potential(const chain_parameters& p, const double* phi) {
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

}  // namespace

chain::chain(chain_parameters params) : m_params(std::move(params)) {
  m_params.validate();
  m_links = m_params.links();
  m_kernels = generated::find_chain(m_links);
  m_physical_kernels = generated::find_physical(m_links);
  m_physical = m_params.is_physical();
  if (m_kernels == nullptr || m_physical_kernels == nullptr) {
    if (m_physical) throw std::invalid_argument(not_built_message(m_links));
    m_loop = &generated::chain_loop::kernels;
    m_packed = m_params.packed();
    return;
  }
  // Where generated code meets the runtime: the kernels must index the arrays as packed().
  const auto mismatch = [&](int state, int param, int want_param) {
    return std::logic_error(fmt::format(
        "the generated kernels for {} links take {} state and {} parameter entries, the runtime "
        "packs {} and {}: regenerate them (cmake --build <build> --target npend_regenerate)",
        m_links, state, param, chain_layout::state_size(m_links), want_param));
  };
  if (m_kernels->state_size != chain_layout::state_size(m_links) ||
      m_kernels->param_size != chain_layout::param_size(m_links))
    throw mismatch(m_kernels->state_size, m_kernels->param_size, chain_layout::param_size(m_links));
  if (m_physical_kernels->state_size != chain_layout::state_size(m_links) ||
      m_physical_kernels->param_size != chain_layout::physical_param_size(m_links) ||
      m_physical_kernels->input_size != chain_layout::input_size(m_links))
    throw mismatch(m_physical_kernels->state_size, m_physical_kernels->param_size,
                   chain_layout::physical_param_size(m_links));
  m_physical_packed = m_params.physical_packed();
  m_packed = m_physical ? m_physical_packed : m_params.packed();
}

const chain_kernels& chain::kernels() const {
  if (m_physical)
    throw std::logic_error("chain::kernels(): a physical chain runs on physical_table()");
  if (m_loop != nullptr)
    throw std::logic_error("chain::kernels(): this chain runs on the loop kernels");
  return *m_kernels;
}

const physical_kernels& chain::physical_table() const {
  if (m_physical_kernels == nullptr) throw no_physical_kernels(m_links, "this computation");
  return *m_physical_kernels;
}

double* chain::loop_workspace(bool jacobian) const {
  thread_local std::vector<double> work;
  const std::size_t size = jacobian ? m_loop->jacobian_workspace_size(m_links)
                                    : static_cast<std::size_t>(m_loop->workspace_size(m_links));
  if (work.size() < size) work.resize(size);
  return work.data();
}

const char* chain::equations_latex() const {
  if (m_loop != nullptr)
    throw std::invalid_argument(fmt::format(
        "the equations of {} links are not derived in this build (it runs them on the loop "
        "kernels); npend-gen --latex {} prints them",
        m_links, m_links));
  return m_physical ? m_physical_kernels->equations_latex() : m_kernels->equations_latex();
}

void chain::fill_inputs(double t, double* w, const double* torques) const noexcept {
  const auto a = m_params.pivot.acceleration_at(t);
  w[chain_layout::pivot_acceleration_index(0)] = a[0];
  w[chain_layout::pivot_acceleration_index(1)] = a[1];
  for (int i = 0; i < m_links; ++i)
    w[chain_layout::torque_index(m_links, i)] = torques != nullptr ? torques[i] : 0.0;
}

std::vector<double> chain::inputs_at(double t) const {
  std::vector<double> w(static_cast<std::size_t>(chain_layout::input_size(m_links)));
  fill_inputs(t, w.data());
  return w;
}

namespace {

// The inputs of one evaluation, on the stack: no allocation inside an integrator's step.
using input_buffer = std::array<double, chain_layout::input_size(chain_layout::max_links)>;

}  // namespace

void chain::evaluate_rhs(const double* x, double t, double* dxdt) const noexcept {
  if (m_loop != nullptr) return m_loop->rhs(m_links, x, m_packed.data(), dxdt, loop_workspace());
  if (!m_physical) return m_kernels->rhs(x, m_packed.data(), dxdt);
  input_buffer w;
  fill_inputs(t, w.data());
  m_physical_kernels->rhs(x, m_packed.data(), w.data(), dxdt);
}

void chain::evaluate_jacobian(const double* x, double t, double* jac) const noexcept {
  if (m_loop != nullptr)
    return m_loop->jacobian(m_links, x, m_packed.data(), jac, loop_workspace(true));
  if (!m_physical) return m_kernels->jacobian(x, m_packed.data(), jac);
  input_buffer w;
  fill_inputs(t, w.data());
  m_physical_kernels->jacobian(x, m_packed.data(), w.data(), jac);
}

void chain::check_size(std::span<const double> v, int expected, const char* what) const {
  if (v.size() != static_cast<std::size_t>(expected))
    throw std::invalid_argument(fmt::format("{} has {} entries; the {}-link chain needs {}", what,
                                            v.size(), m_links, expected));
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

void chain::input_matrix(std::span<const double> phi, std::span<double> dfdw) const {
  check_size(phi, m_links, "phi");
  check_size(dfdw, state_size() * chain_layout::input_size(m_links), "input matrix");
  // A point-mass chain is the physical chain with c = l and nothing else: same B.
  physical_table().input_matrix(phi.data(), m_physical_packed.data(), dfdw.data());
}

void chain::rhs(std::span<const double> x, std::span<double> dxdt, double t,
                std::span<const double> torques) const {
  check_size(x, state_size(), "state x");
  check_size(dxdt, state_size(), "dxdt");
  check_size(torques, m_links, "torques");
  const physical_kernels& kernels = physical_table();
  input_buffer w;
  fill_inputs(t, w.data(), torques.data());
  kernels.rhs(x.data(), m_physical_packed.data(), w.data(), dxdt.data());
}

void chain::jacobian(std::span<const double> x, std::span<double> jac, double t,
                     std::span<const double> torques) const {
  check_size(x, state_size(), "state x");
  check_size(jac, state_size() * state_size(), "jacobian");
  check_size(torques, m_links, "torques");
  const physical_kernels& kernels = physical_table();
  input_buffer w;
  fill_inputs(t, w.data(), torques.data());
  kernels.jacobian(x.data(), m_physical_packed.data(), w.data(), jac.data());
}

void chain::time_derivative(std::span<const double> x, std::span<double> dfdt, double t) const {
  check_size(x, state_size(), "state x");
  check_size(dfdt, state_size(), "dfdt");
  std::fill(dfdt.begin(), dfdt.end(), 0.0);
  if (!m_params.pivot.moves()) return;
  // f is affine in w and w depends on t through the pivot's acceleration only.
  const int dim = state_size(), inputs = chain_layout::input_size(m_links);
  std::vector<double> dfdw(static_cast<std::size_t>(dim * inputs));
  input_matrix(x.first(static_cast<std::size_t>(m_links)), dfdw);
  const auto jerk = m_params.pivot.jerk_at(t);
  for (int i = 0; i < dim; ++i)
    dfdt[static_cast<std::size_t>(i)] =
        dfdw[static_cast<std::size_t>(i * inputs + chain_layout::pivot_acceleration_index(0))] *
            jerk[0] +
        dfdw[static_cast<std::size_t>(i * inputs + chain_layout::pivot_acceleration_index(1))] *
            jerk[1];
}

double chain::hamiltonian(std::span<const double> x, double t) const {
  check_size(x, state_size(), "state x");
  if (!m_params.pivot.moves()) {
    // T = ½ pᵀφ̇ with φ̇ = A⁻¹p, and V without cancellation (see fixed_pivot_potential).
    const auto n = static_cast<std::size_t>(m_links);
    std::vector<double> dphi(n);
    velocities(x.first(n), x.subspan(n, n), dphi);
    double kinetic = 0;
    for (std::size_t i = 0; i < n; ++i) kinetic += x[n + i] * dphi[i];
    return 0.5 * kinetic + fixed_pivot_potential(m_params, x.data());
  }
  if (m_loop != nullptr)
    return m_loop->hamiltonian(m_links, x.data(), m_packed.data(), loop_workspace());
  if (!m_physical) return m_kernels->hamiltonian(x.data(), m_packed.data());
  input_buffer w;
  fill_inputs(t, w.data());
  return m_physical_kernels->hamiltonian(x.data(), m_packed.data(), w.data());
}

double chain::hamiltonian_closed_form(std::span<const double> x) const {
  check_size(x, state_size(), "state x");
  if (m_physical)
    throw std::invalid_argument(
        "the closed-form Hamiltonian is emitted for point-mass chains only");
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
  if (m_loop != nullptr)
    return m_loop->velocities(m_links, phi.data(), p.data(), m_packed.data(), dphi.data(),
                              loop_workspace());
  (m_physical ? m_physical_kernels->velocities : m_kernels->velocities)(
      phi.data(), p.data(), m_packed.data(), dphi.data());
}

void chain::momenta(std::span<const double> phi, std::span<const double> dphi,
                    std::span<double> p) const {
  check_size(phi, m_links, "phi");
  check_size(dphi, m_links, "dphi");
  check_size(p, m_links, "p");
  if (m_loop != nullptr)
    return m_loop->momenta(m_links, phi.data(), dphi.data(), m_packed.data(), p.data(),
                           loop_workspace());
  (m_physical ? m_physical_kernels->momenta : m_kernels->momenta)(phi.data(), dphi.data(),
                                                                  m_packed.data(), p.data());
}

double chain::lagrangian(std::span<const double> phi, std::span<const double> dphi,
                         double t) const {
  check_size(phi, m_links, "phi");
  check_size(dphi, m_links, "dphi");
  if (!m_params.pivot.moves()) return kinetic_energy(phi, dphi) - potential_energy(phi);
  if (m_loop != nullptr)
    return m_loop->lagrangian(m_links, phi.data(), dphi.data(), m_packed.data(), loop_workspace());
  if (!m_physical) return m_kernels->lagrangian(phi.data(), dphi.data(), m_packed.data());
  input_buffer w;
  fill_inputs(t, w.data());
  return m_physical_kernels->lagrangian(phi.data(), dphi.data(), m_packed.data(), w.data());
}

double chain::kinetic_energy(std::span<const double> phi, std::span<const double> dphi) const {
  check_size(phi, m_links, "phi");
  check_size(dphi, m_links, "dphi");
  if (m_loop != nullptr)
    return m_loop->kinetic_energy(m_links, phi.data(), dphi.data(), m_packed.data(),
                                  loop_workspace());
  return (m_physical ? m_physical_kernels->kinetic_energy : m_kernels->kinetic_energy)(
      phi.data(), dphi.data(), m_packed.data());
}

double chain::potential_energy(std::span<const double> phi, double t) const {
  check_size(phi, m_links, "phi");
  if (!m_params.pivot.moves()) return fixed_pivot_potential(m_params, phi.data());
  if (m_loop != nullptr)
    return m_loop->potential_energy(m_links, phi.data(), m_packed.data(), loop_workspace());
  if (!m_physical) return m_kernels->potential_energy(phi.data(), m_packed.data());
  input_buffer w;
  fill_inputs(t, w.data());
  return m_physical_kernels->potential_energy(phi.data(), m_packed.data(), w.data());
}

void chain::mass_matrix(std::span<const double> phi, std::span<double> A) const {
  check_size(phi, m_links, "phi");
  check_size(A, m_links * m_links, "mass matrix");
  if (m_loop != nullptr)
    return m_loop->mass_matrix(m_links, phi.data(), m_packed.data(), A.data(), loop_workspace());
  (m_physical ? m_physical_kernels->mass_matrix : m_kernels->mass_matrix)(
      phi.data(), m_packed.data(), A.data());
}

double chain::det_mass_matrix(std::span<const double> phi) const {
  check_size(phi, m_links, "phi");
  if (m_loop != nullptr)
    return m_loop->det_mass_matrix(m_links, phi.data(), m_packed.data(), loop_workspace());
  return (m_physical ? m_physical_kernels->det_mass_matrix : m_kernels->det_mass_matrix)(
      phi.data(), m_packed.data());
}

double chain::log_det_mass_matrix(std::span<const double> phi) const {
  check_size(phi, m_links, "phi");
  if (m_loop != nullptr)
    return m_loop->log_det_mass_matrix(m_links, phi.data(), m_packed.data(), loop_workspace());
  return std::log(det_mass_matrix(phi));
}

void chain::potential_gradient(std::span<const double> phi, std::span<double> grad,
                               double t) const {
  check_size(phi, m_links, "phi");
  check_size(grad, m_links, "gradient");
  if (m_loop != nullptr)
    return m_loop->potential_gradient(m_links, phi.data(), m_packed.data(), grad.data(),
                                      loop_workspace());
  if (!m_physical) return m_kernels->potential_gradient(phi.data(), m_packed.data(), grad.data());
  input_buffer w;
  fill_inputs(t, w.data());
  m_physical_kernels->potential_gradient(phi.data(), m_packed.data(), w.data(), grad.data());
}

void chain::potential_hessian(std::span<const double> phi, std::span<double> hess, double t) const {
  check_size(phi, m_links, "phi");
  check_size(hess, m_links * m_links, "hessian");
  if (m_loop != nullptr)
    return m_loop->potential_hessian(m_links, phi.data(), m_packed.data(), hess.data(),
                                     loop_workspace());
  if (!m_physical) return m_kernels->potential_hessian(phi.data(), m_packed.data(), hess.data());
  input_buffer w;
  fill_inputs(t, w.data());
  m_physical_kernels->potential_hessian(phi.data(), m_packed.data(), w.data(), hess.data());
}

void chain::positions(std::span<const double> phi, std::span<double> xy) const {
  check_size(phi, m_links, "phi");
  check_size(xy, 2 * m_links, "positions");
  if (m_loop != nullptr)
    return m_loop->positions(m_links, phi.data(), m_packed.data(), xy.data(), loop_workspace());
  (m_physical ? m_physical_kernels->positions : m_kernels->positions)(phi.data(), m_packed.data(),
                                                                      xy.data());
}

void chain::jacobian_vector(std::span<const double> x, std::span<const double> u,
                            std::span<double> ju, double t) const {
  check_size(x, state_size(), "state x");
  check_size(u, state_size(), "direction u");
  check_size(ju, state_size(), "J u");
  if (m_loop != nullptr)
    return m_loop->jacobian_vector(m_links, x.data(), m_packed.data(), u.data(), ju.data(),
                                   loop_workspace());
  const auto dim = static_cast<std::size_t>(state_size());
  std::vector<double> jac(dim * dim);
  evaluate_jacobian(x.data(), t, jac.data());
  for (std::size_t i = 0; i < dim; ++i) {
    double sum = 0;
    for (std::size_t j = 0; j < dim; ++j) sum += jac[i * dim + j] * u[j];
    ju[i] = sum;
  }
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
