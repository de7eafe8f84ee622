// The plots of the motion analyses, one builder per analysis: each writes the CSV tables its
// panels read (through a series_output) and returns the panels. The single commands
// (spectrum, autocorrelation, recurrence, embed, poincare), npend analyze and npend demo
// draw the same panels from the same tables; only the arrangement differs.
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "npend/analysis/chaos/poincare_section.hpp"
#include "npend/analysis/series/autocorrelation.hpp"
#include "npend/analysis/series/delay_embedding.hpp"
#include "npend/analysis/series/embedding_dimension.hpp"
#include "npend/analysis/series/power_spectrum.hpp"
#include "npend/analysis/series/recurrence_times.hpp"
#include "npend/analysis/series/spectral_peaks.hpp"
#include "plotting.hpp"
#include "series_output.hpp"

namespace npend::app {

/// "table_suffix", or "suffix" for the command's main table "".
std::string table_name(std::string_view table, std::string_view suffix);

/// "Hann", "rectangular", … for titles.
std::string window_label(spectral_window w);

/// The spectral density (log scale) with its peaks marked and the strongest labelled: writes
/// `table` (omega, power) and its _peaks (omega, power). The frequency axis ends at
/// `omega_max` or where the density has fallen for good.
cli::plot_panel spectrum_panel(series_output& files, std::string_view table, const time_series& x,
                               const power_spectrum_result& spectrum,
                               const std::vector<spectral_peak>& peaks,
                               std::optional<double> omega_max = {});

/// C_xx(τ) with its first zero and first minimum marked: writes `table` (tau, C).
cli::plot_panel autocorrelation_panel(series_output& files, std::string_view table,
                                      const time_series& x, const autocorrelation_result& c);

/// The average mutual information I(τ) with its first local minimum marked: writes `table`
/// (tau, I). `ami` as choose_delay evaluated it (not empty).
cli::plot_panel mutual_information_panel(series_output& files, std::string_view table,
                                         const time_series& x,
                                         const mutual_information_result& ami);

/// The recurrence statistics' three panels.
struct recurrence_panels {
  cli::plot_panel intervals, distribution, spectrum;
};

/// The intervals T_j against j, their probability density with the mean marked, and the
/// spectrum of the interval sequence: writes `table` (index, time, interval), _histogram
/// (interval, density, width) and _spectrum (omega, power). `what` names the events in
/// titles ("phi3=0 (up)"); `times` are the event times (s).
recurrence_panels recurrence_figure(series_output& files, std::string_view table,
                                    std::string_view what, std::span<const double> times,
                                    const recurrence_statistics& stats);

/// The delay plot x(t) against x(t − τ): writes `table` (t and the delay vectors `v`).
cli::plot_panel delay_plot_panel(series_output& files, std::string_view table, const time_series& x,
                                 const delay_choice& tau, const delay_vectors& v);

/// The false-neighbour fraction and Cao's E1, E2 against m (m = 1..the length of
/// fnn.fraction), the dimension found or given marked: writes `table` (m, fnn, fnn_distance,
/// fnn_attractor, cao_e1, cao_e2).
cli::plot_panel embedding_dimension_panel(series_output& files, std::string_view table,
                                          const false_neighbours_result& fnn, const cao_result& cao,
                                          std::optional<std::size_t> dimension,
                                          std::string_view method);

/// Both of the above: the delay plot x(t) against x(t − τ), and the false-neighbour fraction and
/// Cao's E1, E2 against m (m = 1..the length of fnn.fraction): writes `table` (t and the delay
/// vectors `v`) and _dimension. `dimension` is the one found or given (none if none was found),
/// `method` how ("fnn", "cao" or "given").
std::pair<cli::plot_panel, cli::plot_panel> embedding_figure(
    series_output& files, std::string_view table, const time_series& x, const delay_choice& tau,
    const delay_vectors& v, const false_neighbours_result& fnn, const cao_result& cao,
    std::optional<std::size_t> dimension, std::string_view method);

/// The crossings projected onto two coordinates (state indices), as points: writes `table`
/// (t, phi1..phin, p1..pn, H) of all crossings. `section` names the section in the title.
cli::plot_panel poincare_panel(series_output& files, std::string_view table, const chain& c,
                               std::span<const section_crossing> crossings,
                               std::pair<std::size_t, std::size_t> projection,
                               std::string_view section);

/// A coordinate's time series: writes `table` (t, phi1..phin, p1..pn) of all signals and
/// plots the chosen one over [0, t_max] (0: all).
cli::plot_panel time_series_panel(series_output& files, std::string_view table,
                                  const sampled_signals& signals, std::size_t signal,
                                  double t_max = 0);

}  // namespace npend::app
