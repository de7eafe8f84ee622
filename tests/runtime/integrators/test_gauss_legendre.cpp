// The Gauss–Legendre stepper: its tableaux, its order, energy behaviour, reversibility,
// symplecticity, Newton convergence, failure reports, and odeint's integrate functions.
#include <doctest/doctest.h>

#include <algorithm>
#include <boost/numeric/odeint/integrate/integrate_const.hpp>
#include <boost/numeric/odeint/integrate/integrate_n_steps.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta4.hpp>
#include <cmath>
#include <functional>

#include "npend/chain_system.hpp"
#include "npend/integrators/gauss_legendre.hpp"
#include "reference/reference_trajectory.hpp"
#include "support/test_support.hpp"

using npend::chain;
using npend::gauss_legendre4;
using npend::gauss_legendre6;

namespace {

using rk4 = boost::numeric::odeint::runge_kutta4<std::vector<double>>;

template <int S>
void check_tableau() {
  using T = npend::detail::gauss_legendre_tableau<S>;
  // Nodes: roots of the shifted Legendre polynomial P_s(2c − 1).
  for (double c : T::c) {
    const double x = 2 * c - 1;
    const double legendre = S == 2 ? (3 * x * x - 1) / 2 : (5 * x * x * x - 3 * x) / 2;
    CHECK(std::fabs(legendre) < 1e-15);
  }
  // B(2s): the quadrature is exact for polynomials of degree < 2s.
  for (int k = 1; k <= 2 * S; ++k) {
    double sum = 0;
    for (int i = 0; i < S; ++i) sum += T::b[i] * std::pow(T::c[i], k - 1);
    CHECK(sum == doctest::Approx(1.0 / k).epsilon(1e-15));
  }
  // C(s): collocation, Σ_j a_ij c_j^{k−1} = c_i^k / k.
  for (int i = 0; i < S; ++i)
    for (int k = 1; k <= S; ++k) {
      double sum = 0;
      for (int j = 0; j < S; ++j) sum += T::a[i][j] * std::pow(T::c[j], k - 1);
      CHECK(std::fabs(sum - std::pow(T::c[i], k) / k) < 1e-16);
    }
  // Symplecticity: b_i a_ij + b_j a_ji = b_i b_j.
  for (int i = 0; i < S; ++i)
    for (int j = 0; j < S; ++j)
      CHECK(std::fabs(T::b[i] * T::a[i][j] + T::b[j] * T::a[j][i] - T::b[i] * T::b[j]) < 1e-16);
}

// A moderately excited state (regular motion over a few seconds).
std::vector<double> moderate_state(int n) {
  std::vector<double> x;
  for (int i = 0; i < n; ++i) x.push_back(0.6 * (i % 2 == 0 ? 1 : -1) / (i + 1));
  for (int i = 0; i < n; ++i) x.push_back(0.3 * (i + 1));
  return x;
}

template <class Stepper>
std::vector<double> run(const chain& c, std::vector<double> x, double dt, int steps) {
  Stepper stepper;
  const auto system = npend::make_implicit_system(c);
  for (int k = 0; k < steps; ++k) {
    if constexpr (std::is_same_v<Stepper, rk4>)
      stepper.do_step(system.first, x, k * dt, dt);
    else
      stepper.do_step(system, x, k * dt, dt);
  }
  return x;
}

// Least-squares slope of log(error) against log(dt).
double slope(const std::vector<double>& dts, const std::vector<double>& errors) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const double m = static_cast<double>(dts.size());
  for (std::size_t i = 0; i < dts.size(); ++i) {
    const double x = std::log(dts[i]), y = std::log(errors[i]);
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
  }
  return (m * sxy - sx * sy) / (m * sxx - sx * sx);
}

// max |H(t) − H(0)| / |H(0)| over the first `steps` steps, and over the first tenth.
template <class Stepper>
std::pair<double, double> energy_errors(const chain& c, std::vector<double> x, double dt,
                                        int steps) {
  Stepper stepper;
  const auto system = npend::make_implicit_system(c);
  const double h0 = c.hamiltonian(x);
  double all = 0, first_tenth = 0;
  for (int k = 0; k < steps; ++k) {
    if constexpr (std::is_same_v<Stepper, rk4>)
      stepper.do_step(system.first, x, k * dt, dt);
    else
      stepper.do_step(system, x, k * dt, dt);
    all = std::max(all, std::fabs(c.hamiltonian(x) - h0) / h0);
    if (k < steps / 10) first_tenth = all;
  }
  return {all, first_tenth};
}

