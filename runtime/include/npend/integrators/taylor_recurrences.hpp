// The recurrences of automatic differentiation for Taylor series: the k-th Taylor
// coefficient of a product, a quotient and a sine/cosine pair from the lower ones.
//
// The generated Taylor kernels (generated/taylor_<model>_<n>.cpp) call these once per node
// of the equations' expression graph and per order k; sums and differences they write out
// themselves. A series u is an array of coefficients u[0..m] of u(t0 + τ) = Σ u[j] τ^j, m
// the order. Each sum runs over one series forwards and another backwards; the one read
// backwards is passed mirrored, r[m − j] = u[j], so both run forwards in memory and the sum
// vectorises. The header is self-contained (no library), like <npend/chain_kernels.hpp>, and
// templated on the number type so the same kernels run in double, long double and on dual
// numbers (the variational equations).
// (Jorba & Zou, "A software package for the numerical integration of ODEs by means of
// high-order Taylor methods", Experimental Mathematics 14 (2005), section 2.)
#pragma once

#include <cmath>
#include <cstddef>

namespace npend::taylor {

/// Σ_{j<n} a[j] b[j] in four partial sums: one running sum would make every term wait for
/// the one before (the latency of an add), four fill the vector units. Always inlined: a
/// kernel calls it a hundred times, and GCC's inliner otherwise stops short of that.
template <class T>
[[gnu::always_inline]] inline T dot(const T* a, const T* b, std::ptrdiff_t n) noexcept {
  T s0 = 0, s1 = 0, s2 = 0, s3 = 0;
  std::ptrdiff_t j = 0;
  for (; j + 4 <= n; j += 4) {
    s0 += a[j] * b[j];
    s1 += a[j + 1] * b[j + 1];
    s2 += a[j + 2] * b[j + 2];
    s3 += a[j + 3] * b[j + 3];
  }
  for (; j < n; ++j) s0 += a[j] * b[j];
  return (s0 + s1) + (s2 + s3);
}

/// (a·b)[k] = Σ_{j=0..k} a[j] b[k−j], with b mirrored (b_m[m − j] = b[j]).
///
/// The two terms with a coefficient of order k (a[k] b[0] and a[0] b[k]), just computed, are
/// added last: the sum of the others needs only earlier orders, so it runs while the
/// statements before are still being computed, and a chain of dependent products waits only
/// for those two terms each, not for a whole sum.
template <class T>
inline T product(const T* a, const T* b_m, int m, int k) noexcept {
  if (k == 0) return a[0] * b_m[m];
  const T earlier = dot(a + 1, b_m + (m - k + 1), std::ptrdiff_t{k} - 1);
  return earlier + (a[0] * b_m[m - k] + a[k] * b_m[m]);
}

/// (a/b)[k] for c = a/b with c[0..k−1] known: (a[k] − Σ_{j=0..k−1} c[j] b[k−j]) / b[0],
/// with b mirrored; the term with b[k] last, as in product.
template <class T>
inline T quotient(T a_k, const T* b_m, const T* c, int m, int k) noexcept {
  if (k == 0) return a_k / b_m[m];
  const T earlier = dot(c + 1, b_m + (m - k + 1), std::ptrdiff_t{k} - 1);
  return (a_k - (earlier + c[0] * b_m[m - k])) / b_m[m];
}

/// s[k] and c[k] of s = sin u, c = cos u from s' = c u', c' = −s u':
/// s[k] = (1/k) Σ_{j=0..k−1} c[j] (k−j) u[k−j], c[k] = −(1/k) Σ_{j=0..k−1} s[j] (k−j) u[k−j],
/// with w_m[m − j] = j u[j] (the weighted series of u, mirrored) filled up to j = k; u0 = u[0].
/// The term with u[k] last, as in product.
template <class T>
inline void sin_cos(T u0, const T* w_m, T* s, T* c, int m, int k) noexcept {
  if (k == 0) {
    using std::cos;
    using std::sin;
    s[0] = sin(u0);
    c[0] = cos(u0);
    return;
  }
  const T* w = w_m + (m - k);  // w[j] = (k − j) u[k − j]
  const T inverse = T(1) / static_cast<T>(k);
  s[k] = (dot(c + 1, w + 1, std::ptrdiff_t{k} - 1) + c[0] * w[0]) * inverse;
  c[k] = -(dot(s + 1, w + 1, std::ptrdiff_t{k} - 1) + s[0] * w[0]) * inverse;
}

/// A dual number: a value and its derivative along one direction (forward-mode automatic
/// differentiation). The generated kernels run their recurrences on it too: started from the
/// state x with derivative w, they give the Taylor coefficients of the solution in the values
/// and, in the derivatives, those of the tangent vector w(t) that solves the variational
/// equations w' = J(x(t)) w — the same recurrences differentiated, with no other kernel. The
/// values are computed by the same operations in the same order as in double, so they are the
/// double kernels' to the bit.
struct dual {
  double v = 0;  ///< the value
  double d = 0;  ///< its derivative

  constexpr dual() = default;
  // Implicit from a number (a constant: no derivative), as the recurrences write T(1), T(k),
  // and sums that start at 0.
  constexpr dual(double value, double derivative = 0) noexcept : v(value), d(derivative) {}

  constexpr dual& operator+=(dual b) noexcept {
    v += b.v;
    d += b.d;
    return *this;
  }
};

constexpr dual operator+(dual a, dual b) noexcept { return {a.v + b.v, a.d + b.d}; }
constexpr dual operator-(dual a, dual b) noexcept { return {a.v - b.v, a.d - b.d}; }
constexpr dual operator-(dual a) noexcept { return {-a.v, -a.d}; }
constexpr dual operator*(dual a, dual b) noexcept { return {a.v * b.v, a.v * b.d + a.d * b.v}; }
constexpr dual operator/(dual a, dual b) noexcept {
  const double q = a.v / b.v;
  return {q, (a.d - q * b.d) / b.v};
}
// Found by argument-dependent lookup where the recurrences call sin and cos (sin_cos).
inline dual sin(dual a) noexcept { return {std::sin(a.v), std::cos(a.v) * a.d}; }
inline dual cos(dual a) noexcept { return {std::cos(a.v), -std::sin(a.v) * a.d}; }

}  // namespace npend::taylor
