#include "npend/analysis/series/event_times.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "analysis/detail/argument_checks.hpp"

namespace npend {

namespace {

// The Lagrange cubic through (0, y0), (1, y1), (2, y2), (3, y3), at s.
double cubic_at(const double* y, double s) {
  return -y[0] * (s - 1) * (s - 2) * (s - 3) / 6 + y[1] * s * (s - 2) * (s - 3) / 2 -
         y[2] * s * (s - 1) * (s - 3) / 2 + y[3] * s * (s - 1) * (s - 2) / 6;
}

// Root in [0, 1] (relative to sample j) of the interpolant through g_j and g_{j+1}, which
// have opposite signs (g_j < 0 ≤ g_{j+1} or g_j ≥ 0 > g_{j+1}).
double crossing_offset(std::span<const double> g, std::size_t j, event_interpolation how) {
  const double linear = g[j] / (g[j] - g[j + 1]);
  if (how == event_interpolation::linear || g.size() < 4) return linear;
  const std::size_t first = std::min(j > 0 ? j - 1 : 0, g.size() - 4);
  const double* y = g.data() + first;
  const double shift = static_cast<double>(j - first);  // where sample j sits in the stencil
  // The cubic passes through both samples, so [0, 1] brackets a root: bisect to the last bit.
  double lo = 0, hi = 1;
  const bool rising = g[j] < 0;
  for (int it = 0; it < 60 && hi - lo > 1e-15; ++it) {
    const double mid = 0.5 * (lo + hi);
    const double v = cubic_at(y, shift + mid);
    if ((v < 0) == rising)
      lo = mid;
    else
      hi = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace

std::vector<double> event_times(std::span<const double> g, double dt,
                                const event_options& options) {
  detail::require_finite_series(g, "g", 2);
  detail::require_sample_spacing(dt);
  const bool want_up = options.direction != crossing_direction::down;
  const bool want_down = options.direction != crossing_direction::up;
  std::vector<double> times;
  for (std::size_t j = 0; j + 1 < g.size(); ++j) {
    const bool up = g[j] < 0 && g[j + 1] >= 0;
    const bool down = g[j] >= 0 && g[j + 1] < 0;
    if ((up && want_up) || (down && want_down))
      times.push_back(options.t0 +
                      (static_cast<double>(j) + crossing_offset(g, j, options.interpolation)) * dt);
  }
  return times;
}

}  // namespace npend