// M = ∂Φ/∂x of the map Φ = `steps` steps of size h, by central differences with one
// Richardson step (truncation O(δ⁴)): accurate to ~1e-11 here.
template <class Stepper>
Eigen::MatrixXd flow_jacobian(const chain& c, const std::vector<double>& x, double h, int steps) {
  const int d = c.state_size();
  Eigen::MatrixXd M(d, d);
  const auto central = [&](int k, double delta) -> Eigen::VectorXd {
    std::vector<double> xp = x, xm = x;
    xp[static_cast<std::size_t>(k)] += delta;
    xm[static_cast<std::size_t>(k)] -= delta;
    return (npend::test::to_eigen(run<Stepper>(c, xp, h, steps)) -
            npend::test::to_eigen(run<Stepper>(c, xm, h, steps))) /
           (2 * delta);
  };
  const double delta = 1e-3;
  for (int k = 0; k < d; ++k) M.col(k) = (4 * central(k, delta / 2) - central(k, delta)) / 3;
  return M;
}

double symplecticity_defect(const Eigen::MatrixXd& M) {
  const auto n = M.rows() / 2;
  Eigen::MatrixXd omega = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  omega.topRightCorner(n, n) = Eigen::MatrixXd::Identity(n, n);
  omega.bottomLeftCorner(n, n) = -Eigen::MatrixXd::Identity(n, n);
  return (M.transpose() * omega * M - omega).cwiseAbs().maxCoeff();
}

}  // namespace

TEST_CASE("gauss_legendre tableau: Legendre nodes, order and collocation conditions, symplectic") {
  check_tableau<2>();
  check_tableau<3>();
}

TEST_CASE("gauss_legendre: measured order of convergence is 4 and 6") {
  std::mt19937_64 rng(21);
  const npend::chain_parameters params = npend::test::random_parameters(3, rng);
  const chain c(params);
  const auto x0 = moderate_state(3);
  const double T = 2.0;
  const auto exact =
      npend::reference::reference_trajectory(npend::reference::dense_chain_of(params), x0, {T})
          .front();
  const auto measure = [&](auto stepper_tag, const std::vector<double>& dts) {
    using stepper = typename decltype(stepper_tag)::type;
    std::vector<double> errors;
    for (double dt : dts) {
      const int steps = static_cast<int>(std::lround(T / dt));
      errors.push_back(npend::test::relative_error(run<stepper>(c, x0, dt, steps), exact));
    }
    return errors;
  };
  // Step sizes in the asymptotic range: from the largest to the smallest the errors fall by
  // ~16 resp. ~64 per halving, and the smallest stay far above the reference's ~1e-13.
  const std::vector<double> dts4{0.02, 0.01, 0.005, 0.0025};
  const auto errors4 = measure(std::type_identity<gauss_legendre4>{}, dts4);
  const std::vector<double> dts6{0.02, 0.01, 0.005};
  const auto errors6 = measure(std::type_identity<gauss_legendre6>{}, dts6);
  INFO("gauss4 errors ", errors4[0], " ", errors4[1], " ", errors4[2], " ", errors4[3]);
  INFO("gauss6 errors ", errors6[0], " ", errors6[1], " ", errors6[2]);
  CHECK(errors4.back() > 1e-11);
  CHECK(errors6.back() > 1e-12);
  CHECK(slope(dts4, errors4) == doctest::Approx(4).epsilon(0.05));
  CHECK(slope(dts6, errors6) == doctest::Approx(6).epsilon(0.05));
}

TEST_CASE("gauss_legendre: the energy error stays bounded where rk4's drifts") {
  const chain c(npend::chain_parameters::uniform(3));
  // Regular motion, 10⁵ steps of dt = 0.01 (t = 1000 s): a symplectic method's error
  // oscillates at a fixed level, so its maximum over the whole run is hardly larger than
  // over the first tenth; rk4's grows with t.
  const auto x0 = moderate_state(3);
  const auto [gl4_all, gl4_tenth] = energy_errors<gauss_legendre4>(c, x0, 0.01, 100000);
  const auto [rk4_all, rk4_tenth] = energy_errors<rk4>(c, x0, 0.01, 100000);
  INFO("gauss4: ", gl4_tenth, " -> ", gl4_all, "; rk4: ", rk4_tenth, " -> ", rk4_all);
  CHECK(gl4_all < 1.5 * gl4_tenth);
  CHECK(rk4_all > 5 * rk4_tenth);
  CHECK(gl4_all < rk4_all);
}

