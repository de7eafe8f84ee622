// The paper's nonlinear corrections to the harmonic approximation (§6.4.1, §6.4.2): its
// printed double- and triple-pendulum equations, their power-series solution, the correction
// function Q, and the orders in the amplitude that show they are not a consistent cubic
// correction.
#include <doctest/doctest.h>

#include <boost/numeric/odeint/stepper/runge_kutta4.hpp>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "npend/analysis/stability/harmonic_corrections.hpp"
#include "npend/analysis/stability/normal_modes.hpp"
#include "npend/integrators/integrate.hpp"
#include "support/test_support.hpp"

using npend::chain;
using npend::chain_parameters;
using npend::truncation;

using npend::test::max_difference;

namespace {

std::vector<double> random_vector(std::mt19937_64& rng, int n, double scale) {
  std::uniform_real_distribution<double> u(-scale, scale);
  std::vector<double> v;
  for (int i = 0; i < n; ++i) v.push_back(u(rng));
  return v;
}

// max |residual| / (largest term) of equations given as lists of terms.
double relative_residual(const std::vector<std::vector<double>>& equations) {
  double worst = 0;
  for (const auto& terms : equations) {
    double sum = 0, size = 0;
    for (double t : terms) {
      sum += t;
      size = std::max(size, std::fabs(t));
    }
    worst = std::max(worst, std::fabs(sum) / size);
  }
  return worst;
}

double slope(double error_big, double error_small) { return std::log2(error_big / error_small); }

}  // namespace

TEST_CASE("truncated_acceleration: the paper's printed double-pendulum equations (6.4.1)") {
  std::mt19937_64 rng(51);
  for (int s = 0; s < 50; ++s) {
    const auto p = npend::test::random_parameters(2, rng);
    const chain c(p);
    const double m2 = p.masses[1], mu1 = p.masses[0] + m2, l1 = p.lengths[0], l2 = p.lengths[1];
    const double g = p.g;
    const auto phi = random_vector(rng, 2, 0.5), w = random_vector(rng, 2, 2.0);
    for (const truncation kind : {truncation::harmonic, truncation::paper}) {
      const auto a = npend::truncated_acceleration(c, kind, phi, w);
      const double on = kind == truncation::paper ? 1 : 0;
      // μ₁l₁²φ̈₁ + m₂l₁l₂φ̈₂ + μ₁gl₁φ₁ + m₂l₁l₂(φ₁ − φ₂)φ̇₂² = 0
      // l₁l₂φ̈₁ + l₂²φ̈₂ + gl₂φ₂ − l₁l₂(φ₁ − φ₂)φ̇₁² = 0
      CHECK(relative_residual({{mu1 * l1 * l1 * a[0], m2 * l1 * l2 * a[1], mu1 * g * l1 * phi[0],
                                on * m2 * l1 * l2 * (phi[0] - phi[1]) * w[1] * w[1]},
                               {l1 * l2 * a[0], l2 * l2 * a[1], g * l2 * phi[1],
                                -on * l1 * l2 * (phi[0] - phi[1]) * w[0] * w[0]}}) < 1e-13);
    }
  }
}

