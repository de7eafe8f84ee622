// A hand-written O(n) recursion for Hamilton's equations of the n-link chain, in the style
// of the articulated-body algorithm: the benchmarks' "practical lower limit" for the
// right-hand side, and a second independent check of the generated one. It shares no code
// with the generator.
//
// The recursion. Bob k moves with v_k = v_{k−1} + ω_k n_k, where n_k = (cos φ_k, −sin φ_k)
// is the unit normal of rod k and ω_k = l_k φ̇_k its tangential speed (v_0 = 0 at the fixed
// pivot). The canonical momentum is p_k = ∂T/∂φ̇_k = l_k n_k·P_k, with P_k = Σ_{j≥k} m_j v_j
// the momentum of the sub-chain hanging at joint k. That momentum is affine in the velocity
// of the point the sub-chain hangs from: P_k = I_k v_{k−1} + b_k, where I_k is the
// sub-chain's 2×2 articulated inertia and b_k collects the momenta p_k..p_n. From the
// bottom up (I_{n+1} = 0, b_{n+1} = 0), with Ĩ_k = I_{k+1} + m_k 1, h_k = Ĩ_k n_k,
// d_k = n_k·h_k and q_k = p_k / l_k:
//   I_k = Ĩ_k − h_k h_kᵀ / d_k,     b_k = b_{k+1} + h_k a_k,
//   a_k = (q_k − n_k·b_{k+1}) / d_k,   ω_k = a_k − (h_k / d_k)·v_{k−1}.
// The backward pass accumulates I_k and b_k; the forward pass gets ω_k and v_k from the
// pivot down, and with them, u_k = (sin φ_k, cos φ_k) = −∂n_k/∂φ_k and μ_k = m_k + … + m_n,
//   ṗ_k = ∂L/∂φ_k = −ω_k u_k·P_k − g μ_k l_k sin φ_k,   P_1 = b_1,  P_{k+1} = P_k − m_k v_k.
// Per link: one sin/cos pair, one division, ~40 flops.
//
// Why it is written this way (each measured, g++ -O3): the sine and cosine come from one
// local angle so that the compiler fuses them into one sincos call; they are computed inside
// the backward pass, in its order, so the CPU overlaps the libm calls with the pass's
// division chain (~20–25% faster than a separate trig loop first); the forward pass only needs
// the precomputed a_k and h_k / d_k, which keeps its dependency chain short, and ṗ is formed
// in the same pass from the running sub-chain momentum.
#pragma once

#include <cmath>
#include <cstddef>
#include <span>
#include <stdexcept>
#include <vector>

namespace npend::reference {

class chain_recursion {
 public:
  /// A chain of masses m_1..m_n (kg), rod lengths l_1..l_n (m) and gravity g (m/s²).
  /// Throws std::invalid_argument when the counts differ or n = 0.
  chain_recursion(std::span<const double> masses, std::span<const double> lengths, double g)
      : m_links(masses.size()), m_work(masses.size()) {
    if (masses.empty() || masses.size() != lengths.size())
      throw std::invalid_argument("chain_recursion: need n >= 1 masses and as many lengths");
    double mu = 0;  // the mass hanging at and below joint k
    for (std::size_t k = masses.size(); k-- > 0;) {
      mu += masses[k];
      m_links[k] = {masses[k], 1.0 / lengths[k], g * mu * lengths[k]};
    }
  }

  int links() const { return static_cast<int>(m_links.size()); }

  /// Hamilton's equations: dxdt = f(x), x = [φ_1..φ_n, p_1..p_n] and dxdt both dim 2n.
  /// Uses the object's workspace: one object per thread.
  void rhs(const double* x, double* dxdt) noexcept {
    const std::size_t n = m_links.size();
    const double* phi = x;
    const double* p = x + n;
    const link_constants* const link = m_links.data();
    link_work* const w = m_work.data();

    // Backward: articulated inertia I = [ixx ixy; ixy iyy] and bias b of each sub-chain.
    double ixx = 0, ixy = 0, iyy = 0, bx = 0, by = 0;
    for (std::size_t k = n; k-- > 0;) {
      const double angle = phi[k];  // one load, so that sin and cos fuse into sincos
      const double s = std::sin(angle), c = std::cos(angle);
      const double nx = c, ny = -s;
      ixx += link[k].m;
      iyy += link[k].m;
      const double hx = ixx * nx + ixy * ny, hy = ixy * nx + iyy * ny;
      const double inv_d = 1.0 / (nx * hx + ny * hy);
      const double gx = hx * inv_d, gy = hy * inv_d;
      const double a = (p[k] * link[k].inv_l - (nx * bx + ny * by)) * inv_d;
      w[k] = {s, c, gx, gy, a};
      bx += hx * a;
      by += hy * a;
      ixx -= gx * hx;
      ixy -= gx * hy;
      iyy -= gy * hy;
    }

    // Forward: speeds ω_k, bob velocities v_k and sub-chain momenta P_k from the pivot down.
    double vx = 0, vy = 0, px = bx, py = by;
    for (std::size_t k = 0; k < n; ++k) {
      const double omega = w[k].a - (w[k].gx * vx + w[k].gy * vy);
      dxdt[k] = omega * link[k].inv_l;
      dxdt[n + k] = -omega * (w[k].s * px + w[k].c * py) - link[k].gravity * w[k].s;
      vx += omega * w[k].c;
      vy -= omega * w[k].s;
      px -= link[k].m * vx;
      py -= link[k].m * vy;
    }
  }

 private:
  struct link_constants {
    double m, inv_l;
    double gravity;  ///< g μ_k l_k, so that ∂V/∂φ_k = gravity · sin φ_k
  };
  struct link_work {
    double s, c;    ///< sin φ_k, cos φ_k
    double gx, gy;  ///< h_k / d_k
    double a;       ///< a_k
  };
  std::vector<link_constants> m_links;
  std::vector<link_work> m_work;
};

}  // namespace npend::reference
