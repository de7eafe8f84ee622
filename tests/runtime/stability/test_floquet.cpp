// Floquet multipliers of driven chains against Kapitza's criterion, a hand-integrated Mathieu
// equation, Liouville's formula for damped chains and the reciprocal pairs of undamped ones.
#include <doctest/doctest.h>

#include <Eigen/Dense>
#include <cmath>
#include <complex>
#include <numbers>
#include <string>

#include "npend/analysis/stability/floquet.hpp"

using npend::chain;
using npend::chain_parameters;
using npend::pivot_motion;

namespace {

constexpr double pi = std::numbers::pi;

// The inverted pendulum on a vertically shaken pivot, linearised: θ̈ = (g − a Ω² cos Ωt)/l · θ
// (θ = φ − π). Its monodromy over one period by classical RK4 with many small steps,
// written here by hand: nothing shared with the library's integrators or kernels.
Eigen::Matrix2d mathieu_monodromy(double g, double l, double a, double omega) {
  const double period = 2 * pi / omega;
  const int steps = 20000;
  const double h = period / steps;
  auto f = [&](double t, const Eigen::Matrix2d& y) {
    Eigen::Matrix2d a_t;
    a_t << 0, 1, (g - a * omega * omega * std::cos(omega * t)) / l, 0;
    return Eigen::Matrix2d(a_t * y);
  };
  Eigen::Matrix2d y = Eigen::Matrix2d::Identity();
  for (int k = 0; k < steps; ++k) {
    const double t = k * h;
    const Eigen::Matrix2d k1 = f(t, y), k2 = f(t + h / 2, y + h / 2 * k1),
                          k3 = f(t + h / 2, y + h / 2 * k2), k4 = f(t + h, y + h * k3);
    y += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
  }
  return y;
}

chain inverted_single(double a, double omega) {
  chain_parameters p = chain_parameters::uniform(1, 1.0, 1.0);
  p.pivot = pivot_motion::vertical(a, omega);
  return chain(p);
}

}  // namespace

TEST_CASE("floquet: Kapitza's inverted pendulum is stable iff (a Omega)^2 > 2 g l, far from it") {
  const double a = 0.05, critical = std::sqrt(2 * 9.81) / a;  // 88.6 rad/s
  for (const double omega : {0.6 * critical, 0.85 * critical, 1.2 * critical, 1.6 * critical}) {
    CAPTURE(omega);
    const chain c = inverted_single(a, omega);
    const std::vector<double> x0{pi, 0.0};
    const auto r = npend::floquet_analysis(c, x0);
    CHECK(r.stable == (omega > critical));
    CHECK(r.closure < 1e-12);
    CHECK(r.period == doctest::Approx(2 * pi / omega));
  }
}

TEST_CASE("floquet: just above the Mathieu threshold every frequency is stable, not by rounding") {
  // Upright, θ = φ − π obeys y'' + (δ + ε cos τ) y = 0 with τ = Ωt, δ = −g/(lΩ²), ε = a/l;
  // its transition curve through +1, δ = −ε²/2 + 7ε⁴/32 − 29ε⁶/144, puts the threshold at
  // 88.637 rad/s for a = 0.05. Above it, up to the −1 curve (δ > 0, never reached), every
  // multiplier is on the circle: |μ| − 1 is rounding there, which the error must cover.
  const double a = 0.05, eps = a, g = 9.81;
  const double delta = -eps * eps / 2 + 7 * std::pow(eps, 4) / 32 - 29 * std::pow(eps, 6) / 144;
  const double threshold = std::sqrt(-g / delta);
  CHECK(threshold == doctest::Approx(88.6373).epsilon(1e-5));
  for (double omega = 89; omega <= 95; omega += 0.5) {
    CAPTURE(omega);
    const chain c = inverted_single(a, omega);
    const std::vector<double> x0{pi, 0.0};
    const auto r = npend::floquet_analysis(c, x0);
    CHECK(r.verdict == npend::floquet_verdict::stable);
    CHECK(std::fabs(r.max_modulus - 1) <= r.modulus_error);
  }
}

