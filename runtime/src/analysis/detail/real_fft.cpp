#include "real_fft.hpp"

#include <fftw3.h>

#include <mutex>
#include <new>
#include <stdexcept>

namespace npend::detail {

namespace {

std::mutex& planner_mutex() {
  static std::mutex m;
  return m;
}

}  // namespace

real_fft::real_fft(std::size_t n) : m_n(n) {
  if (n == 0) throw std::invalid_argument("real_fft: the length must be positive");
  m_real = fftw_alloc_real(n);
  m_spectrum = fftw_alloc_complex(n / 2 + 1);
  if (m_real == nullptr || m_spectrum == nullptr) {
    fftw_free(m_real);
    fftw_free(m_spectrum);
    throw std::bad_alloc();
  }
  const std::lock_guard lock(planner_mutex());
  m_forward = fftw_plan_dft_r2c_1d(static_cast<int>(n), m_real,
                                   static_cast<fftw_complex*>(m_spectrum), FFTW_ESTIMATE);
}

real_fft::~real_fft() {
  {
    const std::lock_guard lock(planner_mutex());
    if (m_forward != nullptr) fftw_destroy_plan(static_cast<fftw_plan>(m_forward));
    if (m_backward != nullptr) fftw_destroy_plan(static_cast<fftw_plan>(m_backward));
  }
  fftw_free(m_real);
  fftw_free(m_spectrum);
}

std::span<std::complex<double>> real_fft::spectrum() {
  // fftw_complex is double[2], layout-compatible with std::complex<double> (FFTW manual §4.1.1).
  return {reinterpret_cast<std::complex<double>*>(m_spectrum), m_n / 2 + 1};
}

void real_fft::forward() { fftw_execute(static_cast<fftw_plan>(m_forward)); }

void real_fft::backward() {
  if (m_backward == nullptr) {
    const std::lock_guard lock(planner_mutex());
    // FFTW_ESTIMATE does not touch the buffers while planning.
    m_backward = fftw_plan_dft_c2r_1d(static_cast<int>(m_n), static_cast<fftw_complex*>(m_spectrum),
                                      m_real, FFTW_ESTIMATE);
  }
  fftw_execute(static_cast<fftw_plan>(m_backward));
}

std::size_t fast_fft_size(std::size_t n) {
  for (std::size_t m = n > 0 ? n : 1;; ++m) {
    std::size_t r = m;
    for (const std::size_t p : {2, 3, 5, 7})
      while (r % p == 0) r /= p;
    if (r == 1) return m;
  }
}

}  // namespace npend::detail
