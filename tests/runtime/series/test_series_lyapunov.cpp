// The maximal Lyapunov exponent of a time series by Kantz's method (series_lyapunov.hpp):
// maps whose exponent is known (logistic r = 4: ln 2; Hénon: 0.419 per step), a regular
// pendulum motion (0, as its equations say), and the argument checks.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "npend/analysis/chaos/lyapunov.hpp"
#include "npend/analysis/series/series_lyapunov.hpp"
#include "npend/excitation.hpp"
#include "npend/integrators/integrate.hpp"
#include "support/test_signals.hpp"

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
  const auto x0 =
      npend::deflected_state(c, npend::energy_from_epsilon(c, 0.1), std::vector<double>{1, -1, 1});
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

namespace {

// The bob positions x_k, y_k and velocities of the chain's trajectory from x0 over t_end at
// dt (gauss6): what a camera tracking the three bobs measures.
struct tracked_bobs {
  std::vector<std::vector<double>> observables;  // x_1, y_1, …, then vx_1, vy_1, …
  std::vector<double> x3;
};

tracked_bobs track(const npend::chain& c, const std::vector<double>& x0, double t_end, double dt) {
  const int n = c.links();
  const auto& l = c.parameters().lengths;
  npend::integration_options io;
  io.t_end = t_end;
  io.dt = dt;
  tracked_bobs out;
  out.observables.assign(static_cast<std::size_t>(4 * n), {});
  std::vector<double> xy(static_cast<std::size_t>(2 * n)), dphi(static_cast<std::size_t>(n));
  npend::integrate(c, x0, io, [&](double, std::span<const double> s) {
    const auto phi = s.first(static_cast<std::size_t>(n));
    c.positions(phi, xy);
    c.velocities(phi, s.subspan(static_cast<std::size_t>(n)), dphi);
    double vx = 0, vy = 0;  // v_k = Σ_{i≤k} l_i φ̇_i (cos φ_i, −sin φ_i)
    for (std::size_t k = 0; k < static_cast<std::size_t>(n); ++k) {
      vx += l[k] * dphi[k] * std::cos(phi[k]);
      vy -= l[k] * dphi[k] * std::sin(phi[k]);
      out.observables[2 * k].push_back(xy[2 * k]);
      out.observables[2 * k + 1].push_back(xy[2 * k + 1]);
      out.observables[static_cast<std::size_t>(2 * n) + 2 * k].push_back(vx);
      out.observables[static_cast<std::size_t>(2 * n) + 2 * k + 1].push_back(vy);
    }
    out.x3.push_back(xy[4]);
    return npend::observer_action::proceed;
  });
  return out;
}

// The command line's defaults for several columns: dimension 1, the delay only as the
// Theiler window, a horizon of 40 delays.
npend::series_lyapunov_options multivariate_options(std::size_t delay) {
  npend::series_lyapunov_options o;
  o.stretching.delay = delay;
  o.stretching.dimension = 1;
  o.stretching.theiler_window = delay;
  o.stretching.horizon = 40 * delay;
  o.stretching.step = o.stretching.horizon / 200;
  return o;
}

}  // namespace

