// Unstable periodic orbits from close returns, checked independently: every orbit integrated
// again with rkf78 closes and keeps the trajectory's energy, its multipliers come in
// reciprocal pairs, the orbits found are distinct and prime (rkf78's own section points),
// the single pendulum's orbit has the exact period 4K(k)/ω0.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "npend/analysis/chaos/poincare_section.hpp"
#include "npend/analysis/orbits/unstable_orbits.hpp"
#include "npend/integrators/integrate.hpp"

using npend::chain;
using npend::chain_parameters;

namespace {

// All arms deflected by one angle, at rest, with energy e: the command line's default start.
std::vector<double> upo_deflected_start(const chain& c, double e) {
  const int n = c.links();
  double weight = 0;  // V = weight·(1 − cos φ) for equal angles
  const auto& p = c.parameters();
  for (int i = 0; i < n; ++i)
    for (int k = i; k < n; ++k)
      weight +=
          p.masses[static_cast<std::size_t>(k)] * p.g * p.lengths[static_cast<std::size_t>(i)];
  std::vector<double> x(static_cast<std::size_t>(2 * n), std::acos(1 - e / weight));
  std::fill(x.begin() + n, x.end(), 0.0);
  return x;
}

// ‖φ(T) − x0 − 2πw‖∞ with rkf78 at tolerance 1e-14.
double upo_rkf78_closure(const chain& c, const npend::unstable_orbit& u) {
  npend::integration_options run;
  run.stepper = npend::stepper_kind::rkf78;
  run.t_end = u.period;
  run.dt = u.period;
  run.abs_tol = run.rel_tol = 1e-14;
  const npend::integration_result back = npend::integrate(c, u.x0, run);
  double gap = 0;
  for (std::size_t i = 0; i < u.x0.size(); ++i) {
    const double turns = i < u.winding.size() ? 2 * std::numbers::pi * u.winding[i] : 0.0;
    gap = std::max(gap, std::fabs(back.state[i] - u.x0[i] - turns));
  }
  return gap;
}

// The upward crossings of φ_1 = 0 in one period by rkf78 (angles on the circle).
std::vector<std::vector<double>> upo_rkf78_section(const chain& c, const npend::unstable_orbit& u) {
  npend::integration_options run;
  run.stepper = npend::stepper_kind::rkf78;
  run.t_end = u.period;
  run.dt = u.period;
  run.abs_tol = run.rel_tol = 1e-13;
  const auto p =
      npend::poincare_section(c, u.x0, npend::section_plane::coordinate(c.links(), 0, 0.0), run);
  std::vector<std::vector<double>> points;
  for (const auto& x : p.crossings) {
    std::vector<double> s = x.state;
    for (int i = 0; i < c.links(); ++i)
      s[static_cast<std::size_t>(i)] = npend::wrapped_angle(s[static_cast<std::size_t>(i)]);
    points.push_back(s);
  }
  return points;
}

double upo_distance(const std::vector<double>& a, const std::vector<double>& b, int links) {
  double d = 0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    const double delta = a[k] - b[k];
    d = std::max(
        d, std::fabs(k < static_cast<std::size_t>(links) ? npend::wrapped_angle(delta) : delta));
  }
  return d;
}