TEST_CASE("truncated_acceleration: the paper's printed triple-pendulum equations (6.4.2)") {
  std::mt19937_64 rng(52);
  for (int s = 0; s < 50; ++s) {
    const auto p = npend::test::random_parameters(3, rng);
    const chain c(p);
    const double m3 = p.masses[2], mu2 = p.masses[1] + m3, mu1 = p.masses[0] + mu2;
    const double l1 = p.lengths[0], l2 = p.lengths[1], l3 = p.lengths[2], g = p.g;
    const auto f = random_vector(rng, 3, 0.5), w = random_vector(rng, 3, 2.0);
    const auto a = npend::truncated_acceleration(c, truncation::paper, f, w);
    CHECK(relative_residual({{mu1 * l1 * l1 * a[0], mu2 * l1 * l2 * a[1], m3 * l1 * l3 * a[2],
                              mu1 * g * l1 * f[0], mu2 * l1 * l2 * (f[0] - f[1]) * w[1] * w[1],
                              m3 * l1 * l3 * (f[0] - f[2]) * w[2] * w[2]},
                             {mu2 * l1 * l2 * a[0], mu2 * l2 * l2 * a[1], m3 * l2 * l3 * a[2],
                              mu2 * g * l2 * f[1], -mu2 * l1 * l2 * (f[0] - f[1]) * w[0] * w[0],
                              m3 * l2 * l3 * (f[1] - f[2]) * w[2] * w[2]},
                             {l1 * l3 * a[0], l2 * l3 * a[1], l3 * l3 * a[2], g * l3 * f[2],
                              -l1 * l3 * (f[0] - f[2]) * w[0] * w[0],
                              -l2 * l3 * (f[1] - f[2]) * w[1] * w[1]}}) < 1e-13);
  }
}

TEST_CASE("exact_acceleration: solves the exact Euler-Lagrange equations") {
  // Σ_j A_ij φ̈_j + Σ_j μ_max(i,j) l_i l_j sin(φ_i − φ_j) φ̇_j² + μ_i g l_i sin φ_i = 0 with
  // A_ij = μ_max(i,j) l_i l_j cos(φ_i − φ_j), μ_j = m_j + … + m_n (docs/paper.md, conventions).
  std::mt19937_64 rng(53);
  for (int n = 1; n <= 5; ++n) {
    const auto p = npend::test::random_parameters(n, rng);
    const chain c(p);
    std::vector<double> mu(static_cast<std::size_t>(n));
    for (int j = n - 1; j >= 0; --j)
      mu[static_cast<std::size_t>(j)] = p.masses[static_cast<std::size_t>(j)] +
                                        (j + 1 < n ? mu[static_cast<std::size_t>(j + 1)] : 0);
    const auto f = random_vector(rng, n, 2.0), w = random_vector(rng, n, 2.0);
    const auto a = npend::exact_acceleration(c, f, w);
    std::vector<std::vector<double>> equations;
    for (std::size_t i = 0; i < static_cast<std::size_t>(n); ++i) {
      std::vector<double> terms{mu[i] * p.g * p.lengths[i] * std::sin(f[i])};
      for (std::size_t j = 0; j < static_cast<std::size_t>(n); ++j) {
        const double coupling = mu[std::max(i, j)] * p.lengths[i] * p.lengths[j];
        terms.push_back(coupling * std::cos(f[i] - f[j]) * a[j]);
        terms.push_back(coupling * std::sin(f[i] - f[j]) * w[j] * w[j]);
      }
      equations.push_back(terms);
    }
    CHECK(relative_residual(equations) < 1e-12);
  }
}

TEST_CASE("truncated_acceleration: the paper's correction is not a consistent cubic one") {
  // The error of the truncated φ̈ against the exact one at a start scaled by ε: O(ε³) for the
  // harmonic and for the paper's equations — the paper's velocity terms leave other terms of
  // the same order out — and O(ε⁵) once every cubic term is in.
  std::mt19937_64 rng(54);
  const chain c(npend::test::random_parameters(3, rng));
  const auto f = random_vector(rng, 3, 1.0), w = random_vector(rng, 3, 3.0);
  const auto defect = [&](truncation kind, double eps) {
    std::vector<double> fe = f, we = w;
    for (auto& v : fe) v *= eps;
    for (auto& v : we) v *= eps;
    return max_difference(npend::truncated_acceleration(c, kind, fe, we),
                          npend::exact_acceleration(c, fe, we));
  };
  const double eps = 0.01;
  CHECK(slope(defect(truncation::harmonic, eps), defect(truncation::harmonic, eps / 2)) ==
        doctest::Approx(3).epsilon(0.01));
  CHECK(slope(defect(truncation::paper, eps), defect(truncation::paper, eps / 2)) ==
        doctest::Approx(3).epsilon(0.01));
  CHECK(slope(defect(truncation::cubic, eps), defect(truncation::cubic, eps / 2)) ==
        doctest::Approx(5).epsilon(0.02));
  // The paper's defect does not become small against the harmonic one as ε → 0.
  CHECK(defect(truncation::paper, 1e-3) > 0.1 * defect(truncation::harmonic, 1e-3));
}

