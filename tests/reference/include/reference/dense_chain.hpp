// An independent, hand-written numeric implementation of the n-link chain, straight from
// the formulas in docs/paper.md ("Conventions"): dense A_ij = μ_max(i,j) l_i l_j
// cos(φ_i − φ_j), an LDLᵀ solve for φ̇, the explicit ṗ formula, and a hand-derived
// analytic Jacobian. It shares no code with the generator: the tests compare the two, and
// the benchmarks time it as "what a careful user would write with Eigen" — so the
// pointer-based rhs and jacobian work in a preallocated workspace (no allocation per call)
// and take the n² angle differences from the 2n sines and cosines by the addition theorems
// (the first version, with n² libm calls and allocating per call, had a 2–7× slower rhs).
//
// The physical chain (rigid links, joint springs and damping, torques, a pivot accelerating
// with a) has the same structure, hand-derived from rigid-body kinematics: link k's mass m_k
// sits at c_k down the link, so for i < j, A_ij = l_i (m_j c_j + μ_{j+1} l_j) cos(φ_i − φ_j)
// and A_ii = J_i + m_i c_i² + μ_{i+1} l_i²; gravity and the inertial force act on the
// moments G_i = m_i c_i + μ_{i+1} l_i: ∂V/∂φ_i = G_i ((g − a_y) sin φ_i + a_x cos φ_i) plus
// the springs' k_i(θ_i − θ̄_i) − k_{i+1}(θ_{i+1} − θ̄_{i+1}); the joint torques
// τ_j = u_j − b_j θ̇_j enter ṗ_i as τ_i − τ_{i+1}. (physical(); set_inputs() for a and u.)
#pragma once

#include <Eigen/Dense>
#include <cmath>
#include <vector>

namespace npend::reference {

class dense_chain {
 public:
  using row_major_matrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

  /// Scratch space of one evaluation for n links; reused so that rhs and jacobian never
  /// allocate. One per thread.
  struct workspace {
    explicit workspace(int n)
        : s(n),
          c(n),
          dphi(n),
          w(n),
          Ad(n),
          A(n, n),
          KS(n, n),
          Ainv(n, n),
          G(n, n),
          dphi_dphi(n, n),
          Fphi(n, n),
          Fdphi(n, n),
          ldlt(n) {}
    Eigen::VectorXd s, c;  ///< sin φ_i, cos φ_i
    Eigen::VectorXd dphi;  ///< φ̇ = A⁻¹ p
    Eigen::VectorXd w;     ///< w_i = Σ_j μ_max l_i l_j sin(φ_i − φ_j) φ̇_j
    Eigen::VectorXd Ad;    ///< A φ̇
    Eigen::MatrixXd A;     ///< mass matrix, A_ij = K_ij cos(φ_i − φ_j)
    Eigen::MatrixXd KS;    ///< K_ij sin(φ_i − φ_j) = ∂A_ij/∂φ_j
    Eigen::MatrixXd Ainv, G, dphi_dphi, Fphi, Fdphi;
    Eigen::LDLT<Eigen::MatrixXd> ldlt;
  };

  dense_chain(std::vector<double> masses, std::vector<double> lengths, double g)
      : m_m(std::move(masses)), m_l(std::move(lengths)), m_g(g), m_n(static_cast<int>(m_m.size())) {
    m_mu.assign(m_m.size(), 0.0);
    double below = 0;
    for (int j = m_n - 1; j >= 0; --j) m_mu[index(j)] = below += m_m[index(j)];
    m_K.resize(m_n, m_n);
    m_gravity.resize(m_n);
    for (int i = 0; i < m_n; ++i) {
      for (int j = 0; j < m_n; ++j) m_K(i, j) = mu_max(i, j) * l(i) * l(j);
      m_gravity(i) = m_g * mu(i) * l(i);
    }
  }

