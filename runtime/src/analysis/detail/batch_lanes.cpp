#include "batch_lanes.hpp"

#include <batch_index.hpp>

namespace npend::detail {

const batch_kernels* lane_kernels(const chain& c) {
  if (c.is_physical()) return nullptr;
  const batch_kernels* k = generated::find_batch(c.links());
  // The kernels must have been compiled for this translation unit's lane count.
  return k != nullptr && k->width == batch_width ? k : nullptr;
}

void lane_system::operator()(const double* x, double* dxdt) {
  if (m_tangent == 0) {
    m_kernels.rhs_batch(x, m_params, dxdt);
    return;
  }
  const auto at = [](std::size_t i) { return i * W; };
  m_kernels.tangent_batch(x, x + at(vector(0)), m_params, dxdt, dxdt + at(vector(0)));
  for (std::size_t j = 1; j < m_tangent; ++j)
    m_kernels.tangent_batch(x, x + at(vector(j)), m_params, m_scratch.data(),
                            dxdt + at(vector(j)));
  if (!m_indicators) return;
  const double* w = x + at(vector(0));
  const double* dw = dxdt + at(vector(0));
  for (std::size_t l = 0; l < W; ++l) {
    double along = 0, squares = 0;
    for (std::size_t i = 0; i < m_d; ++i) {
      along += w[at(i) + l] * dw[at(i) + l];
      squares += w[at(i) + l] * w[at(i) + l];
    }
    const double t = x[at(time()) + l];
    dxdt[at(time()) + l] = 1;
    dxdt[at(y()) + l] = t * (along / squares);
    dxdt[at(z()) + l] = t > 0 ? 2 * x[at(y()) + l] / t : 0.0;
  }
}

void lane_rk4::step(int blocks) {
  const std::size_t size = m_block * static_cast<std::size_t>(blocks);
  double* x = m_x.data();
  double *k1 = m_k1.data(), *k2 = m_k2.data(), *k3 = m_k3.data(), *k4 = m_k4.data();
  double* tmp = m_tmp.data();
  const double half = m_half, zero = m_zero, full = m_full, sixth = m_sixth, third = m_third;
  rhs(blocks, x, k1);
#pragma omp simd
  for (std::size_t i = 0; i < size; ++i) tmp[i] = x[i] + half * k1[i];
  rhs(blocks, tmp, k2);
  // odeint keeps the zero coefficients of its Butcher rows (0 · k is not always 0).
#pragma omp simd
  for (std::size_t i = 0; i < size; ++i) tmp[i] = x[i] + zero * k1[i] + half * k2[i];
  rhs(blocks, tmp, k3);
#pragma omp simd
  for (std::size_t i = 0; i < size; ++i)
    tmp[i] = x[i] + zero * k1[i] + zero * k2[i] + full * k3[i];
  rhs(blocks, tmp, k4);
#pragma omp simd
  for (std::size_t i = 0; i < size; ++i)
    x[i] = x[i] + sixth * k1[i] + third * k2[i] + third * k3[i] + sixth * k4[i];
}

void lane_rk4::rhs(int blocks, const double* x, double* dxdt) {
  for (int b = 0; b < blocks; ++b) {
    const std::size_t o = m_block * static_cast<std::size_t>(b);
    m_system(x + o, dxdt + o);
  }
}

}  // namespace npend::detail