TEST_CASE("floquet: the multipliers are the linear Mathieu equation's") {
  for (const double omega : {40.0, 75.0, 110.0, 160.0}) {
    CAPTURE(omega);
    const auto r =
        npend::floquet_analysis(inverted_single(0.05, omega), std::vector<double>{pi, 0.0});
    const Eigen::Vector2cd ev = mathieu_monodromy(9.81, 1.0, 0.05, omega).eigenvalues();
    // The same pair, in either order (the chain's state is (φ, p = m l² φ̇), a similarity).
    const double direct = std::abs(r.multipliers[0] - ev(0)) + std::abs(r.multipliers[1] - ev(1));
    const double swapped = std::abs(r.multipliers[0] - ev(1)) + std::abs(r.multipliers[1] - ev(0));
    CHECK(std::min(direct, swapped) < 1e-8 * (1 + std::abs(ev(0))));
  }
}

TEST_CASE("floquet: an undamped driven triple pendulum's multipliers come in reciprocal pairs") {
  chain_parameters p = chain_parameters::uniform(3, 1.0, 0.5);
  p.make_uniform_rods();
  p.pivot = pivot_motion::vertical(0.02, 150.0);
  const auto r = npend::floquet_analysis(chain(p), std::vector<double>{pi, pi, pi, 0, 0, 0});
  std::complex<double> product = 1;
  for (const auto& m : r.multipliers) product *= m;
  CHECK(std::abs(product - 1.0) < 1e-10);  // det M = 1: the flow preserves volume
  // Each μ has a partner 1/μ (up to conjugation, the spectrum is real-symmetric).
  for (const auto& m : r.multipliers) {
    double nearest = 1e300;
    for (const auto& other : r.multipliers) nearest = std::min(nearest, std::abs(other * m - 1.0));
    CHECK(nearest < 1e-8);
  }
}

TEST_CASE("floquet: a damped chain's det M is exp(integral of tr J) (Liouville)") {
  // One rod with damping b: tr J = dφ̇/dφ + dṗ/dp = 0 − b/I for every state.
  chain_parameters p = chain_parameters::uniform(1, 1.0, 1.0);
  p.make_uniform_rods();
  p.damping = {0.05};
  p.pivot = pivot_motion::vertical(0.1, 40.0);
  const auto r = npend::floquet_analysis(chain(p), std::vector<double>{pi, 0.0});
  const double inertia = 1.0 / 3;
  std::complex<double> det = 1;
  for (const auto& m : r.multipliers) det *= m;
  CHECK(det.real() == doctest::Approx(std::exp(-0.05 / inertia * r.period)).epsilon(1e-10));
  CHECK(std::abs(det.imag()) < 1e-12);
}

TEST_CASE("floquet: refuses a chain without a drive") {
  const chain c(chain_parameters::uniform(1));
  CHECK_THROWS_AS(npend::floquet_analysis(c, std::vector<double>{0.0, 0.0}), std::invalid_argument);
}

