#include "rigid_articulated_form.hpp"

namespace npend::gen {

namespace {
std::size_t u(int i) { return static_cast<std::size_t>(i); }

// A 2-vector or a symmetric 2 × 2 matrix in one link's frame (n, u).
struct vec2 {
  sx n, u;
};
struct sym2 {
  sx nn, nu, uu;
};

// Components in frame k of a vector given in frame k + 1: n_{k+1} = C n_k − S u_k,
// u_{k+1} = S n_k + C u_k.
vec2 to_upper_frame(vec2 v, sx C, sx S) { return {C * v.n + S * v.u, C * v.u - S * v.n}; }

sym2 to_upper_frame(sym2 r, sx C, sx S) {
  const sx cc = C * C, ss = S * S, cs = C * S;
  const sx cross = (cs + cs) * r.nu;
  return {cc * r.nn + cross + ss * r.uu, cs * (r.uu - r.nn) + (cc - ss) * r.nu,
          ss * r.nn - cross + cc * r.uu};
}

// Components in frame k + 1 of a vector given in frame k (the inverse turn).
vec2 to_lower_frame(vec2 v, sx C, sx S) { return {C * v.n - S * v.u, S * v.n + C * v.u}; }

}  // namespace

rigid_articulated_form::rigid_articulated_form(int links, bool joint_features, expr_graph& graph)
    : m_n(links), m_joint_features(joint_features), m_graph(&graph) {
  const int n = m_n;
  std::vector<sx> s, c;
  for (int k = 0; k < n; ++k) {
    const sx phi = graph.input(input_kind::phi, k);
    s.push_back(sin(phi));
    c.push_back(cos(phi));
    m_mass.push_back(graph.input(input_kind::mass, k));
    m_length.push_back(graph.input(input_kind::length, k));
    m_com.push_back(graph.input(input_kind::com, k));
    m_inertia.push_back(graph.input(input_kind::inertia, k));
  }
  m_sin = s;
  m_cos = c;
  for (int k = 0; k + 1 < n; ++k) {
    m_cd.push_back(c[u(k)] * c[u(k + 1)] + s[u(k)] * s[u(k + 1)]);
    m_sd.push_back(s[u(k + 1)] * c[u(k)] - c[u(k + 1)] * s[u(k)]);
  }
  // The articulated mass from the tip up; zero below the last link.
  const sx zero = graph.constant(0), one = graph.constant(1);
  m_steps.resize(u(n));
  sym2 below{zero, zero, zero};  // R_{k+1} in frame k + 1
  sx det = zero, trace = zero;   // det R_{k+1}, tr R_{k+1}: the same in every frame
  for (int k = n - 1; k >= 0; --k) {
    const auto i = u(k);
    const sym2 r = k + 1 < n ? to_upper_frame(below, m_cd[i], m_sd[i]) : below;
    const sx m = m_mass[i], l = m_length[i], cm = m_com[i], J = m_inertia[i];
    const sx e = l - cm;
    pivot_step& st = m_steps[i];
    st.D = m * (cm * cm) + J + (l * l) * r.nn;
    st.inv_D = one / st.D;
    st.gn = cm * m + l * r.nn;
    st.gu = l * r.nu;
    st.Rnu = r.nu;
    st.Ruu = r.uu;
    const sx me2 = m * (e * e);
    const sx next_det = ((J + me2) * det + J * m * (trace + m) + m * me2 * r.nn) * st.inv_D;
    below = {(J * (r.nn + m) + me2 * r.nn) * st.inv_D, (J - m * cm * e) * r.nu * st.inv_D,
             (J * (r.uu + m) + (l * l) * det + (l * l) * m * r.nn + m * (cm * cm) * (r.uu + m)) *
                 st.inv_D};
    det = next_det;
    trace = below.nn + below.uu;
  }
}

rigid_articulated_form::motion rigid_articulated_form::solve(const std::vector<sx>& p) const {
  const int n = m_n;
  expr_graph& g = *m_graph;
  const sx zero = g.constant(0), half = g.constant(GiNaC::numeric(1, 2));
  // b from the tip up, and a_k = (p_k − l_k b_n)/D_k, with b turned into link k's frame.
  std::vector<sx> a(u(n)), bu(u(n), zero);
  vec2 below{zero, zero};  // b_{k+1} in frame k + 1
  for (int k = n - 1; k >= 0; --k) {
    const auto i = u(k);
    const vec2 b = k + 1 < n ? to_upper_frame(below, m_cd[i], m_sd[i]) : below;
    a[i] = (p[i] - m_length[i] * b.n) * m_steps[i].inv_D;
    bu[i] = b.u;
    below = {b.n + m_steps[i].gn * a[i], b.u + m_steps[i].gu * a[i]};
  }
  // From the pivot down, with v_{k−1} = (x, y) in link k's frame.
  motion out;
  vec2 v{zero, zero};
  sx twice_t = zero;
  for (int k = 0; k < n; ++k) {
    const auto i = u(k);
    const pivot_step& st = m_steps[i];
    const sx m = m_mass[i], l = m_length[i], cm = m_com[i];
    const sx dphi = a[i] - (st.gn * v.n + st.gu * v.u) * st.inv_D;
    const vec2 lower{v.n + l * dphi, v.u};                     // v_k
    const sx axial = st.Rnu * lower.n + st.Ruu * v.u + bu[i];  // u_k·P_{k+1}
    out.dphi.push_back(dphi);
    out.kinetic_force.push_back(-(dphi * (cm * m * v.u + l * axial)));
    const sx vc = v.n + cm * dphi;
    twice_t = twice_t + m * (vc * vc + v.u * v.u) + m_inertia[i] * (dphi * dphi);
    if (k + 1 < n) v = to_lower_frame(lower, m_cd[i], m_sd[i]);
  }
  out.kinetic_energy = half * twice_t;
  return out;
}

sx rigid_articulated_form::mass_matrix_determinant() const {
  sx det = m_graph->constant(1);
  for (const pivot_step& st : m_steps) det = det * st.D;
  return det;
}

std::vector<sx> rigid_articulated_form::potential_force() const {
  const int n = m_n;
  expr_graph& g = *m_graph;
  const sx gravity = g.input(input_kind::gravity);
  const sx field_y = m_joint_features ? gravity - g.input(input_kind::drive, 1) : gravity;
  std::vector<sx> out(u(n));
  sx below = g.constant(0);  // μ_{k+1}
  for (int k = n - 1; k >= 0; --k) {
    const auto i = u(k);
    const sx moment = m_mass[i] * m_com[i] + m_length[i] * below;
    sx field = field_y * m_sin[i];
    if (m_joint_features) field = field + g.input(input_kind::drive, 0) * m_cos[i];
    out[i] = -(moment * field);
    below = below + m_mass[i];
  }
  if (!m_joint_features) return out;
  // Spring k acts on link k and, reversed, on link k − 1.
  for (int k = 0; k < n; ++k) {
    sx theta = g.input(input_kind::phi, k);
    if (k > 0) theta = theta - g.input(input_kind::phi, k - 1);
    const sx torque =
        g.input(input_kind::stiffness, k) * (theta - g.input(input_kind::rest_angle, k));
    out[u(k)] = out[u(k)] - torque;
    if (k > 0) out[u(k - 1)] = out[u(k - 1)] + torque;
  }
  return out;
}

std::vector<sx> rigid_articulated_form::joint_force(const std::vector<sx>& dphi) const {
  const int n = m_n;
  expr_graph& g = *m_graph;
  std::vector<sx> out(u(n), g.constant(0));
  if (!m_joint_features) return out;
  for (int k = 0; k < n; ++k) {
    const sx rate = k > 0 ? dphi[u(k)] - dphi[u(k - 1)] : dphi[u(k)];
    const sx tau = g.input(input_kind::torque, k) - g.input(input_kind::damping, k) * rate;
    out[u(k)] = out[u(k)] + tau;
    if (k > 0) out[u(k - 1)] = out[u(k - 1)] - tau;
  }
  return out;
}

}  // namespace npend::gen
