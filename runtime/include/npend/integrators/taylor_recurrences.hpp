// The recurrences of automatic differentiation for Taylor series: the k-th Taylor
// coefficient of a product, a quotient and a sine/cosine pair from the lower ones.
//
// The generated Taylor kernels (generated/taylor_<model>_<n>.cpp) call these once per node
// of the equations' expression graph and per order k; sums and differences they write out
// themselves. A series u is an array of coefficients u[0..k] of u(t0 + τ) = Σ u[j] τ^j.
// The header is self-contained (no library), like <npend/chain_kernels.hpp>, and templated
// on the number type so the same kernels run in double and long double.
// (Jorba & Zou, "A software package for the numerical integration of ODEs by means of
// high-order Taylor methods", Experimental Mathematics 14 (2005), section 2.)
#pragma once

#include <cmath>
#include <cstddef>

namespace npend::taylor {

/// (a·b)[k] = Σ_{j=0..k} a[j] b[k−j].
template <class T>
inline T product(const T* a, const T* b, int k) noexcept {
  T sum = a[k] * b[0];
  for (std::ptrdiff_t j = 0, n = k; j < n; ++j) sum += a[j] * b[n - j];
  return sum;
}

/// (a/b)[k] for c = a/b with c[0..k−1] known: (a[k] − Σ_{j=1..k} b[j] c[k−j]) / b[0].
template <class T>
inline T quotient(T a_k, const T* b, const T* c, int k) noexcept {
  T sum = a_k;
  for (std::ptrdiff_t j = 0, n = k; j < n; ++j) sum -= b[n - j] * c[j];
  return sum / b[0];
}

/// s[k] and c[k] of s = sin u, c = cos u from s' = c u', c' = −s u':
/// s[k] = (1/k) Σ_{j=1..k} j u[j] c[k−j], c[k] = −(1/k) Σ_{j=1..k} j u[j] s[k−j].
template <class T>
inline void sin_cos(const T* u, T* s, T* c, int k) noexcept {
  if (k == 0) {
    using std::cos;
    using std::sin;
    s[0] = sin(u[0]);
    c[0] = cos(u[0]);
    return;
  }
  T ss = 0, cc = 0;
  for (std::ptrdiff_t i = 0, n = k; i < n; ++i) {  // j = k − i runs k..1
    const T ju = static_cast<T>(n - i) * u[n - i];
    ss += ju * c[i];
    cc += ju * s[i];
  }
  s[k] = ss / static_cast<T>(k);
  c[k] = -cc / static_cast<T>(k);
}

}  // namespace npend::taylor