// The properties every orbit of a search must have, checked with rkf78.
void upo_check_orbits(const chain& c, const npend::unstable_orbit_search_result& r,
                      const npend::unstable_orbit_search_options& o) {
  const int n = c.links();
  for (std::size_t k = 0; k < r.orbits.size(); ++k) {
    const npend::unstable_orbit& u = r.orbits[k];
    CAPTURE(u.period);
    if (k > 0) CHECK(u.period >= r.orbits[k - 1].period);
    CHECK(u.period >= o.period_min);
    CHECK(u.period <= o.period_max * (1 + 1e-9));
    CHECK(upo_rkf78_closure(c, u) <= 1e-9);
    CHECK(c.hamiltonian(u.x0) == doctest::Approx(r.energy).epsilon(1e-10));
    REQUIRE(u.multipliers.size() == static_cast<std::size_t>(2 * n - 2));
    // Symplectic monodromy: the eigenvalues pair up as μ, 1/μ̄ — the product of the largest
    // and the smallest modulus is 1.
    CHECK(std::abs(u.multipliers.front()) * std::abs(u.multipliers.back()) ==
          doctest::Approx(1.0).epsilon(1e-6));
    CHECK(u.lyapunov_rate == doctest::Approx(std::log(u.max_multiplier) / u.period));
    // rkf78's own section points are the orbit's, and none recurs within the period (prime).
    const auto points = upo_rkf78_section(c, u);
    REQUIRE(points.size() == u.section_points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
      double nearest = 1e300;
      for (const auto& q : u.section_points)
        nearest = std::min(nearest, upo_distance(points[i], q, n));
      CHECK(nearest <= 1e-8);
      for (std::size_t j = 0; j < i; ++j) CHECK(upo_distance(points[i], points[j], n) > 1e-6);
    }
  }
  // Distinct: no two orbits of one period share a section point, nor does one share one with
  // the other's time reversal (φ, p) → (φ, −p) of its downward crossings (rkf78's).
  for (std::size_t a = 0; a < r.orbits.size(); ++a)
    for (std::size_t b = 0; b < a; ++b) {
      const auto& u = r.orbits[a];
      const auto& v = r.orbits[b];
      if (std::fabs(u.period - v.period) > 1e-6 * u.period) continue;
      for (const auto& p : upo_rkf78_section(c, u))
        for (const auto& q : upo_rkf78_section(c, v)) CHECK(upo_distance(p, q, n) > 1e-6);
    }
}

}  // namespace

TEST_CASE("find_unstable_orbits: the double pendulum at 30 J, orbits closed by rkf78") {
  const chain c(chain_parameters::uniform(2, 1.0, 1.0, 9.81));
  const std::vector<double> start = upo_deflected_start(c, 30.0);
  REQUIRE(c.hamiltonian(start) == doctest::Approx(30.0).epsilon(1e-12));
  npend::unstable_orbit_search_options o;
  o.period_max = 4.5;
  o.search_time = 300;
  o.max_candidates = 12;
  const auto r = npend::find_unstable_orbits(c, start, o);
  CHECK(r.energy == doctest::Approx(30.0).epsilon(1e-12));
  CHECK(!r.stopped);
  CHECK(r.crossings > 50);
  CHECK(r.tried <= 12);
  CHECK(r.converged >= r.orbits.size());
  REQUIRE(r.orbits.size() >= 3);
  upo_check_orbits(c, r, o);
  // In the chaotic sea: unstable orbits, separating at rates of the order of the trajectory's
  // Lyapunov exponent (about 1/s here).
  REQUIRE(r.lyapunov_exponent > 0.3);
  const auto unstable = std::count_if(r.orbits.begin(), r.orbits.end(), [](const auto& u) {
    return !u.stable && u.lyapunov_rate > 0;
  });
  CHECK(unstable >= 3);
  double fastest = 0;
  for (const auto& u : r.orbits) fastest = std::max(fastest, u.lyapunov_rate);
  CHECK(fastest > 0.5 * r.lyapunov_exponent);
  for (const auto& u : r.orbits) CHECK((u.copies == 1 || u.copies == 2 || u.copies == 4));
}

TEST_CASE("find_unstable_orbits: the triple pendulum at 50 J has an unstable orbit") {
  const chain c(chain_parameters::uniform(3, 1.0, 1.0, 9.81));
  const std::vector<double> start = upo_deflected_start(c, 50.0);
  npend::unstable_orbit_search_options o;
  o.period_max = 4;
  o.search_time = 600;
  o.max_candidates = 8;
  const auto r = npend::find_unstable_orbits(c, start, o);
  REQUIRE(!r.orbits.empty());
  upo_check_orbits(c, r, o);
  CHECK(std::any_of(r.orbits.begin(), r.orbits.end(),
                    [](const auto& u) { return !u.stable && u.lyapunov_rate > 0.5; }));
  CHECK(r.lyapunov_exponent > 0.5);
}