namespace {

// The lowest drive frequency that holds the chain upright, by bisection on the Floquet
// verdict (stable above it, unstable below, in [lo, hi]).
double stabilising_frequency(chain_parameters p, double amplitude, double lo, double hi) {
  const int n = p.links();
  const std::vector<double> up(static_cast<std::size_t>(n), pi);
  std::vector<double> x0 = up;
  x0.resize(static_cast<std::size_t>(2 * n), 0.0);
  const auto stable = [&](double omega) {
    p.pivot = pivot_motion::vertical(amplitude, omega);
    return npend::floquet_analysis(chain(p), x0).stable;
  };
  REQUIRE_FALSE(stable(lo));
  REQUIRE(stable(hi));
  for (int k = 0; k < 40; ++k) {
    const double mid = std::sqrt(lo * hi);
    (stable(mid) ? hi : lo) = mid;
  }
  return hi;
}

// Acheson's lower limit from Kapitza's averaged potential, to leading order in a/l: the fast
// vertical force a Ω² cos Ωt · G(φ) with G = ∂(Σ m_k y_k)/∂φ adds (a²Ω²/4) Gᵀ A⁻¹ G to V.
// At the inverted position G = 0 and ∂G/∂φ = diag(G'_i), so the effective stiffness is
// (a²Ω²/2) D A⁻¹ D − g D with D = diag(m_i c_i + μ_{i+1} l_i): positive definite iff
// (aΩ)² > 2 g · max eig(D, D A⁻¹ D). A(π) and D hand-written from the geometry.
double averaged_threshold(const chain_parameters& p, bool rods) {
  const int n = p.links();
  Eigen::MatrixXd A(n, n);
  Eigen::VectorXd d(n);
  const auto m = [&](int i) { return p.masses[static_cast<std::size_t>(i)]; };
  const auto l = [&](int i) { return p.lengths[static_cast<std::size_t>(i)]; };
  const auto c = [&](int i) { return rods ? l(i) / 2 : l(i); };
  const auto below = [&](int i) {
    double s = 0;
    for (int k = i + 1; k < n; ++k) s += m(k);
    return s;
  };
  for (int i = 0; i < n; ++i) {
    d(i) = m(i) * c(i) + below(i) * l(i);
    A(i, i) = (rods ? m(i) * l(i) * l(i) / 12 : 0.0) + m(i) * c(i) * c(i) + below(i) * l(i) * l(i);
    for (int j = i + 1; j < n; ++j)  // all angles π: cos(φ_i − φ_j) = 1
      A(i, j) = A(j, i) = l(i) * (m(j) * c(j) + below(j) * l(j));
  }
  const Eigen::MatrixXd D = d.asDiagonal();
  const Eigen::MatrixXd M = D * A.inverse() * D;
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(D, M);
  return std::sqrt(2 * 9.81 * eig.eigenvalues().maxCoeff());
}

}  // namespace

TEST_CASE(
    "floquet: Acheson's stabilised double and triple pendulums start where the averaged "
    "potential says") {
  // a/l = 0.01: the averaged potential is the leading order in a/l; measured, the two agree
  // to 3e-5 (1.98095 vs 1.98091 m/s for one point mass, 3.07211 vs 3.07210 for three).
  const double l = 0.2, a = 0.002;
  for (const bool rods : {false, true}) {
    for (int n = 1; n <= 3; ++n) {
      CAPTURE(n);
      CAPTURE(rods);
      chain_parameters p = chain_parameters::uniform(n, 1.0, l);
      if (rods) p.make_uniform_rods();
      const double predicted = averaged_threshold(p, rods);
      const double measured =
          a * stabilising_frequency(p, a, 0.5 * predicted / a, 2 * predicted / a);
      const std::string line = std::string(rods ? "rods" : "point masses") +
                               ", n = " + std::to_string(n) + ": a*Omega threshold " +
                               std::to_string(measured) + " m/s, averaged potential " +
                               std::to_string(predicted) + " m/s";
      MESSAGE(line);
      CHECK(measured == doctest::Approx(predicted).epsilon(1e-3));
    }
  }
}

