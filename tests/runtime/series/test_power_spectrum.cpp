// power_spectrum and find_spectral_peaks on signals whose spectra are known.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <random>
#include <stdexcept>

#include "npend/analysis/series/power_spectrum.hpp"
#include "npend/analysis/series/spectral_peaks.hpp"
#include "support/test_signals.hpp"

using namespace npend;
using npend::test::sum_of_sines;

namespace {

double mean_of(const std::vector<double>& x) {
  double m = 0;
  for (double v : x) m += v;
  return m / static_cast<double>(x.size());
}

}  // namespace

TEST_CASE("power_spectrum: sums of sines give peaks at their frequencies within one bin") {
  const double dt = 0.01;
  const std::size_t n = 4096;  // Δω = 2π/40.96 s ≈ 0.153 rad/s; the lines sit between bins
  const std::vector<test::sine_component> lines{
      {1.0, 3.1, 0.2}, {0.3, 7.77, 1.1}, {0.05, 12.4, -0.4}};
  const auto x = sum_of_sines(lines, n, dt, 2.5);  // the offset is removed
  for (const auto window :
       {spectral_window::hann, spectral_window::hamming, spectral_window::blackman}) {
    CAPTURE(spectral_window_name(window));
    const auto s = power_spectrum(x, dt, {.window = window});
    CHECK(s.resolution == doctest::Approx(2 * std::numbers::pi / (n * dt)).epsilon(1e-15));
    CHECK(s.omega.size() == n / 2 + 1);
    const auto peaks = find_spectral_peaks(s);
    REQUIRE(peaks.size() == 3);  // the windows' sidelobes stay below the threshold
    for (std::size_t k = 0; k < 3; ++k) {
      CAPTURE(k);
      // Strongest first; the log-parabola puts each within a tenth of a bin of the truth.
      CHECK(std::fabs(peaks[k].omega - lines[k].omega) < 0.1 * s.resolution);
      CHECK(std::fabs(s.omega[peaks[k].bin] - lines[k].omega) <= s.resolution);
      // The line's area Σρ Δω over its main lobe is its mean square a²/2.
      double area = 0;
      for (std::size_t b = peaks[k].bin - 5; b <= peaks[k].bin + 5; ++b)
        area += s.power[b] * s.resolution;
      CHECK(area == doctest::Approx(lines[k].amplitude * lines[k].amplitude / 2).epsilon(0.02));
    }
  }
}

TEST_CASE("power_spectrum: Parseval — the summed density is the (windowed) mean square") {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> normal(0.3, 1.7);
  std::vector<double> x(1001);  // odd length: no Nyquist bin
  for (auto& v : x) v = normal(rng);
  const double dt = 0.02, m = mean_of(x);
  double variance = 0;
  for (double v : x) variance += (v - m) * (v - m) / static_cast<double>(x.size());

  const auto flat = power_spectrum(x, dt, {.window = spectral_window::none});
  double sum = 0;
  for (double p : flat.power) sum += p * flat.resolution;
  CHECK(sum == doctest::Approx(variance).epsilon(1e-12));

  const auto hann = power_spectrum(x, dt);
  const auto w = window_coefficients(spectral_window::hann, x.size());
  double windowed = 0, norm = 0;
  for (std::size_t j = 0; j < x.size(); ++j) {
    windowed += w[j] * w[j] * (x[j] - m) * (x[j] - m);
    norm += w[j] * w[j];
  }
  sum = 0;
  for (double p : hann.power) sum += p * hann.resolution;
  CHECK(sum == doctest::Approx(windowed / norm).epsilon(1e-12));
}

TEST_CASE("power_spectrum: Welch averaging of white noise is flat at σ² dt / π") {
  std::mt19937_64 rng(11);
  const double sigma = 2, dt = 0.01;
  std::normal_distribution<double> normal(0, sigma);
  std::vector<double> x(1 << 16);
  for (auto& v : x) v = normal(rng);
  const auto s = power_spectrum(x, dt, {.segment_length = 256, .overlap = 0.5});
  CHECK(s.segment_length == 256);
  CHECK(s.segments == (x.size() - 256) / 128 + 1);
  CHECK(s.resolution == doctest::Approx(2 * std::numbers::pi / (256 * dt)));
  // One-sided density of white noise of variance σ²: σ² dt/π, on every bin but 0 and Nyquist.
  double level = 0;
  for (std::size_t k = 1; k < 128; ++k) level += s.power[k] / 127;
  CHECK(level == doctest::Approx(sigma * sigma * dt / std::numbers::pi).epsilon(0.02));
}

TEST_CASE("power_spectrum: segments start every L(1 − overlap) samples") {
  const auto x = sum_of_sines({{1, 5, 0}}, 1000, 0.01);
  // Starts 0, 128, …, 640 (the next, 768, would end past 1000).
  CHECK(power_spectrum(x, 0.01, {.segment_length = 256, .overlap = 0.5}).segments == 6);
  CHECK(power_spectrum(x, 0.01, {.segment_length = 256, .overlap = 0}).segments == 3);
  CHECK(power_spectrum(x, 0.01, {.segment_length = 1000}).segments == 1);
}

