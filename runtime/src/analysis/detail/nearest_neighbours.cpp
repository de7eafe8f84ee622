#include "nearest_neighbours.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <nanoflann.hpp>
#include <stdexcept>

namespace npend::detail {

namespace {

// nanoflann's dataset concept over strided rows.
struct strided_rows {
  std::span<const double> points;
  std::size_t stride;
  std::size_t count;

  std::size_t kdtree_get_point_count() const { return count; }
  double kdtree_get_pt(std::uint32_t row, std::size_t coordinate) const {
    return points[row * stride + coordinate];
  }
  template <class box>
  bool kdtree_get_bbox(box&) const {
    return false;
  }
};

// A nanoflann result set keeping the nearest point outside the query's Theiler window at a
// nonzero distance. The tree reports squared Euclidean distances; worstDist() bounds them
// for the points that could still improve on the best.
class nearest_admissible {
 public:
  nearest_admissible(const strided_rows& rows, std::size_t dimension, std::size_t query,
                     std::size_t window, vector_norm norm)
      : m_rows(rows), m_dimension(dimension), m_query(query), m_window(window), m_norm(norm) {}

  double worstDist() const { return m_bound; }
  bool full() const { return m_best.index != neighbour::none; }
  bool addPoint(double distance_squared, std::uint32_t row) {
    const std::size_t gap = row > m_query ? row - m_query : m_query - row;
    if (gap <= m_window || distance_squared == 0) return true;
    if (m_norm == vector_norm::euclidean) {
      if (distance_squared < m_bound) {
        m_best = {row, std::sqrt(distance_squared)};
        m_bound = distance_squared;
      }
      return true;
    }
    double largest = 0;
    for (std::size_t c = 0; c < m_dimension; ++c)
      largest = std::max(largest, std::fabs(m_rows.kdtree_get_pt(row, c) -
                                            m_rows.points[m_query * m_rows.stride + c]));
    if (!full() || largest < m_best.distance) {
      m_best = {row, largest};
      // Any point closer in the maximum norm is within √m · largest in the Euclidean one.
      m_bound = static_cast<double>(m_dimension) * largest * largest;
    }
    return true;  // keep searching
  }
  const neighbour& best() const { return m_best; }

 private:
  const strided_rows& m_rows;
  std::size_t m_dimension, m_query, m_window;
  vector_norm m_norm;
  double m_bound = std::numeric_limits<double>::infinity();
  neighbour m_best;
};

using tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, strided_rows>,
                                                 strided_rows, -1, std::uint32_t>;

}  // namespace

std::vector<neighbour> nearest_neighbours(std::span<const double> points, std::size_t stride,
                                          std::size_t dimension, std::size_t theiler_window,
                                          vector_norm norm, std::size_t max_queries) {
  if (dimension == 0 || dimension > stride || points.size() % stride != 0)
    throw std::invalid_argument("nearest_neighbours: inconsistent row layout");
  const std::size_t count = points.size() / stride;
  if (count >= std::numeric_limits<std::uint32_t>::max())
    throw std::invalid_argument("nearest_neighbours: too many points for a 32-bit index");
  const strided_rows rows{points, stride, count};
  const tree index(static_cast<int>(dimension), rows,
                   nanoflann::KDTreeSingleIndexAdaptorParams(10));
  std::vector<neighbour> result(count);
  const std::size_t queries = max_queries == 0 ? count : std::min(count, max_queries);
  for (std::size_t k = 0; k < queries; ++k) {
    const std::size_t i = k * count / queries;  // evenly spaced, all rows when queries = count
    nearest_admissible best(rows, dimension, i, theiler_window, norm);
    index.findNeighbors(best, points.data() + i * stride, nanoflann::SearchParams());
    result[i] = best.best();
  }
  return result;
}

}  // namespace npend::detail
