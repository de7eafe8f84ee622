// A high-precision reference for the n-link chain, and the componentwise condition number
// of every kernel output, for the accuracy tests (tests/generated/test_kernel_accuracy.cpp).
//
// The formulas are the dense ones of PAPER-NOTES.md ("Conventions"), written once for any
// scalar type: A_ij = μ_max(i,j) l_i l_j cos(φ_i − φ_j) with the cosine of the difference
// taken as c_i c_j + s_i s_j, φ̇ = A⁻¹p by an LDLᵀ factorisation, the explicit ṗ formula
// ṗ_i = −φ̇_i Σ_{j≠i} μ_max(i,j) l_i l_j sin(φ_i − φ_j) φ̇_j − g μ_i l_i sin φ_i, the Jacobian
// by the chain rule (the formulas of dense_chain.hpp), H = ½ pᵀφ̇ + V and det A = Π pivots.
// They share no code with the generator.
//
// The function evaluated is that of the data a kernel works from: the sines s_i and cosines
// c_i of the angles (a kernel gets them from libm, correct to about one rounding), the
// momenta, masses, lengths and g. Instantiated with a quadruple-precision type, it gives the
// true values to far more digits than a double holds (LDLᵀ in binary128 loses at most the
// scaled condition number of A, below 1e16 for mass and length ratios up to 1e8, of its 34
// digits). Instantiated with dual numbers over that type, seeded along one datum x_j, it
// gives ∂y/∂x_j exactly (forward differentiation, no step size), and so the componentwise
// condition number of every output y:
//   κ(y) |y| = Σ_j |∂y/∂x_j| |x_j|,
// the first-order bound of |Δy| when every datum carries a relative error of 1. An
// algorithm that is accurate "to a small multiple of the condition number times machine
// epsilon" computes y with |ŷ − y| ≤ c ε Σ_j |∂y/∂x_j| |x_j|.
#pragma once

#include <cmath>
#include <cstddef>
#include <vector>

