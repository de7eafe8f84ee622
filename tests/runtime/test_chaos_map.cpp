// The chaos map's cells (analysis/chaos_map.hpp): the energy bound on flips against Heyl's
// closed forms for the double pendulum from rest, and the flip time against a gauss6
// integration that looks for the flip on its own.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "npend/analysis/chaos_map.hpp"
#include "npend/integrate.hpp"

TEST_CASE("chaos map: the energy bound on flips is Heyl's for point masses and for rods") {
  // From rest, E = m g l (3 - 2 cos phi1 - cos phi2) for point masses: the second arm can
  // only flip if E >= 2 m g l, i.e. 2 cos phi1 + cos phi2 <= 1. For uniform rods E =
  // m g l (3/2 (1 - cos phi1) + 1/2 (1 - cos phi2)) and the bound is 3 cos phi1 + cos phi2 <= 2.
  const npend::chain points(npend::chain_parameters::uniform(2));
  npend::chain_parameters p = npend::chain_parameters::uniform(2);
  p.make_uniform_rods();
  const npend::chain rods(p);
  for (double a = -3.0; a <= 3.0; a += 0.37)
    for (double b = -3.0; b <= 3.0; b += 0.41) {
      const std::vector<double> x{a, b, 0, 0};
      INFO("phi = (" << a << ", " << b << ")");
      CHECK(npend::energy_forbids_flip(points, x) == (2 * std::cos(a) + std::cos(b) > 1));
      CHECK(npend::energy_forbids_flip(rods, x) == (3 * std::cos(a) + std::cos(b) > 2));
    }
}

TEST_CASE("chaos map: the flip time agrees with a gauss6 run watching the angles") {
  const npend::chain c(npend::chain_parameters::uniform(2));
  for (const auto& start : {std::vector<double>{2.0, 2.5, 0, 0},
                            {-1.5, 2.9, 0, 0},
                            std::vector<double>{2.8, -0.3, 0, 0}}) {
    const double t_flip = npend::flip_time(c, start, {30.0, 0.01, 0});
    REQUIRE(std::isfinite(t_flip));
    // gauss6 at dt = 1e-3, stopped at the first grid point where an arm is past upright.
    npend::integration_options o;
    o.t_end = 30;
    o.dt = 1e-3;
    double seen = std::numeric_limits<double>::infinity();
    npend::integrate(c, start, o, [&](double t, std::span<const double> x) {
      if (std::fabs(x[0]) >= std::numbers::pi || std::fabs(x[1]) >= std::numbers::pi) {
        seen = t;
        return npend::observer_action::stop;
      }
      return npend::observer_action::proceed;
    });
    INFO("start (" << start[0] << ", " << start[1] << "): rk4 " << t_flip << " s, gauss6 " << seen
                   << " s");
    // rk4's flip is the end of the step that crossed: within one step of the true time.
    CHECK(std::fabs(t_flip - seen) <= 0.0101);
  }
  // Ruled out by the energy: +inf without integrating; arm 1 alone flips later or never.
  CHECK(std::isinf(npend::flip_time(c, std::vector<double>{0.5, 0.5, 0, 0}, {30.0, 0.01, 0})));
  CHECK(npend::flip_time(c, std::vector<double>{2.0, 2.5, 0, 0}, {30.0, 0.01, 1}) >=
        npend::flip_time(c, std::vector<double>{2.0, 2.5, 0, 0}, {30.0, 0.01, 0}));
}

TEST_CASE("chaos map: bad options and chains are refused") {
  const npend::chain c(npend::chain_parameters::uniform(2));
  const std::vector<double> x{2.0, 2.5, 0, 0};
  CHECK_THROWS_AS(npend::flip_time(c, x, {1.0, 0.0, 0}), std::invalid_argument);
  CHECK_THROWS_AS(npend::flip_time(c, x, {1.0, 0.01, 3}), std::invalid_argument);
  CHECK_THROWS_AS(npend::flip_time(c, std::vector<double>{1.0, 0}, {1.0, 0.01, 0}),
                  std::invalid_argument);
}

TEST_CASE("chaos map: the energy bound holds with springs and damping, and not under a drive") {
  // Point masses m = l = 1 from rest with springs k_1, k_2 (rest angles 0) on the joint angles
  // θ_1 = φ_1, θ_2 = φ_2 − φ_1: H = g (3 − 2 cos φ1 − cos φ2) + ½ k_1 φ1² + ½ k_2 (φ2 − φ1)²,
  // and arm 2 upright needs at least V = 2 g (arm 1: 4 g). Springs only add energy that is
  // never negative, and damping only takes energy out, so H < 2 g still rules a flip out.
  npend::chain_parameters p = npend::chain_parameters::uniform(2);
  p.stiffness = {3.0, 1.5};
  p.rest_angles = {0.0, 0.0};
  npend::chain_parameters damped = p;
  damped.damping = {0.4, 0.2};
  const npend::chain springs(p), both(damped);
  npend::chain_parameters driven = npend::chain_parameters::uniform(2);
  driven.pivot = npend::pivot_motion::vertical(0.05, 30);
  const npend::chain drive(driven);
  const double g = p.g;
  long ruled_out = 0;
  for (double a = -3.0; a <= 3.0; a += 0.37)
    for (double b = -3.0; b <= 3.0; b += 0.41) {
      const std::vector<double> x{a, b, 0, 0};
      const double h = g * (3 - 2 * std::cos(a) - std::cos(b)) + 0.5 * 3.0 * a * a +
                       0.5 * 1.5 * (b - a) * (b - a);
      INFO("phi = (" << a << ", " << b << "), H = " << h);
      CHECK(springs.hamiltonian(x) == doctest::Approx(h).epsilon(1e-12));
      CHECK(npend::energy_forbids_flip(springs, x) == (h < 2 * g));
      CHECK(npend::energy_forbids_flip(both, x) == (h < 2 * g));
      CHECK_FALSE(npend::energy_forbids_flip(drive, x));
      ruled_out += h < 2 * g ? 1 : 0;
    }
  CHECK(ruled_out > 0);
  // A drive of zero amplitude leaves the fixed-pivot chain (on the other kernels: the same
  // flip to within a step).
  const std::vector<double> x{2.0, 2.5, 0, 0};
  const npend::flip_options o{30.0, 0.01, 0};
  const double free_flip = npend::flip_time(npend::chain(npend::chain_parameters::uniform(2)), x, o);
  REQUIRE(std::isfinite(free_flip));
  npend::chain_parameters still = npend::chain_parameters::uniform(2);
  still.pivot = npend::pivot_motion::vertical(0.0, 30);
  CHECK(std::fabs(npend::flip_time(npend::chain(still), x, o) - free_flip) <= o.dt);
}
