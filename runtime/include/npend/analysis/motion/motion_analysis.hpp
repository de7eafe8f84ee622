// Every analysis of paper §6.6 for one simulated start, from one integration: the time
// series of a coordinate, its spectral density and autocorrelation, the delay embedding, the
// Poincaré section and the recurrence times of an event. npend analyze writes it to a folder;
// npend demo runs it for a periodic and a chaotic start and draws the paper's figures.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "npend/analysis/chaos/poincare_section.hpp"
#include "npend/analysis/series/autocorrelation.hpp"
#include "npend/analysis/series/delay_embedding.hpp"
#include "npend/analysis/series/embedding_dimension.hpp"
#include "npend/analysis/series/power_spectrum.hpp"
#include "npend/analysis/series/recurrence_times.hpp"
#include "npend/analysis/series/sampled_signals.hpp"
#include "npend/analysis/series/spectral_peaks.hpp"

namespace npend {

struct motion_analysis_options {
  std::size_t coordinate = 0;  ///< state index of the analysed time series
  section_plane section;       ///< the Poincaré section
  crossing_direction section_direction = crossing_direction::up;
  section_plane event;  ///< the recurrence event
  crossing_direction event_direction = crossing_direction::both;
  std::size_t max_dimension = 10;  ///< embedding dimensions tested
};

struct motion_analysis {
  sampled_signals signals;                          ///< every coordinate on the sample grid
  time_series series;                               ///< the analysed coordinate
  integration_result run;                           ///< how the integration ended
  std::vector<section_crossing> section;            ///< Poincaré crossings over the whole run
  npend::section_quality section_quality;           ///< of `section`, against H(x0)
  std::vector<double> event_times;                  ///< s, over the whole run
  power_spectrum_result spectrum;                   ///< Hann window, one segment
  std::vector<spectral_peak> peaks;                 ///< default peak options, strongest first
  autocorrelation_result autocorrelation;           ///< lags up to half the series
  std::optional<recurrence_statistics> recurrence;  ///< none for fewer than 3 events
  delay_choice tau;                                 ///< automatic
  false_neighbours_result fnn;
  cao_result cao;
  std::optional<std::size_t> dimension;  ///< by false nearest neighbours, if found
  delay_vectors vectors;  ///< in the dimension found (at least 2, at most 3); empty if none
  /// Whether the embedding was computed (tau, fnn, cao and vectors are set).
  bool embedded() const { return !fnn.fraction.empty(); }
  double largest_angle = 0;        ///< max |φ_i| over the steps of the run (rad)
  std::vector<std::string> notes;  ///< what could not be computed, and why
};

/// Integrates `sim` once (its samples for the series, its whole run for the section and the
/// events) and runs every analysis. A run its run control stops (run.stopped) is returned as
/// it stands, nothing analysed. Throws std::invalid_argument for a coordinate ≥ 2n, bad
/// sections, or a series that does not move (a start at rest in an equilibrium);
/// npend::integration_error if the integration cannot go on. Analyses the data do not
/// allow (too few events, no delay) leave notes.
motion_analysis analyze_motion(const simulated_start& sim, const motion_analysis_options& options);

}  // namespace npend