TEST_CASE("second_order_series: the paper's power series agrees with its equations to O(t^3)") {
  std::mt19937_64 rng(55);
  const chain c(npend::test::random_parameters(2, rng));
  const std::vector<double> f{0.3, -0.2}, w{1.0, 0.5};
  const auto series = npend::second_order_series(c, truncation::paper, f, w);
  CHECK(series.angles(0) == f);
  CHECK(series.rates(0) == w);
  // The paper's equations integrated by RK4 with tiny steps to t and 2t.
  const auto integrated = [&](double t) {
    std::vector<double> y{f[0], f[1], w[0], w[1]};
    boost::numeric::odeint::runge_kutta4<std::vector<double>> rk4;
    const auto rhs = [&](const std::vector<double>& x, std::vector<double>& dx, double) {
      const auto a = npend::truncated_acceleration(c, truncation::paper, std::span(x).first(2),
                                                   std::span(x).subspan(2));
      dx = {x[2], x[3], a[0], a[1]};
    };
    for (int k = 0; k < 1000; ++k) rk4.do_step(rhs, y, k * t / 1000, t / 1000);
    return std::vector<double>{y[0], y[1]};
  };
  const double t = 0.01;
  const double e1 = max_difference(series.angles(t), integrated(t));
  const double e2 = max_difference(series.angles(2 * t), integrated(2 * t));
  CHECK(slope(e2, e1) == doctest::Approx(3).epsilon(0.02));
}

TEST_CASE("correction_function: Q = phi1 phi2 / (dphi1 dphi2)") {
  CHECK(npend::correction_function(std::vector<double>{0.2, 0.3}, std::vector<double>{2, 3}) ==
        doctest::Approx(0.01).epsilon(1e-15));
  CHECK(std::isnan(
      npend::correction_function(std::vector<double>{0.2, 0.3, 1}, std::vector<double>{0, 3, 1})));
  CHECK_THROWS_AS(npend::correction_function(std::vector<double>{0.2}, std::vector<double>{1}),
                  std::invalid_argument);
}

