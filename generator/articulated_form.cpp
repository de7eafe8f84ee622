#include "articulated_form.hpp"

namespace npend::gen {

namespace {
std::size_t u(int i) { return static_cast<std::size_t>(i); }
}  // namespace

rod_turn turn_between(sx s, sx c, sx s_next, sx c_next) {
  return {c * c_next + s * s_next, s_next * c - c_next * s};
}

elimination_step eliminate_tip(sx mass, sx q) {
  expr_graph& g = *mass.graph;
  elimination_step e;
  e.d = e.r = mass;
  e.inv_d = g.constant(1) / mass;
  e.num = q;
  e.a = q * e.inv_d;
  e.rsc = e.gamma = e.beta = g.constant(0);
  return e;
}

elimination_step eliminate_link(sx mass, sx C, sx S, sx q, sx q_next, sx r_next, sx beta_next) {
  expr_graph& g = *mass.graph;
  elimination_step e;
  e.d = mass + r_next * (S * S);
  e.inv_d = g.constant(1) / e.d;
  e.r = mass * (mass + r_next) * e.inv_d;
  e.rsc = r_next * (S * C);
  e.gamma = e.rsc * e.inv_d;
  e.num = q - C * q_next - S * beta_next;
  e.a = e.num * e.inv_d;
  e.beta = C * beta_next - S * q_next + e.rsc * e.a;
  return e;
}

pivot_step pivot_link(sx a, sx gamma, sx r, sx beta, sx x, sx y) {
  pivot_step step;
  step.w = a - gamma * y;
  step.omega = step.w - x;
  step.axial = r * y + beta;
  step.kinetic_force = -(step.omega * step.axial);
  return step;
}

pivot_step pivot_link(sx a, sx gamma, sx r, sx beta, sx x, sx y, sx C, sx S) {
  pivot_step step = pivot_link(a, gamma, r, beta, x, y);
  step.x_next = C * step.w - S * y;
  step.y_next = S * step.w + C * y;
  return step;
}

// Every node of the value pass, per link k (C, S and the products of them only for k < n − 1).
struct articulated_form::values {
  std::vector<sx> q, d, inv_d, r, gamma, rsc, num, a, beta;  // elimination from the tip
  std::vector<sx> x, y, w, omega, axial, kinetic_force;      // the pass from the pivot
};

articulated_form::articulated_form(int links, expr_graph& graph) : n(links), m_graph(&graph) {
  for (int k = 0; k < n; ++k) {
    const sx phi = graph.input(input_kind::phi, k);
    s.push_back(sin(phi));
    c.push_back(cos(phi));
    mass.push_back(graph.input(input_kind::mass, k));
    inv_length.push_back(graph.constant(1) / graph.input(input_kind::length, k));
  }
  for (int k = 0; k + 1 < n; ++k) {
    const rod_turn t = turn_between(s[u(k)], c[u(k)], s[u(k + 1)], c[u(k + 1)]);
    cd.push_back(t.C);
    sd.push_back(t.S);
  }
}

articulated_form::values articulated_form::evaluate(const std::vector<sx>& p) const {
  const sx zero = m_graph->constant(0);
  values v;
  const auto nn = u(n);
  for (int k = 0; k < n; ++k) v.q.push_back(p[u(k)] * inv_length[u(k)]);
  v.d = v.inv_d = v.r = v.num = v.a = std::vector<sx>(nn);
  v.gamma = v.rsc = v.beta = std::vector<sx>(nn, zero);
  for (int k = n - 1; k >= 0; --k) {
    const auto i = u(k);
    const elimination_step e = k == n - 1 ? eliminate_tip(mass[i], v.q[i])
                                          : eliminate_link(mass[i], cd[i], sd[i], v.q[i],
                                                           v.q[i + 1], v.r[i + 1], v.beta[i + 1]);
    v.d[i] = e.d;
    v.inv_d[i] = e.inv_d;
    v.r[i] = e.r;
    v.num[i] = e.num;
    v.a[i] = e.a;
    if (k == n - 1) continue;
    v.rsc[i] = e.rsc;
    v.gamma[i] = e.gamma;
    v.beta[i] = e.beta;
  }
  sx x = zero, y = zero;
  for (int k = 0; k < n; ++k) {
    const auto i = u(k);
    const pivot_step step =
        k + 1 < n ? pivot_link(v.a[i], v.gamma[i], v.r[i], v.beta[i], x, y, cd[i], sd[i])
                  : pivot_link(v.a[i], v.gamma[i], v.r[i], v.beta[i], x, y);
    v.x.push_back(x);
    v.y.push_back(y);
    v.w.push_back(step.w);
    v.omega.push_back(step.omega);
    v.axial.push_back(step.axial);
    v.kinetic_force.push_back(step.kinetic_force);
    if (k + 1 < n) {
      x = step.x_next;
      y = step.y_next;
    }
  }
  return v;
}

articulated_form::motion articulated_form::solve(const std::vector<sx>& p) const {
  values v = evaluate(p);
  return {std::move(v.omega), std::move(v.w), std::move(v.y), std::move(v.kinetic_force)};
}

sx articulated_form::kinetic_energy(const motion& m) const {
  sx twice_t = m_graph->constant(0);
  for (int k = 0; k < n; ++k)
    twice_t = twice_t + mass[u(k)] * (m.w[u(k)] * m.w[u(k)] + m.y[u(k)] * m.y[u(k)]);
  return m_graph->constant(GiNaC::numeric(1, 2)) * twice_t;
}

sx articulated_form::mass_matrix_determinant() const {
  // The pivots d_k do not depend on the momenta.
  const values v = evaluate(std::vector<sx>(u(n), m_graph->constant(0)));
  sx lengths = m_graph->constant(1), pivots = m_graph->constant(1);
  for (int k = 0; k < n; ++k) {
    lengths = lengths * m_graph->input(input_kind::length, k);
    pivots = pivots * v.d[u(k)];
  }
  return lengths * lengths * pivots;
}

// The derivative of the value pass along one direction, given the derivatives dC_k, dS_k
// (k < n − 1) and dq_k of its inputs: forward-mode differentiation written out, because most
// links of most directions see no source of their own. There the tangent moves by the
// factors of the elimination, ρ_k = C_k m_k / d_k (= C_k − S_k γ_k), ξ_k = S_k (m_k + r_{k+1})
// / d_k (= C_k γ_k + S_k) and ρ_k², which are free of cancellation and shared by all
// directions:
//   tip-ward:             dr_k = ρ_k² dr_{k+1}, d(1/d_k) = −S_k²/d_k² dr_{k+1},
//                         dγ_k = S_k C_k m_k/d_k² dr_{k+1},
//                         da_k = −S_k/d_k dβ_{k+1} − a_k S_k²/d_k dr_{k+1},
//                         dβ_k = ρ_k dβ_{k+1} + a_k S_k C_k m_k/d_k dr_{k+1},
//   pivot-ward:           dx_{k+1} = −ξ_k dy_k, dy_{k+1} = ρ_k dy_k, dω_k = −γ_k dy_k − dx_k.
// Every other link takes the general product and quotient rules. Both are exact; the
// verifier checks the Jacobian they build.
articulated_form::tangent articulated_form::propagate(const values& v, const std::vector<sx>& dC,
                                                      const std::vector<sx>& dS,
                                                      const std::vector<sx>& dq) const {
  expr_graph& g = *m_graph;
  const sx zero = g.constant(0);
  auto is_zero = [&](sx a) { return g.is_constant(a, 0); };
  auto rho = [&](int k) { return cd[u(k)] * (mass[u(k)] * v.inv_d[u(k)]); };
  auto inv_d2 = [&](int k) { return v.inv_d[u(k)] * v.inv_d[u(k)]; };
  const auto nn = u(n);

  // Elimination: d, 1/d, r, r S C and γ (the momentum-independent half).
  std::vector<sx> d_inv(nn, zero), d_r(nn, zero), d_rsc(nn, zero), d_gamma(nn, zero);
  for (int k = n - 2; k >= 0; --k) {
    const auto i = u(k);
    const sx C = cd[i], S = sd[i], dr1 = d_r[i + 1], r1 = v.r[i + 1];
    if (is_zero(dC[i]) && is_zero(dS[i])) {
      if (is_zero(dr1)) continue;
      d_r[i] = (rho(k) * rho(k)) * dr1;
      d_inv[i] = -(((S * S) * inv_d2(k)) * dr1);
      d_rsc[i] = (S * C) * dr1;
      d_gamma[i] = ((S * C) * (mass[i] * inv_d2(k))) * dr1;
      continue;
    }
    const sx d_sc = dS[i] * C + S * dC[i];
    const sx d_d = dr1 * (S * S) + r1 * (g.constant(2) * (S * dS[i]));
    d_inv[i] = -(d_d * inv_d2(k));
    d_r[i] = (mass[i] * dr1) * v.inv_d[i] + (mass[i] * (mass[i] + r1)) * d_inv[i];
    d_rsc[i] = dr1 * (S * C) + r1 * d_sc;
    d_gamma[i] = d_rsc[i] * v.inv_d[i] + v.rsc[i] * d_inv[i];
  }

  // a and β from the tip.
  std::vector<sx> d_a(nn, zero), d_beta(nn, zero);
  d_a[nn - 1] = dq[nn - 1] * v.inv_d[nn - 1];
  for (int k = n - 2; k >= 0; --k) {
    const auto i = u(k);
    const sx C = cd[i], S = sd[i];
    const bool own_source =
        !is_zero(dq[i]) || !is_zero(dq[i + 1]) || !is_zero(dC[i]) || !is_zero(dS[i]);
    if (!own_source) {
      // Only dβ_{k+1} and the elimination's dr_{k+1} come in:
      //   da_k = −S_k/d_k dβ_{k+1} − a_k S_k²/d_k dr_{k+1},
      //   dβ_k = ρ_k dβ_{k+1} + a_k S_k C_k m_k/d_k dr_{k+1}.
      const sx db1 = d_beta[i + 1], dr1 = d_r[i + 1];
      d_a[i] = -((S * v.inv_d[i]) * db1 + (v.a[i] * ((S * S) * v.inv_d[i])) * dr1);
      d_beta[i] = rho(k) * db1 + (v.a[i] * ((S * C) * (mass[i] * v.inv_d[i]))) * dr1;
      continue;
    }
    const sx d_num =
        dq[i] - (dC[i] * v.q[i + 1] + C * dq[i + 1]) - (dS[i] * v.beta[i + 1] + S * d_beta[i + 1]);
    d_a[i] = d_num * v.inv_d[i] + v.num[i] * d_inv[i];
    d_beta[i] = dC[i] * v.beta[i + 1] + C * d_beta[i + 1] - (dS[i] * v.q[i + 1] + S * dq[i + 1]) +
                (d_rsc[i] * v.a[i] + v.rsc[i] * d_a[i]);
  }

  // The velocities from the pivot.
  tangent t;
  sx dx = zero, dy = zero;
  for (int k = 0; k < n; ++k) {
    const auto i = u(k);
    const bool last = k + 1 == n;
    const bool sourceless = is_zero(d_a[i]) && is_zero(d_gamma[i]) && is_zero(d_r[i]) &&
                            is_zero(d_beta[i]) && (last || (is_zero(dC[i]) && is_zero(dS[i])));
    sx d_omega, d_force, dx_next = zero, dy_next = zero;
    if (sourceless) {
      d_omega = -(v.gamma[i] * dy) - dx;
      d_force = -(d_omega * v.axial[i] + (v.omega[i] * v.r[i]) * dy);
      if (!last) {
        dx_next = -((sd[i] * ((mass[i] + v.r[i + 1]) * v.inv_d[i])) * dy);
        dy_next = rho(k) * dy;
      }
    } else {
      const sx dw = d_a[i] - (d_gamma[i] * v.y[i] + v.gamma[i] * dy);
      d_omega = dw - dx;
      const sx d_axial = d_r[i] * v.y[i] + v.r[i] * dy + d_beta[i];
      d_force = -(d_omega * v.axial[i] + v.omega[i] * d_axial);
      if (!last) {
        dx_next = dC[i] * v.w[i] + cd[i] * dw - (dS[i] * v.y[i] + sd[i] * dy);
        dy_next = dS[i] * v.w[i] + sd[i] * dw + (dC[i] * v.y[i] + cd[i] * dy);
      }
    }
    t.omega.push_back(d_omega);
    t.kinetic_force.push_back(d_force);
    dx = dx_next;
    dy = dy_next;
  }
  return t;
}

articulated_form::tangent articulated_form::along_angle(const std::vector<sx>& p, int k) const {
  const values v = evaluate(p);
  const sx zero = m_graph->constant(0);
  std::vector<sx> dC(u(n), zero), dS(u(n), zero), dq(u(n), zero);
  // φ_k enters δ_{k−1} = φ_k − φ_{k−1} with +1 and δ_k = φ_{k+1} − φ_k with −1.
  if (k > 0) {
    dC[u(k - 1)] = -sd[u(k - 1)];
    dS[u(k - 1)] = cd[u(k - 1)];
  }
  if (k + 1 < n) {
    dC[u(k)] = sd[u(k)];
    dS[u(k)] = -cd[u(k)];
  }
  return propagate(v, dC, dS, dq);
}

articulated_form::tangent articulated_form::along_scaled_momentum(const std::vector<sx>& p,
                                                                  int k) const {
  const values v = evaluate(p);
  const sx zero = m_graph->constant(0);
  std::vector<sx> dC(u(n), zero), dS(u(n), zero), dq(u(n), zero);
  dq[u(k)] = m_graph->constant(1);
  return propagate(v, dC, dS, dq);
}

}  // namespace npend::gen
