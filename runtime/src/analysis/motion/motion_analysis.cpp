#include "npend/analysis/motion/motion_analysis.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <utility>

namespace npend {

motion_analysis analyze_motion(const simulated_start& sim, const motion_analysis_options& options) {
  const auto links = static_cast<std::size_t>(sim.pendulum.links());
  if (options.coordinate >= 2 * links)
    throw std::invalid_argument(
        fmt::format("analyze_motion: coordinate is {}: the state has {} entries",
                    options.coordinate, 2 * links));
  motion_analysis a;
  crossing_locator section(sim.pendulum, options.section, options.section_direction);
  crossing_locator events(sim.pendulum, options.event, options.event_direction);
  simulated_signals simulated = simulate_signals(sim, [&](const integration_step& step) {
    section(step);
    events(step);
    for (std::size_t i = 0; i < links; ++i)
      a.largest_angle = std::max(a.largest_angle, std::fabs(step.x_end()[i]));
    return observer_action::proceed;
  });
  a.signals = std::move(simulated.signals);
  a.run = simulated.run;
  if (a.run.stopped) return a;
  // Only a plane of unwrapped angles is moved by a flip.
  const auto on_unwrapped_angles = [&](const section_plane& s) {
    return !s.circular &&
           std::any_of(s.normal.begin(), s.normal.begin() + static_cast<std::ptrdiff_t>(links),
                       [](double w) { return w != 0; });
  };
  if (a.largest_angle > std::numbers::pi &&
      (on_unwrapped_angles(options.section) || on_unwrapped_angles(options.event)))
    a.notes.emplace_back(unwrapped_angles_note);
  a.series = signal_at(a.signals, options.coordinate);
  const auto& x = a.series.values;
  const auto [low, high] = std::minmax_element(x.begin(), x.end());
  if (*low == *high)
    throw std::invalid_argument(fmt::format(
        "{} stays at {} over the whole series: nothing moves (give a start away from rest)",
        a.series.name, *low));
  a.section = section.crossings();
  a.section_quality =
      crossing_quality(sim.pendulum, options.section, a.section, sim.pendulum.hamiltonian(sim.x0));
  a.event_times = crossing_times(events.crossings());

  a.spectrum = power_spectrum(x, a.series.dt);
  a.peaks = find_spectral_peaks(a.spectrum);
  a.autocorrelation = autocorrelation(x, a.series.dt, x.size() / 2);
  if (a.event_times.size() >= 3)
    a.recurrence = recurrence_times(a.event_times);
  else
    a.notes.push_back(fmt::format(
        "only {} event{} in {:g} s: no recurrence statistics (at least "
        "3 are needed; try a longer --t-end)",
        a.event_times.size(), a.event_times.size() == 1 ? "" : "s", sim.integration.t_end));
  if (a.section.empty())
    a.notes.push_back(fmt::format("the trajectory never crosses the Poincare section in {:g} s",
                                  sim.integration.t_end));

  a.tau = choose_delay(x, a.series.dt);
  if (!a.tau.found) {
    a.notes.push_back(
        "no delay: the mutual information, the autocorrelation and the spectrum give none");
    return a;
  }
  const std::size_t theiler = a.tau.samples;
  try {
    // Both or neither: the plots show them side by side.
    auto fnn = false_nearest_neighbours(x, a.tau.samples, options.max_dimension,
                                        {.theiler_window = theiler});
    a.cao = cao_embedding(x, a.tau.samples, options.max_dimension, {.theiler_window = theiler});
    a.fnn = std::move(fnn);
  } catch (const std::invalid_argument& e) {
    a.notes.push_back(fmt::format("no embedding dimension: {}", e.what()));
    return a;
  }
  if (a.fnn.found)
    a.dimension = a.fnn.dimension;
  else
    a.notes.push_back(fmt::format("no embedding dimension up to {} by false nearest neighbours",
                                  options.max_dimension));
  a.vectors =
      delay_embedding(x, a.tau.samples, std::clamp<std::size_t>(a.dimension.value_or(2), 2, 3));
  return a;
}

}  // namespace npend
