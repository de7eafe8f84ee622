#include "npend/analysis/series/histogram.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "analysis/detail/argument_checks.hpp"

namespace npend {

namespace {

constexpr std::size_t max_automatic_bins = 200;
constexpr double degenerate_spread = 1e-9;  // relative range below which values count as equal
constexpr double degenerate_width = 1e-3;   // relative width of the single bin they then get

std::size_t automatic_bins(std::vector<double> sorted, double range) {
  const auto n = static_cast<double>(sorted.size());
  const auto quantile = [&](double q) {
    const double pos = q * (n - 1);
    const auto lo = static_cast<std::size_t>(std::floor(pos));
    const std::size_t hi = std::min(lo + 1, sorted.size() - 1);
    return sorted[lo] + (pos - static_cast<double>(lo)) * (sorted[hi] - sorted[lo]);
  };
  const double iqr = quantile(0.75) - quantile(0.25);
  double bins = std::ceil(std::log2(n)) + 1;  // Sturges
  if (iqr > 0) bins = std::ceil(range / (2 * iqr * std::cbrt(1 / n)));
  return static_cast<std::size_t>(std::clamp(bins, 1.0, static_cast<double>(max_automatic_bins)));
}

}  // namespace

histogram probability_histogram(std::span<const double> values, std::size_t bins) {
  detail::require_finite_series(values, "values", 1);
  std::vector<double> sorted(values.begin(), values.end());
  std::sort(sorted.begin(), sorted.end());
  double lo = sorted.front(), hi = sorted.back();
  const double magnitude = std::max(std::fabs(lo), std::fabs(hi));
  if (hi - lo <= degenerate_spread * magnitude) {
    // All equal up to rounding: one bin around them.
    const double centre = 0.5 * (lo + hi);
    const double half = 0.5 * degenerate_width * (magnitude == 0 ? 1.0 : magnitude);
    lo = centre - half;
    hi = centre + half;
    bins = 1;
  }
  if (bins == 0) bins = automatic_bins(std::move(sorted), hi - lo);

  histogram h;
  const double width = (hi - lo) / static_cast<double>(bins);
  h.edges.resize(bins + 1);
  for (std::size_t b = 0; b <= bins; ++b) h.edges[b] = lo + static_cast<double>(b) * width;
  h.edges.back() = hi;
  h.counts.assign(bins, 0);
  for (const double v : values) {
    auto b = static_cast<std::size_t>((v - lo) / width);
    ++h.counts[std::min(b, bins - 1)];
  }
  h.density.resize(bins);
  for (std::size_t b = 0; b < bins; ++b)
    h.density[b] = static_cast<double>(h.counts[b]) / (static_cast<double>(values.size()) * width);
  return h;
}

}  // namespace npend