TEST_CASE(
    "series_lyapunov_exponent: tracked bobs of the chaotic triple pendulum give its lambda_1") {
  // The strong start φ = (1.5, 1.5, 1.5): the tangent map's maximal exponent of the same run
  // against Kantz's estimate from the six bob positions and velocities, standardised and
  // embedded side by side (2·10⁵ samples at dt = 0.01 s).
  const npend::chain c(npend::chain_parameters::uniform(3));
  const std::vector<double> x0{1.5, 1.5, 1.5, 0, 0, 0};
  constexpr double dt = 0.01, t_end = 2000;
  const tracked_bobs bobs = track(c, x0, t_end, dt);
  npend::lyapunov_options lo;
  lo.integration.t_end = t_end;
  lo.integration.dt = dt;
  const auto equations = npend::maximal_lyapunov_exponent(c, x0, lo);
  const auto r = npend::series_lyapunov_exponent(npend::standardised_series(bobs.observables), dt,
                                                 multivariate_options(54));
  CAPTURE(r.maximal_exponent);
  CAPTURE(r.uncertainty);
  CAPTURE(r.fit_from);
  CAPTURE(r.fit_to);
  CAPTURE(equations.exponents[0]);
  CHECK(r.linear_region);
  CHECK(equations.exponents[0] > 1);
  CHECK(std::fabs(r.maximal_exponent - equations.exponents[0]) <= r.uncertainty);
  CHECK(r.uncertainty < 0.35);

  // The horizontal position of the third bob alone, embedded with the command's defaults
  // (m = 6, τ from the mutual information): its delay vectors' neighbours are false
  // neighbours, the curve has no linear region, and no exponent is claimed.
  npend::series_lyapunov_options scalar;
  scalar.stretching.delay = 67;  // 0.67 s, the first minimum of the mutual information
  scalar.stretching.dimension = 6;
  scalar.stretching.theiler_window = 5 * 67;
  scalar.stretching.horizon = 40 * 67;
  scalar.stretching.step = scalar.stretching.horizon / 200;
  const auto alone = npend::series_lyapunov_exponent(bobs.x3, dt, scalar);
  CAPTURE(alone.maximal_exponent);
  CHECK_FALSE(alone.linear_region);
  CHECK(alone.nonlinearity.find("false neighbours") != std::string::npos);
}

TEST_CASE("series_lyapunov_exponent: tracked bobs of a regular motion give 0") {
  const npend::chain c(npend::chain_parameters::uniform(3));
  const std::vector<double> x0{0.1, 0.1, 0.1, 0, 0, 0};
  const tracked_bobs bobs = track(c, x0, 1000, 0.01);
  const auto r = npend::series_lyapunov_exponent(npend::standardised_series(bobs.observables), 0.01,
                                                 multivariate_options(54));
  CAPTURE(r.maximal_exponent);
  CAPTURE(r.uncertainty);
  CHECK(r.linear_region);
  CHECK(std::fabs(r.maximal_exponent) < 0.02);
}

TEST_CASE("stretching_curves: several series must be sampled together, standardised_series") {
  const std::vector<std::vector<double>> uneven{npend::test::henon_x(500),
                                                npend::test::henon_x(400)};
  CHECK_THROWS_WITH_AS(npend::stretching_curves(uneven, map_options(1).stretching),
                       doctest::Contains("sampled together"), std::invalid_argument);
  const std::vector<std::vector<double>> scaled =
      npend::standardised_series(std::vector<std::vector<double>>{{1.0, 3.0, 5.0, 7.0}});
  // Mean 4, standard deviation √5.
  CHECK(scaled[0][0] == doctest::Approx(-3 / std::sqrt(5.0)).epsilon(1e-15));
  CHECK(scaled[0][3] == doctest::Approx(3 / std::sqrt(5.0)).epsilon(1e-15));
  CHECK_THROWS_AS(npend::standardised_series(std::vector<std::vector<double>>{{2.0, 2.0}}),
                  std::invalid_argument);
  // One series side by side with itself doubles the squared distances: the curves shift by
  // ln √2 and the slope stays.
  const std::vector<double> h = npend::test::henon_x(4000);
  const auto one = npend::stretching_curves(h, map_options(2).stretching);
  auto o = map_options(2).stretching;
  o.radii = {one.curves[1].radius * std::sqrt(2.0)};
  auto single = map_options(2).stretching;
  single.radii = {one.curves[1].radius};
  const auto a = npend::stretching_curves(h, single);
  const auto b = npend::stretching_curves(std::vector<std::vector<double>>{h, h}, o);
  for (std::size_t p = 0; p < a.steps.size(); ++p)
    CHECK(b.curves[0].s[p] ==
          doctest::Approx(a.curves[0].s[p] + 0.5 * std::log(2.0)).epsilon(1e-12));
}

