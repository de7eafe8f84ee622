// The pendulum on a cart at run time: the cart-pole's linearisation and LQR against the
// textbook model, the conservation of the total horizontal momentum and of the energy, and
// the power the cart's damping dissipates.
#include <doctest/doctest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "npend/analysis/stability/lqr.hpp"
#include "npend/chain.hpp"
#include "npend/integrators/integrate.hpp"

using npend::chain;
using npend::chain_parameters;

namespace cart_chain_test {

constexpr double pi = std::numbers::pi;
using row_major = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

chain_parameters on_cart(chain_parameters p, double cart_mass, double cart_damping = 0) {
  p.cart_mass = cart_mass;
  p.cart_damping = cart_damping;
  return p;
}

// A point-mass chain of n links with unequal masses and lengths on a cart of mass M.
chain_parameters uneven_cart(int n, double cart_mass, double cart_damping = 0) {
  chain_parameters p = chain_parameters::uniform(n);
  for (int i = 0; i < n; ++i) {
    p.masses[static_cast<std::size_t>(i)] = 0.7 + 0.3 * i;
    p.lengths[static_cast<std::size_t>(i)] = 1.1 - 0.2 * i;
  }
  return on_cart(p, cart_mass, cart_damping);
}

// The test cases stay in the namespace too: the tests are compiled in unity batches, where a
// using-directive would carry these names into the files after this one.

TEST_CASE("chain on a cart: layout of the state, mass matrix and positions") {
  const chain c(uneven_cart(2, 1.5));
  CHECK(c.has_cart());
  CHECK(c.links() == 2);
  CHECK(c.coordinates() == 3);
  CHECK(c.state_size() == 6);
  CHECK(c.actuators() == 3);
  CHECK(c.points() == 3);
  const std::vector<double> q{0.4, 0.3, -0.2};
  std::vector<double> xy(6), A(9);
  c.positions(q, xy);
  // The cart at (x_c, 0), bob k at x_c + Σ l_i sin φ_i, Σ l_i cos φ_i (y down).
  const auto& l = c.parameters().lengths;
  CHECK(xy[0] == doctest::Approx(0.4).epsilon(1e-15));
  CHECK(xy[1] == 0.0);
  CHECK(xy[2] == doctest::Approx(0.4 + l[0] * std::sin(0.3)).epsilon(1e-14));
  CHECK(xy[3] == doctest::Approx(l[0] * std::cos(0.3)).epsilon(1e-14));
  CHECK(xy[4] ==
        doctest::Approx(0.4 + l[0] * std::sin(0.3) + l[1] * std::sin(-0.2)).epsilon(1e-14));
  CHECK(xy[5] == doctest::Approx(l[0] * std::cos(0.3) + l[1] * std::cos(-0.2)).epsilon(1e-14));
  // A_xx is the whole mass that moves with the cart.
  c.mass_matrix(q, A);
  CHECK(A[0] == doctest::Approx(1.5 + 0.7 + 1.0).epsilon(1e-14));
  std::vector<double> too_few(4);
  CHECK_THROWS_AS(c.positions(q, too_few), std::invalid_argument);
}

TEST_CASE("chain on a cart: the upright cart-pole's unstable eigenvalue") {
  // Point mass m on a massless rod l over a cart M: linearised at the top, λ² = g(M + m)/(M l)
  // for the falling mode and λ = 0 twice for the cart's free translation.
  const double m = 0.8, l = 1.3, M = 2.5, g = 9.81;
  const chain c(on_cart(chain_parameters::uniform(1, m, l, g), M));
  const std::vector<double> x{0.0, pi, 0.0, 0.0};
  const Eigen::MatrixXd J = Eigen::Map<const row_major>(c.jacobian(x).data(), 4, 4);
  Eigen::VectorXcd ev = J.eigenvalues();
  std::vector<double> magnitudes;
  for (Eigen::Index i = 0; i < 4; ++i) magnitudes.push_back(std::abs(ev(i)));
  std::sort(magnitudes.begin(), magnitudes.end());
  const double lambda = std::sqrt(g * (M + m) / (M * l));
  CHECK(magnitudes[0] < 1e-6);  // the double zero, split by rounding as √ε
  CHECK(magnitudes[1] < 1e-6);
  CHECK(magnitudes[2] == doctest::Approx(lambda).epsilon(1e-12));
  CHECK(magnitudes[3] == doctest::Approx(lambda).epsilon(1e-12));
}

TEST_CASE("lqr: the cart-pole pushed at the cart against the textbook model") {
  const double m = 0.8, l = 1.3, M = 2.5, g = 9.81;
  const chain c(on_cart(chain_parameters::uniform(1, m, l, g), M));
  const std::vector<double> up{0.0, pi};
  const std::vector<int> cart_only{0};
  const npend::lqr_design d = npend::lqr(c, up, cart_only);
  REQUIRE(d.controllable);
  for (const auto& s : d.closed_loop) CHECK(s.real() < 0);
  // The force enters ṗ_x alone: p_x is the canonical momentum of x_c, F its generalised force.
  CHECK(d.B == std::vector<double>{0, 0, 1, 0});

  // The textbook model in z = (x, φ, ẋ, φ̇) at φ = π: M₀ z̈ = −K₀ z + (F, 0) with
  // M₀ = [[M + m, −m l], [−m l, m l²]] and K₀ = diag(0, −m g l). The design's feedback
  // u = −K x with x = (q, p), p = M₀ q̇ to first order, must give the same closed loop.
  Eigen::Matrix2d M0, K0;
  M0 << M + m, -m * l, -m * l, m * l * l;
  K0 << 0, 0, 0, -m * g * l;
  Eigen::Matrix4d At = Eigen::Matrix4d::Zero();
  At.topRightCorner<2, 2>() = Eigen::Matrix2d::Identity();
  At.bottomLeftCorner<2, 2>() = -M0.inverse() * K0;
  Eigen::Vector4d Bt = Eigen::Vector4d::Zero();
  Bt.tail<2>() = M0.inverse() * Eigen::Vector2d(1, 0);
  Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
  T.bottomRightCorner<2, 2>() = M0;
  const Eigen::RowVector4d K = Eigen::Map<const Eigen::RowVector4d>(d.gain.data());
  const Eigen::Vector4cd textbook = (At - Bt * K * T).eigenvalues();
  // The open loop: λ² (λ² − g(M + m)/(M l)).
  CHECK(d.open_loop.front().real() ==
        doctest::Approx(std::sqrt(g * (M + m) / (M * l))).epsilon(1e-12));
  for (const auto& s : d.closed_loop) {
    double nearest = 1e300;
    for (Eigen::Index i = 0; i < 4; ++i) nearest = std::min(nearest, std::abs(textbook(i) - s));
    CHECK(nearest < 1e-9 * (1 + std::abs(s)));
  }
}

TEST_CASE("chain on a cart: total horizontal momentum and energy conserved") {
  const chain c(uneven_cart(2, 1.5));
  const std::vector<double> x0{0.1, 1.2, -0.7, 0.4, 0.3, -0.2};
  // p_x is the total horizontal momentum M ẋ + Σ m_k ẋ_k, with ẋ_k = ẋ + Σ_{i≤k} l_i cos φ_i φ̇_i.
  std::vector<double> dq(3);
  c.velocities(std::span(x0).first(3), std::span(x0).subspan(3), dq);
  const auto& ms = c.parameters().masses;
  const auto& ls = c.parameters().lengths;
  double momentum = 1.5 * dq[0], bob_rate = dq[0];
  for (int k = 0; k < 2; ++k) {
    bob_rate += ls[static_cast<std::size_t>(k)] * std::cos(x0[static_cast<std::size_t>(1 + k)]) *
                dq[static_cast<std::size_t>(1 + k)];
    momentum += ms[static_cast<std::size_t>(k)] * bob_rate;
  }
  CHECK(momentum == doctest::Approx(x0[3]).epsilon(1e-14));

  npend::integration_options o;
  o.stepper = npend::stepper_kind::gauss6;
  o.t_end = 5;
  o.dt = 1e-3;
  const auto r = npend::integrate(c, x0, o);
  // ṗ_x = −∂H/∂x_c = 0 exactly: only rounding moves it.
  CHECK(std::fabs(r.state[3] - x0[3]) < 1e-12);
  const double h0 = c.hamiltonian(x0);
  CHECK(std::fabs(c.hamiltonian(r.state) - h0) < 1e-10 * std::fabs(h0));
}

TEST_CASE("chain on a cart: the cart's damping dissipates b_x ẋ²") {
  const double b = 0.6;
  const chain c(uneven_cart(2, 1.5, b));
  const std::vector<double> x{0.1, 1.2, -0.7, 0.4, 0.3, -0.2};
  std::vector<double> f(6), dq(3);
  c.rhs(x, f);
  c.velocities(std::span(x).first(3), std::span(x).subspan(3), dq);
  // dH/dt = ∇H · f along the flow, by a central difference.
  const double h = 1e-5;
  std::vector<double> ahead(x), behind(x);
  for (std::size_t i = 0; i < 6; ++i) {
    ahead[i] += h * f[i];
    behind[i] -= h * f[i];
  }
  const double rate = (c.hamiltonian(ahead) - c.hamiltonian(behind)) / (2 * h);
  // Central difference: truncation O(h²), rounding about 1e-16 H / h; both far below 1e-6.
  CHECK(rate == doctest::Approx(-b * dq[0] * dq[0]).epsilon(1e-6));
  CHECK(std::fabs(dq[0]) > 0.01);  // the cart moves: the check means something
  CHECK(c.parameters().is_damped());
}

TEST_CASE("chain_parameters::validate: the cart's refusals") {
  auto p = chain_parameters::uniform(2);
  p.cart_mass = 0.0;
  CHECK_THROWS_WITH_AS(p.validate(), doctest::Contains("cart mass is 0"), std::invalid_argument);
  p.cart_mass = 1.0;
  p.cart_damping = -1;
  CHECK_THROWS_WITH_AS(p.validate(), doctest::Contains("cart damping is -1"),
                       std::invalid_argument);
  p.cart_mass.reset();
  p.cart_damping = 0.5;
  CHECK_THROWS_WITH_AS(p.validate(), doctest::Contains("cart damping needs a cart"),
                       std::invalid_argument);
  p.cart_damping = 0;
  p.cart_mass = 1.0;
  p.pivot = npend::pivot_motion::vertical(0.01, 100);
  CHECK_THROWS_WITH_AS(p.validate(), doctest::Contains("a cart and a moving pivot"),
                       std::invalid_argument);
}

}  // namespace cart_chain_test
