#include "npend/analysis/series/spectral_peaks.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <stdexcept>

#include "analysis/detail/curve_features.hpp"

namespace npend {

namespace {

// Lowest density between bin k and the nearest bin that is higher than ρ_k, walking in
// direction `step` (±1); the walk stops at the spectrum's end if no bin is higher.
double base_towards(const std::vector<double>& p, std::size_t k, int step) {
  double lowest = p[k];
  for (auto j = static_cast<std::ptrdiff_t>(k) + step;
       j >= 0 && j < static_cast<std::ptrdiff_t>(p.size()); j += step) {
    const double v = p[static_cast<std::size_t>(j)];
    if (v > p[k]) break;
    lowest = std::min(lowest, v);
  }
  return lowest;
}

// How much higher than the highest bin a spectral line can really be: the inverse of the
// window's scalloping gain |W(½)/W(0)|², the power its main lobe keeps half a bin off centre
// (2.47 for the rectangular window, 1.39 for Hann). A refined density above this bound is
// an artefact of the parabola, not of the signal. It hardly depends on the segment length,
// so the limit of long segments (1024 samples) serves every spectrum.
double scalloping_bound(spectral_window window) {
  constexpr std::size_t length = 1024;
  const std::vector<double> w = window_coefficients(window, length);
  std::complex<double> at_half_bin = 0;
  double at_centre = 0;
  for (std::size_t j = 0; j < length; ++j) {
    at_centre += w[j];
    at_half_bin += w[j] * std::polar(1.0, -std::numbers::pi * static_cast<double>(j) /
                                              static_cast<double>(length));
  }
  return at_centre * at_centre / std::norm(at_half_bin);
}

}  // namespace

std::vector<spectral_peak> find_spectral_peaks(const power_spectrum_result& spectrum,
                                               const peak_options& options) {
  const auto& p = spectrum.power;
  if (p.size() < 3)
    throw std::invalid_argument(
        fmt::format("spectrum has {} bins; at least 3 are needed", p.size()));
  if (spectrum.omega.size() != p.size())
    throw std::invalid_argument(fmt::format("spectrum.omega has {} entries, spectrum.power {}",
                                            spectrum.omega.size(), p.size()));
  if (!(options.threshold >= 0 && options.threshold <= 1))
    throw std::invalid_argument(
        fmt::format("threshold must be in [0, 1], got {}", options.threshold));
  if (!(options.min_prominence >= 0 && options.min_prominence <= 1))
    throw std::invalid_argument(
        fmt::format("min_prominence must be in [0, 1], got {}", options.min_prominence));

  std::vector<std::size_t> maxima;
  double strongest = 0;
  for (std::size_t k = 1; k + 1 < p.size(); ++k)
    if (p[k - 1] < p[k] && p[k] >= p[k + 1]) {
      maxima.push_back(k);
      strongest = std::max(strongest, p[k]);
    }

  const double bound = scalloping_bound(spectrum.window);
  std::vector<spectral_peak> peaks;
  for (const std::size_t k : maxima) {
    if (p[k] < options.threshold * strongest) continue;
    const double prominence = p[k] - std::max(base_towards(p, k, -1), base_towards(p, k, +1));
    if (prominence < options.min_prominence * p[k]) continue;
    spectral_peak peak;
    peak.bin = k;
    peak.prominence = prominence;
    peak.omega = spectrum.omega[k];
    peak.power = p[k];
    // Parabolic interpolation of ln ρ. It needs positive neighbours (they are, unless a
    // window null falls exactly on a bin) and none at ω = 0: every segment has its mean
    // removed, so the DC bin holds rounding noise, and ln of it would throw the vertex
    // anywhere. In those cases, and where the vertex would rise above what a sampled line
    // can (the scalloping bound), the bin value stands.
    if (k >= 2 && p[k - 1] > 0 && p[k + 1] > 0) {
      const double a = std::log(p[k - 1]), b = std::log(p[k]), c = std::log(p[k + 1]);
      const double delta = detail::parabola_vertex_offset(a, b, c);
      const double vertex = std::exp(b - 0.25 * (a - c) * delta);
      if (vertex <= bound * p[k]) {
        peak.omega = spectrum.omega[k] + delta * (spectrum.omega[k + 1] - spectrum.omega[k]);
        peak.power = vertex;
      }
    }
    peaks.push_back(peak);
  }
  std::stable_sort(peaks.begin(), peaks.end(), [](const spectral_peak& a, const spectral_peak& b) {
    return a.power > b.power;
  });
  if (options.max_peaks > 0 && peaks.size() > options.max_peaks) peaks.resize(options.max_peaks);
  return peaks;
}

}  // namespace npend