  /// The physical chain: centres of mass c, inertias J, joint stiffnesses k, rest angles
  /// θ̄ and damping b (each dim n), inputs a = 0, u = 0 until set_inputs.
  static dense_chain physical(std::vector<double> masses, std::vector<double> lengths, double g,
                              const std::vector<double>& com, const std::vector<double>& inertia,
                              std::vector<double> stiffness, std::vector<double> rest,
                              std::vector<double> damping) {
    dense_chain d(std::move(masses), std::move(lengths), g);
    d.m_physical = true;
    const int n = d.m_n;
    d.m_G.resize(n);
    for (int i = 0; i < n; ++i) {
      const double below = i + 1 < n ? d.mu(i + 1) : 0.0;
      d.m_G(i) = d.m_m[index(i)] * com[index(i)] + below * d.l(i);
      for (int j = i + 1; j < n; ++j) {
        const double below_j = j + 1 < n ? d.mu(j + 1) : 0.0;
        d.m_K(i, j) = d.m_K(j, i) = d.l(i) * (d.m_m[index(j)] * com[index(j)] + below_j * d.l(j));
      }
      d.m_K(i, i) = inertia[index(i)] + d.m_m[index(i)] * com[index(i)] * com[index(i)] +
                    below * d.l(i) * d.l(i);
    }
    d.m_k = std::move(stiffness);
    d.m_rest = std::move(rest);
    d.m_b = std::move(damping);
    d.m_u.assign(index(n), 0.0);
    return d;
  }

  /// The pivot's acceleration (a_x, a_y) and the joint torques u (dim n) of a physical chain.
  void set_inputs(double ax, double ay, std::vector<double> torques) {
    m_ax = ax;
    m_ay = ay;
    m_u = std::move(torques);
  }

  int links() const { return m_n; }
  double mu(int j) const { return m_mu[index(j)]; }
  double l(int j) const { return m_l[index(j)]; }
  double mu_max(int i, int j) const { return mu(i > j ? i : j); }

  /// Hamilton's equations, allocation-free: x = [φ, p] and dxdt both dim 2n.
  /// φ̇ = A⁻¹p by LDLᵀ, and
  /// ṗ_i = −l_i φ̇_i Σ_{j≠i} μ_max(i,j) l_j sin(φ_i − φ_j) φ̇_j − μ_i g l_i sin φ_i.
  void rhs(const double* x, double* dxdt, workspace& ws) const {
    const Eigen::Map<const Eigen::VectorXd> p(x + m_n, m_n);
    assemble(x, ws);
    ws.ldlt.compute(ws.A);
    ws.dphi = ws.ldlt.solve(p);
    ws.w.noalias() = ws.KS * ws.dphi;  // the diagonal of KS is zero: the sum skips j = i
    Eigen::Map<Eigen::VectorXd>(dxdt, m_n) = ws.dphi;
    if (m_physical) {
      Eigen::Map<Eigen::VectorXd>(dxdt + m_n, m_n) =
          -ws.dphi.cwiseProduct(ws.w) - potential_gradient(x) + joint_forces(ws.dphi);
      return;
    }
    Eigen::Map<Eigen::VectorXd>(dxdt + m_n, m_n) =
        -ws.dphi.cwiseProduct(ws.w) - m_gravity.cwiseProduct(ws.s);
  }

  /// ∂V/∂φ of the physical chain (gravity, the pivot's inertial force, springs).
  Eigen::VectorXd potential_gradient(const double* phi) const {
    Eigen::VectorXd grad(m_n);
    for (int i = 0; i < m_n; ++i)
      grad(i) = m_G(i) * ((m_g - m_ay) * std::sin(phi[i]) + m_ax * std::cos(phi[i])) +
                m_k[index(i)] * (joint_angle(phi, i) - m_rest[index(i)]);
    for (int i = 0; i + 1 < m_n; ++i)
      grad(i) -= m_k[index(i + 1)] * (joint_angle(phi, i + 1) - m_rest[index(i + 1)]);
    return grad;
  }

  /// Q_i = τ_i − τ_{i+1} with the joint torques τ_j = u_j − b_j θ̇_j.
  Eigen::VectorXd joint_forces(const Eigen::VectorXd& dphi) const {
    Eigen::VectorXd tau(m_n), q(m_n);
    for (int j = 0; j < m_n; ++j)
      tau(j) = m_u[index(j)] - m_b[index(j)] * (dphi(j) - (j > 0 ? dphi(j - 1) : 0.0));
    for (int i = 0; i < m_n; ++i) q(i) = tau(i) - (i + 1 < m_n ? tau(i + 1) : 0.0);
    return q;
  }

