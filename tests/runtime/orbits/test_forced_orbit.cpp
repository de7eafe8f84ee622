// Forced orbits of driven chains and their continuation in the drive frequency, against
// floquet_analysis at the upright pendulum, the Mathieu equation's transition curve (Kapitza's
// threshold with its corrections in a/l), an independent re-integration with another stepper,
// and Liouville's det M = 1.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "npend/analysis/orbits/forced_orbit.hpp"
#include "npend/analysis/stability/floquet.hpp"
#include "npend/integrators/integrate.hpp"

using npend::chain;
using npend::chain_parameters;
using npend::pivot_motion;

namespace {

constexpr double forced_pi = std::numbers::pi;

chain forced_chain(int links, double length, pivot_motion drive) {
  chain_parameters p = chain_parameters::uniform(links, 1.0, length, 9.81);
  p.pivot = drive;
  return chain(p);
}

// The largest distance from a multiplier of `a` to the nearest of `b` (the same set in
// either order).
double forced_set_distance(const std::vector<std::complex<double>>& a,
                           const std::vector<std::complex<double>>& b) {
  double worst = 0;
  for (const auto& m : a) {
    double nearest = INFINITY;
    for (const auto& n : b) nearest = std::min(nearest, std::abs(m - n));
    worst = std::max(worst, nearest);
  }
  return worst;
}

// Kapitza's threshold from the Mathieu equation. Linearised about the upright position,
// θ = φ − π obeys θ̈ = (g − aΩ² cos Ωt)/l · θ, i.e. y'' + (δ + ε cos τ) y = 0 with τ = Ωt,
// δ = −g/(lΩ²), ε = a/l. Its upright solution becomes stable across the transition curve
// of the 2π-periodic solution (multiplier +1), δ = −ε²/2 + 7ε⁴/32 − 29ε⁶/144 + O(ε⁸) (the
// series of the Mathieu characteristic value a₀(q) = −q²/2 + 7q⁴/128 − 29q⁶/2304, q = 2ε,
// δ = a₀/4). Leading order: Ω² = 2gl/a², Kapitza's estimate.
double forced_mathieu_threshold(double g, double l, double a) {
  const double e = a / l, e2 = e * e;
  const double minus_delta = e2 / 2 - 7 * e2 * e2 / 32 + 29 * e2 * e2 * e2 / 144;
  return std::sqrt(g / (l * minus_delta));
}

}  // namespace

TEST_CASE("continue_drive: the upright pendulum's multipliers are floquet_analysis's") {
  const double a = 0.05;
  const chain c = forced_chain(1, 1.0, pivot_motion::vertical(a, 60.0));
  const std::vector<double> upright{forced_pi, 0.0};
  npend::drive_continuation_options opts;
  opts.frequency_end = 130;
  const npend::drive_branch branch = npend::continue_drive(c, upright, opts);
  CHECK(branch.end_reason == "reached frequency_end");
  REQUIRE(branch.points.size() >= 20);
  CHECK(branch.points.front().frequency == 60.0);
  CHECK(branch.points.back().frequency == 130.0);
  for (const npend::forced_point& p : branch.points) {
    CAPTURE(p.frequency);
    CHECK(p.closure <= 1e-11);
    CHECK(p.period == doctest::Approx(2 * forced_pi / p.frequency).epsilon(1e-15));
    // The upright state is an exact orbit at every Ω: the shooting keeps it.
    CHECK(std::fabs(p.x0[0] - forced_pi) <= 1e-12);
    CHECK(std::fabs(p.x0[1]) <= 1e-12);
    REQUIRE(p.multipliers.size() == 2);
    const npend::floquet_result f =
        npend::floquet_analysis(npend::with_drive_frequency(c, p.frequency), upright);
    CHECK(forced_set_distance(p.multipliers, f.multipliers) <= 1e-9 * (1 + p.max_multiplier));
    CHECK(p.max_multiplier == doctest::Approx(f.max_modulus).epsilon(1e-9));
    // The same criterion on floquet's max |μ|. (floquet's own verdict weighs max |μ| − 1
    // against an error estimate that can fall below the eigenvalues' last-ulp rounding: at
    // 91.5 rad/s it has max |μ| − 1 = 1.1e-15 against ±9.2e-16, and says unstable.)
    CHECK(p.stable == (f.max_modulus <= 1 + opts.orbit.stability_tolerance));
    // Undamped: det M = μ₁μ₂ = 1.
    CHECK(std::abs(p.multipliers[0] * p.multipliers[1] - 1.0) <= 1e-8);
  }
  // Unstable below Kapitza's threshold (88.6 rad/s), stable above: one change.
  CHECK_FALSE(branch.points.front().stable);
  CHECK(branch.points.back().stable);
  REQUIRE(branch.changes.size() == 1);
  CHECK(branch.changes[0].stable_above);
}