TEST_CASE("power_spectrum: bad arguments throw std::invalid_argument naming them") {
  const std::vector<double> x{1, 2, 3, 4, 5, 6, 7, 8};
  const auto message = [&](auto f) {
    try {
      f();
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no exception");
  };
  CHECK(message([&] { power_spectrum(std::vector<double>{1}, 0.1); }).find("x has 1 samples") == 0);
  CHECK(message([&] { power_spectrum(x, 0); }).find("dt must be positive") == 0);
  std::vector<double> bad = x;
  bad[3] = std::nan("");
  CHECK(message([&] { power_spectrum(bad, 0.1); }).find("x[3] is not finite") == 0);
  CHECK(message([&] { power_spectrum(x, 0.1, {.segment_length = 9}); }).find("segment_length") ==
        0);
  CHECK(message([&] { power_spectrum(x, 0.1, {.overlap = 1}); }).find("overlap") == 0);
}

TEST_CASE("find_spectral_peaks: prominence, threshold and order on a hand-made spectrum") {
  power_spectrum_result s;
  s.power = {0, 10, 1, 3, 2.5, 2.8, 0.5, 6, 0};
  for (std::size_t k = 0; k < s.power.size(); ++k) s.omega.push_back(0.5 * static_cast<double>(k));
  // Local maxima at bins 1, 3, 5, 7; their bases (the higher of the lowest points before a
  // higher bin on either side) are 0, 1, 2.5 and 0.5.
  const auto all = find_spectral_peaks(s, {.min_prominence = 0});
  REQUIRE(all.size() == 4);
  std::map<std::size_t, double> prominence;
  for (const auto& p : all) prominence[p.bin] = p.prominence;
  CHECK(prominence[1] == 10);
  CHECK(prominence[3] == 2);
  CHECK(prominence[5] == doctest::Approx(0.3).epsilon(1e-12));  // 2.8 − 2.5
  CHECK(prominence[7] == 5.5);
  // Strongest first (by the refined density).
  for (std::size_t k = 1; k < all.size(); ++k) CHECK(all[k - 1].power >= all[k].power);
  CHECK(all[0].bin == 1);
  CHECK(all[1].bin == 7);
  // Default prominence (half the own height) drops bin 5; a threshold of 0.35 drops bin 3.
  CHECK(find_spectral_peaks(s).size() == 3);
  CHECK(find_spectral_peaks(s, {.threshold = 0.35}).size() == 2);
  CHECK(find_spectral_peaks(s, {.max_peaks = 1}).front().bin == 1);
  for (const auto& p : all) CHECK(std::fabs(p.omega - s.omega[p.bin]) <= 0.25);
  // A zero neighbour leaves the bin value standing.
  CHECK(all[0].omega == s.omega[1]);
  CHECK(all[0].power == 10);
  CHECK_THROWS_AS(find_spectral_peaks(s, {.threshold = 2}), std::invalid_argument);
}

TEST_CASE("find_spectral_peaks: the log-parabola refinement is exact on a Gaussian lobe") {
  power_spectrum_result s;
  const double centre = 10.123, width = 0.7, height = 3.5;
  for (std::size_t k = 0; k < 60; ++k) {
    const double w = 0.5 * static_cast<double>(k);
    s.omega.push_back(w);
    s.power.push_back(height * std::exp(-(w - centre) * (w - centre) / (2 * width * width)));
  }
  const auto peaks = find_spectral_peaks(s);
  REQUIRE(peaks.size() == 1);
  CHECK(peaks[0].omega == doctest::Approx(centre).epsilon(1e-12));
  CHECK(peaks[0].power == doctest::Approx(height).epsilon(1e-12));
}

TEST_CASE("find_spectral_peaks: no refined density above the bins next to the emptied DC bin") {
  // A ramp x_j = a + b j has |X_k|² = b² N² / (4 sin²(πk/N)) for k ≠ 0 (geometric sum), largest at
  // k = 1, and its DC bin is emptied by the mean removal. The log-parabola through ln ρ_0 (a
  // rounding residue) used to report a peak 3600 times the largest bin.
  constexpr std::size_t n = 128;
  std::vector<double> ramp(n);
  for (std::size_t j = 0; j < n; ++j) ramp[j] = 0.37 + 0.1 * static_cast<double>(j);
  const auto s = power_spectrum(ramp, 1.0, {.window = spectral_window::none});
  const double ratio =
      std::pow(std::sin(2 * std::numbers::pi / n) / std::sin(std::numbers::pi / n), 2);
  CHECK(s.power[1] / s.power[2] == doctest::Approx(ratio).epsilon(1e-10));
  const double largest = *std::max_element(s.power.begin(), s.power.end());
  const auto peaks = find_spectral_peaks(s, {.max_peaks = 2});
  REQUIRE(!peaks.empty());
  CHECK(peaks[0].bin == 1);
  CHECK(peaks[0].power == s.power[1]);
  CHECK(peaks[0].omega == s.omega[1]);
  for (const auto& p : peaks) CHECK(p.power <= largest);
}

TEST_CASE("find_spectral_peaks: refinement stays within the window's scalloping bound") {
  // A sine exactly half-way between two bins is the worst case of scalloping: the refined
  // density may exceed the bins by at most |W(0)/W(½)|², which for the rectangular window
  // is (π/2)² (the Dirichlet kernel half a bin off centre).
  constexpr std::size_t n = 1024;
  const double dt = 0.01;
  const double omega = 2 * std::numbers::pi * 100.5 / (static_cast<double>(n) * dt);
  std::vector<double> x(n);
  for (std::size_t j = 0; j < n; ++j) x[j] = std::sin(omega * static_cast<double>(j) * dt);
  for (const auto window : {spectral_window::none, spectral_window::hann}) {
    const auto s = power_spectrum(x, dt, {.window = window});
    const auto peaks = find_spectral_peaks(s, {.max_peaks = 1});
    REQUIRE(peaks.size() == 1);
    const double largest = *std::max_element(s.power.begin(), s.power.end());
    const double bound = window == spectral_window::none ? std::pow(std::numbers::pi / 2, 2) : 1.39;
    CHECK(peaks[0].power <= bound * largest * (1 + 1e-9));
    CHECK(std::fabs(peaks[0].omega - omega) <= 0.5 * s.resolution * (1 + 1e-9));
  }
}
