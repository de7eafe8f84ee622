// npend recurrence: recurrence-time statistics (paper §6.6.3, Abb. 6.11 and 6.12) — the
// intervals between events such as phi3 = 0 or phi2 = phi3, their distribution and spectrum.
#include <fmt/format.h>

#include <algorithm>
#include <functional>
#include <iostream>
#include <nlohmann/json.hpp>
#include <numbers>

#include "command.hpp"
#include "input_parsing.hpp"
#include "npend/analysis/chaos/poincare_section.hpp"
#include "npend/analysis/series/event_times.hpp"
#include "npend/analysis/series/recurrence_times.hpp"
#include "npend/analysis/series/spectral_peaks.hpp"
#include "section_spec.hpp"
#include "series_figures.hpp"
#include "series_output.hpp"
#include "time_series_source.hpp"

namespace npend::app {

namespace {

struct recurrence_options {
  cli::series_options series;
  std::string event, direction = "both", interpolation;
  std::size_t bins = 0;
  bool json = false;
  bool unwrapped = false;
  std::string out;
};

// The event times of a CSV file's signals: sign changes of signal − level or signal − other
// between the samples, located by linear or cubic interpolation.
std::vector<double> sampled_event_times(const sampled_signals& signals,
                                        const cli::section_spec& spec, const std::string& text,
                                        const event_options& options) {
  const time_series signal = cli::select_signal(signals, spec.left, "--event");
  std::vector<double> g = signal.values;
  if (spec.level) {
    for (double& v : g) v -= *spec.level;
  } else {
    const time_series other = cli::select_signal(signals, spec.right, "--event");
    if (other.name == signal.name)
      throw cli::input_error(fmt::format("--event: '{}' compares a signal with itself", text));
    for (std::size_t j = 0; j < g.size(); ++j) g[j] -= other.values[j];
  }
  return event_times(g, signals.dt, options);
}

int run_recurrence(const recurrence_options& o) {
  const crossing_direction direction = cli::parse_direction(o.direction, "--direction");
  const cli::section_spec spec = cli::parse_section_spec(o.event, "--event");
  series_output files(o.out);
  const auto simulation = o.series.simulation(4);
  if (simulation && !o.interpolation.empty())
    throw cli::input_error(
        "--interpolation: only for --input; a simulation's events are located on the "
        "integrator's steps");
  if (!simulation && o.unwrapped)
    throw cli::input_error(
        "--unwrapped: only for a simulation; the events of a file's columns are of their values "
        "as written");
  const cli::angle_mode angles = o.unwrapped ? cli::angle_mode::unwrapped : cli::angle_mode::circle;
  event_interpolation interpolation = event_interpolation::cubic;
  if (o.interpolation == "linear")
    interpolation = event_interpolation::linear;
  else if (!o.interpolation.empty() && o.interpolation != "cubic")
    throw cli::input_error(
        fmt::format("--interpolation: '{}' is not linear or cubic", o.interpolation));

  std::vector<double> times;
  std::string source;
  std::size_t samples = 0;
  double dt = 0;
  if (simulation) {
    // Located on the steps (dense output and Hénon's trick), like the Poincaré crossings.
    crossing_locator locator(
        simulation->pendulum,
        cli::section_from_spec(spec, simulation->pendulum.links(), "--event", angles), direction);
    cli::simulate_with_progress(*simulation, std::ref(locator));
    times = crossing_times(locator.crossings());
    source = simulation->source;
    dt = simulation->integration.dt;
  } else {
    const sampled_signals signals = o.series.load(4);
    times = sampled_event_times(
        signals, spec, o.event,
        {.direction = direction, .interpolation = interpolation, .t0 = signals.t0});
    source = signals.source;
    samples = signals.samples();
    dt = signals.dt;
  }
  if (times.size() < 3)
    throw cli::input_error(
        fmt::format("--event: {} has {} event{} in {}; at least 3 are needed for two intervals",
                    o.event, times.size(), times.size() == 1 ? "" : "s", source));
  const auto stats = recurrence_times(times, {.bins = o.bins});
  const auto peaks = find_spectral_peaks(stats.spectrum, {.max_peaks = 5});
  // A strictly periodic signal: equal intervals up to rounding, an interval spectrum of noise.
  const bool constant = stats.standard_deviation <= 1e-9 * stats.mean;
  const std::string what =
      o.event + (direction == crossing_direction::both ? "" : " (" + o.direction + ")");

  if (files.enabled()) {
    const auto panels = recurrence_figure(files, "", what, times, stats);
    files.write_plot(
        {.description = {fmt::format("npend recurrence: intervals between the events {} of {}",
                                     what, source),
                         fmt::format("data: {} (intervals), {} (their density), {} (their "
                                     "spectrum)",
                                     files.file_name(""), files.file_name("histogram"),
                                     files.file_name("spectrum"))},
         .width = 1500,
         .height = 520,
         .columns = 3,
         .panels = {panels.intervals, panels.distribution, panels.spectrum}});
  }

  if (o.json) {
    nlohmann::json j{
        {"source", source},
        {"event", o.event},
        {"direction", o.direction},
        {"interpolation", simulation                ? "steps"
                          : o.interpolation.empty() ? std::string("cubic")
                                                    : o.interpolation},
        {"angles", simulation ? nlohmann::json(cli::angle_mode_name(angles)) : nlohmann::json()},
        {"count", times.size()},
        {"times", times},
        {"intervals", stats.intervals},
        {"mean", stats.mean},
        {"standard_deviation", stats.standard_deviation}};
    files.add_to(j);
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  if (simulation)
    fmt::print("Recurrence of the events {} in the {} over {:g} s\n\n", what, source,
               simulation->integration.t_end);
  else
    fmt::print("Recurrence of the events {} in {} ({} samples, dt = {:.6g} s)\n\n", what, source,
               samples, dt);
  fmt::print("events: {}, intervals: {}\n", times.size(), stats.intervals.size());
  fmt::print("mean interval T = {:.6g} s, standard deviation {:.3g} s, range {:.6g} .. {:.6g} s\n",
             stats.mean, stats.standard_deviation,
             *std::min_element(stats.intervals.begin(), stats.intervals.end()),
             *std::max_element(stats.intervals.begin(), stats.intervals.end()));
  fmt::print("histogram: {} bins of {:.3g} s\n", stats.distribution.counts.size(),
             stats.distribution.edges[1] - stats.distribution.edges[0]);
  if (constant)
    fmt::print(
        "the intervals are constant (a periodic signal): their spectrum is rounding noise\n");
  else if (!peaks.empty())
    fmt::print(
        "interval spectrum: strongest line at omega = {:.4g} rad/event (period {:.4g} events)\n",
        peaks.front().omega, 2 * std::numbers::pi / peaks.front().omega);
  files.print();
  return 0;
}

}  // namespace

void add_recurrence_command(CLI::App& app, command_list& commands) {
  auto o = std::make_shared<recurrence_options>();
  CLI::App* cmd = app.add_subcommand(
      "recurrence",
      "Recurrence-time statistics: intervals between events, their density and spectrum");
  o->series.add_to(*cmd, cli::series_use::events);
  cmd->add_option("--event", o->event,
                  "NAME=VALUE: the signal crosses a level (phi3=0); NAME=OTHER: two signals cross "
                  "(phi2=phi3). Names are CSV column names or numbers, or a simulation's "
                  "coordinates phi1..phin, p1..pn")
      ->required();
  cmd->add_option("--direction", o->direction, "Crossings counted: up, down or both")
      ->capture_default_str();
  cmd->add_option("--interpolation", o->interpolation,
                  "CSV input: event times between samples by linear or cubic (default) "
                  "interpolation");
  cmd->add_option("--bins", o->bins, "Histogram bins (0: Freedman-Diaconis)")
      ->capture_default_str();
  cmd->add_flag("--unwrapped", o->unwrapped,
                "Simulation: events of angles on the unwrapped angle (phi3=0 and phi3=2pi "
                "differ) instead of on the circle (every passage of the arm; the default)");
  cmd->add_flag("--json", o->json, "Print JSON");
  cmd->add_option("--out", o->out,
                  "Write FILE.csv (index, time, interval), FILE_histogram.csv, FILE_spectrum.csv "
                  "and the plot FILE.png with its gnuplot script FILE.gp");
  commands.push_back({cmd, [o] { return run_recurrence(*o); }});
}

}  // namespace npend::app