TEST_CASE("continue_drive: Kapitza's threshold, against floquet and the Mathieu equation") {
  // Continued downwards, from the stable side.
  const double g = 9.81, l = 1.0, a = 0.05;
  const chain c = forced_chain(1, l, pivot_motion::vertical(a, 140.0));
  const std::vector<double> upright{forced_pi, 0.0};
  npend::drive_continuation_options opts;
  opts.frequency_end = 50;
  const npend::drive_branch branch = npend::continue_drive(c, upright, opts);
  REQUIRE(branch.end_reason == "reached frequency_end");
  REQUIRE(branch.changes.size() == 1);
  const npend::drive_stability_change& k = branch.changes[0];
  CHECK(k.stable_above);
  CHECK(k.kind == npend::nnm_bifurcation_kind::branch_point);
  CHECK(k.bracket <= 1e-8 * k.frequency);
  CHECK(k.stable_side.frequency > k.unstable_side.frequency);
  // Through +1: the unstable side's pair is real, μ > 1 and 1/μ.
  const auto top = k.unstable_side.multipliers.front();
  CHECK(top.real() > 1);
  CHECK(std::fabs(top.imag()) == 0.0);
  // floquet_analysis on either side of it, 1e-6 away: unstable below, stable above.
  for (const double factor : {1 - 1e-6, 1 + 1e-6}) {
    CAPTURE(factor);
    const auto f =
        npend::floquet_analysis(npend::with_drive_frequency(c, k.frequency * factor), upright);
    CHECK(f.stable == (factor > 1));
  }
  // The Mathieu transition curve through ε⁶ leaves O(ε⁸) ≈ 1e-11; the Gauss–Legendre map
  // (400 steps per period) and the bisection (1e-8) dominate.
  const double mathieu = forced_mathieu_threshold(g, l, a);
  CHECK(std::fabs(k.frequency / mathieu - 1) <= 5e-8);
  // Kapitza's leading-order estimate √(2gl)/a is low by the relative 7ε²/32 + O(ε⁴).
  const double kapitza = std::sqrt(2 * g * l) / a;
  const double e2 = (a / l) * (a / l);
  CHECK(k.frequency > kapitza);
  CHECK(std::fabs(k.frequency / kapitza - 1 - 7 * e2 / 32) <= 2 * e2 * e2);
}

TEST_CASE("forced_orbit: the double pendulum's forced swing re-integrated with rkf78") {
  // Shaken sideways below its lower mode (ω₁ = 2.40 rad/s), the hanging double pendulum
  // swings with the drive: a forced response, not an equilibrium.
  const chain c0 = forced_chain(2, 1.0, pivot_motion::horizontal(0.15, 1.5));
  npend::drive_continuation_options opts;
  opts.frequency_end = 2.1;
  opts.orbit.steps = 200;
  const npend::drive_branch branch = npend::continue_drive(c0, std::vector<double>(4, 0.0), opts);
  REQUIRE(branch.end_reason == "reached frequency_end");
  // The response grows towards the resonance.
  for (std::size_t i = 1; i < branch.points.size(); ++i)
    CHECK(branch.points[i].amplitudes[0] > branch.points[i - 1].amplitudes[0]);
  const npend::forced_point& p = branch.points.back();
  CHECK(p.amplitudes[0] > 0.2);
  CHECK(p.amplitudes[1] > 0.2);
  // det M = 1 (the drive is Hamiltonian): the product of all four multipliers.
  std::complex<double> product = 1;
  for (const auto& mu : p.multipliers) product *= mu;
  CHECK(std::abs(product - 1.0) <= 1e-8);
  // The start re-integrated by rkf78 from t = 0 over the period: back to the start.
  const chain c = npend::with_drive_frequency(c0, p.frequency);
  npend::integration_options run;
  run.stepper = npend::stepper_kind::rkf78;
  run.t_end = p.period;
  run.dt = p.period;
  run.abs_tol = run.rel_tol = 1e-14;
  const npend::integration_result back = npend::integrate(c, p.x0, run);
  REQUIRE(back.t == doctest::Approx(p.period).epsilon(1e-15));
  double gap = 0, half_gap = 0;
  for (std::size_t i = 0; i < p.x0.size(); ++i)
    gap = std::max(gap, std::fabs(back.state[i] - p.x0[i]));
  CHECK(gap <= 1e-9);
  // Not a trivial return: half a period later it is elsewhere.
  run.t_end = run.dt = p.period / 2;
  const npend::integration_result half = npend::integrate(c, p.x0, run);
  for (std::size_t i = 0; i < p.x0.size(); ++i)
    half_gap = std::max(half_gap, std::fabs(half.state[i] - p.x0[i]));
  CHECK(half_gap > 0.3);
}