TEST_CASE("floquet: a slowly unstable, heavily damped inverted pendulum is unstable") {
  // Overdamped (b = 1e5 N m s), the inverted link creeps away at the rate λ = m g l / b
  // (inertia and the drive's averaged force are O(1/b) smaller): max |μ| = e^{λT} with
  // λ T = 1.962e-5 · 2π/250 = 4.93e-7, which a fixed tolerance of 1e-6 called stable.
  chain_parameters p = chain_parameters::uniform(1, 1.0, 0.2);
  p.damping = {1e5};
  p.pivot = pivot_motion::vertical(0.01, 250.0);
  const auto r = npend::floquet_analysis(chain(p), std::vector<double>{pi, 0.0});
  const double growth = 1.0 * 9.81 * 0.2 / 1e5 * (2 * pi / 250);
  CHECK(r.max_modulus - 1 == doctest::Approx(growth).epsilon(1e-2));
  CHECK(r.modulus_error < 1e-2 * growth);
  CHECK(r.verdict == npend::floquet_verdict::unstable);
  CHECK_FALSE(r.stable);
}

TEST_CASE("floquet: a damped chain is stable inside the circle, marginal within the error") {
  // Hanging, lightly damped: every multiplier is inside the circle by ~ b T / (2 m l²).
  chain_parameters p = chain_parameters::uniform(1, 1.0, 1.0);
  p.pivot = pivot_motion::vertical(0.01, 40.0);
  const double period = 2 * pi / 40;
  p.damping = {0.05};
  const auto decaying = npend::floquet_analysis(chain(p), std::vector<double>{0.0, 0.0});
  CHECK(1 - decaying.max_modulus == doctest::Approx(0.05 / 2 * period).epsilon(2e-2));
  CHECK(decaying.modulus_error < 1e-3 * (1 - decaying.max_modulus));
  CHECK(decaying.verdict == npend::floquet_verdict::stable);
  // Damped by 1e-15: |μ| = 1 − 4e-17, below the rounding of the eigenvalues: the
  // integration cannot tell, and says so rather than guessing.
  p.damping = {1e-15};
  const auto faint = npend::floquet_analysis(chain(p), std::vector<double>{0.0, 0.0});
  CHECK(std::fabs(faint.max_modulus - 1) <= faint.modulus_error);
  CHECK(faint.modulus_error < 1e-12);
  CHECK(faint.verdict == npend::floquet_verdict::marginal);
  CHECK_FALSE(faint.stable);
}

TEST_CASE("floquet: the error estimate bounds the change to a run with many more steps") {
  // The Mathieu pendulum near its threshold, with few steps: the error estimate (the change
  // from half the steps) must cover the distance to a run with 8 times the steps.
  const chain c = inverted_single(0.05, 75.0);
  npend::floquet_options coarse, fine;
  coarse.steps = 16;
  fine.steps = 128;
  const auto a = npend::floquet_analysis(c, std::vector<double>{pi, 0.0}, coarse);
  const auto b = npend::floquet_analysis(c, std::vector<double>{pi, 0.0}, fine);
  CHECK(a.modulus_error > 0);
  CHECK(std::fabs(a.max_modulus - b.max_modulus) <= a.modulus_error);
  CHECK(b.modulus_error < a.modulus_error);
}

TEST_CASE(
    "floquet_frequency_scan: Kapitza's stable window starts where a^2 Omega^2 / (2 g l) = 1") {
  // a/l = 0.01: the averaged potential's criterion holds to far better than the 1 % grid
  // (3e-5, the test of Acheson's pendulums above), and no grid point lies that close to it.
  const double a = 0.002, l = 0.2, g = 9.81, critical = std::sqrt(2 * g * l) / a;  // 990 rad/s
  chain_parameters p = chain_parameters::uniform(1, 1.0, l, g);
  p.pivot = pivot_motion::vertical(a, 1.0);
  std::vector<double> omega;
  for (int k = 0; k <= 20; ++k) omega.push_back(905 + 10.0 * k);
  const std::vector<double> x0{pi, 0.0};
  const auto scan = npend::floquet_frequency_scan(chain(p), x0, omega);
  REQUIRE(scan.points.size() == omega.size());
  CHECK_FALSE(scan.stopped);
  double first_above = 0;
  for (const double w : omega)
    if (w > critical) {
      first_above = w;
      break;
    }
  for (std::size_t k = 0; k < omega.size(); ++k) {
    CAPTURE(omega[k]);
    CHECK(scan.points[k].frequency == omega[k]);
    CHECK(scan.points[k].stable == (omega[k] > critical));
  }
  REQUIRE(scan.stable_windows.size() == 1);
  CHECK(scan.stable_windows.front().first == first_above);
  CHECK(scan.stable_windows.front().second == omega.back());
}

