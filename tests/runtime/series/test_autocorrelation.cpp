// autocorrelation: the Wiener–Khinchin route against direct sums and a sine's cosine.
#include <doctest/doctest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>

#include "npend/analysis/series/autocorrelation.hpp"
#include "support/test_signals.hpp"

using namespace npend;

TEST_CASE("autocorrelation: equals the direct linear (not circular) sum at every lag") {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1, 2);
  std::vector<double> x(300);
  for (auto& v : x) v = u(rng);
  double mean = 0;
  for (double v : x) mean += v / static_cast<double>(x.size());
  const auto c = autocorrelation(x, 0.5);
  REQUIRE(c.value.size() == x.size());
  double zero = 0;
  for (double v : x) zero += (v - mean) * (v - mean);
  for (std::size_t k = 0; k < x.size(); ++k) {
    double direct = 0;  // only the N − k overlapping products: no wrap-around
    for (std::size_t j = 0; j + k < x.size(); ++j) direct += (x[j] - mean) * (x[j + k] - mean);
    CHECK(c.value[k] == doctest::Approx(direct / zero).epsilon(1e-12).scale(1));
    CHECK(c.lag[k] == 0.5 * static_cast<double>(k));
  }
  CHECK(c.value[0] == doctest::Approx(1).epsilon(1e-15));
}

TEST_CASE("autocorrelation: of a sine is a cosine, first zero at T/4, first minimum at T/2") {
  const double dt = 0.001, omega = 2 * std::numbers::pi * 3.0,
               period = 2 * std::numbers::pi / omega;
  const std::size_t n = 16384;
  const auto x = test::sum_of_sines({{1.3, omega, 0.4}}, n, dt, 0.7);
  const auto c = autocorrelation(x, dt, n / 2);
  REQUIRE(c.value.size() == n / 2 + 1);
  double worst = 0;
  for (std::size_t k = 0; k <= n / 2; ++k) {
    // The biased estimate tapers the cosine by the overlap (N − k)/N.
    const double expected =
        (1 - static_cast<double>(k) / n) * std::cos(omega * static_cast<double>(k) * dt);
    worst = std::max(worst, std::fabs(c.value[k] - expected));
  }
  // Edge terms of a finite sine are O(1/(ω N dt)) ≈ 3e-3.
  CHECK(worst < 5e-3);
  REQUIRE(c.first_zero);
  REQUIRE(c.first_minimum);
  CHECK(*c.first_zero == doctest::Approx(period / 4).epsilon(1e-3));
  CHECK(*c.first_minimum == doctest::Approx(period / 2).epsilon(2e-3));
}

TEST_CASE(
    "autocorrelation: a monotone ramp has neither a zero within a short lag range nor a minimum") {
  std::vector<double> ramp(100);
  for (std::size_t j = 0; j < ramp.size(); ++j) ramp[j] = static_cast<double>(j);
  const auto c = autocorrelation(ramp, 1.0, 10);
  CHECK_FALSE(c.first_zero);
  CHECK_FALSE(c.first_minimum);
  CHECK(c.value.size() == 11);
}

TEST_CASE("autocorrelation: bad arguments throw naming them") {
  CHECK_THROWS_WITH_AS(autocorrelation(std::vector<double>(10, 2.0), 0.1),
                       "x is constant: its autocorrelation is undefined", std::invalid_argument);
  const std::vector<double> x{1, 2, 3};
  CHECK_THROWS_WITH_AS(autocorrelation(x, 0.1, 3), "max_lag must be below the 3 samples, got 3",
                       std::invalid_argument);
  CHECK_THROWS_AS(autocorrelation(x, -1), std::invalid_argument);
}

TEST_CASE("autocorrelation: the unbiased estimate divides lag k by N - k") {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1, 2);
  std::vector<double> x(257);
  for (auto& v : x) v = u(rng);
  const double n = static_cast<double>(x.size());
  double mean = 0;
  for (double v : x) mean += v / n;
  double variance = 0;  // Σ y² / N
  for (double v : x) variance += (v - mean) * (v - mean) / n;
  const auto c = autocorrelation(x, 0.1, 200, autocorrelation_estimator::unbiased);
  for (std::size_t k = 0; k <= 200; ++k) {
    double direct = 0;
    for (std::size_t j = 0; j + k < x.size(); ++j) direct += (x[j] - mean) * (x[j + k] - mean);
    direct /= n - static_cast<double>(k);
    CHECK(c.value[k] == doctest::Approx(direct / variance).epsilon(1e-11).scale(1));
  }
  // For a sine of whole periods there is no (1 − τ/T) taper: C(τ) = cos(ωτ) up to the
  // edge effects of the finite window (a few per cent at half the series).
  const double dt = 0.001, omega = 2 * std::numbers::pi * 4.0;
  const auto s = test::sum_of_sines({{1.0, omega, 0.0}}, 8000, dt, 0.0);
  const auto biased = autocorrelation(s, dt, 4000);
  const auto unbiased = autocorrelation(s, dt, 4000, autocorrelation_estimator::unbiased);
  const std::size_t half = 4000;  // τ = 4 s, a whole number of periods: cos = 1
  CHECK(unbiased.value[half] == doctest::Approx(1).epsilon(0.02));
  CHECK(biased.value[half] == doctest::Approx(0.5).epsilon(0.02));
  CHECK(autocorrelation_estimator_from_name("unbiased") == autocorrelation_estimator::unbiased);
  CHECK(!autocorrelation_estimator_from_name("fair"));
}