namespace npend::reference {

#if defined(__SIZEOF_FLOAT128__)
using quad = __float128;  // binary128 in software (libgcc), no libquadmath needed
#else
using quad = long double;  // binary128 on the platforms without __float128 (aarch64)
#endif

/// A forward-mode dual number: value v and derivative d along one direction.
template <class T>
struct dual {
  T v{}, d{};
  dual() = default;
  dual(T value, T derivative = T(0)) : v(value), d(derivative) {}  // NOLINT: implicit
};
template <class T>
dual<T> operator+(dual<T> a, dual<T> b) {
  return {a.v + b.v, a.d + b.d};
}
template <class T>
dual<T> operator-(dual<T> a, dual<T> b) {
  return {a.v - b.v, a.d - b.d};
}
template <class T>
dual<T> operator-(dual<T> a) {
  return {-a.v, -a.d};
}
template <class T>
dual<T> operator*(dual<T> a, dual<T> b) {
  return {a.v * b.v, a.d * b.v + a.v * b.d};
}
template <class T>
dual<T> operator/(dual<T> a, dual<T> b) {
  const T v = a.v / b.v;
  return {v, (a.d - v * b.d) / b.v};
}
template <class T>
dual<T>& operator+=(dual<T>& a, dual<T> b) {
  return a = a + b;
}
template <class T>
dual<T>& operator-=(dual<T>& a, dual<T> b) {
  return a = a - b;
}

/// The data of one evaluation (each of dimension n, except g).
template <class T>
struct chain_data {
  std::vector<T> s, c;  ///< sin φ_i, cos φ_i
  std::vector<T> p;     ///< canonical momenta
  std::vector<T> m, l;  ///< masses, lengths
  T g{};
};

/// Everything the kernels compute from the data, at one point.
template <class T>
struct chain_values {
  std::vector<T> dphi;  ///< φ̇ = A⁻¹p (n)
  std::vector<T> f;     ///< [φ̇, ṗ] (2n)
  std::vector<T> jac;   ///< ∂f/∂[φ, p], row-major (2n × 2n)
  T hamiltonian{}, kinetic{}, det{};
};

template <class T>
chain_values<T> evaluate_dense(const chain_data<T>& in) {
  const std::size_t n = in.m.size();
  auto at = [n](std::size_t i, std::size_t j) { return i * n + j; };
  std::vector<T> mu(n);
  T below(0);
  for (std::size_t j = n; j-- > 0;) mu[j] = below = below + in.m[j];
  // A_ij = K_ij cos(φ_i − φ_j), KS_ij = K_ij sin(φ_i − φ_j), K_ij = μ_max(i,j) l_i l_j.
  std::vector<T> A(n * n), KS(n * n);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < n; ++j) {
      const T k = mu[i > j ? i : j] * in.l[i] * in.l[j];
      A[at(i, j)] = i == j ? k : k * (in.c[i] * in.c[j] + in.s[i] * in.s[j]);
      KS[at(i, j)] = i == j ? T(0) : k * (in.s[i] * in.c[j] - in.c[i] * in.s[j]);
    }
  // LDLᵀ (A is symmetric positive definite).
  std::vector<T> L(n * n, T(0)), D(n);
  for (std::size_t j = 0; j < n; ++j) {
    T d = A[at(j, j)];
    for (std::size_t k = 0; k < j; ++k) d = d - L[at(j, k)] * L[at(j, k)] * D[k];
    D[j] = d;
    L[at(j, j)] = T(1);
    for (std::size_t i = j + 1; i < n; ++i) {
      T v = A[at(i, j)];
      for (std::size_t k = 0; k < j; ++k) v = v - L[at(i, k)] * L[at(j, k)] * D[k];
      L[at(i, j)] = v / d;
    }
  }
  auto solve = [&](std::vector<T> b) {
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t k = 0; k < i; ++k) b[i] = b[i] - L[at(i, k)] * b[k];
    for (std::size_t i = 0; i < n; ++i) b[i] = b[i] / D[i];
    for (std::size_t i = n; i-- > 0;)
      for (std::size_t k = i + 1; k < n; ++k) b[i] = b[i] - L[at(k, i)] * b[k];
    return b;
  };

  chain_values<T> out;
  out.dphi = solve(in.p);
  const auto& v = out.dphi;
  std::vector<T> w(n, T(0)), Av(n, T(0));
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < n; ++j) {
      w[i] = w[i] + KS[at(i, j)] * v[j];
      Av[i] = Av[i] + A[at(i, j)] * v[j];
    }
  out.f.resize(2 * n);
  for (std::size_t i = 0; i < n; ++i) {
    out.f[i] = v[i];
    out.f[n + i] = -(v[i] * w[i]) - in.g * mu[i] * in.l[i] * in.s[i];
  }

  // The Jacobian (dense_chain.hpp): ∂φ̇/∂p = A⁻¹, ∂φ̇/∂φ = −A⁻¹G with G(:, k) = (∂A/∂φ_k)φ̇,
  // and ṗ = F(φ, φ̇) differentiated by the chain rule.
  std::vector<T> Ainv(n * n);
  for (std::size_t k = 0; k < n; ++k) {
    std::vector<T> e(n, T(0));
    e[k] = T(1);
    const auto col = solve(e);
    for (std::size_t i = 0; i < n; ++i) Ainv[at(i, k)] = col[i];
  }
  std::vector<T> G(n * n), Bphi(n * n, T(0)), Fphi(n * n), Fdphi(n * n);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t k = 0; k < n; ++k) {
      G[at(i, k)] = i == k ? -w[i] : KS[at(i, k)] * v[k];
      Fphi[at(i, k)] =
          i == k ? -(v[i] * (Av[i] - A[at(i, i)] * v[i])) - in.g * mu[i] * in.l[i] * in.c[i]
                 : v[i] * A[at(i, k)] * v[k];
      Fdphi[at(i, k)] = i == k ? -w[i] : -(v[i] * KS[at(i, k)]);
    }
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t k = 0; k < n; ++k)
      for (std::size_t j = 0; j < n; ++j)
        Bphi[at(i, k)] = Bphi[at(i, k)] - Ainv[at(i, j)] * G[at(j, k)];
  const std::size_t dim = 2 * n;
  out.jac.assign(dim * dim, T(0));
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t k = 0; k < n; ++k) {
      T cphi = Fphi[at(i, k)], dp(0);
      for (std::size_t j = 0; j < n; ++j) {
        cphi = cphi + Fdphi[at(i, j)] * Bphi[at(j, k)];
        dp = dp + Fdphi[at(i, j)] * Ainv[at(j, k)];
      }
      out.jac[i * dim + k] = Bphi[at(i, k)];
      out.jac[i * dim + n + k] = Ainv[at(i, k)];
      out.jac[(n + i) * dim + k] = cphi;
      out.jac[(n + i) * dim + n + k] = dp;
    }

  T twice_t(0), potential(0), det(1);
  for (std::size_t i = 0; i < n; ++i) {
    twice_t = twice_t + in.p[i] * v[i];
    potential = potential + in.g * mu[i] * in.l[i] * (T(1) - in.c[i]);
    det = det * D[i];
  }
  out.kinetic = twice_t / T(2);
  out.hamiltonian = out.kinetic + potential;
  out.det = det;
  return out;
}