namespace {

// Asks to stop at once.
struct stop_now final : npend::run_control {
  bool stop_requested() override { return true; }
};

}  // namespace

TEST_CASE("floquet_frequency_scan: a stop request ends it at the first frequency, bad arguments") {
  chain_parameters p = chain_parameters::uniform(1);
  p.pivot = pivot_motion::vertical(0.05, 100.0);
  const chain c(p);
  const std::vector<double> x0{pi, 0.0}, omega{100.0, 200.0};
  stop_now stop;
  npend::floquet_options o;
  o.control = &stop;
  const auto scan = npend::floquet_frequency_scan(c, x0, omega, o);
  CHECK(scan.stopped);
  CHECK(scan.stopped_at == 100.0);
  CHECK(scan.points.empty());
  CHECK(scan.stable_windows.empty());
  CHECK_THROWS_AS(npend::floquet_frequency_scan(chain(chain_parameters::uniform(1)), x0, omega),
                  std::invalid_argument);
  CHECK_THROWS_AS(npend::floquet_frequency_scan(c, x0, std::vector<double>{}),
                  std::invalid_argument);
  CHECK_THROWS_AS(npend::floquet_frequency_scan(c, x0, std::vector<double>{100.0, -1.0}),
                  std::invalid_argument);
}

// The monodromy on Taylor's method (floquet_options::stepper = taylor): the variational
// equations' own Taylor series, against the same closed forms and against gauss6.
namespace {

npend::floquet_options taylor_at(double tolerance) {
  npend::floquet_options o;
  o.stepper = npend::stepper_kind::taylor;
  o.tolerance = tolerance;
  return o;
}

}  // namespace

TEST_CASE("floquet (taylor): the multipliers are the linear Mathieu equation's") {
  for (const double omega : {40.0, 75.0, 110.0, 160.0}) {
    CAPTURE(omega);
    const auto r = npend::floquet_analysis(inverted_single(0.05, omega),
                                           std::vector<double>{pi, 0.0}, taylor_at(1e-13));
    const Eigen::Vector2cd ev = mathieu_monodromy(9.81, 1.0, 0.05, omega).eigenvalues();
    const double direct = std::abs(r.multipliers[0] - ev(0)) + std::abs(r.multipliers[1] - ev(1));
    const double swapped = std::abs(r.multipliers[0] - ev(1)) + std::abs(r.multipliers[1] - ev(0));
    CHECK(std::min(direct, swapped) < 1e-8 * (1 + std::abs(ev(0))));
    CHECK(r.closure < 1e-12);
    CHECK(r.steps > 0);
  }
}

TEST_CASE("floquet (taylor): just above the Mathieu threshold every frequency is stable") {
  // As the gauss6 case above: the error (the change from 100 times the tolerance, and
  // rounding) must cover |μ| − 1 where every multiplier is on the circle; Taylor's steps are
  // not symplectic, so truncation, not only rounding, leaves them off it.
  for (double omega = 89; omega <= 95; omega += 1) {
    CAPTURE(omega);
    const auto r = npend::floquet_analysis(inverted_single(0.05, omega),
                                           std::vector<double>{pi, 0.0}, taylor_at(1e-13));
    CHECK(r.verdict == npend::floquet_verdict::stable);
    CHECK(std::fabs(r.max_modulus - 1) <= r.modulus_error);
  }
}