TEST_CASE("forced_orbit: over two drive periods the multipliers are squared") {
  // The single pendulum shaken sideways above its frequency (ω₀ = 3.13 rad/s).
  const chain c = forced_chain(1, 1.0, pivot_motion::horizontal(0.1, 5.0));
  const std::vector<double> rest{0.0, 0.0};
  const npend::forced_orbit_result one = npend::forced_orbit(c, rest);
  npend::forced_orbit_options twice;
  twice.periods = 2;
  const npend::forced_orbit_result two = npend::forced_orbit(c, rest, twice);
  REQUIRE(one.converged);
  REQUIRE(two.converged);
  CHECK(two.period == doctest::Approx(2 * one.period).epsilon(1e-15));
  CHECK(std::fabs(one.x0[0]) > 0.02);  // swings against the drive, p = 0 at t = 0
  CHECK(two.x0[0] == doctest::Approx(one.x0[0]).epsilon(1e-9));
  CHECK(two.x0[1] == doctest::Approx(one.x0[1]).scale(1).epsilon(1e-9));
  std::vector<std::complex<double>> squared;
  for (const auto& mu : one.multipliers) squared.push_back(mu * mu);
  CHECK(forced_set_distance(two.multipliers, squared) <= 1e-9);
  CHECK(one.stable);
  CHECK(std::abs(one.multipliers[0] * one.multipliers[1] - 1.0) <= 1e-8);
}

TEST_CASE("forced_orbit: refuses damping, a fixed pivot, a custom path, a cart and wrong sizes") {
  chain_parameters damped = chain_parameters::uniform(2);
  damped.damping = {0.1, 0.0};
  damped.pivot = pivot_motion::vertical(0.01, 50.0);
  const std::vector<double> x{0.1, 0.1, 0, 0};
  CHECK_THROWS_WITH_AS(npend::forced_orbit(chain(damped), x),
                       doctest::Contains("damping is excluded"), std::invalid_argument);
  CHECK_THROWS_WITH_AS(npend::forced_orbit(chain(chain_parameters::uniform(2)), x),
                       doctest::Contains("see periodic_orbit"), std::invalid_argument);
  chain_parameters custom = chain_parameters::uniform(2);
  custom.pivot.type = pivot_motion::kind::custom;
  custom.pivot.position = [](double) { return pivot_motion::vec2{0, 0}; };
  custom.pivot.velocity = custom.pivot.position;
  custom.pivot.acceleration = custom.pivot.position;
  CHECK_THROWS_WITH_AS(npend::forced_orbit(chain(custom), x), doctest::Contains("custom path"),
                       std::invalid_argument);
  chain_parameters cart = chain_parameters::uniform(2);
  cart.cart_mass = 1.0;
  CHECK_THROWS_WITH_AS(npend::forced_orbit(chain(cart), std::vector<double>(6, 0.0)),
                       doctest::Contains("cart"), std::invalid_argument);
  const chain driven = forced_chain(2, 1.0, pivot_motion::vertical(0.01, 50.0));
  CHECK_THROWS_WITH_AS(npend::forced_orbit(driven, std::vector<double>{0.1, 0.1}),
                       doctest::Contains("x0_guess has 2 entries"), std::invalid_argument);
  npend::forced_orbit_options bad;
  bad.periods = 0;
  CHECK_THROWS_AS(npend::forced_orbit(driven, x, bad), std::invalid_argument);
  npend::drive_continuation_options cont;
  cont.frequency_end = 50.0;
  CHECK_THROWS_WITH_AS(npend::continue_drive(driven, x, cont), doctest::Contains("equals"),
                       std::invalid_argument);
  cont.frequency_end = -1;
  CHECK_THROWS_AS(npend::continue_drive(driven, x, cont), std::invalid_argument);
  CHECK_THROWS_WITH_AS(npend::continue_drive(chain(damped), x, cont),
                       doctest::Contains("continue_drive: the chain is damped"),
                       std::invalid_argument);
}

