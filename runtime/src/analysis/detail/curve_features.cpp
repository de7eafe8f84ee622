#include "curve_features.hpp"

#include <algorithm>
#include <cmath>

namespace npend::detail {

std::optional<double> first_zero_crossing(std::span<const double> y, double dx) {
  if (y.empty() || !(y[0] > 0)) return std::nullopt;
  for (std::size_t k = 1; k < y.size(); ++k)
    if (y[k] <= 0) {
      const double s = y[k - 1] / (y[k - 1] - y[k]);  // in (0, 1]
      return (static_cast<double>(k - 1) + s) * dx;
    }
  return std::nullopt;
}

std::optional<double> first_local_minimum(std::span<const double> y, double dx) {
  for (std::size_t k = 1; k + 1 < y.size(); ++k)
    if (y[k] < y[k - 1] && y[k] <= y[k + 1])
      return (static_cast<double>(k) + parabola_vertex_offset(y[k - 1], y[k], y[k + 1])) * dx;
  return std::nullopt;
}

std::optional<double> first_local_minimum_within(std::span<const double> y, double dx,
                                                 std::size_t h) {
  for (std::size_t k = 1; k + h < y.size(); ++k) {
    bool lowest = y[k] < y[k - 1];
    for (std::size_t j = k > h ? k - h : 0; lowest && j <= k + h; ++j) lowest = y[j] >= y[k];
    if (lowest) return static_cast<double>(k) * dx;
  }
  return std::nullopt;
}

double parabola_vertex_offset(double a, double b, double c) {
  const double curvature = a - 2 * b + c;
  if (curvature == 0) return 0;
  return std::clamp(0.5 * (a - c) / curvature, -0.5, 0.5);
}

}  // namespace npend::detail