/// The reference values at one point and, for each output, Σ_j |∂y/∂x_j| |x_j| over the
/// data x = (s, c, p, m, l, g): the first-order error bound for relative data errors of 1.
struct reference_point {
  chain_values<quad> value;
  chain_values<quad> sensitivity;
};

namespace detail {
inline quad magnitude(quad x) { return x < 0 ? -x : x; }
}  // namespace detail

/// The reference at angles φ (dim n), momenta p (dim n), masses, lengths and g.
inline reference_point precise_reference(const std::vector<double>& phi,
                                         const std::vector<double>& p,
                                         const std::vector<double>& masses,
                                         const std::vector<double>& lengths, double g) {
  const std::size_t n = masses.size();
  chain_data<quad> data;
  for (std::size_t i = 0; i < n; ++i) {
    // sinl/cosl are correct to ~1e-19, a thousandth of a double's rounding.
    data.s.push_back(static_cast<quad>(std::sin(static_cast<long double>(phi[i]))));
    data.c.push_back(static_cast<quad>(std::cos(static_cast<long double>(phi[i]))));
    data.p.push_back(p[i]);
    data.m.push_back(masses[i]);
    data.l.push_back(lengths[i]);
  }
  data.g = g;

  reference_point out;
  out.value = evaluate_dense(data);
  auto& sens = out.sensitivity;
  sens.dphi.assign(n, 0);
  sens.f.assign(2 * n, 0);
  sens.jac.assign(4 * n * n, 0);

  // One forward-mode sweep per datum: x_j ∂y/∂x_j, summed in magnitude.
  auto add = [](std::vector<quad>& acc, const std::vector<dual<quad>>& y) {
    for (std::size_t i = 0; i < acc.size(); ++i) acc[i] += detail::magnitude(y[i].d);
  };
  auto lift = [](const std::vector<quad>& x) {
    return std::vector<dual<quad>>(x.begin(), x.end());
  };
  const std::size_t data_count = 5 * n + 1;
  for (std::size_t j = 0; j < data_count; ++j) {
    chain_data<dual<quad>> d{lift(data.s), lift(data.c), lift(data.p),
                             lift(data.m), lift(data.l), data.g};
    std::vector<dual<quad>>* const fields[] = {&d.s, &d.c, &d.p, &d.m, &d.l};
    if (j < 5 * n) {
      auto& x = (*fields[j / n])[j % n];
      x.d = x.v;  // seed x_j ∂/∂x_j
    } else {
      d.g.d = d.g.v;
    }
    const auto y = evaluate_dense(d);
    add(sens.dphi, y.dphi);
    add(sens.f, y.f);
    add(sens.jac, y.jac);
    sens.hamiltonian += detail::magnitude(y.hamiltonian.d);
    sens.kinetic += detail::magnitude(y.kinetic.d);
    sens.det += detail::magnitude(y.det.d);
  }
  return out;
}

}  // namespace npend::reference
