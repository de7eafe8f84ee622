// FFTW3 transforms of real data (private to the runtime): one plan pair per length, buffers
// owned by the object.
#pragma once

#include <complex>
#include <cstddef>
#include <span>

namespace npend::detail {

/// Forward r2c and backward c2r transforms of length n, both unnormalised (as FFTW's):
/// forward gives X_k = Σ_j x_j e^{−2πijk/n}, k = 0..n/2; backward(forward(x)) = n x.
/// Plans are made with FFTW_ESTIMATE under a lock (FFTW's planner is not thread-safe);
/// distinct objects may then be used from different threads.
class real_fft {
 public:
  explicit real_fft(std::size_t n);
  ~real_fft();
  real_fft(const real_fft&) = delete;
  real_fft& operator=(const real_fft&) = delete;

  std::size_t size() const { return m_n; }
  /// The real buffer (dim n): input of forward(), output of backward().
  std::span<double> real() { return {m_real, m_n}; }
  /// The half spectrum (dim n/2 + 1): output of forward(), input of backward() (which
  /// overwrites it).
  std::span<std::complex<double>> spectrum();

  void forward();
  void backward();

 private:
  std::size_t m_n;
  double* m_real = nullptr;
  void* m_spectrum = nullptr;  // fftw_complex*
  void* m_forward = nullptr;   // fftw_plan
  void* m_backward = nullptr;  // fftw_plan, made on first use
};

/// The smallest m ≥ n whose prime factors are 2, 3, 5 and 7 (fast FFTW lengths).
std::size_t fast_fft_size(std::size_t n);

}  // namespace npend::detail
