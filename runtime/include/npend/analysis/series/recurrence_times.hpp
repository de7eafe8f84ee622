// Recurrence-time statistics (paper §6.6.3, Abb. 6.11 and 6.12): the intervals between
// successive events, their distribution and their spectrum.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "npend/analysis/series/histogram.hpp"
#include "npend/analysis/series/power_spectrum.hpp"

namespace npend {

struct recurrence_options {
  std::size_t bins = 0;  ///< histogram bins (0: automatic, see probability_histogram)
  spectral_window window = spectral_window::hann;  ///< for the interval sequence's spectrum
};

struct recurrence_statistics {
  std::vector<double> intervals;  ///< T_j = t_{j+1} − t_j in s (dim events − 1)
  double mean = 0;                ///< mean interval T̄ in s
  double standard_deviation = 0;  ///< of the intervals (1/(M−1) normalisation), s
  histogram distribution;         ///< the intervals' probability density (1/s over s)
  /// Spectral density of the interval sequence T_j against the event index j (mean removed,
  /// one segment): ω is in rad per event, from 0 to π, and power in s²·event/rad.
  power_spectrum_result spectrum;
};

/// The statistics of the intervals between `event_times` (s, ascending, at least 3 so that
/// there are two intervals) — from event_times on sampled data, or exact times from a
/// trajectory's dense output. A pure oscillation crossing a level through its centre gives
/// every interval equal to half its period. Throws std::invalid_argument for fewer than 3
/// times, a non-finite or non-increasing time, or bad options.
recurrence_statistics recurrence_times(std::span<const double> event_times,
                                       const recurrence_options& options = {});

}  // namespace npend
