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
  npend::chain_parameters p = npend::chain_parameters::uniform(2);
  p.damping = {0.1, 0.1};
  CHECK_THROWS_AS(npend::flip_time(npend::chain(p), x, {1.0, 0.01, 0}), std::invalid_argument);
}
