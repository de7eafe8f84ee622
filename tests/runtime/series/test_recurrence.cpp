// event_times, recurrence_times and probability_histogram on events with known times.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>

#include "npend/analysis/series/event_times.hpp"
#include "npend/analysis/series/histogram.hpp"
#include "npend/analysis/series/recurrence_times.hpp"
#include "support/test_signals.hpp"

using namespace npend;
using std::numbers::pi;

namespace {

// Largest distance between equally long lists of times.
double worst_difference(const std::vector<double>& a, const std::vector<double>& b) {
  REQUIRE(a.size() == b.size());
  double worst = 0;
  for (std::size_t k = 0; k < a.size(); ++k) worst = std::max(worst, std::fabs(a[k] - b[k]));
  return worst;
}

}  // namespace

// The crossings of sin(ωt) = ½ sampled every dt, located by `how`, against the exact times
// (going up at ωt = π/6 + 2πk, down at 5π/6 + 2πk): the largest error, and the exact lists.
struct crossing_errors {
  double up, down, both;
};

crossing_errors level_crossing_errors(double dt, event_interpolation how) {
  const double omega = 2 * pi * 1.7, level = 0.5, t0 = 3.0, span = 10.0;
  const auto n = static_cast<std::size_t>(span / dt);
  const auto x = test::sum_of_sines({{1, omega, 0}}, n, dt);
  std::vector<double> g(n);
  for (std::size_t j = 0; j < n; ++j) g[j] = x[j] - level;
  std::vector<double> up, down, both;
  for (int k = 0; k < 20; ++k)
    for (const double phase : {pi / 6, 5 * pi / 6}) {
      const double t = (phase + 2 * pi * k) / omega;
      if (t > dt * static_cast<double>(n - 1)) continue;
      (phase < pi / 2 ? up : down).push_back(t0 + t);
      both.push_back(t0 + t);
    }
  return {
      worst_difference(
          event_times(g, dt, {.direction = crossing_direction::up, .interpolation = how, .t0 = t0}),
          up),
      worst_difference(
          event_times(g, dt,
                      {.direction = crossing_direction::down, .interpolation = how, .t0 = t0}),
          down),
      worst_difference(event_times(g, dt, {.interpolation = how, .t0 = t0}), both)};
}

TEST_CASE("event_times: level crossings of a sine, linear O(dt²) and cubic O(dt⁴)") {
  const auto linear = level_crossing_errors(0.01, event_interpolation::linear);
  const auto linear_half = level_crossing_errors(0.005, event_interpolation::linear);
  const auto cubic = level_crossing_errors(0.01, event_interpolation::cubic);
  const auto cubic_half = level_crossing_errors(0.005, event_interpolation::cubic);
  CHECK(cubic.both == std::max(cubic.up, cubic.down));
  // Linear: error ≈ x'' dt²/(8 x') ≈ 7e-5 s at dt = 0.01; halving dt quarters it.
  CHECK(linear.both < 2e-4);
  CHECK(linear.both / linear_half.both == doctest::Approx(4).epsilon(0.1));
  // Cubic: two orders more.
  CHECK(cubic.both < 1e-6);
  CHECK(cubic.both / cubic_half.both == doctest::Approx(16).epsilon(0.25));
}

TEST_CASE("event_times: stretched neighbours — two signals crossing") {
  // sin ωt = cos ωt at ωt = π/4 + kπ.
  const double omega = 3.0, dt = 0.005;
  const auto a = test::sum_of_sines({{1, omega, 0}}, 4000, dt);
  const auto b = test::sum_of_sines({{1, omega, pi / 2}}, 4000, dt);
  std::vector<double> g(a.size());
  for (std::size_t j = 0; j < g.size(); ++j) g[j] = a[j] - b[j];
  std::vector<double> expected;
  for (int k = 0; (pi / 4 + k * pi) / omega < dt * 3999; ++k)
    expected.push_back((pi / 4 + k * pi) / omega);
  CHECK(worst_difference(event_times(g, dt), expected) < 1e-9);
}

