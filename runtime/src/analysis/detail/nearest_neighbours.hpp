// Nearest-neighbour searches on delay vectors with a k-d tree (nanoflann), private to the
// runtime.
#pragma once

#include <cstddef>
#include <limits>
#include <span>
#include <vector>

namespace npend::detail {

enum class vector_norm { euclidean, maximum };

struct neighbour {
  static constexpr std::size_t none = std::numeric_limits<std::size_t>::max();
  std::size_t index = none;  ///< row of the nearest admissible neighbour, or none
  double distance = 0;       ///< in the chosen norm
};

/// For every row i of the row-major `points` (rows of `stride` values, of which the first
/// `dimension` are searched), its nearest neighbour in `norm` among the rows j with
/// |i − j| > theiler_window (rows are consecutive in time) and a nonzero distance (exact
/// duplicates say nothing about the geometry). Requires dimension ≤ stride. The tree is
/// Euclidean; for the maximum norm the search keeps the Euclidean radius √m times the best
/// maximum-norm distance so far, which contains every closer point, so the result is exact.
/// With `max_queries` > 0 only that many evenly spaced rows are queried (the others get
/// none); every row stays a candidate neighbour.
std::vector<neighbour> nearest_neighbours(std::span<const double> points, std::size_t stride,
                                          std::size_t dimension, std::size_t theiler_window,
                                          vector_norm norm = vector_norm::euclidean,
                                          std::size_t max_queries = 0);

}  // namespace npend::detail
