#include "general_form.hpp"

namespace npend::gen {

namespace {

std::size_t u(int i) { return static_cast<std::size_t>(i); }

}  // namespace

general_form::general_form(const polynomial_space& space, const chain_mechanics& mech,
                           const lagrangian_hessians& hessians, expr_graph& graph)
    : m_space(&space),
      m_mech(&mech),
      m_hessians(&hessians),
      m_graph(&graph),
      m_n(space.coordinates()) {
  m_vars = variable_nodes(space, graph);
  const int n = m_n;
  // A's entries (symmetric: the lower triangle), then A = L D Lᵀ column by column.
  std::vector<std::vector<sx>> a(u(n));
  for (int i = 0; i < n; ++i)
    for (int j = 0; j <= i; ++j)
      a[u(i)].push_back(to_graph(space.canonical(mech.mass_matrix(u(i), u(j))), m_vars, graph));
  m_lower.assign(u(n), std::vector<sx>(u(n)));
  m_pivots.resize(u(n));
  for (int j = 0; j < n; ++j) {
    sx d = a[u(j)][u(j)];
    for (int k = 0; k < j; ++k) d = d - m_lower[u(j)][u(k)] * m_lower[u(j)][u(k)] * m_pivots[u(k)];
    m_pivots[u(j)] = d;
    for (int i = j + 1; i < n; ++i) {
      sx s = a[u(i)][u(j)];
      for (int k = 0; k < j; ++k)
        s = s - m_lower[u(i)][u(k)] * m_lower[u(j)][u(k)] * m_pivots[u(k)];
      m_lower[u(i)][u(j)] = s / d;
    }
  }
  for (int i = 0; i < n; ++i) m_p.push_back(coordinate_input(space, input_kind::p, i, graph));
  m_dphi = solve(m_p);
  // From here on the polynomials in φ̇ read the computed velocities.
  for (int i = 0; i < n; ++i) m_vars[u(space.coordinate_id(var_kind::dphi, i))] = m_dphi[u(i)];
}

std::vector<sx> general_form::solve(const std::vector<sx>& b) const {
  const int n = m_n;
  std::vector<sx> y = b;
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < i; ++k) y[u(i)] = y[u(i)] - m_lower[u(i)][u(k)] * y[u(k)];
  for (int i = 0; i < n; ++i) y[u(i)] = y[u(i)] / m_pivots[u(i)];
  for (int i = n - 1; i >= 0; --i)
    for (int k = i + 1; k < n; ++k) y[u(i)] = y[u(i)] - m_lower[u(k)][u(i)] * y[u(k)];
  return y;
}

sx general_form::node(const GiNaC::ex& e) const {
  return to_graph(m_space->canonical(e), m_vars, *m_graph);
}

std::vector<sx> general_form::momentum_rates() const {
  std::vector<sx> out;
  for (int i = 0; i < m_n; ++i)
    out.push_back(node((m_mech->dL_dphi[u(i)] + m_mech->force[u(i)]).expand()));
  return out;
}

sx general_form::hamiltonian() const {
  sx pv = m_graph->constant(0);
  for (int i = 0; i < m_n; ++i) pv = pv + m_p[u(i)] * m_dphi[u(i)];
  return m_graph->constant(GiNaC::numeric(1, 2)) * pv + node(m_mech->potential);
}

sx general_form::mass_matrix_determinant() const {
  sx det = m_graph->constant(1);
  for (const sx d : m_pivots) det = det * d;
  return det;
}

std::vector<sx> general_form::jacobian() const {
  const int n = m_n, dim = 2 * n;
  expr_graph& g = *m_graph;
  // W = A⁻¹, column by column.
  std::vector<std::vector<sx>> w(u(n));  // w[k] = column k
  for (int k = 0; k < n; ++k) {
    std::vector<sx> e(u(n), g.constant(0));
    e[u(k)] = g.constant(1);
    w[u(k)] = solve(e);
  }
  // lpd is ∂²L/∂φ∂φ̇ (Lpd(k, :) = ∂p/∂φ_k, which gives ∂φ̇/∂φ); fpd = ∂ṗ/∂φ̇ at fixed φ
  // adds the damping forces' ∂Q/∂φ̇ to it.
  std::vector<std::vector<sx>> lpp(u(n), std::vector<sx>(u(n))), lpd = lpp, fpd = lpp;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      lpp[u(i)][u(j)] = node(m_hessians->phi_phi(u(i), u(j)));
      lpd[u(i)][u(j)] = node(m_hessians->phi_dphi(u(i), u(j)));
      fpd[u(i)][u(j)] =
          node((m_hessians->phi_dphi(u(i), u(j)) + m_hessians->force_dphi(u(i), u(j))).expand());
    }
  std::vector<sx> out(u(dim * dim));
  auto at = [&](int row, int col) -> sx& { return out[u(row * dim + col)]; };
  // B(:, k) = −A⁻¹ ∂²L/∂φ̇∂φ_k = −W · Lpd(k, :)ᵀ.
  std::vector<std::vector<sx>> b(u(n), std::vector<sx>(u(n)));
  for (int k = 0; k < n; ++k)
    for (int i = 0; i < n; ++i) {
      sx s = g.constant(0);
      for (int j = 0; j < n; ++j) s = s + w[u(j)][u(i)] * lpd[u(k)][u(j)];
      b[u(i)][u(k)] = -s;
    }
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < n; ++k) {
      at(i, k) = b[u(i)][u(k)];
      at(i, n + k) = w[u(k)][u(i)];
    }
  if (!m_hessians->has_damping) {
    for (int i = 0; i < n; ++i)
      for (int k = 0; k < n; ++k) at(n + k, n + i) = -b[u(i)][u(k)];  // ∂ṗ/∂p = −(∂φ̇/∂φ)ᵀ
    // C = L_φφ + L_φφ̇ B, symmetric: each pair computed once.
    for (int k = 0; k < n; ++k)
      for (int i = k; i < n; ++i) {
        sx c = lpp[u(i)][u(k)];
        for (int j = 0; j < n; ++j) c = c + lpd[u(i)][u(j)] * b[u(j)][u(k)];
        at(n + i, k) = at(n + k, i) = c;
      }
    return out;
  }
  // Damped: the flow is no longer Hamiltonian, so neither shortcut holds. With
  // F = ∂ṗ/∂φ̇|_φ = L_φφ̇ + ∂Q/∂φ̇: ∂ṗ/∂φ = L_φφ + F B and ∂ṗ/∂p = F A⁻¹.
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < n; ++k) {
      sx c = lpp[u(i)][u(k)], d = g.constant(0);
      for (int j = 0; j < n; ++j) {
        c = c + fpd[u(i)][u(j)] * b[u(j)][u(k)];
        d = d + fpd[u(i)][u(j)] * w[u(k)][u(j)];
      }
      at(n + i, k) = c;
      at(n + i, n + k) = d;
    }
  return out;
}

}  // namespace npend::gen
