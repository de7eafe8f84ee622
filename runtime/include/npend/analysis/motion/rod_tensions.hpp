// The rod tensions of a chain of point masses: Lagrange's equations of the first kind
// (paper §6.3.1), the constraint forces that keep every rod at its length.
//
// Bob k (mass m_k, y pointing down) is pulled up its own rod by τ_k and down the next rod by
// τ_{k+1}: m_k a_k = −τ_k u_k + τ_{k+1} u_{k+1} + m_k g ŷ, u_k = (sin φ_k, cos φ_k) pointing
// from joint k to bob k, τ_{n+1} = 0. A rod keeps its length when the relative acceleration of
// its ends has the centripetal component u_k·(a_k − a_{k−1}) = −l_k φ̇_k² (a_0 = 0: the pivot
// is fixed). Putting Newton's a_k into it gives, for k = 1..n, with C_k = cos(φ_{k+1} − φ_k)
// and 1/m_0 = 0,
//   (1/m_k + 1/m_{k−1}) τ_k − (C_{k−1}/m_{k−1}) τ_{k−1} − (C_k/m_k) τ_{k+1}
//       = l_k φ̇_k² + [k = 1] g cos φ_1,
// a symmetric positive definite tridiagonal system in the positions and velocities alone —
// no accelerations — solved in O(n). (At rest τ_k = g μ_k, the weight below; the single
// pendulum's τ = m g cos φ + m l φ̇².) Tensions are positive when a rod pulls.
#pragma once

#include <span>
#include <vector>

#include "npend/chain.hpp"

namespace npend {

/// τ_1..τ_n (N) of the point-mass chain at the state x = [φ, p] (dim 2n), into tau (dim n).
/// Throws std::invalid_argument for a physical chain (rigid links, joint springs, damping,
/// torques or a moving pivot make the joint forces more than a tension along the rod) and
/// for wrong sizes.
void rod_tensions(const chain& c, std::span<const double> x, std::span<double> tau);

/// As above, returned.
std::vector<double> rod_tensions(const chain& c, std::span<const double> x);

}  // namespace npend