TEST_CASE("floquet (taylor): the driven triple pendulum's monodromy is gauss6's") {
  // Uniform rods (the physical chain's Taylor kernels, the drive a series in time), det M = 1.
  chain_parameters p = chain_parameters::uniform(3, 1.0, 0.5);
  p.make_uniform_rods();
  p.pivot = pivot_motion::vertical(0.02, 150.0);
  const chain c(p);
  const std::vector<double> x0{pi, pi, pi, 0, 0, 0};
  npend::floquet_options fine_gauss;
  fine_gauss.steps = 1600;
  const auto g = npend::floquet_analysis(c, x0, fine_gauss);
  const auto t = npend::floquet_analysis(c, x0, taylor_at(1e-14));
  REQUIRE(t.monodromy.size() == g.monodromy.size());
  double largest = 0, difference = 0;
  for (std::size_t i = 0; i < t.monodromy.size(); ++i) {
    largest = std::max(largest, std::fabs(g.monodromy[i]));
    difference = std::max(difference, std::fabs(t.monodromy[i] - g.monodromy[i]));
  }
  CHECK(difference < 1e-9 * largest);
  CHECK(std::fabs(t.max_modulus - g.max_modulus) <= t.modulus_error + g.modulus_error);
  CHECK(t.verdict == g.verdict);
  std::complex<double> product = 1;
  for (const auto& m : t.multipliers) product *= m;
  CHECK(std::abs(product - 1.0) < 1e-10);
}

TEST_CASE("floquet (taylor): a damped chain's det M is exp(integral of tr J) (Liouville)") {
  chain_parameters p = chain_parameters::uniform(1, 1.0, 1.0);
  p.make_uniform_rods();
  p.damping = {0.05};
  p.pivot = pivot_motion::vertical(0.1, 40.0);
  const auto r = npend::floquet_analysis(chain(p), std::vector<double>{pi, 0.0}, taylor_at(1e-13));
  std::complex<double> det = 1;
  for (const auto& m : r.multipliers) det *= m;
  CHECK(det.real() == doctest::Approx(std::exp(-0.05 * 3 * r.period)).epsilon(1e-10));
  CHECK(std::abs(det.imag()) < 1e-12);
}

TEST_CASE("floquet (taylor): the error estimate bounds the change to a far tighter run") {
  const chain c = inverted_single(0.05, 75.0);
  const auto loose = npend::floquet_analysis(c, std::vector<double>{pi, 0.0}, taylor_at(1e-7));
  const auto tight = npend::floquet_analysis(c, std::vector<double>{pi, 0.0}, taylor_at(1e-14));
  CHECK(loose.modulus_error > 0);
  CHECK(std::fabs(loose.max_modulus - tight.max_modulus) <= loose.modulus_error);
  CHECK(tight.modulus_error < loose.modulus_error);
}

TEST_CASE("floquet: refuses steppers without a monodromy, bad taylor tolerances and chains") {
  const chain c = inverted_single(0.05, 75.0);
  const std::vector<double> x0{pi, 0.0};
  npend::floquet_options rk4;
  rk4.stepper = npend::stepper_kind::rk4;
  CHECK_THROWS_WITH_AS(npend::floquet_analysis(c, x0, rk4),
                       "Floquet analysis integrates with gauss6, taylor, not rk4",
                       std::invalid_argument);
  for (const double tol : {0.0, -1e-10, 1e-5, std::nan("")}) {
    CAPTURE(tol);
    CHECK_THROWS_AS(npend::floquet_analysis(c, x0, taylor_at(tol)), std::invalid_argument);
  }
  // Seven point masses run on the loop kernels, which have no Taylor recurrences (the period
  // map over an explicit period: an undriven chain).
  const chain loops(chain_parameters::uniform(7));
  std::string message;
  try {
    npend::floquet_analysis(loops, std::vector<double>(14, 0.0), taylor_at(1e-12), 1.0);
  } catch (const std::invalid_argument& e) {
    message = e.what();
  }
  CHECK(message.find("needs the generated Taylor kernels") != std::string::npos);
}