// The shooting on Taylor's method (forced_orbit_options::stepper = taylor).
namespace {

npend::forced_orbit_options forced_taylor(double tolerance = 1e-14) {
  npend::forced_orbit_options o;
  o.stepper = npend::stepper_kind::taylor;
  o.integration_tolerance = tolerance;
  return o;
}

}  // namespace

TEST_CASE("forced_orbit (taylor): the double pendulum's forced swing, against gauss6 and rkf78") {
  const chain c = forced_chain(2, 1.0, pivot_motion::horizontal(0.15, 2.0));
  const std::vector<double> rest(4, 0.0);
  const npend::forced_orbit_result t = npend::forced_orbit(c, rest, forced_taylor());
  npend::forced_orbit_options fine;
  fine.steps = 1600;
  const npend::forced_orbit_result g = npend::forced_orbit(c, rest, fine);
  REQUIRE(t.converged);
  REQUIRE(g.converged);
  CHECK(t.steps > 0);
  CHECK(t.steps < g.steps);
  for (std::size_t i = 0; i < t.x0.size(); ++i) CHECK(std::fabs(t.x0[i] - g.x0[i]) <= 1e-9);
  CHECK(forced_set_distance(t.multipliers, g.multipliers) <= 1e-8);
  // The amplitudes sample 16 points a step, gauss6's its 1600 step points: the peak differs by
  // the sampling, (ω Δt)²/8 of it at most.
  for (std::size_t i = 0; i < t.amplitudes.size(); ++i)
    CHECK(t.amplitudes[i] == doctest::Approx(g.amplitudes[i]).epsilon(1e-3));
  CHECK(t.amplitudes[0] > 0.1);
  // The start re-integrated by rkf78 over the period returns to itself.
  npend::integration_options run;
  run.stepper = npend::stepper_kind::rkf78;
  run.t_end = run.dt = t.period;
  run.abs_tol = run.rel_tol = 1e-14;
  const npend::integration_result back = npend::integrate(c, t.x0, run);
  double gap = 0;
  for (std::size_t i = 0; i < t.x0.size(); ++i)
    gap = std::max(gap, std::fabs(back.state[i] - t.x0[i]));
  CHECK(gap <= 1e-10);
}

TEST_CASE("continue_drive (taylor): Kapitza's threshold against the Mathieu equation") {
  const double g = 9.81, l = 1.0, a = 0.05;
  const chain c = forced_chain(1, l, pivot_motion::vertical(a, 140.0));
  npend::drive_continuation_options opts;
  opts.orbit = forced_taylor();
  opts.frequency_end = 50;
  const npend::drive_branch branch =
      npend::continue_drive(c, std::vector<double>{forced_pi, 0.0}, opts);
  REQUIRE(branch.end_reason == "reached frequency_end");
  REQUIRE(branch.changes.size() == 1);
  const npend::drive_stability_change& k = branch.changes[0];
  CHECK(k.stable_above);
  CHECK(std::fabs(k.frequency / forced_mathieu_threshold(g, l, a) - 1) <= 5e-8);
}

TEST_CASE("forced_orbit (taylor): refuses other steppers and bad tolerances") {
  const chain c = forced_chain(1, 1.0, pivot_motion::horizontal(0.1, 5.0));
  const std::vector<double> rest{0.0, 0.0};
  npend::forced_orbit_options rk4;
  rk4.stepper = npend::stepper_kind::rk4;
  CHECK_THROWS_WITH_AS(npend::forced_orbit(c, rest, rk4),
                       "forced_orbit: the shooting integrates with gauss6, taylor, not rk4",
                       std::invalid_argument);
  for (const double tol : {0.0, 1e-5, std::nan("")}) {
    CAPTURE(tol);
    CHECK_THROWS_AS(npend::forced_orbit(c, rest, forced_taylor(tol)), std::invalid_argument);
  }
}