TEST_CASE("harmonic_correction_study: each approximation's order in the amplitude") {
  const chain c(chain_parameters::uniform(3));
  const std::vector<double> f{0.3, -0.3, 0.3}, w{0.6, 0.6, 0.6};
  const auto s = npend::harmonic_correction_study(c, f, w);
  REQUIRE(s.tracks.size() == 5);
  REQUIRE(s.t.size() == 201);
  // Default horizon: a quarter of the shortest linear period.
  const double omega3 = npend::normal_modes(c, std::vector<double>(3, 0.0)).modes[2].frequency;
  CHECK(s.horizon == doctest::Approx(0.25 * 2 * std::numbers::pi / omega3).epsilon(1e-15));
  // The harmonic solution is the exact solution of the harmonic equations: the truncation
  // `harmonic` integrated independently must give it.
  {
    std::vector<double> y{f[0], f[1], f[2], w[0], w[1], w[2]};
    boost::numeric::odeint::runge_kutta4<std::vector<double>> rk4;
    const auto rhs = [&](const std::vector<double>& x, std::vector<double>& dx, double) {
      const auto a = npend::truncated_acceleration(c, truncation::harmonic, std::span(x).first(3),
                                                   std::span(x).subspan(3));
      dx = {x[3], x[4], x[5], a[0], a[1], a[2]};
    };
    const int steps = 2000;
    for (int k = 0; k < steps; ++k) rk4.do_step(rhs, y, k * s.horizon / steps, s.horizon / steps);
    CHECK(max_difference({y[0], y[1], y[2]}, s.tracks[0].angles.back()) < 1e-10);
  }
  const auto order = [&](const std::string& name) {
    for (const auto& t : s.tracks)
      if (t.name == name) return t.order;
    FAIL("no track " << name);
    return 0.0;
  };
  // Errors against the true motion over the horizon, as the start shrinks: ε³ for the
  // harmonic solution and the paper's equations alike, ε⁵ for the cubic truncation; the
  // second-order series are dominated by their O(t³) truncation, which is linear in ε.
  CHECK(order("harmonic solution") == doctest::Approx(3).epsilon(0.03));
  CHECK(order("paper equations") == doctest::Approx(3).epsilon(0.03));
  CHECK(order("cubic equations") == doctest::Approx(5).epsilon(0.03));
  CHECK(order("harmonic series") == doctest::Approx(1).epsilon(0.1));
  CHECK(order("paper series") == doctest::Approx(1).epsilon(0.1));
  REQUIRE(s.defects.size() == 3);
  CHECK(s.defects[0].order == doctest::Approx(3).epsilon(0.03));
  CHECK(s.defects[1].order == doctest::Approx(3).epsilon(0.03));
  CHECK(s.defects[2].order == doctest::Approx(5).epsilon(0.03));
  // Q's first pole is where φ̇₁φ̇₂ changes sign: check on the chain itself, integrated
  // independently to just before and just after it.
  REQUIRE(std::isfinite(s.true_q_pole));
  const auto rates_at = [&](double t) {
    npend::integration_options o;
    o.t_end = t;
    o.dt = t / 1000;
    const auto x = npend::integrate(c, c.state_from_velocities(f, w), o).state;
    std::vector<double> v(3);
    c.velocities(std::span(x).first(3), std::span(x).subspan(3), v);
    return v[0] * v[1];
  };
  CHECK(rates_at(s.true_q_pole - 1e-3) * rates_at(s.true_q_pole + 1e-3) < 0);
  // The cubic truncation finds it; the harmonic and the paper's approximations find it early.
  CHECK(s.tracks[4].q_pole == doctest::Approx(s.true_q_pole).epsilon(0.02));
  CHECK(s.tracks[0].q_pole < 0.8 * s.true_q_pole);
  CHECK(s.tracks[3].q_pole < 0.8 * s.true_q_pole);
  // Q along the true motion from the start's own values.
  CHECK(s.true_q.front() == doctest::Approx(f[0] * f[1] / (w[0] * w[1])).epsilon(1e-12));
}

TEST_CASE("harmonic_correction_study: bad arguments are refused with the reason") {
  using doctest::Contains;
  using npend::harmonic_correction_study;
  const chain c2(chain_parameters::uniform(2));
  const std::vector<double> zero{0, 0}, some{0.1, 0.2}, one{0.1};
  CHECK_THROWS_WITH_AS(harmonic_correction_study(chain(chain_parameters::uniform(1)), one, one),
                       Contains("at least 2 links"), std::invalid_argument);
  CHECK_THROWS_WITH_AS(harmonic_correction_study(c2, zero, zero), Contains("at rest"),
                       std::invalid_argument);
  CHECK_THROWS_WITH_AS(harmonic_correction_study(c2, one, some), Contains("phi and dphi"),
                       std::invalid_argument);
  npend::correction_study_options o;
  o.scales = {0.5};
  CHECK_THROWS_WITH_AS(harmonic_correction_study(c2, some, some, o), Contains("at least 2 scales"),
                       std::invalid_argument);
  o.scales = {0.5, 0.5};
  CHECK_THROWS_WITH_AS(harmonic_correction_study(c2, some, some, o), Contains("given twice"),
                       std::invalid_argument);
  o = {};
  o.samples = 1;
  CHECK_THROWS_WITH_AS(harmonic_correction_study(c2, some, some, o), Contains("samples"),
                       std::invalid_argument);
}
