// The signals the time-series analyses work on (paper §6.6): named series on one uniform
// time grid, from a simulated chain — its coordinates φ_1..φ_n, p_1..p_n and the bounded
// observables of its angles — or from measured data read by an application.
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "npend/chain.hpp"
#include "npend/integrators/integrate.hpp"

namespace npend {

/// Named signals sampled on one uniform time grid t_j = t0 + j dt.
struct sampled_signals {
  std::string source;              ///< where they came from, for messages and reports ("data.csv")
  double t0 = 0;                   ///< s
  double dt = 0;                   ///< s
  std::vector<std::string> names;  ///< one per signal; for CSV files the header or "1", "2", …
  std::vector<std::vector<double>> values;  ///< one series per signal, all of equal length
  /// The signals' units for plots ("rad", "kg m^2/s"): known for a simulation, empty (unknown)
  /// for data files.
  std::vector<std::string> units;
  /// Selector numbers (1-based) of the signals: their column in the file, counting the time
  /// column, as gnuplot and cut count.
  std::vector<std::size_t> numbers;
  std::string time_name;           ///< the time column's name, if there is one
  std::size_t time_number = 0;     ///< its column number (1-based), 0 if none
  std::size_t default_signal = 0;  ///< the signal chosen when none is named

  std::size_t samples() const { return values.empty() ? 0 : values.front().size(); }
};

/// One signal chosen from sampled_signals.
struct time_series {
  std::string source, name;
  double t0 = 0, dt = 0;
  std::vector<double> values;
  std::string unit;  ///< for plots; empty if unknown
};

/// Signal k (< signals.names.size(); not checked) as a time series of its own.
time_series signal_at(const sampled_signals& signals, std::size_t k);

/// The name of state index `index` (< 2n) of an n-link chain: "phi3", "p1".
std::string coordinate_name(std::size_t index, int links);

/// A simulated start: the chain, its start state, and the integration that samples it.
struct simulated_start {
  npend::chain pendulum;
  std::vector<double> x0;           ///< [φ, p] (dim 2n)
  integration_options integration;  ///< its output grid is the sample grid
  std::size_t samples = 0;          ///< grid points recorded as signals (0: none)
  std::string source;               ///< "simulation: 3 links, E = 14.7 J, gauss6, dt = 0.001 s"
};

/// What simulate_signals recorded, and how its integration ended.
struct simulated_signals {
  sampled_signals signals;
  integration_result run;  ///< run.stopped: the run control stopped it before t_end
};

/// Integrates `s` to its t_end (with its run control, if any) and records its first
/// s.samples grid points as the signals phi1..phin, p1..pn (t0 and dt of the grid; the
/// default signal is phin), passing every step to `step_observer` if given (for events
/// located on the steps). A run stopped early has fewer samples. Throws as npend::integrate
/// does.
simulated_signals simulate_signals(const simulated_start& s,
                                   const step_observer_function& step_observer = {});

/// A bounded observable of the simulation signals `s` of chain `c` (whose first n signals
/// are φ_1..φ_n): sin_phiK, cos_phiK, wrapped_phiK (in [−π, π]), or the bob positions xK,
/// yK (m, y down; eq. 6.1), K = 1..n. An arm that turns over makes φ_K a ramp; these stay
/// bounded. None if `name` is not one of them.
std::optional<time_series> chain_observable(const sampled_signals& s, const chain& c,
                                            std::string_view name);

/// Whether `x` is an angle φ_K whose series winds by more than a turn (max − min > 2π): its
/// spectrum, autocorrelation and mutual information are then those of a ramp.
bool winds_over(const time_series& x);

}  // namespace npend