TEST_CASE(
    "gauss_legendre: chaotic triple pendulum keeps |dH/H| < 1e-10 with order 6 at dt = 1e-3") {
  const chain c(npend::chain_parameters::uniform(3));
  const std::vector<double> x0{1.5, 1.5, 1.5, 0, 0, 0};  // the benchmark's start
  const auto [gl6, gl6_tenth] = energy_errors<gauss_legendre6>(c, x0, 1e-3, 100000);
  const auto [rk4_all, rk4_tenth] = energy_errors<rk4>(c, x0, 1e-3, 100000);
  INFO("gauss6 ", gl6, ", rk4 ", rk4_all, " over 100 s");
  CHECK(gl6 < 1e-10);
  CHECK(rk4_all > 10 * gl6);
}

TEST_CASE(
    "gauss_legendre: the Newton iteration leaves no drift, weak motion keeps |dH/H| at round-off") {
  // Small zigzag oscillations for 60 s at dt = 1e-3: the method's own energy error is ~1e-15
  // here, so what shows is what the Newton iteration leaves behind. Stopped at a relative
  // error of one rounding unit per step, the leftover adds up (it is smooth along the
  // trajectory) to ~1e-11; iterated to round-off it stays at the rounding level.
  const chain c(npend::chain_parameters::uniform(3));
  std::vector<double> x{0.1828, -0.1828, 0.1828, 0, 0, 0};
  const auto system = npend::make_implicit_system(c);
  const double h0 = c.hamiltonian(x), dt = 1e-3;
  gauss_legendre6 stepper;
  double worst = 0;
  for (int k = 0; k < 60000; ++k) {
    stepper.do_step(system, x, k * dt, dt);
    worst = std::max(worst, std::fabs(c.hamiltonian(x) - h0) / h0);
  }
  INFO("max |dH/H| ", worst);
  CHECK(worst < 1e-13);
}

TEST_CASE("gauss_legendre: forward then backward returns to the start (symmetric method)") {
  std::mt19937_64 rng(22);
  const chain c(npend::test::random_parameters(3, rng));
  const auto x0 = moderate_state(3);
  const double dt = 0.01;
  const int steps = 200;
  const auto back = [&](auto stepper_tag) {
    using stepper = typename decltype(stepper_tag)::type;
    const auto there = run<stepper>(c, x0, dt, steps);
    return npend::test::relative_error(run<stepper>(c, there, -dt, steps), x0);
  };
  const double gl4 = back(std::type_identity<gauss_legendre4>{});
  const double gl6 = back(std::type_identity<gauss_legendre6>{});
  const double rk = back(std::type_identity<rk4>{});
  INFO("gauss4 ", gl4, ", gauss6 ", gl6, ", rk4 ", rk);
  // Round-off only (a few units in the last place over 2 × 200 steps).
  CHECK(gl4 < 1e-13);
  CHECK(gl6 < 1e-13);
  CHECK(rk > 1e-8);  // not symmetric: the test tells the difference
}

TEST_CASE("gauss_legendre: the numerical flow is symplectic, M^T Omega M = Omega") {
  std::mt19937_64 rng(23);
  for (int n : {2, 3}) {
    const chain c(npend::test::random_parameters(n, rng));
    const auto x = npend::test::random_state(n, rng, 1.0);
    const double h = 0.05;
    for (int steps : {1, 5}) {
      const double gl4 = symplecticity_defect(flow_jacobian<gauss_legendre4>(c, x, h, steps));
      const double gl6 = symplecticity_defect(flow_jacobian<gauss_legendre6>(c, x, h, steps));
      const double rk = symplecticity_defect(flow_jacobian<rk4>(c, x, h, steps));
      INFO("n = ", n, ", ", steps, " steps of h = ", h, ": gauss4 ", gl4, ", gauss6 ", gl6,
           ", rk4 ", rk);
      CHECK(gl4 < 1e-10);
      CHECK(gl6 < 1e-10);
      CHECK(rk > 1e-8);  // rk4 is not symplectic: the test tells the difference
    }
  }
}

TEST_CASE("gauss_legendre: converges to the same stage values whatever the Newton matrix") {
  const chain c(npend::chain_parameters::uniform(3));
  const auto system = npend::make_implicit_system(c);
  std::vector<double> reused{1.5, 1.5, 1.5, 0, 0, 0}, fresh = reused;
  gauss_legendre6 a, b;
  const double dt = 1e-3;
  for (int k = 0; k < 100; ++k) {
    a.do_step(system, reused, k * dt, dt);  // extrapolated start, Newton matrix kept
    b.reset();                              // Z = 0 start, matrix factored at x every step
    b.do_step(system, fresh, k * dt, dt);
  }
  // Equal to round-off (bit for bit over the first steps; the chaotic flow then amplifies
  // the last bits).
  INFO("difference ", npend::test::relative_error(reused, fresh));
  CHECK(npend::test::relative_error(reused, fresh) < 1e-13);
  // Work: a few iterations per step, the matrix reused over many steps.
  const auto& s = a.statistics();
  CHECK(s.steps == 100);
  CHECK(static_cast<double>(s.newton_iterations) / static_cast<double>(s.steps) < 4);
  CHECK(s.factorizations < s.steps / 10);
  CHECK(b.statistics().factorizations == 100);
}

