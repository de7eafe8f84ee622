#include "npend/analysis/stability/lqr.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "analysis/detail/dense_eigen.hpp"
#include "npend/integrators/integrate_system.hpp"

// SLICOT (Debian's libslicot-dev): SB02MD solves the continuous algebraic Riccati equation
// AᵀX + XA − XGX + Q = 0 by the Schur vectors of the Hamiltonian matrix (Laub's method).
// Fortran calling convention of gfortran: everything by reference, LOGICAL as int, and the
// lengths of the CHARACTER arguments appended as size_t.
extern "C" void sb02md_(const char* dico, const char* hinv, const char* uplo, const char* scal,
                        const char* sort, const int* n, double* a, const int* lda, double* g,
                        const int* ldg, double* q, const int* ldq, double* rcond, double* wr,
                        double* wi, double* s, const int* lds, double* u, const int* ldu,
                        int* iwork, double* dwork, const int* ldwork, int* bwork, int* info,
                        std::size_t, std::size_t, std::size_t, std::size_t, std::size_t);

namespace npend {

namespace {

using row_major = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

std::vector<std::complex<double>> eigenvalues_by_real_part(const Eigen::MatrixXd& m) {
  const Eigen::VectorXcd ev = detail::general_eigenvalues(m);
  std::vector<std::complex<double>> out(ev.data(), ev.data() + ev.size());
  std::sort(out.begin(), out.end(), [](auto a, auto b) {
    return a.real() != b.real() ? a.real() > b.real() : a.imag() > b.imag();
  });
  return out;
}

// The eigenvalues λ of A with rank [A − λI, B] < d (Popov–Belevitch–Hautus).
std::vector<std::complex<double>> uncontrollable_modes(const Eigen::MatrixXd& A,
                                                       const Eigen::MatrixXd& B) {
  const Eigen::Index d = A.rows();
  const double scale = std::max(1.0, std::max(A.norm(), B.norm()));
  std::vector<std::complex<double>> out;
  for (const auto& lambda : eigenvalues_by_real_part(A)) {
    Eigen::MatrixXcd pencil(d, d + B.cols());
    pencil.leftCols(d) = A.cast<std::complex<double>>();
    pencil.leftCols(d).diagonal().array() -= lambda;
    pencil.rightCols(B.cols()) = B.cast<std::complex<double>>();
    const Eigen::JacobiSVD<Eigen::MatrixXcd> svd(pencil);
    if (svd.singularValues()(d - 1) < 1e-9 * scale) out.push_back(lambda);
  }
  return out;
}

// X of AᵀX + XA − X G X + Q = 0 by SB02MD; throws if SLICOT reports a failure.
Eigen::MatrixXd solve_riccati(const Eigen::MatrixXd& A, const Eigen::MatrixXd& G,
                              const Eigen::MatrixXd& Q, double& rcond) {
  const int n = static_cast<int>(A.rows());
  // Column-major copies, as Fortran reads them.
  Eigen::MatrixXd a = A, g = G, q = Q;
  std::vector<double> wr(2 * static_cast<std::size_t>(n)), wi(wr.size()),
      s(4 * static_cast<std::size_t>(n * n)), u(s.size());
  std::vector<int> iwork(2 * static_cast<std::size_t>(n)), bwork(iwork.size());
  const int two_n = 2 * n, ldwork = std::max(2, 6 * n) * 4;
  std::vector<double> dwork(static_cast<std::size_t>(ldwork));
  int info = 0;
  sb02md_("C", "D", "U", "G", "S", &n, a.data(), &n, g.data(), &n, q.data(), &n, &rcond, wr.data(),
          wi.data(), s.data(), &two_n, u.data(), &two_n, iwork.data(), dwork.data(), &ldwork,
          bwork.data(), &info, 1, 1, 1, 1, 1);
  if (info != 0)
    throw std::invalid_argument(
        fmt::format("the Riccati equation has no stabilising solution (SLICOT SB02MD info = {}{})",
                    info, info == 5 ? ": the system is not stabilisable from these joints" : ""));
  return q;
}

// "1,2" for the 0-based joints {0, 1}.
std::string joint_list(const std::vector<int>& joints) {
  std::string out;
  for (const int j : joints) {
    if (!out.empty()) out += ',';
    out += std::to_string(j + 1);
  }
  return out;
}

}  // namespace

lqr_design lqr(const chain& c, std::span<const double> angles, std::span<const int> actuated,
               const lqr_weights& weights) {
  // n: the coordinates q (the angles, after the cart's position on a cart); motors: the
  // actuators (the joints, after the cart's force on a cart).
  const int n = c.coordinates(), d = c.state_size(), motors = c.actuators();
  if (angles.size() != static_cast<std::size_t>(n))
    throw std::invalid_argument(
        c.has_cart() ? fmt::format("the equilibrium has {} coordinates; the {}-link chain on a "
                                   "cart needs {} (the cart's position, then the angles)",
                                   angles.size(), c.links(), n)
                     : fmt::format("the equilibrium has {} angles; the {}-link chain needs {}",
                                   angles.size(), n, n));
  if (c.parameters().pivot.moves())
    throw std::invalid_argument(
        "LQR needs a fixed pivot: on a moving one the linearisation depends on time");
  for (const double w : {weights.angle, weights.momentum, weights.torque})
    if (!(w > 0) || !std::isfinite(w))
      throw std::invalid_argument(
          fmt::format("the LQR weights must be positive and finite, got {}", w));
  lqr_design design;
  if (actuated.empty())
    for (int j = 0; j < motors; ++j) design.actuated.push_back(j);
  else
    design.actuated.assign(actuated.begin(), actuated.end());
  std::sort(design.actuated.begin(), design.actuated.end());
  for (std::size_t k = 0; k < design.actuated.size(); ++k) {
    const int j = design.actuated[k];
    if (j < 0 || j >= motors)
      throw std::invalid_argument(
          c.has_cart()
              ? fmt::format("actuator {} does not exist: the chain on a cart has actuators "
                            "1..{} (the cart's force, then the joints)",
                            j + 1, motors)
              : fmt::format("joint {} does not exist: the chain has joints 1..{}", j + 1, n));
    if (k > 0 && design.actuated[k - 1] == j)
      throw std::invalid_argument(fmt::format("joint {} is listed twice", j + 1));
  }

  // An equilibrium: ∂V/∂φ = 0 (relative to the size of its terms, gravity's m g l).
  std::vector<double> grad(static_cast<std::size_t>(n));
  c.potential_gradient(angles, grad);
  double scale = c.parameters().g;
  for (int i = 0; i < c.links(); ++i)
    scale = std::max(scale, c.parameters().g * c.parameters().masses[static_cast<std::size_t>(i)] *
                                c.parameters().lengths[static_cast<std::size_t>(i)]);
  for (int i = 0; i < n; ++i)
    if (std::fabs(grad[static_cast<std::size_t>(i)]) > 1e-9 * scale)
      throw std::invalid_argument(
          fmt::format("the angles are not an equilibrium: dV/dphi_{} = {:.3g} (it must vanish)",
                      i + 1, grad[static_cast<std::size_t>(i)]));

  design.equilibrium.assign(angles.begin(), angles.end());
  design.equilibrium.resize(static_cast<std::size_t>(d), 0.0);
  const int m = static_cast<int>(design.actuated.size()), inputs = c.input_size();
  design.A = c.jacobian(design.equilibrium);
  std::vector<double> dfdw(static_cast<std::size_t>(d * inputs));
  c.input_matrix(angles, dfdw);
  design.B.resize(static_cast<std::size_t>(d * m));
  for (int i = 0; i < d; ++i)
    for (int k = 0; k < m; ++k)
      design.B[static_cast<std::size_t>(i * m + k)] = dfdw[static_cast<std::size_t>(
          i * inputs + c.actuator_input(design.actuated[static_cast<std::size_t>(k)]))];

  const Eigen::MatrixXd A = Eigen::Map<const row_major>(design.A.data(), d, d);
  const Eigen::MatrixXd B = Eigen::Map<const row_major>(design.B.data(), d, m);
  design.open_loop = eigenvalues_by_real_part(A);
  design.uncontrollable = uncontrollable_modes(A, B);
  design.controllable = design.uncontrollable.empty();
  for (const auto& lambda : design.uncontrollable)
    if (lambda.real() >= 0)
      throw std::invalid_argument(
          fmt::format("the equilibrium cannot be stabilised from {} {}: its mode with eigenvalue "
                      "{:.6g}{:+.6g}i is unstable and not controllable",
                      c.has_cart() ? "actuators" : "joints", joint_list(design.actuated),
                      lambda.real(), lambda.imag()));

  Eigen::VectorXd q(d);
  q.head(n).setConstant(weights.angle);
  q.tail(n).setConstant(weights.momentum);
  const Eigen::MatrixXd Q = q.asDiagonal();
  const Eigen::MatrixXd G = B * B.transpose() / weights.torque;
  const Eigen::MatrixXd X = solve_riccati(A, G, Q, design.riccati_rcond);
  const Eigen::MatrixXd K = B.transpose() * X / weights.torque;

  design.riccati.resize(static_cast<std::size_t>(d * d));
  Eigen::Map<row_major>(design.riccati.data(), d, d) = X;
  design.gain.resize(static_cast<std::size_t>(m * d));
  Eigen::Map<row_major>(design.gain.data(), m, d) = K;
  // Relative to the size of the equation's terms (a backward-error measure): Q alone would
  // flatter well-scaled designs and condemn the large X of an underactuated one.
  design.riccati_residual = (A.transpose() * X + X * A - X * G * X + Q).norm() /
                            (2 * A.norm() * X.norm() + G.norm() * X.squaredNorm() + Q.norm());
  design.closed_loop = eigenvalues_by_real_part(A - B * K);
  return design;
}

std::vector<double> feedback_rhs::torques(std::span<const double> x) const {
  const int d = m_chain->state_size();
  const int m = static_cast<int>(m_design->actuated.size());
  std::vector<double> u(static_cast<std::size_t>(m_chain->actuators()), 0.0);
  for (int k = 0; k < m; ++k) {
    double s = 0;
    for (int j = 0; j < d; ++j)
      s += m_design->gain[static_cast<std::size_t>(k * d + j)] *
           (x[static_cast<std::size_t>(j)] - m_design->equilibrium[static_cast<std::size_t>(j)]);
    u[static_cast<std::size_t>(m_design->actuated[static_cast<std::size_t>(k)])] = -s;
  }
  return u;
}

void feedback_rhs::operator()(const std::vector<double>& x, std::vector<double>& dxdt,
                              double t) const {
  m_chain->rhs(x, dxdt, t, torques(x));
}

void feedback_jacobian::operator()(const std::vector<double>& x, row_major& J, double t,
                                   std::vector<double>& dfdt) const {
  const int n = m_chain->coordinates(), d = m_chain->state_size(), inputs = m_chain->input_size();
  const int m = static_cast<int>(m_design->actuated.size());
  const std::vector<double> u = feedback_rhs(*m_chain, *m_design).torques(x);
  m_chain->jacobian(x, std::span<double>(J.data(), static_cast<std::size_t>(d * d)), t, u);
  // d/dx of f(x, u(x)) = ∂f/∂x + ∂f/∂u ∂u/∂x, with ∂u/∂x = −K on the actuated joints.
  std::vector<double> dfdw(static_cast<std::size_t>(d * inputs));
  m_chain->input_matrix(std::span<const double>(x).first(static_cast<std::size_t>(n)), dfdw);
  for (int i = 0; i < d; ++i)
    for (int k = 0; k < m; ++k) {
      const double b = dfdw[static_cast<std::size_t>(
          i * inputs + m_chain->actuator_input(m_design->actuated[static_cast<std::size_t>(k)]))];
      if (b == 0.0) continue;
      for (int j = 0; j < d; ++j)
        J(i, j) -= b * m_design->gain[static_cast<std::size_t>(k * d + j)];
    }
  m_chain->time_derivative(x, dfdt, t);
}

integration_result integrate_under_feedback(const chain& c, const lqr_design& design,
                                            std::span<const double> x0,
                                            const integration_options& options,
                                            const observer_function& observer,
                                            const step_observer_function& step_observer) {
  return integrate_system(make_feedback_system(c, design), x0, options, observer, step_observer);
}

}  // namespace npend
