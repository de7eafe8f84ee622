// Validity of the harmonic approximation (paper §6.4): backbone curves of the normal modes.
// The single pendulum's frequency is known exactly (ω = π ω₀ / (2 K(sin(θ₀/2))), K the
// complete elliptic integral of the first kind); the chains' backbones start quadratically.
#include <doctest/doctest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>

#include "npend/analysis/stability/backbone.hpp"
#include "npend/analysis/stability/normal_modes.hpp"
#include "support/test_support.hpp"

using npend::chain;
using npend::chain_parameters;

namespace {

using npend::pendulum_frequency_ratio;

// The amplitude at which the exact ratio is 1 − shift (it falls monotonically), by bisection.
double pendulum_threshold(double shift) {
  double low = 0, high = 3;
  for (int k = 0; k < 60; ++k) {
    const double middle = 0.5 * (low + high);
    (1 - pendulum_frequency_ratio(middle) < shift ? low : high) = middle;
  }
  return 0.5 * (low + high);
}

}  // namespace

TEST_CASE("measure_mode_frequency: a single pendulum swings at the elliptic integral's frequency") {
  const chain c(chain_parameters{{0.7}, {1.3}, 9.81});
  const double omega0 = std::sqrt(9.81 / 1.3);
  for (double amplitude : {0.05, 0.5, 1.5, 2.5, 3.0}) {
    CAPTURE(amplitude);
    const auto p = npend::measure_mode_frequency(c, 1, amplitude);
    REQUIRE(p.measured);
    CHECK(p.frequency ==
          doctest::Approx(omega0 * pendulum_frequency_ratio(amplitude)).epsilon(1e-9));
    CHECK(p.relative_shift ==
          doctest::Approx(pendulum_frequency_ratio(amplitude) - 1).epsilon(1e-8));
    CHECK(p.period_spread < 1e-8);   // a periodic orbit
    CHECK(p.min_mode_share == 1.0);  // one mode only
    CHECK(p.energy == doctest::Approx(0.7 * 9.81 * 1.3 * (1 - std::cos(amplitude))).epsilon(1e-14));
  }
}

TEST_CASE("backbone_curve: the single pendulum's 1 % and 5 % amplitudes") {
  const chain c(chain_parameters::uniform(1));
  std::vector<double> amplitudes;
  for (int k = 1; k <= 12; ++k) amplitudes.push_back(0.1 * k);
  const auto r = npend::backbone_curve(c, 1, amplitudes);
  CHECK(r.linear_frequency == doctest::Approx(std::sqrt(9.81)).epsilon(1e-14));
  REQUIRE(r.points.size() == 12);
  REQUIRE(r.thresholds.size() == 2);
  for (const auto& t : r.thresholds) {
    CAPTURE(t.shift);
    REQUIRE(t.amplitude.has_value());
    CHECK(std::fabs(*t.amplitude - pendulum_threshold(t.shift)) < 1e-4);
    CHECK(t.energy == doctest::Approx(9.81 * (1 - std::cos(*t.amplitude))).epsilon(1e-12));
  }
  // A shift beyond the scanned amplitudes is not reached.
  npend::backbone_options far;
  far.thresholds = {0.5};
  CHECK_FALSE(npend::backbone_curve(c, 1, amplitudes, far).thresholds[0].amplitude.has_value());
}

TEST_CASE(
    "backbone_curve: every mode of a chain starts at its normal-mode frequency, shifting with "
    "a^2") {
  std::mt19937_64 rng(45);
  const chain c(npend::test::random_parameters(3, rng));
  const auto lin = npend::normal_modes(c, std::vector<double>(3, 0.0));
  for (int mode = 1; mode <= 3; ++mode) {
    CAPTURE(mode);
    const auto r = npend::backbone_curve(c, mode, std::vector<double>{0.02, 0.01});
    CHECK(r.linear_frequency == lin.modes[static_cast<std::size_t>(mode - 1)].frequency);
    CHECK(r.points[0].amplitude == 0.01);  // ascending
    const auto& small = r.points[0];
    const auto& twice = r.points[1];
    // The backbone ω(a) = ω_k (1 + c a² + O(a⁴)): the shift quadruples when a doubles.
    CHECK(std::fabs(small.relative_shift) < 1e-3);
    CHECK(twice.relative_shift / small.relative_shift == doctest::Approx(4).epsilon(0.01));
    // Launched along its shape, the motion stays in the mode.
    CHECK(small.min_mode_share > 0.9999);
    CHECK(small.period_spread < 1e-4);
  }
}