  /// The analytic Jacobian, allocation-free, row-major 2n × 2n:
  /// ∂φ̇/∂p = A⁻¹, ∂φ̇/∂φ_k = −A⁻¹(∂A/∂φ_k)φ̇, and the chain rule for ṗ(φ, φ̇(φ, p)).
  void jacobian(const double* x, double* jac, workspace& ws) const {
    const int n = m_n;
    const Eigen::Map<const Eigen::VectorXd> p(x + n, n);
    assemble(x, ws);
    ws.ldlt.compute(ws.A);
    ws.Ainv.setIdentity();
    ws.ldlt.solveInPlace(ws.Ainv);
    ws.dphi = ws.ldlt.solve(p);
    ws.w.noalias() = ws.KS * ws.dphi;
    ws.Ad.noalias() = ws.A * ws.dphi;

    // G(:, k) = (∂A/∂φ_k) φ̇: G_ik = KS_ik φ̇_k (i ≠ k), G_kk = −w_k.
    ws.G = ws.KS * ws.dphi.asDiagonal();
    ws.G.diagonal() -= ws.w;
    ws.dphi_dphi.noalias() = -ws.Ainv * ws.G;

    // ṗ = F(φ, φ̇) = −φ̇ ∘ w − g μ l ∘ sin φ, differentiated at fixed φ̇ and at fixed φ:
    // ∂F_i/∂φ_k = φ̇_i A_ik φ̇_k (i ≠ k), ∂F_i/∂φ_i = −φ̇_i Σ_{j≠i} A_ij φ̇_j − g μ_i l_i cos φ_i;
    // ∂F_i/∂φ̇_k = −φ̇_i KS_ik (i ≠ k), ∂F_i/∂φ̇_i = −w_i.
    ws.Fphi = ws.dphi.asDiagonal() * ws.A * ws.dphi.asDiagonal();
    if (m_physical) {
      ws.Fphi.diagonal() -= ws.dphi.cwiseProduct(ws.Ad);
      ws.Fphi -= potential_hessian(ws);
    } else {
      ws.Fphi.diagonal() -= ws.dphi.cwiseProduct(ws.Ad) + m_gravity.cwiseProduct(ws.c);
    }
    ws.Fdphi = -(ws.dphi.asDiagonal() * ws.KS);
    ws.Fdphi.diagonal() -= ws.w;
    if (m_physical) ws.Fdphi -= damping_matrix();

    Eigen::Map<row_major_matrix> J(jac, 2 * n, 2 * n);
    J.topLeftCorner(n, n) = ws.dphi_dphi;
    J.topRightCorner(n, n) = ws.Ainv;
    J.bottomLeftCorner(n, n) = ws.Fphi;
    J.bottomLeftCorner(n, n).noalias() += ws.Fdphi * ws.dphi_dphi;
    J.bottomRightCorner(n, n).noalias() = ws.Fdphi * ws.Ainv;
  }

  // Convenience forms for the tests (they allocate).

  Eigen::MatrixXd mass_matrix(const Eigen::VectorXd& phi) const {
    workspace ws(m_n);
    assemble(phi.data(), ws);
    return ws.A;
  }

  Eigen::VectorXd velocities(const Eigen::VectorXd& phi, const Eigen::VectorXd& p) const {
    return mass_matrix(phi).ldlt().solve(p);
  }

  Eigen::VectorXd rhs(const Eigen::VectorXd& x) const {
    workspace ws(m_n);
    Eigen::VectorXd f(2 * m_n);
    rhs(x.data(), f.data(), ws);
    return f;
  }

  Eigen::MatrixXd jacobian(const Eigen::VectorXd& x) const {
    workspace ws(m_n);
    row_major_matrix J(2 * m_n, 2 * m_n);
    jacobian(x.data(), J.data(), ws);
    return J;
  }

  double kinetic_energy(const Eigen::VectorXd& phi, const Eigen::VectorXd& dphi) const {
    return 0.5 * dphi.dot(mass_matrix(phi) * dphi);
  }

