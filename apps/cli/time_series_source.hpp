// Where the commands of the time-series analyses (spectrum, autocorrelation, recurrence,
// embed, analyze) get their data: a CSV file (--input, --column, --dt) — a user's measured
// pendulum data — or a simulated start (--links N [params] --phi/--p/--dphi/--energy,
// --samples, --dt, --coordinate, --stepper), whose trajectory's coordinates phi1..phin,
// p1..pn on the output grid are the signals. series_options::load is the one place where
// the choice is made; every command works on either unchanged.
#pragma once

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "chain_options.hpp"
#include "csv_table.hpp"
#include "integrator_options.hpp"
#include "npend/analysis/series/sampled_signals.hpp"
#include "npend/chain.hpp"
#include "npend/integrators/integrate.hpp"
#include "start_options.hpp"
#include "terminal_run.hpp"

namespace npend::cli {

using npend::sampled_signals;
using npend::simulated_start;
using npend::time_series;

/// The signals of a parsed CSV table. The time column is the one whose header is t or time
/// (any case, optionally with a unit: "t (s)", "time [s]"); its spacing must be uniform (every
/// t_j within 1% of a step of t_0 + j dt, dt = (t_last − t_0)/(N − 1)) and agree with
/// `dt_option` if given. Without a time column `dt_option` is required. Throws input_error
/// with a one-line message for each failure, and when there are fewer than `min_samples`
/// rows or no signal column.
sampled_signals signals_from_csv(const csv_table& table, std::string_view source,
                                 std::optional<double> dt_option, std::size_t min_samples);

/// `x` if every sample is finite and not all are equal; else throws input_error naming
/// `option`, the signal and its source: only the signals an analysis uses must be finite
/// (a NaN in another column of a file blocks nothing), and a constant one has nothing to
/// analyse.
time_series checked_signal(time_series x, std::string_view option);

/// The signal `selector` names: a column name, else a 1-based column number; empty selects
/// the default signal. `option` names the option in messages ("--column"). The signal is
/// checked_signal's.
time_series select_signal(const sampled_signals& signals, std::string_view selector,
                          std::string_view option);

/// The most bytes read_text_file reads: 1 GiB, some ten times a table of the longest series a
/// simulation gives (2^22 samples).
inline constexpr std::size_t max_text_file_bytes = std::size_t{1} << 30;

/// The whole text of a file (or a pipe or device: /dev/stdin). Throws input_error naming
/// `option`: "cannot read 'x.csv': <reason>", "'dir' is a directory", for more than
/// `max_bytes`, and at the first byte of binary data (binary_data_message) — so an endless
/// device is never read without bound; throws interrupted when SIGINT or SIGTERM arrives
/// while reading.
std::string read_text_file(const std::string& path, std::string_view option,
                           std::size_t max_bytes = max_text_file_bytes);

/// compute(s) — a computation that integrates the simulated start s and returns a result
/// with its `run` (npend::integration_result) — with a progress bar on a terminal and Ctrl-C
/// as the run control of s's integration. Throws cli::interrupted when a signal stopped it:
/// a series cut short would be analysed as if it were the whole.
template <class Compute>
auto on_terminal(simulated_start s, Compute&& compute) {
  terminal_run control;
  s.integration.control = &control;
  auto result = compute(std::as_const(s));
  control.finish();
  if (control.interrupted())
    throw interrupted(
        fmt::format("interrupted at t = {} s of the simulation; nothing analysed", result.run.t),
        control.exit_code());
  return result;
}

/// npend::simulate_signals on_terminal. Throws npend::integration_error if the integration
/// cannot go on.
sampled_signals simulate_with_progress(const simulated_start& s,
                                       const step_observer_function& step_observer = {});

/// How a command uses its series, which decides the options it gets.
enum class series_use {
  signal,  ///< one signal: --input or a simulated start of --samples samples; --column
  events,  ///< events between signals: --input or a simulated start over --t-end; no --column
  whole,   ///< a simulated start only, both --samples and --t-end (npend analyze)
};

/// The options that say where a command's time series comes from.
struct series_options {
  std::string input, column, dt;
  chain_options chain;
  start_options start;
  std::string samples, t_end;
  integrator_options integrator;  ///< --stepper, --abs-tol, --rel-tol

  /// Adds the options of `use` to `command`: --input (not for whole), --column alias
  /// --coordinate (signal and whole), --dt, the chain and start options, --samples (signal
  /// and whole), --t-end (events and whole), --stepper, --abs-tol, --rel-tol. The command
  /// must outlive this object's use of it.
  void add_to(CLI::App& command, series_use use = series_use::signal);

  /// Whether the series is simulated (--links given) rather than read (--input).
  bool simulated() const;

  /// The simulated start, if --links was given: t_end = (samples − 1)·dt for signal, --t-end
  /// (default 200 s) for events, the larger of the two for whole; dt default 0.001 s;
  /// stepper default gauss6; at least `min_samples` samples (default 16384, at most 2²²).
  /// Throws input_error for a missing or mixed source and every bad option (naming it), and
  /// for options of a simulation given with --input.
  std::optional<simulated_start> simulation(std::size_t min_samples) const;

  /// The signals: from the CSV file given with --input, or simulated; at least
  /// `min_samples` samples. Throws input_error for a missing source or bad data.
  sampled_signals load(std::size_t min_samples) const;

  /// load(), then the signal named by --column (a CSV column) or --coordinate (phi3, p_2, …
  /// for a simulation; default phin).
  time_series load_one(std::size_t min_samples) const;

 private:
  const CLI::App* m_command = nullptr;
  series_use m_use = series_use::signal;
};

}  // namespace npend::cli