TEST_CASE("backbone_curve: thresholds lie where the measured shift reaches them") {
  const chain c(chain_parameters::uniform(2));
  const auto r = npend::backbone_curve(c, 2, std::vector<double>{0.1, 0.2, 0.3, 0.4, 0.5, 0.6});
  REQUIRE(r.thresholds[0].amplitude.has_value());
  REQUIRE(r.thresholds[1].amplitude.has_value());
  CHECK(*r.thresholds[0].amplitude < *r.thresholds[1].amplitude);
  for (const auto& t : r.thresholds) {
    CAPTURE(t.shift);
    const double a = *t.amplitude;
    const auto below = npend::measure_mode_frequency(c, 2, a - 2e-4);
    const auto above = npend::measure_mode_frequency(c, 2, a + 2e-4);
    CHECK(std::fabs(below.relative_shift) < t.shift);
    CHECK(std::fabs(above.relative_shift) >= t.shift);
  }
}

TEST_CASE("backbone_curve: bad arguments are refused with the reason") {
  using doctest::Contains;
  const chain c(chain_parameters::uniform(2));
  CHECK_THROWS_WITH_AS(npend::backbone_curve(c, 0, std::vector<double>{0.1}),
                       Contains("mode 0 does not exist"), std::invalid_argument);
  CHECK_THROWS_WITH_AS(npend::backbone_curve(c, 3, std::vector<double>{0.1}),
                       Contains("modes 1..2"), std::invalid_argument);
  CHECK_THROWS_WITH_AS(npend::backbone_curve(c, 1, std::vector<double>{}),
                       Contains("no amplitudes"), std::invalid_argument);
  CHECK_THROWS_WITH_AS(npend::backbone_curve(c, 1, std::vector<double>{0.1, 3.2}),
                       Contains("not in (0, pi)"), std::invalid_argument);
  CHECK_THROWS_WITH_AS(npend::measure_mode_frequency(c, 1, -0.1), Contains("not in (0, pi)"),
                       std::invalid_argument);
  npend::backbone_options o;
  o.periods = 2;
  CHECK_THROWS_WITH_AS(npend::measure_mode_frequency(c, 1, 0.1, o), Contains("periods"),
                       std::invalid_argument);
  o = {};
  o.thresholds = {0.01, 1.5};
  CHECK_THROWS_WITH_AS(npend::measure_mode_frequency(c, 1, 0.1, o), Contains("threshold 1.5"),
                       std::invalid_argument);
}

TEST_CASE("pendulum_period: 2 pi sqrt(l/g) for small swings, and the amplitude series beyond") {
  const double l = 1.3, g = 9.81, small = 2 * std::numbers::pi * std::sqrt(l / g);
  CHECK(npend::pendulum_period(0.0, l, g) == doctest::Approx(small).epsilon(1e-15));
  CHECK(npend::pendulum_period(1e-4, l, g) == doctest::Approx(small).epsilon(1e-9));
  // T = T₀ (1 + a²/16 + 11 a⁴/3072 + 173 a⁶/737280 + 22931 a⁸/1321205760 + …); the next
  // term is below 1e-11 of T₀ at a = 0.3.
  for (const double a : {0.1, 0.3}) {
    CAPTURE(a);
    const double a2 = a * a;
    const double series = small * (1 + a2 / 16 + 11 * a2 * a2 / 3072 + 173 * a2 * a2 * a2 / 737280 +
                                   22931 * a2 * a2 * a2 * a2 / 1321205760);
    CHECK(npend::pendulum_period(a, l, g) == doctest::Approx(series).epsilon(1e-11));
    // The frequency ratio is T₀ / T.
    CHECK(pendulum_frequency_ratio(a) == doctest::Approx(small / series).epsilon(1e-11));
  }
  // Near the top the period grows without bound, like (4/ω₀) ln(8/(π − a)) for a → π (the
  // next term is (π − a)²/16 of it: 6e-8 at 1e-3 rad from the top).
  const double close = std::numbers::pi - 1e-3;
  CHECK(npend::pendulum_period(close, l, g) ==
        doctest::Approx(4 * std::sqrt(l / g) * std::log(8 / (std::numbers::pi - close)))
            .epsilon(1e-6));
  CHECK(pendulum_frequency_ratio(0.0) == doctest::Approx(1.0).epsilon(1e-15));
  CHECK_THROWS_AS(npend::pendulum_period(std::numbers::pi, l, g), std::invalid_argument);
  CHECK_THROWS_AS(npend::pendulum_period(-0.1, l, g), std::invalid_argument);
  CHECK_THROWS_AS(npend::pendulum_period(0.5, 0.0, g), std::invalid_argument);
  CHECK_THROWS_AS(npend::pendulum_period(0.5, l, -1.0), std::invalid_argument);
  CHECK_THROWS_AS(pendulum_frequency_ratio(4.0), std::invalid_argument);
}
