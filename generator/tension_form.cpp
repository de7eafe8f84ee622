#include "tension_form.hpp"

namespace npend::gen {

namespace {
std::size_t u(int i) { return static_cast<std::size_t>(i); }
}  // namespace

tension_form::tension_form(int links, expr_graph& graph) : n(links) {
  for (int i = 0; i < n; ++i) {
    const sx phi = graph.input(input_kind::phi, i);
    s.push_back(sin(phi));
    c.push_back(cos(phi));
    inv_mass.push_back(graph.constant(1) / graph.input(input_kind::mass, i));
    inv_length.push_back(graph.constant(1) / graph.input(input_kind::length, i));
  }
  for (int i = 0; i + 1 < n; ++i) {
    // Angle differences through products, so the kernel needs only 2n trigonometric calls.
    cd.push_back(c[u(i)] * c[u(i + 1)] + s[u(i)] * s[u(i + 1)]);
    sd.push_back(s[u(i)] * c[u(i + 1)] - c[u(i)] * s[u(i + 1)]);
    z_off.push_back(-(inv_mass[u(i)] * cd[u(i)]));
    q_off.push_back(inv_mass[u(i)] * sd[u(i)]);
  }
  for (int i = 0; i < n; ++i)
    z_diag.push_back(i == 0 ? inv_mass[0] : inv_mass[u(i)] + inv_mass[u(i - 1)]);

  // LDLᵀ of the tridiagonal Ẑ (symmetric positive definite, so no pivoting is needed).
  for (int i = 0; i < n; ++i) {
    pivot.push_back(i == 0 ? z_diag[0] : z_diag[u(i)] - ell[u(i - 1)] * z_off[u(i - 1)]);
    inv_pivot.push_back(graph.constant(1) / pivot[u(i)]);
    if (i + 1 < n) ell.push_back(z_off[u(i)] * inv_pivot[u(i)]);
  }
}

tension_form::flow tension_form::solve(const std::vector<sx>& p) const {
  flow f;
  for (int i = 0; i < n; ++i) f.q.push_back(p[u(i)] * inv_length[u(i)]);
  const auto& q = f.q;

  // b = Q̂ᵀ q, then forward and back substitution with L D Lᵀ.
  std::vector<sx> y;
  for (int i = 0; i < n; ++i) {
    sx b = p[0].graph->constant(0);
    if (i > 0) b = b + q_off[u(i - 1)] * q[u(i - 1)];
    if (i + 1 < n) b = b - q_off[u(i)] * q[u(i + 1)];
    y.push_back(i == 0 ? b : b - ell[u(i - 1)] * y[u(i - 1)]);
  }
  f.tau.assign(u(n), sx{});
  for (int i = n - 1; i >= 0; --i) {
    f.tau[u(i)] = y[u(i)] * inv_pivot[u(i)];
    if (i + 1 < n) f.tau[u(i)] = f.tau[u(i)] - ell[u(i)] * f.tau[u(i + 1)];
  }

  for (int i = 0; i < n; ++i) {
    sx w = z_diag[u(i)] * q[u(i)];
    if (i > 0) w = w + z_off[u(i - 1)] * q[u(i - 1)] + q_off[u(i - 1)] * f.tau[u(i - 1)];
    if (i + 1 < n) w = w + z_off[u(i)] * q[u(i + 1)] - q_off[u(i)] * f.tau[u(i + 1)];
    f.omega.push_back(w);
  }
  return f;
}

std::vector<sx> tension_form::z_inverse() const {
  // From Lᵀ M = D⁻¹ L⁻¹: M_ij = −ℓ_i M_{i+1,j} (j > i), M_ii = 1/d_i − ℓ_i M_{i+1,i}.
  std::vector<sx> m(u(n * n));
  auto at = [&](int i, int j) -> sx& { return m[u(i * n + j)]; };
  for (int i = n - 1; i >= 0; --i) {
    for (int j = n - 1; j > i; --j) at(i, j) = at(j, i) = -(ell[u(i)] * at(i + 1, j));
    at(i, i) = (i + 1 < n) ? inv_pivot[u(i)] - ell[u(i)] * at(i + 1, i) : inv_pivot[u(i)];
  }
  return m;
}

sx tension_form::z_determinant() const {
  sx det = pivot[0];
  for (int i = 1; i < n; ++i) det = det * pivot[u(i)];
  return det;
}

}  // namespace npend::gen
