#include "npend/analysis/series/recurrence_times.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

namespace npend {

recurrence_statistics recurrence_times(std::span<const double> event_times,
                                       const recurrence_options& options) {
  const std::size_t n = event_times.size();
  if (n < 3)
    throw std::invalid_argument(
        fmt::format("event_times has {} events; at least 3 are needed for two intervals", n));
  for (std::size_t j = 0; j < n; ++j) {
    if (!std::isfinite(event_times[j]))
      throw std::invalid_argument(fmt::format("event_times[{}] is not finite", j));
    if (j > 0 && !(event_times[j] > event_times[j - 1]))
      throw std::invalid_argument(
          fmt::format("event_times must increase: event_times[{}] = {} follows {}", j,
                      event_times[j], event_times[j - 1]));
  }
  recurrence_statistics r;
  r.intervals.resize(n - 1);
  for (std::size_t j = 0; j + 1 < n; ++j) r.intervals[j] = event_times[j + 1] - event_times[j];
  const auto m = static_cast<double>(r.intervals.size());
  for (const double t : r.intervals) r.mean += t;
  r.mean /= m;
  double squares = 0;
  for (const double t : r.intervals) squares += (t - r.mean) * (t - r.mean);
  r.standard_deviation = std::sqrt(squares / (m - 1));
  r.distribution = probability_histogram(r.intervals, options.bins);
  r.spectrum = power_spectrum(r.intervals, 1.0, {.window = options.window});
  return r;
}

}  // namespace npend