TEST_CASE("kantz_options: the defaults for one series and for several, counted by hand") {
  // One series: m = 6, the Theiler window (m − 1)τ, the horizon 40 τ within a quarter of
  // the series, evaluated at every sample up to 200 points.
  auto o = npend::kantz_options(10000, 1, {.delay = 7});
  CHECK(o.stretching.delay == 7);
  CHECK(o.stretching.dimension == 6);
  CHECK(o.stretching.theiler_window == 35);
  CHECK(o.stretching.horizon == 280);
  CHECK(o.stretching.step == 1);
  CHECK_FALSE(o.fit_from.has_value());
  // A short series: a quarter of its 1000 samples bounds the horizon.
  o = npend::kantz_options(1000, 1, {.delay = 10});
  CHECK(o.stretching.horizon == 250);
  // Several series: the observables themselves (m = 1), the window at least one delay; a
  // horizon of 4000 samples is evaluated every 20th.
  o = npend::kantz_options(100000, 3, {.delay = 100});
  CHECK(o.stretching.dimension == 1);
  CHECK(o.stretching.theiler_window == 100);
  CHECK(o.stretching.horizon == 4000);
  CHECK(o.stretching.step == 20);
  // What is chosen stays, except a horizon below 2 samples.
  o = npend::kantz_options(
      1000, 1,
      {.delay = 3, .dimension = 2, .theiler_window = 0, .horizon = 1, .radii = {0.5, 1.0}});
  CHECK(o.stretching.dimension == 2);
  CHECK(o.stretching.theiler_window == 0);
  CHECK(o.stretching.horizon == 2);
  CHECK(o.stretching.radii == std::vector<double>{0.5, 1.0});
  o = npend::kantz_options(1000, 1, {.delay = 3, .fit_from = 0.1, .fit_to = 0.4});
  CHECK(o.fit_from == 0.1);
  CHECK(o.fit_to == 0.4);
  CHECK(npend::kantz_dimension(1) == 6);
  CHECK(npend::kantz_dimension(4) == 1);
  CHECK_THROWS_AS(npend::kantz_dimension(0), std::invalid_argument);
  CHECK_THROWS_AS(npend::kantz_options(1000, 1, {.delay = 0}), std::invalid_argument);
  CHECK_THROWS_AS(npend::kantz_options(0, 1, {.delay = 1}), std::invalid_argument);
  CHECK_THROWS_AS(npend::kantz_options(1000, 0, {.delay = 1}), std::invalid_argument);
  CHECK_THROWS_AS(npend::kantz_options(1000, 1, {.delay = 1, .dimension = 0}),
                  std::invalid_argument);
}

TEST_CASE("series_lyapunov_exponent: a sine's curve barely rises, and the result warns of it") {
  // Motion on a closed loop: neighbours keep their distance, S stays flat (rise ≈ 0).
  const double dt = 0.01, period = 1.2345;
  std::vector<double> x;
  for (int j = 0; j < 4000; ++j) x.push_back(std::sin(2 * std::numbers::pi * j * dt / period));
  const auto o = npend::kantz_options(x.size(), 1, {.delay = 31});
  const auto r = npend::series_lyapunov_exponent(x, dt, o);
  double low = INFINITY, high = -INFINITY;
  for (double v : r.stretching.curves[r.stretching.curves.size() / 2].s)
    if (std::isfinite(v)) {
      low = std::min(low, v);
      high = std::max(high, v);
    }
  CHECK(r.rise == high - low);
  CHECK(r.rise < 3);
  bool warned = false;
  for (const auto& w : r.warnings)
    warned = warned || w.starts_with("the stretching curve rises by only");
  CHECK(warned);
  // Without a linear region the first warning says so, with the reason.
  if (!r.linear_region) CHECK(r.warnings.front() == "no estimate: " + r.nonlinearity);
}
