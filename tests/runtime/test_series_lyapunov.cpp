// The maximal Lyapunov exponent of a time series by Kantz's method (series_lyapunov.hpp):
// maps whose exponent is known (logistic r = 4: ln 2; Hénon: 0.419 per step), a regular
// pendulum motion (0, as its equations say), and the argument checks.
#include "support/test_signals.hpp"

#include "npend/analysis/lyapunov.hpp"
#include "npend/analysis/series_lyapunov.hpp"
#include "npend/excitation.hpp"
#include "npend/integrate.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace {

npend::series_lyapunov_options map_options(std::size_t dimension) {
  npend::series_lyapunov_options o;
  o.stretching.delay = 1;
  o.stretching.dimension = dimension;
  o.stretching.horizon = 20;
  return o;
}

}  // namespace

TEST_CASE("series_lyapunov_exponent: the Henon map's 0.419 per step within its uncertainty") {
  const auto r = npend::series_lyapunov_exponent(npend::test::henon_x(10000), 1.0, map_options(2));
  CAPTURE(r.maximal_exponent);
  CAPTURE(r.uncertainty);
  // The literature value 0.41922 (e.g. Sprott, Chaos and Time-Series Analysis, table A.1).
  CHECK(std::fabs(r.maximal_exponent - 0.41922) <= 3 * r.uncertainty);
  CHECK(r.uncertainty < 0.03);
  CHECK(r.automatic_range);
  CHECK(r.fit_from >= 1);
  CHECK(r.fits.size() == 3);
  REQUIRE(r.stretching.curves.size() == 3);
  // S grows from its start: the separations stretch.
  const auto& s = r.stretching.curves[1].s;
  CHECK(s[10] > s[1] + 3);
}

TEST_CASE("series_lyapunov_exponent: the logistic map at r = 4 gives ln 2, also on a given range") {
  std::vector<double> x;
  double a = 0.3;
  for (int i = 0; i < 10100; ++i) {
    a = 4 * a * (1 - a);
    if (i >= 100) x.push_back(a);
  }
  // Sampled every 0.5 s: the exponent is per second, ln 2 / 0.5.
  auto o = map_options(1);
  const auto r = npend::series_lyapunov_exponent(x, 0.5, o);
  CHECK(std::fabs(r.maximal_exponent - 2 * std::numbers::ln2) <= 3 * r.uncertainty);
  o.fit_from = 1;
  o.fit_to = 4;
  const auto given = npend::series_lyapunov_exponent(x, 0.5, o);
  CHECK_FALSE(given.automatic_range);
  CHECK(given.fit_to == 4);
  CHECK(std::fabs(given.maximal_exponent - 2 * std::numbers::ln2) <= 3 * given.uncertainty);
}

TEST_CASE("series_lyapunov_exponent: a regular pendulum motion gives 0, as its equations do") {
  // The demo's weak zigzag start (eps = 0.1): quasi-periodic motion, x_3 = sum sin(phi_i).
  const npend::chain c(npend::chain_parameters::uniform(3));
  const auto x0 = npend::deflected_state(c, npend::energy_from_epsilon(c, 0.1),
                                         std::vector<double>{1, -1, 1});
  npend::integration_options io;
  io.t_end = 600;
  io.dt = 0.01;
  std::vector<double> x3;
  npend::integrate(c, x0, io, [&](double, std::span<const double> s) {
    x3.push_back(std::sin(s[0]) + std::sin(s[1]) + std::sin(s[2]));
    return npend::observer_action::proceed;
  });
  npend::lyapunov_options lo;
  lo.integration = io;
  const auto equations = npend::maximal_lyapunov_exponent(c, x0, lo);
  npend::series_lyapunov_options o;
  o.stretching.delay = 63;  // the first minimum of the mutual information, 0.63 s
  o.stretching.dimension = 6;
  o.stretching.theiler_window = 5 * 63;
  o.stretching.horizon = 2500;
  o.stretching.step = 12;
  const auto r = npend::series_lyapunov_exponent(x3, io.dt, o);
  CAPTURE(r.maximal_exponent);
  CAPTURE(r.uncertainty);
  CAPTURE(equations.exponents[0]);
  CHECK(std::fabs(r.maximal_exponent) < 0.02);
  CHECK(std::fabs(r.maximal_exponent - equations.exponents[0]) <=
        3 * std::hypot(r.uncertainty, equations.block_standard_error[0]) + 0.01);
}

TEST_CASE("stretching_curves: bad arguments are refused with the reason") {
  using doctest::Contains;
  const auto x = npend::test::henon_x(200);
  npend::stretching_options o;
  o.delay = 0;
  CHECK_THROWS_WITH_AS(npend::stretching_curves(x, o), Contains("delay"), std::invalid_argument);
  o = {};
  o.radii = {-1};
  CHECK_THROWS_WITH_AS(npend::stretching_curves(x, o), Contains("radius"), std::invalid_argument);
  o = {};
  o.horizon = 500;
  CHECK_THROWS_WITH_AS(npend::stretching_curves(x, o), Contains("needs more than"),
                       std::invalid_argument);
  const std::vector<double> constant(500, 1.0);
  CHECK_THROWS_WITH_AS(npend::stretching_curves(constant, {}), Contains("constant"),
                       std::invalid_argument);
  auto s = map_options(2);
  s.fit_from = 5;
  s.fit_to = 50;
  CHECK_THROWS_WITH_AS(npend::series_lyapunov_exponent(npend::test::henon_x(2000), 1.0, s),
                       Contains("fit range"), std::invalid_argument);
}
