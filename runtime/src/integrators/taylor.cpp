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

void check_tolerances(double abs_tol, double rel_tol) {
  if (!(abs_tol >= 0 && rel_tol >= 0 && (abs_tol > 0 || rel_tol > 0)) || !std::isfinite(abs_tol) ||
      !std::isfinite(rel_tol))
    throw std::invalid_argument(
        fmt::format("taylor stepper: tolerances abs {} and rel {} must be finite, >= 0 and one > 0",
                    abs_tol, rel_tol));
}

// The order given, or (0) the one the smaller positive tolerance asks for.
int chosen_order(double abs_tol, double rel_tol, int order) {
  check_tolerances(abs_tol, rel_tol);
  if (order == 0) {
    const double smaller =
        abs_tol > 0 && rel_tol > 0 ? std::min(abs_tol, rel_tol) : std::max(abs_tol, rel_tol);
    // Beyond taylor_max_order a tighter tolerance only shortens the steps (below double's
    // precision it cannot be met anyway: the step size collapses and the run says so).
    return std::min(taylor_order_for(std::min(smaller, 0.5)), taylor_max_order);
  }
  if (order < 2 || order > taylor_max_order)
    throw std::invalid_argument(fmt::format(
        "taylor stepper: the order {} must lie in 2..{} (0 chooses it from the tolerance)", order,
        taylor_max_order));
  return order;
}

// Jorba & Zou's step (taylor.hpp) from the bound ε·s and the norms of the last two
// coefficients: +inf where both vanish (an equilibrium).
template <class T>
T step_length(T bound, T previous, T last, int order) {
  using std::pow;
  T h = std::numeric_limits<T>::infinity();
  if (previous > 0) h = std::min(h, T(pow(bound / previous, T(1) / T(order - 1))));
  if (last > 0) h = std::min(h, T(pow(bound / last, T(1) / T(order))));
  return h * T(std::exp(-0.7 / (order - 1)));
}