TEST_CASE("gauss_legendre: a long chain keeps its Newton matrix over many steps (O(d^2) steps)") {
  // 40 links (d = 80): factoring the 240 x 240 Newton matrix costs as much as ~80 iterations,
  // so an old matrix is kept while it contracts at all well. The stages are the same as with
  // a matrix factored afresh at every step; only the work differs.
  const chain c(npend::chain_parameters::uniform(40, 1.0 / 40, 1.0 / 40));
  const auto system = npend::make_implicit_system(c);
  std::vector<double> reused(80, 0.0);
  std::fill(reused.begin(), reused.begin() + 40, 0.5);
  std::vector<double> fresh = reused;
  const double energy = c.hamiltonian(reused);
  gauss_legendre6 a, b;
  const double dt = 1e-3;
  constexpr int steps = 150;
  for (int k = 0; k < steps; ++k) {
    a.do_step(system, reused, k * dt, dt);
    b.reset();
    b.do_step(system, fresh, k * dt, dt);
  }
  INFO("difference ", npend::test::relative_error(reused, fresh));
  CHECK(npend::test::relative_error(reused, fresh) < 1e-12);
  CHECK(std::fabs(c.hamiltonian(reused) - energy) < 1e-13 * energy);
  const auto& s = a.statistics();
  INFO("factorizations ", s.factorizations, ", iterations ", s.newton_iterations);
  CHECK(s.factorizations <= steps / 10);
  CHECK(static_cast<double>(s.newton_iterations) / steps < 20);
  CHECK(b.statistics().factorizations == steps);
}

TEST_CASE("gauss_legendre: odeint's integrate_const and integrate_n_steps drive it") {
  namespace odeint = boost::numeric::odeint;
  const chain c(npend::chain_parameters::uniform(2));
  const auto system = npend::make_implicit_system(c);
  const std::vector<double> x0{0.4, -0.3, 0.2, 0.1};
  const auto manual = run<gauss_legendre6>(c, x0, 0.01, 100);

  gauss_legendre6 stepper;
  std::vector<double> x = x0;
  int observed = 0;
  const auto steps =
      odeint::integrate_const(std::ref(stepper), system, x, 0.0, 1.0, 0.01,
                              [&](const std::vector<double>&, double) { ++observed; });
  CHECK(steps == 100);
  CHECK(observed == 101);
  CHECK(stepper.statistics().steps == 100);
  CHECK(x == manual);

  std::vector<double> y = x0;
  odeint::integrate_n_steps(gauss_legendre6(), system, y, 0.0, 0.01, 100);
  CHECK(y == manual);
}

TEST_CASE("gauss_legendre: a step it cannot solve throws integration_error with the time") {
  const chain c(npend::chain_parameters::uniform(3));
  const auto system = npend::make_implicit_system(c);
  SUBCASE("a step far too long for the motion") {
    std::vector<double> x{1.5, 1.5, 1.5, 0, 0, 0};
    gauss_legendre4 stepper;
    try {
      for (int k = 0; k < 100; ++k) stepper.do_step(system, x, 2.0 * k, 2.0);
      FAIL("no integration_error");
    } catch (const npend::integration_error& e) {
      const std::string what = e.what();
      INFO(what);
      CHECK(what.find("Gauss-Legendre (order 4) step from t = ") != std::string::npos);
      CHECK(what.find("try a smaller dt") != std::string::npos);
      CHECK(std::fmod(e.time(), 2.0) == 0.0);
    }
  }
  SUBCASE("too few iterations allowed") {
    std::vector<double> x{1.5, 1.5, 1.5, 0, 0, 0};
    gauss_legendre6 stepper(std::numeric_limits<double>::epsilon(), 2);
    CHECK_THROWS_WITH_AS(stepper.do_step(system, x, 0.0, 0.05),
                         doctest::Contains("the iteration limit was reached"),
                         npend::integration_error);
  }
  CHECK_THROWS_AS(gauss_legendre4(0.0), std::invalid_argument);
  CHECK_THROWS_AS(gauss_legendre4(1e-15, 1), std::invalid_argument);
  std::vector<double> x{0.1, 0.1, 0.1, 0, 0, 0};
  gauss_legendre4 stepper;
  CHECK_THROWS_AS(stepper.do_step(system, x, 0.0, 0.0), std::invalid_argument);
}
