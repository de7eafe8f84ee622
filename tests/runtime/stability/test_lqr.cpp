// LQR at the standing chain: the Riccati solution against the Hamiltonian matrix's stable
// eigenvalues and the optimal cost, and the nonlinear chain caught by the feedback.
#include <doctest/doctest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numbers>

#include "npend/analysis/stability/lqr.hpp"
#include "npend/integrators/integrate_system.hpp"

using npend::chain;
using npend::chain_parameters;

namespace {

constexpr double pi = std::numbers::pi;
using row_major = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

Eigen::MatrixXd matrix(const std::vector<double>& v, Eigen::Index rows, Eigen::Index cols) {
  return Eigen::Map<const row_major>(v.data(), rows, cols);
}

// The largest deviation from upright after t_end seconds under the design's feedback.
double deviation_after(const chain& c, const npend::lqr_design& d, std::vector<double> x0,
                       double t_end) {
  npend::integration_options o;
  o.stepper = npend::stepper_kind::gauss6;
  o.t_end = t_end;
  o.dt = 1e-3;
  const auto r = npend::integrate_system(npend::make_feedback_system(c, d), x0, o);
  double dev = 0;
  for (std::size_t i = 0; i < r.state.size(); ++i)
    dev = std::max(dev, std::fabs(r.state[i] - d.equilibrium[i]));
  return dev;
}

}  // namespace

TEST_CASE("lqr: the standing triple pendulum with motors at all joints") {
  const chain c(chain_parameters::uniform(3));
  const std::vector<double> up{pi, pi, pi};
  const npend::lqr_design d = npend::lqr(c, up);
  const int n = 3, dim = 6;
  REQUIRE(d.controllable);
  CHECK(d.riccati_residual < 1e-13);
  CHECK(d.open_loop.front().real() > 1.0);  // the standing chain is unstable
  for (const auto& l : d.closed_loop) CHECK(l.real() < 0);

  // Independent of SLICOT: the closed-loop eigenvalues are the stable half of the
  // Hamiltonian matrix [[A, −B R⁻¹ Bᵀ], [−Q, −Aᵀ]] (R = 1, Q = diag(10, 10, 10, 1, 1, 1)).
  const Eigen::MatrixXd A = matrix(d.A, dim, dim), B = matrix(d.B, dim, n);
  Eigen::VectorXd q(dim);
  q << 10, 10, 10, 1, 1, 1;
  Eigen::MatrixXd H(2 * dim, 2 * dim);
  H << A, -B * B.transpose(), -Eigen::MatrixXd(q.asDiagonal()), -A.transpose();
  const Eigen::VectorXcd hev = H.eigenvalues();
  std::vector<std::complex<double>> stable;
  for (Eigen::Index i = 0; i < hev.size(); ++i)
    if (hev(i).real() < 0) stable.push_back(hev(i));
  REQUIRE(stable.size() == 6);
  for (const auto& l : d.closed_loop) {
    double nearest = 1e300;
    for (const auto& s : stable) nearest = std::min(nearest, std::abs(s - l));
    CHECK(nearest < 1e-8 * (1 + std::abs(l)));
  }

  // The optimal cost from x0 is x0ᵀ X x0: integrate xᵀQx + uᵀRu along the linear closed loop.
  const Eigen::MatrixXd K = matrix(d.gain, n, dim), X = matrix(d.riccati, dim, dim);
  const Eigen::MatrixXd closed = A - B * K;
  Eigen::VectorXd x(dim);
  x << 0.05, -0.03, 0.02, 0.01, 0.0, -0.02;
  const double predicted = x.dot(X * x);
  double cost = 0;
  const double h = 1e-3;
  auto integrand = [&](const Eigen::VectorXd& s) {
    const Eigen::VectorXd u = -K * s;
    return s.dot(q.asDiagonal() * s) + u.dot(u);
  };
  for (int k = 0; k < 60000; ++k) {  // 60 s: the slowest closed-loop mode has decayed
    const Eigen::VectorXd k1 = closed * x, k2 = closed * (x + h / 2 * k1),
                          k3 = closed * (x + h / 2 * k2), k4 = closed * (x + h * k3);
    const Eigen::VectorXd next = x + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
    cost += h / 6 *
            (integrand(x) + 4 * integrand(x + h / 2 * k1 + h / 8 * (k2 - k1)) + integrand(next));
    x = next;
  }
  CHECK(cost == doctest::Approx(predicted).epsilon(1e-5));
}

TEST_CASE("lqr: the nonlinear standing triple pendulum started 0.1 rad off returns upright") {
  const chain c(chain_parameters::uniform(3));
  const npend::lqr_design d = npend::lqr(c, std::vector<double>{pi, pi, pi});
  const std::vector<double> x0{pi + 0.1, pi + 0.1, pi + 0.1, 0, 0, 0};
  CHECK(deviation_after(c, d, x0, 20.0) < 1e-6);
}

TEST_CASE(
    "lqr: a motor at the first joint alone (underactuated) still controls the standing "
    "triple pendulum") {
  const chain c(chain_parameters::uniform(3));
  const std::vector<int> base{0};
  const npend::lqr_design d = npend::lqr(c, std::vector<double>{pi, pi, pi}, base);
  CHECK(d.controllable);
  CHECK(d.gain.size() == 6);
  CHECK(d.riccati_residual < 1e-13);
  for (const auto& l : d.closed_loop) CHECK(l.real() < 0);
  const std::vector<double> x0{pi + 0.01, pi - 0.01, pi + 0.01, 0, 0, 0};
  CHECK(deviation_after(c, d, x0, 30.0) < 1e-6);
}

TEST_CASE("lqr: refuses what is not an equilibrium or not stabilisable") {
  const chain c(chain_parameters::uniform(2));
  CHECK_THROWS_WITH_AS(npend::lqr(c, std::vector<double>{1.0, pi}),
                       doctest::Contains("not an equilibrium"), std::invalid_argument);
  chain_parameters driven = chain_parameters::uniform(1);
  driven.pivot = npend::pivot_motion::vertical(0.1, 50);
  CHECK_THROWS_WITH_AS(npend::lqr(chain(driven), std::vector<double>{pi}),
                       doctest::Contains("fixed pivot"), std::invalid_argument);
  const std::vector<int> bad{0, 0};
  CHECK_THROWS_WITH_AS(npend::lqr(c, std::vector<double>{pi, pi}, bad),
                       doctest::Contains("listed twice"), std::invalid_argument);
}