TEST_CASE("find_unstable_orbits: the single pendulum's one orbit has the period 4K(k)/ω0") {
  const double g = 9.81, l = 0.7, phi0 = 2.0;
  const chain c(chain_parameters::uniform(1, 1.0, l, g));
  const std::vector<double> start{phi0, 0.0};
  npend::unstable_orbit_search_options o;
  o.period_max = 3;
  o.search_time = 20;
  o.max_candidates = 3;
  o.lyapunov = false;
  const auto r = npend::find_unstable_orbits(c, start, o);
  REQUIRE(r.orbits.size() == 1);
  const npend::unstable_orbit& u = r.orbits.front();
  const double exact = 4 * std::comp_ellint_1(std::sin(phi0 / 2)) / std::sqrt(g / l);
  CHECK(u.period == doctest::Approx(exact).epsilon(1e-10));
  CHECK(u.multipliers.empty());
  CHECK(u.lyapunov_rate == 0.0);
  CHECK(u.stable);
  CHECK(u.copies == 1);  // the swing is its own time reversal and mirror image
  CHECK(std::isnan(r.lyapunov_exponent));
  CHECK(r.duplicates + 1 == r.converged);
}

TEST_CASE("find_unstable_orbits: a period range below every orbit finds none") {
  const chain c(chain_parameters::uniform(2, 1.0, 1.0, 9.81));
  npend::unstable_orbit_search_options o;
  o.period_max = 0.5;  // the fastest linear mode's period is 0.86 s
  o.search_time = 50;
  o.lyapunov = false;
  const auto r = npend::find_unstable_orbits(c, upo_deflected_start(c, 30.0), o);
  CHECK(r.orbits.empty());
  CHECK(r.candidates == 0);
}

TEST_CASE("find_unstable_orbits: a run control stops the search") {
  struct upo_stopper final : npend::run_control {
    bool stop_requested() override { return true; }
  } stop;
  const chain c(chain_parameters::uniform(2, 1.0, 1.0, 9.81));
  npend::unstable_orbit_search_options o;
  o.period_max = 4;
  o.search_time = 100;
  o.control = &stop;
  const auto r = npend::find_unstable_orbits(c, upo_deflected_start(c, 30.0), o);
  CHECK(r.stopped);
  CHECK(r.orbits.empty());
}

TEST_CASE("find_unstable_orbits: refuses bad input with a message naming it") {
  const std::vector<double> x{1.0, 1.0, 0, 0};
  npend::unstable_orbit_search_options o;
  o.period_max = 4;
  chain_parameters damped = chain_parameters::uniform(2);
  damped.damping = {0.1, 0.0};
  CHECK_THROWS_WITH_AS(npend::find_unstable_orbits(chain(damped), x, o),
                       doctest::Contains("find_unstable_orbits: the chain is damped"),
                       std::invalid_argument);
  chain_parameters driven = chain_parameters::uniform(2);
  driven.pivot = npend::pivot_motion::vertical(0.01, 50.0);
  CHECK_THROWS_WITH_AS(npend::find_unstable_orbits(chain(driven), x, o),
                       doctest::Contains("pivot is driven"), std::invalid_argument);
  chain_parameters cart = chain_parameters::uniform(2);
  cart.cart_mass = 2.0;
  const std::vector<double> y(6, 0.5);
  CHECK_THROWS_WITH_AS(npend::find_unstable_orbits(chain(cart), y, o), doctest::Contains("cart"),
                       std::invalid_argument);
  const chain c(chain_parameters::uniform(2));
  CHECK_THROWS_WITH_AS(npend::find_unstable_orbits(c, std::vector<double>{1.0, 0.0}, o),
                       doctest::Contains("start has 2 entries"), std::invalid_argument);
  const auto refuses = [&](auto change, const char* message) {
    npend::unstable_orbit_search_options bad = o;
    change(bad);
    CHECK_THROWS_WITH_AS(npend::find_unstable_orbits(c, x, bad), doctest::Contains(message),
                         std::invalid_argument);
  };
  refuses([](auto& b) { b.period_max = 0; }, "period_max must be positive");
  refuses([](auto& b) { b.period_max = -1; }, "period_max must be positive");
  refuses([](auto& b) { b.period_min = 4; }, "period_min must be in [0, period_max");
  refuses([](auto& b) { b.period_min = -1; }, "period_min must be in [0, period_max");
  refuses([](auto& b) { b.search_time = 0; }, "search_time must be positive");
  refuses([](auto& b) { b.dt = 1000; }, "dt (1000 s) must be shorter than search_time");
  refuses([](auto& b) { b.return_tolerance = 0; }, "return_tolerance must be positive");
  refuses([](auto& b) { b.max_candidates = 0; }, "max_candidates must be >= 1");
  refuses([](auto& b) { b.max_orbits = -1; }, "max_orbits must be >= 0");
  refuses([](auto& b) { b.segment_time = 0; }, "segment_time must be positive");
}
