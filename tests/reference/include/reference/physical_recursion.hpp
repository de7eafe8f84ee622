// A hand-written O(n) recursion for Hamilton's equations of the physical chain (rigid links,
// joint springs and damping, joint torques, an accelerating pivot; docs/model.md): the
// benchmarks' lower limit for the physical right-hand side and a check of the generated one
// that shares no code with the generator. It extends chain_recursion.hpp from point masses to
// rigid links, in lab-frame components where the generator works in each link's own frame
// (generator/rigid_articulated_form.hpp), so the two are written differently.
//
// Kinematics in the pivot's frame. Link k has u_k = (sin φ_k, cos φ_k) along it and
// n_k = (cos φ_k, −sin φ_k) across it; its upper joint moves with v (v = 0 at the pivot), its
// centre of mass with v + c_k φ̇_k n_k and its lower joint with v + l_k φ̇_k n_k. The momentum
// of link k is p_k = n_k·(c_k m_k v_c,k + l_k P_{k+1}) + J_k φ̇_k, P_{k+1} the linear momentum
// of the links below. That momentum is affine in the velocity of the joint it hangs from,
// P_{k+1} = I_{k+1} v_k + b_{k+1} (I the 2 × 2 articulated inertia). From the tip up, with
// h_k = c_k m_k n_k + l_k I_{k+1} n_k and d_k = m_k c_k² + J_k + l_k² n_k·I_{k+1} n_k:
//   a_k = (p_k − l_k n_k·b_{k+1}) / d_k,   φ̇_k = a_k − h_k·v / d_k,
//   I_k = m_k 1 + I_{k+1} − h_k h_kᵀ / d_k,   b_k = b_{k+1} + h_k a_k.
// From the pivot down, P_1 = b_1 and P_{k+1} = P_k − m_k v_c,k, and
//   ṗ_k = −φ̇_k u_k·(c_k m_k v_c,k + l_k P_{k+1}) − ∂V/∂φ_k + τ_k − τ_{k+1},
// ∂V/∂φ_k = G_k ((g − a_y) sin φ_k + a_x cos φ_k) + k_k (θ_k − θ̄_k) − k_{k+1}(θ_{k+1} − θ̄_{k+1}),
// G_k = m_k c_k + l_k μ_{k+1}, θ_k = φ_k − φ_{k−1}, and the joint torques τ_j = u_j − b_j θ̇_j.
// Per link: one sin/cos pair, one division.
#pragma once

#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <vector>

namespace npend::reference {

class physical_recursion {
 public:
  /// Per link (each dim n ≥ 1): mass, length, centre of mass c, inertia J about it, joint
  /// stiffness, rest angle and damping; gravity g. Throws std::invalid_argument for
  /// mismatched sizes or n = 0.
  physical_recursion(const std::vector<double>& masses, const std::vector<double>& lengths,
                     double g, const std::vector<double>& com, const std::vector<double>& inertia,
                     const std::vector<double>& stiffness, const std::vector<double>& rest,
                     const std::vector<double>& damping)
      : m_g(g), m_links(masses.size()), m_work(masses.size()), m_torque(masses.size(), 0.0) {
    const std::size_t n = masses.size();
    for (const auto* v : {&lengths, &com, &inertia, &stiffness, &rest, &damping})
      if (v->size() != n) throw std::invalid_argument("physical_recursion: sizes differ");
    if (n == 0) throw std::invalid_argument("physical_recursion: need n >= 1 links");
    double below = 0;  // μ_{k+1}
    for (std::size_t k = n; k-- > 0;) {
      m_links[k] = {
          masses[k],    lengths[k], com[k],    inertia[k], masses[k] * com[k] + lengths[k] * below,
          stiffness[k], rest[k],    damping[k]};
      below += masses[k];
    }
  }

  /// The pivot's acceleration (a_x, a_y) and the joint torques u (dim n).
  void set_inputs(double ax, double ay, const std::vector<double>& torques) {
    if (torques.size() != m_links.size())
      throw std::invalid_argument("physical_recursion: one torque per joint");
    m_ax = ax;
    m_ay = ay;
    m_torque = torques;
  }

  /// Hamilton's equations: dxdt = f(x), x = [φ_1..φ_n, p_1..p_n] and dxdt both dim 2n.
  /// Uses the object's workspace: one object per thread.
  void rhs(const double* x, double* dxdt) noexcept {
    const std::size_t n = m_links.size();
    const double* phi = x;
    const double* p = x + n;
    const link_constants* const link = m_links.data();
    link_work* const w = m_work.data();

    // Tip up: articulated inertia I = [ixx ixy; ixy iyy] and bias b of the links below.
    double ixx = 0, ixy = 0, iyy = 0, bx = 0, by = 0;
    for (std::size_t k = n; k-- > 0;) {
      const double angle = phi[k];
      const double s = std::sin(angle), c = std::cos(angle);
      const double nx = c, ny = -s;
      const double l = link[k].l, cm = link[k].c, m = link[k].m;
      const double inx = ixx * nx + ixy * ny, iny = ixy * nx + iyy * ny;  // I_{k+1} n
      const double hx = cm * m * nx + l * inx, hy = cm * m * ny + l * iny;
      const double inv_d = 1.0 / (m * cm * cm + link[k].J + l * l * (nx * inx + ny * iny));
      const double a = (p[k] - l * (nx * bx + ny * by)) * inv_d;
      w[k] = {s, c, hx * inv_d, hy * inv_d, a};
      bx += hx * a;
      by += hy * a;
      ixx += m - hx * hx * inv_d;
      ixy -= hx * hy * inv_d;
      iyy += m - hy * hy * inv_d;
    }

    // Pivot down: rates, the running momentum of the links below, and the forces.
    double vx = 0, vy = 0, px = bx, py = by, previous_rate = 0, previous_angle = 0;
    const double gy = m_g - m_ay;
    for (std::size_t k = 0; k < n; ++k) {
      const link_constants& L = link[k];
      const double rate = w[k].a - (w[k].gx * vx + w[k].gy * vy);
      const double nx = w[k].c, ny = -w[k].s;
      const double vcx = vx + L.c * rate * nx, vcy = vy + L.c * rate * ny;
      px -= L.m * vcx;  // now P_{k+1}
      py -= L.m * vcy;
      dxdt[k] = rate;
      const double kinetic =
          -rate * (w[k].s * (L.c * L.m * vcx + L.l * px) + w[k].c * (L.c * L.m * vcy + L.l * py));
      const double gravity = L.G * (gy * w[k].s + m_ax * w[k].c);
      const double spring = L.k * (phi[k] - previous_angle - L.rest);
      const double tau = m_torque[k] - L.b * (rate - previous_rate);
      dxdt[n + k] = kinetic - gravity - spring + tau;
      // Joint k's spring and torque act on link k − 1 with the opposite sign.
      if (k > 0) dxdt[n + k - 1] += spring - tau;
      vx += L.l * rate * nx;
      vy += L.l * rate * ny;
      previous_rate = rate;
      previous_angle = phi[k];
    }
  }

 private:
  struct link_constants {
    double m, l, c, J;
    double G;  ///< m_k c_k + l_k μ_{k+1}: the moment gravity acts on
    double k, rest, b;
  };
  struct link_work {
    double s, c;    ///< sin φ_k, cos φ_k
    double gx, gy;  ///< h_k / d_k
    double a;       ///< a_k
  };
  double m_g, m_ax = 0, m_ay = 0;
  std::vector<link_constants> m_links;
  std::vector<link_work> m_work;
  std::vector<double> m_torque;
};

}  // namespace npend::reference
