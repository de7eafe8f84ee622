#include "npend/analysis/series/embedding_dimension.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

#include "analysis/detail/argument_checks.hpp"
#include "analysis/detail/nearest_neighbours.hpp"

namespace npend {

namespace {

// Checks shared by both methods; returns the standard deviation of x.
double check_series(std::span<const double> x, std::size_t delay, std::size_t max_dimension,
                    std::size_t deepest, std::size_t theiler_window) {
  if (delay == 0) throw std::invalid_argument("delay must be at least 1 sample");
  if (max_dimension == 0) throw std::invalid_argument("max_dimension must be at least 1");
  const std::size_t needed = deepest * delay + 2 * theiler_window + 3;
  if (x.size() < needed)
    throw std::invalid_argument(fmt::format(
        "x has {} samples; max_dimension {} at delay {} with a Theiler window of {} needs at "
        "least {}",
        x.size(), max_dimension, delay, theiler_window, needed));
  detail::require_finite_series(x, "x", 0);
  detail::require_varying(x, "x", "it has no embedding dimension");
  double mean = 0;
  for (const double v : x) mean += v;
  mean /= static_cast<double>(x.size());
  double squares = 0;
  for (const double v : x) squares += (v - mean) * (v - mean);
  return std::sqrt(squares / static_cast<double>(x.size()));
}

// The rows (x_j, x_{j+τ}, …, x_{j+mτ}), j = 0..N−1−mτ, and the nearest neighbour of each in
// its first m coordinates; the last one is the coordinate that dimension m + 1 adds.
struct neighbours_in_dimension {
  std::vector<double> rows;
  std::size_t count = 0;
  std::vector<detail::neighbour> nearest;
};

neighbours_in_dimension find_neighbours(std::span<const double> x, std::size_t delay, std::size_t m,
                                        std::size_t theiler_window, detail::vector_norm norm,
                                        std::size_t reference_points) {
  neighbours_in_dimension r;
  r.count = x.size() - m * delay;
  r.rows.resize(r.count * (m + 1));
  for (std::size_t j = 0; j < r.count; ++j)
    for (std::size_t c = 0; c <= m; ++c) r.rows[j * (m + 1) + c] = x[j + c * delay];
  r.nearest = detail::nearest_neighbours(r.rows, m + 1, m, theiler_window, norm, reference_points);
  return r;
}

}  // namespace

false_neighbours_result false_nearest_neighbours(std::span<const double> x, std::size_t delay,
                                                 std::size_t max_dimension,
                                                 const false_neighbours_options& options) {
  if (!(options.distance_ratio > 0) || !(options.attractor_ratio > 0))
    throw std::invalid_argument(
        fmt::format("distance_ratio and attractor_ratio must be positive, got {} and {}",
                    options.distance_ratio, options.attractor_ratio));
  if (!(options.threshold > 0 && options.threshold <= 1))
    throw std::invalid_argument(
        fmt::format("threshold must be in (0, 1], got {}", options.threshold));
  const double sigma = check_series(x, delay, max_dimension, max_dimension, options.theiler_window);

  false_neighbours_result r;
  for (std::size_t m = 1; m <= max_dimension; ++m) {
    const auto [rows, count, nearest] =
        find_neighbours(x, delay, m, options.theiler_window, detail::vector_norm::euclidean,
                        options.reference_points);
    std::size_t total = 0, by_distance = 0, by_attractor = 0, either = 0;
    for (std::size_t i = 0; i < count; ++i) {
      if (nearest[i].index == detail::neighbour::none) continue;
      const double gap = rows[i * (m + 1) + m] - rows[nearest[i].index * (m + 1) + m];
      const double r_m = nearest[i].distance;
      const bool distance = std::fabs(gap) > options.distance_ratio * r_m;
      const bool attractor = std::hypot(r_m, gap) > options.attractor_ratio * sigma;
      ++total;
      by_distance += distance;
      by_attractor += attractor;
      either += distance || attractor;
    }
    const auto share = [total](std::size_t k) {
      return total > 0 ? static_cast<double>(k) / static_cast<double>(total) : 1.0;
    };
    r.fraction.push_back(share(either));
    r.fraction_distance.push_back(share(by_distance));
    r.fraction_attractor.push_back(share(by_attractor));
    if (!r.found && r.fraction.back() < options.threshold) {
      r.found = true;
      r.dimension = m;
    }
  }
  return r;
}

cao_result cao_embedding(std::span<const double> x, std::size_t delay, std::size_t max_dimension,
                         const cao_options& options) {
  if (!(options.saturation > 0 && options.saturation <= 1) ||
      !(options.change > 0 && options.change <= 1))
    throw std::invalid_argument(
        fmt::format("saturation and change must be in (0, 1], got {} and {}", options.saturation,
                    options.change));
  check_series(x, delay, max_dimension, max_dimension + 1, options.theiler_window);

  // E(d) and E*(d) for d = 1..max_dimension + 1.
  std::vector<double> e, e_star;
  for (std::size_t d = 1; d <= max_dimension + 1; ++d) {
    const auto [rows, count, nearest] =
        find_neighbours(x, delay, d, options.theiler_window, detail::vector_norm::maximum,
                        options.reference_points);
    double ratio_sum = 0, gap_sum = 0;
    std::size_t total = 0;
    for (std::size_t i = 0; i < count; ++i) {
      if (nearest[i].index == detail::neighbour::none) continue;
      const double gap = rows[i * (d + 1) + d] - rows[nearest[i].index * (d + 1) + d];
      // Maximum norm: ‖y(d+1) − y_n(d+1)‖ = max(‖y(d) − y_n(d)‖, |gap|).
      ratio_sum += std::max(nearest[i].distance, std::fabs(gap)) / nearest[i].distance;
      gap_sum += std::fabs(gap);
      ++total;
    }
    if (total == 0)
      throw std::invalid_argument("x: no point has a neighbour at a nonzero distance");
    e.push_back(ratio_sum / static_cast<double>(total));
    e_star.push_back(gap_sum / static_cast<double>(total));
  }
  cao_result r;
  for (std::size_t d = 0; d < max_dimension; ++d) {
    r.e1.push_back(e[d + 1] / e[d]);
    r.e2.push_back(e_star[d] > 0 ? e_star[d + 1] / e_star[d] : 1.0);
  }
  for (std::size_t d = 0; d + 1 < max_dimension && !r.found; ++d)
    if (r.e1[d] >= options.saturation &&
        std::fabs(r.e1[d + 1] - r.e1[d]) <= options.change * r.e1[d]) {
      r.found = true;
      r.dimension = d + 1;
    }
  return r;
}

}  // namespace npend
