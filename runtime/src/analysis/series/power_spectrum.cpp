#include "npend/analysis/series/power_spectrum.hpp"

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "analysis/detail/argument_checks.hpp"
#include "analysis/detail/real_fft.hpp"

namespace npend {

namespace {

constexpr std::array window_names{
    std::pair{spectral_window::none, std::string_view{"none"}},
    std::pair{spectral_window::hann, std::string_view{"hann"}},
    std::pair{spectral_window::hamming, std::string_view{"hamming"}},
    std::pair{spectral_window::blackman, std::string_view{"blackman"}},
};

}  // namespace

std::string_view spectral_window_name(spectral_window w) {
  for (const auto& [window, name] : window_names)
    if (window == w) return name;
  throw std::invalid_argument("spectral_window_name: unknown window");
}

std::optional<spectral_window> spectral_window_from_name(std::string_view name) {
  for (const auto& [window, known] : window_names)
    if (known == name) return window;
  return std::nullopt;
}

std::vector<double> window_coefficients(spectral_window w, std::size_t length) {
  std::vector<double> c(length, 1.0);
  for (std::size_t j = 0; j < length; ++j) {
    const double phase =
        2 * std::numbers::pi * static_cast<double>(j) / static_cast<double>(length);
    switch (w) {
      case spectral_window::none:
        break;
      case spectral_window::hann:
        c[j] = 0.5 - 0.5 * std::cos(phase);
        break;
      case spectral_window::hamming:
        c[j] = 0.54 - 0.46 * std::cos(phase);
        break;
      case spectral_window::blackman:
        c[j] = 0.42 - 0.5 * std::cos(phase) + 0.08 * std::cos(2 * phase);
        break;
    }
  }
  return c;
}

power_spectrum_result power_spectrum(std::span<const double> x, double dt,
                                     const spectrum_options& options) {
  detail::require_finite_series(x, "x", 2);
  detail::require_sample_spacing(dt);
  const std::size_t n = x.size();
  const std::size_t length = options.segment_length == 0 ? n : options.segment_length;
  if (length < 2 || length > n)
    throw std::invalid_argument(fmt::format(
        "segment_length must be 0 (whole series) or in [2, {}] samples, got {}", n, length));
  if (!(options.overlap >= 0 && options.overlap < 1))
    throw std::invalid_argument(fmt::format("overlap must be in [0, 1), got {}", options.overlap));
  const auto step = std::max<std::size_t>(
      1,
      static_cast<std::size_t>(std::lround(static_cast<double>(length) * (1 - options.overlap))));

  const std::vector<double> w = window_coefficients(options.window, length);
  double window_power = 0;
  for (double v : w) window_power += v * v;

  power_spectrum_result r;
  r.window = options.window;
  r.segment_length = length;
  r.resolution = 2 * std::numbers::pi / (static_cast<double>(length) * dt);
  const std::size_t bins = length / 2 + 1;
  r.omega.resize(bins);
  r.power.assign(bins, 0.0);
  for (std::size_t k = 0; k < bins; ++k) r.omega[k] = static_cast<double>(k) * r.resolution;

  detail::real_fft fft(length);
  for (std::size_t start = 0; start + length <= n; start += step) {
    const auto segment = x.subspan(start, length);
    double mean = 0;
    for (double v : segment) mean += v;
    mean /= static_cast<double>(length);
    const auto in = fft.real();
    for (std::size_t j = 0; j < length; ++j) in[j] = w[j] * (segment[j] - mean);
    fft.forward();
    const auto spectrum = fft.spectrum();
    for (std::size_t k = 0; k < bins; ++k) r.power[k] += std::norm(spectrum[k]);
    ++r.segments;
  }
  // Two-sided density |X_k|² dt / (2π Σw²) per segment (Parseval: Σ_k over all L bins times
  // Δω gives Σ(w x)²/Σw²); one-sided doubles every bin but ω = 0 and, for even L, the
  // Nyquist bin.
  const double scale = dt / (2 * std::numbers::pi * window_power * static_cast<double>(r.segments));
  for (std::size_t k = 0; k < bins; ++k) {
    const bool unpaired = k == 0 || (length % 2 == 0 && k == length / 2);
    r.power[k] *= (unpaired ? 1.0 : 2.0) * scale;
  }
  return r;
}

}  // namespace npend