// The step's length and sign from the rule's h: no longer than |limit| (0: no limit), and
// |fallback| where the rule gives none (an equilibrium, or NaN coefficients: the run reports
// the state).
template <class T>
T signed_step(T h, T direction, T limit, T fallback) {
  using std::fabs;
  if (limit != 0) h = std::min(h, T(fabs(limit)));
  if (!(h < std::numeric_limits<T>::infinity())) h = fabs(fallback);
  return direction < 0 ? -h : h;
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
      m_order(chosen_order(abs_tol, rel_tol, order)) {
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
  coefficients();
  const auto stride = static_cast<std::size_t>(m_order + 1);
  const auto norm = [&](int j) {
    T largest = 0;
    for (std::size_t i = 0; i < m_x.size(); ++i)
      largest = std::max(largest, T(fabs(m_series[i * stride + static_cast<std::size_t>(j)])));
    return largest;
  };
  // The absolute tolerance rules where it is the larger bound, the relative one elsewhere.
  const T bound = std::max(T(m_abs_tol), T(m_rel_tol) * norm(0));
  const T h = signed_step(step_length(bound, norm(m_order - 1), norm(m_order), m_order), direction,
                          limit, fallback);
  m_t_begin = m_t;
  m_h = h;
  state_at(h, m_x.data());
  m_t = m_t_begin + h;
  return h;
}

// Horner's rule, four coordinates at a time: their sums are independent, so their
// multiply-adds overlap rather than each waiting for the one before (a dense output on a
// fine grid spent most of its time here). Each sum is the same operations in the same order
// as one coordinate's Horner loop.
template <class T>
void taylor_integrator<T>::state_at(T tau, T* x) const {
  const auto stride = static_cast<std::size_t>(m_order + 1);
  const std::size_t d = m_x.size();
  std::size_t i = 0;
  for (; i + 4 <= d; i += 4) {
    const T* c0 = m_series.data() + i * stride;
    const T *c1 = c0 + stride, *c2 = c1 + stride, *c3 = c2 + stride;
    T s0 = c0[m_order], s1 = c1[m_order], s2 = c2[m_order], s3 = c3[m_order];
    for (int k = m_order - 1; k >= 0; --k) {
      s0 = s0 * tau + c0[k];
      s1 = s1 * tau + c1[k];
      s2 = s2 * tau + c2[k];
      s3 = s3 * tau + c3[k];
    }
    x[i] = s0;
    x[i + 1] = s1;
    x[i + 2] = s2;
    x[i + 3] = s3;
  }
  for (; i < d; ++i) {
    const T* c = m_series.data() + i * stride;
    T sum = c[m_order];
    for (int k = m_order - 1; k >= 0; --k) sum = sum * tau + c[k];
    x[i] = sum;
  }
}

template class taylor_integrator<double>;
template class taylor_integrator<long double>;

taylor_tangents::taylor_tangents(const kernel_set& kernels, double abs_tol, double rel_tol,
                                 int vectors, int order)
    : m_kernels(&kernels),
      m_taylor(&taylor_kernels_of(kernels)),
      m_abs_tol(abs_tol),
      m_rel_tol(rel_tol),
      m_order(chosen_order(abs_tol, rel_tol, order)),
      m_vectors(static_cast<std::size_t>(vectors)) {
  if (vectors < 1)
    throw std::invalid_argument(
        fmt::format("taylor stepper: {} tangent vectors; at least one is needed", vectors));
  const auto stride = static_cast<std::size_t>(m_order + 1);
  const auto d = static_cast<std::size_t>(m_taylor->state_size);
  const auto& packed = kernels.packed();
  m_params.assign(packed.begin(), packed.end());  // constants: no derivative
  m_input_values.assign(static_cast<std::size_t>(m_taylor->input_size) * stride, 0.0);
  m_inputs.assign(m_input_values.size(), taylor::dual{});
  m_series.assign(m_vectors * d * stride, taylor::dual{});
  m_work.assign(static_cast<std::size_t>(m_taylor->work_slots) * stride, taylor::dual{});
  m_x.assign(d, 0.0);
  m_w.assign(m_vectors * d, 0.0);
  // Inputs without a series (a custom pivot path) are refused now, not in the first step.
  if (m_taylor->input_size > 0) kernels.input_series(0.0, m_order, m_input_values.data());
}

void taylor_tangents::reset(double t, const double* x, const double* W) {
  std::copy(x, x + m_x.size(), m_x.begin());
  std::copy(W, W + m_w.size(), m_w.begin());
  m_t = m_t_begin = t;
}

void taylor_tangents::coefficients() {
  const auto stride = static_cast<std::size_t>(m_order + 1);
  const std::size_t d = m_x.size();
  if (m_taylor->input_size > 0) {
    m_kernels->input_series(m_t, m_order, m_input_values.data());
    std::copy(m_input_values.begin(), m_input_values.end(), m_inputs.begin());
  }
  for (std::size_t j = 0; j < m_vectors; ++j) {
    taylor::dual* series = m_series.data() + j * d * stride;
    for (std::size_t i = 0; i < d; ++i) series[i * stride] = {m_x[i], m_w[j * d + i]};
    m_taylor->coefficients_dual(m_params.data(), m_inputs.data(), m_order, series, m_work.data());
  }
}

double taylor_tangents::step(double direction, double limit, double fallback) {
  coefficients();
  const auto stride = static_cast<std::size_t>(m_order + 1);
  const std::size_t d = m_x.size();
  // The largest coefficient of order k of the state (the same in every vector's run) and of
  // the vectors.
  const auto norm = [&](int k) {
    double largest = 0;
    for (std::size_t j = 0; j < m_vectors; ++j)
      for (std::size_t i = 0; i < d; ++i) {
        const taylor::dual& c = m_series[(j * d + i) * stride + static_cast<std::size_t>(k)];
        largest = std::max({largest, std::fabs(c.v), std::fabs(c.d)});
      }
    return largest;
  };
  const double bound = std::max(m_abs_tol, m_rel_tol * norm(0));
  const double h = signed_step(step_length(bound, norm(m_order - 1), norm(m_order), m_order),
                               direction, limit, fallback);
  m_t_begin = m_t;
  state_at(h, m_x.data(), m_w.data());
  m_t = m_t_begin + h;
  return h;
}

// Horner's rule for each series, the value and the derivative side by side (two
// independent sums); the state's values from the first vector's series.
void taylor_tangents::state_at(double tau, double* x, double* W) const {
  const auto stride = static_cast<std::size_t>(m_order + 1);
  const std::size_t d = m_x.size();
  for (std::size_t j = 0; j < m_vectors; ++j)
    for (std::size_t i = 0; i < d; ++i) {
      const taylor::dual* c = m_series.data() + (j * d + i) * stride;
      double value = c[m_order].v, derivative = c[m_order].d;
      for (int k = m_order - 1; k >= 0; --k) {
        value = value * tau + c[k].v;
        derivative = derivative * tau + c[k].d;
      }
      if (j == 0) x[i] = value;
      W[j * d + i] = derivative;
    }
}

void taylor_tangents::state_values_at(double tau, double* x) const {
  const auto stride = static_cast<std::size_t>(m_order + 1);
  for (std::size_t i = 0; i < m_x.size(); ++i) {
    const taylor::dual* c = m_series.data() + i * stride;
    double value = c[m_order].v;
    for (int k = m_order - 1; k >= 0; --k) value = value * tau + c[k].v;
    x[i] = value;
  }
}

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
