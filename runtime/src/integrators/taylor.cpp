#include "npend/integrators/taylor.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace npend {

namespace {

// The recurrences in T: the double kernels or their long double twin.
void run_kernels(const taylor_kernels& k, const double* params, const double* inputs, int order,
                 double* series, double* work) {
  k.coefficients(params, inputs, order, series, work);
}
void run_kernels(const taylor_kernels& k, const long double* params, const long double* inputs,
                 int order, long double* series, long double* work) {
  k.coefficients_long(params, inputs, order, series, work);
}

const taylor_kernels& taylor_kernels_of(const kernel_set& kernels) {
  const taylor_kernels* k = kernels.taylor();
  if (k == nullptr)
    throw std::invalid_argument(fmt::format(
        "the taylor stepper needs the generated Taylor kernels, which the {}-link chain runs "
        "without (it runs on the loop kernels): build its link count (CMake option "
        "NPEND_LINKS) or use another stepper",
        kernels.links()));
  return *k;
}

}  // namespace

int taylor_order_for(double tolerance) {
  if (!(tolerance > 0 && tolerance < 1))
    throw std::invalid_argument(
        fmt::format("taylor_order_for: the tolerance {} must lie in (0, 1)", tolerance));
  return std::max(2, static_cast<int>(std::ceil(-0.5 * std::log(tolerance) + 1)));
}

template <class T>
taylor_integrator<T>::taylor_integrator(const kernel_set& kernels, double abs_tol, double rel_tol,
                                        int order)
    : m_kernels(&kernels),
      m_taylor(&taylor_kernels_of(kernels)),
      m_abs_tol(abs_tol),
      m_rel_tol(rel_tol),
      m_order(order) {
  if (!(abs_tol >= 0 && rel_tol >= 0 && (abs_tol > 0 || rel_tol > 0)) || !std::isfinite(abs_tol) ||
      !std::isfinite(rel_tol))
    throw std::invalid_argument(
        fmt::format("taylor stepper: tolerances abs {} and rel {} must be finite, >= 0 and one > 0",
                    abs_tol, rel_tol));
  if (order == 0) {
    const double smaller =
        abs_tol > 0 && rel_tol > 0 ? std::min(abs_tol, rel_tol) : std::max(abs_tol, rel_tol);
    // Beyond taylor_max_order a tighter tolerance only shortens the steps (below double's
    // precision it cannot be met anyway: the step size collapses and the run says so).
    m_order = std::min(taylor_order_for(std::min(smaller, 0.5)), taylor_max_order);
  }
  if (m_order < 2 || m_order > taylor_max_order)
    throw std::invalid_argument(fmt::format(
        "taylor stepper: the order {} must lie in 2..{} (0 chooses it from the tolerance)", order,
        taylor_max_order));
  const auto stride = static_cast<std::size_t>(m_order + 1);
  const auto& packed = kernels.packed();
  m_params.assign(packed.begin(), packed.end());
  m_inputs.assign(static_cast<std::size_t>(m_taylor->input_size) * stride, T(0));
  m_series.assign(static_cast<std::size_t>(m_taylor->state_size) * stride, T(0));
  m_work.assign(static_cast<std::size_t>(m_taylor->work_slots) * stride, T(0));
  m_x.assign(static_cast<std::size_t>(m_taylor->state_size), T(0));
  // Inputs without a series (a custom pivot path) are refused now, not in the first step.
  if (m_taylor->input_size > 0) kernels.input_series(0.0, m_order, m_inputs.data());
}

template <class T>
void taylor_integrator<T>::reset(T t, const T* x) {
  std::copy(x, x + m_x.size(), m_x.begin());
  m_t = m_t_begin = t;
  m_h = 0;
}

template <class T>
void taylor_integrator<T>::coefficients() {
  const auto stride = static_cast<std::size_t>(m_order + 1);
  for (std::size_t i = 0; i < m_x.size(); ++i) m_series[i * stride] = m_x[i];
  if (m_taylor->input_size > 0)
    m_kernels->input_series(static_cast<double>(m_t), m_order, m_inputs.data());
  run_kernels(*m_taylor, m_params.data(), m_inputs.data(), m_order, m_series.data(), m_work.data());
}

template <class T>
T taylor_integrator<T>::step(T direction, T limit, T fallback) {
  using std::fabs;
  using std::pow;
  coefficients();
  const auto stride = static_cast<std::size_t>(m_order + 1);
  const auto norm = [&](int j) {
    T largest = 0;
    for (std::size_t i = 0; i < m_x.size(); ++i)
      largest = std::max(largest, T(fabs(m_series[i * stride + static_cast<std::size_t>(j)])));
    return largest;
  };
  // The absolute tolerance rules where it is the larger bound, the relative one elsewhere.
  const T size = norm(0);
  const T bound = std::max(T(m_abs_tol), T(m_rel_tol) * size);
  T h = std::numeric_limits<T>::infinity();
  for (const int j : {m_order - 1, m_order}) {
    const T coefficient = norm(j);
    if (coefficient > 0) h = std::min(h, T(pow(bound / coefficient, T(1) / T(j))));
  }
  h *= T(std::exp(-0.7 / (m_order - 1)));
  if (limit != 0) h = std::min(h, T(fabs(limit)));
  // No coefficient to go by (an equilibrium), or NaN ones (the run reports the state).
  if (!(h < std::numeric_limits<T>::infinity())) h = fabs(fallback);
  h = direction < 0 ? -h : h;
  m_t_begin = m_t;
  m_h = h;
  state_at(h, m_x.data());
  m_t = m_t_begin + h;
  return h;
}

template <class T>
void taylor_integrator<T>::state_at(T tau, T* x) const {
  const auto stride = static_cast<std::size_t>(m_order + 1);
  for (std::size_t i = 0; i < m_x.size(); ++i) {
    const T* c = m_series.data() + i * stride;
    T sum = c[m_order];
    for (int k = m_order - 1; k >= 0; --k) sum = sum * tau + c[k];
    x[i] = sum;
  }
}

template class taylor_integrator<double>;
template class taylor_integrator<long double>;

void taylor_stepper::initialize(const state_type& x0, double t0, double dt0) {
  if (x0.size() != m_integrator.dimension())
    throw std::invalid_argument(fmt::format("taylor stepper: the state has {} entries, not {}",
                                            x0.size(), m_integrator.dimension()));
  m_integrator.reset(t0, x0.data());
  m_dt0 = dt0;
}

std::pair<double, double> taylor_stepper::step() {
  const double from = m_integrator.time();
  m_integrator.step(m_dt0, 0, m_dt0);
  return {from, m_integrator.time()};
}

void taylor_stepper::calc_state(double t, state_type& x) const {
  x.resize(m_integrator.dimension());
  m_integrator.state_at(t - m_integrator.step_begin(), x.data());
}

}  // namespace npend