TEST_CASE("recurrence_times: the intervals of a pure oscillation are its half period") {
  const double omega = 2 * pi * 1.3, dt = 0.001;
  const auto x = test::sum_of_sines({{0.8, omega, 0.3}}, 16384, dt);
  const auto times = event_times(x, dt);
  const auto r = recurrence_times(times);
  REQUIRE(r.intervals.size() == times.size() - 1);
  REQUIRE(r.intervals.size() > 30);
  for (const double t : r.intervals) CHECK(t == doctest::Approx(pi / omega).epsilon(1e-9));
  CHECK(r.mean == doctest::Approx(pi / omega).epsilon(1e-10));
  CHECK(r.standard_deviation < 1e-9);
  // Equal intervals: one bin holding all of them, a density integrating to 1.
  REQUIRE(r.distribution.density.size() == 1);
  CHECK(r.distribution.counts[0] == r.intervals.size());
  CHECK(r.distribution.density[0] * (r.distribution.edges[1] - r.distribution.edges[0]) ==
        doctest::Approx(1).epsilon(1e-12));
}

TEST_CASE("recurrence_times: exact event times go straight in") {
  const std::vector<double> times{0, 1, 3, 4, 6, 7, 9, 10, 12};
  const auto r = recurrence_times(times, {.bins = 2});
  CHECK(r.intervals == std::vector<double>{1, 2, 1, 2, 1, 2, 1, 2});
  CHECK(r.mean == 1.5);
  CHECK(r.standard_deviation == doctest::Approx(std::sqrt(8 * 0.25 / 7)));
  CHECK(r.distribution.counts == std::vector<std::size_t>{4, 4});
  // Alternating intervals: the whole spectrum sits at ω = π rad/event.
  const auto& p = r.spectrum.power;
  CHECK(std::max_element(p.begin(), p.end()) - p.begin() == static_cast<long>(p.size() - 1));
  CHECK(r.spectrum.omega.back() == doctest::Approx(pi));
  CHECK_THROWS_WITH_AS(recurrence_times(std::vector<double>{0, 1}),
                       "event_times has 2 events; at least 3 are needed for two intervals",
                       std::invalid_argument);
  CHECK_THROWS_AS(recurrence_times(std::vector<double>{0, 2, 1}), std::invalid_argument);
}

TEST_CASE("probability_histogram: counts, unit area, Freedman-Diaconis bins") {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<double> v(8000);
  for (auto& x : v) x = u(rng);
  const auto h = probability_histogram(v);
  // Uniform: IQR ≈ 1/2 (± O(N^−½)), so h = 2 IQR N^(−1/3) ≈ 0.05: about 20 bins over [0, 1).
  CHECK(h.counts.size() >= 19);
  CHECK(h.counts.size() <= 21);
  const auto fixed = probability_histogram(v, 7);
  REQUIRE(fixed.counts.size() == 7);
  double area = 0;
  std::size_t total = 0;
  for (std::size_t b = 0; b < 7; ++b) {
    std::size_t count = 0;
    for (const double x : v)
      if (x >= fixed.edges[b] && (x < fixed.edges[b + 1] || (b == 6 && x <= fixed.edges[7])))
        ++count;
    CHECK(fixed.counts[b] == count);
    total += count;
    area += fixed.density[b] * (fixed.edges[b + 1] - fixed.edges[b]);
  }
  CHECK(total == v.size());
  CHECK(area == doctest::Approx(1).epsilon(1e-12));
  CHECK(fixed.edges.front() == *std::min_element(v.begin(), v.end()));
  CHECK(fixed.edges.back() == *std::max_element(v.begin(), v.end()));
}

TEST_CASE("event_times: bad arguments throw naming them") {
  CHECK_THROWS_WITH_AS(event_times(std::vector<double>{1}, 0.1),
                       "g has 1 samples; at least 2 are needed", std::invalid_argument);
  CHECK_THROWS_WITH_AS(event_times(std::vector<double>{1, INFINITY}, 0.1),
                       "g[1] is not finite (inf)", std::invalid_argument);
  CHECK_THROWS_AS(event_times(std::vector<double>{1, -1}, 0), std::invalid_argument);
}