  double potential_energy(const Eigen::VectorXd& phi) const {
    double v = 0;
    if (m_physical) {
      for (int j = 0; j < m_n; ++j) {
        const double stretch = joint_angle(phi.data(), j) - m_rest[index(j)];
        v += m_G(j) * ((m_g - m_ay) * (1 - std::cos(phi(j))) + m_ax * std::sin(phi(j))) +
             m_k[index(j)] / 2 * stretch * stretch;
      }
      return v;
    }
    for (int j = 0; j < m_n; ++j) v += m_g * mu(j) * l(j) * (1 - std::cos(phi(j)));
    return v;
  }

  double hamiltonian(const Eigen::VectorXd& x) const {
    const Eigen::VectorXd phi = x.head(m_n), p = x.tail(m_n);
    return 0.5 * p.dot(velocities(phi, p)) + potential_energy(phi);
  }

  /// [x_1, y_1, ..., x_n, y_n], y down (eq. 6.1).
  Eigen::VectorXd positions(const Eigen::VectorXd& phi) const {
    Eigen::VectorXd xy(2 * m_n);
    double x = 0, y = 0;
    for (int k = 0; k < m_n; ++k) {
      x += l(k) * std::sin(phi(k));
      y += l(k) * std::cos(phi(k));
      xy(2 * k) = x;
      xy(2 * k + 1) = y;
    }
    return xy;
  }

 private:
  static std::size_t index(int j) { return static_cast<std::size_t>(j); }

  static double joint_angle(const double* phi, int j) {
    return phi[j] - (j > 0 ? phi[j - 1] : 0.0);
  }

  // ∂²V/∂φ²: gravity and drive on the diagonal, the springs tridiagonal.
  Eigen::MatrixXd potential_hessian(const workspace& ws) const {
    Eigen::MatrixXd h = Eigen::MatrixXd::Zero(m_n, m_n);
    for (int i = 0; i < m_n; ++i) {
      h(i, i) = m_G(i) * ((m_g - m_ay) * ws.c(i) - m_ax * ws.s(i)) + m_k[index(i)];
      if (i + 1 < m_n) {
        h(i, i) += m_k[index(i + 1)];
        h(i, i + 1) = h(i + 1, i) = -m_k[index(i + 1)];
      }
    }
    return h;
  }

  // −∂Q/∂φ̇ = Dᵀ diag(b) D, D the difference matrix θ̇ = D φ̇.
  Eigen::MatrixXd damping_matrix() const {
    Eigen::MatrixXd d = Eigen::MatrixXd::Zero(m_n, m_n);
    for (int i = 0; i < m_n; ++i) {
      d(i, i) = m_b[index(i)] + (i + 1 < m_n ? m_b[index(i + 1)] : 0.0);
      if (i + 1 < m_n) d(i, i + 1) = d(i + 1, i) = -m_b[index(i + 1)];
    }
    return d;
  }

  /// sin φ_i, cos φ_i, then A_ij = K_ij cos(φ_i − φ_j) and KS_ij = K_ij sin(φ_i − φ_j) with
  /// K_ij = μ_max(i,j) l_i l_j, the differences by the addition theorems.
  void assemble(const double* phi, workspace& ws) const {
    for (int i = 0; i < m_n; ++i) {
      const double angle = phi[i];  // one load, so that sin and cos fuse into sincos
      ws.s(i) = std::sin(angle);
      ws.c(i) = std::cos(angle);
    }
    // Column by column, so that Eigen vectorises (an element loop over A(i, j) does not).
    for (int j = 0; j < m_n; ++j) {
      ws.A.col(j) = m_K.col(j).cwiseProduct(ws.c * ws.c(j) + ws.s * ws.s(j));
      ws.KS.col(j) = m_K.col(j).cwiseProduct(ws.s * ws.c(j) - ws.c * ws.s(j));
    }
  }

  std::vector<double> m_m, m_l, m_mu;
  double m_g;
  int m_n;
  Eigen::MatrixXd m_K;        ///< μ_max(i,j) l_i l_j
  Eigen::VectorXd m_gravity;  ///< g μ_i l_i
  // The physical chain (physical()).
  bool m_physical = false;
  Eigen::VectorXd m_G;  ///< m_i c_i + μ_{i+1} l_i
  std::vector<double> m_k, m_rest, m_b, m_u;
  double m_ax = 0, m_ay = 0;
};

}  // namespace npend::reference
