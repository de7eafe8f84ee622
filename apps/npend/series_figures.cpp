#include "series_figures.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <tuple>

#include "section_spec.hpp"

namespace npend::app {

namespace {

// The plot's upper frequency: where the density has fallen for good — 1.5 times the
// frequency below which 99.9% of the power lies, at least 1.25 times the highest reported
// peak, at most the Nyquist frequency.
double plot_limit(const power_spectrum_result& s, const std::vector<spectral_peak>& peaks) {
  double total = 0;
  for (const double p : s.power) total += p;
  double cumulative = 0, limit = s.omega.back();
  for (std::size_t k = 0; k < s.power.size(); ++k) {
    cumulative += s.power[k];
    if (cumulative >= 0.999 * total) {
      limit = 1.5 * s.omega[k];
      break;
    }
  }
  for (const auto& p : peaks) limit = std::max(limit, 1.25 * p.omega);
  return std::min(limit, s.omega.back());
}

// The tick spacing 1, 2 or 5 × 10^k nearest to range/count (on a log scale): about `count`
// ticks.
double tick_step(double range, double count) {
  const double raw = range / count;
  const double decade = std::pow(10.0, std::floor(std::log10(raw)));
  double best = decade;
  for (const double m : {2.0, 5.0, 10.0})
    if (std::fabs(std::log(m * decade / raw)) < std::fabs(std::log(best / raw))) best = m * decade;
  return best;
}

// A signal's name in gnuplot's enhanced text: phi3 as φ_3, p3 as p_3, others as they are.
std::string display_name(const std::string& name) {
  for (const auto& [prefix, shown] : {std::pair{"phi", "φ"}, {"p", "p"}})
    if (name.starts_with(prefix) && name.size() > std::string_view(prefix).size() &&
        std::all_of(name.begin() + static_cast<std::ptrdiff_t>(std::string_view(prefix).size()),
                    name.end(), [](char c) { return c >= '0' && c <= '9'; }))
      return fmt::format("{}_{{{}}}", shown, name.substr(std::string_view(prefix).size()));
  return name;
}

// A signal's value at `argument` with its unit: "φ_3(t − τ) (rad)", "x(t) ([x])".
std::string value_label(const time_series& x, std::string_view argument) {
  if (x.unit.empty()) return fmt::format("x({}) ([x])", argument);
  return fmt::format("{}({}) ({})", display_name(x.name), argument, x.unit);
}

// The unit of a spectral density of x: "rad^2 s/rad", "[x]^2 s/rad".
std::string density_unit(const time_series& x) {
  if (x.unit.empty()) return "[x]^2 s/rad";
  return x.unit.find(' ') == std::string::npos ? fmt::format("{}^2 s/rad", x.unit)
                                               : fmt::format("({})^2 s/rad", x.unit);
}

// A state coordinate as a gnuplot axis label with its unit.
std::string coordinate_label(std::size_t index, int links) {
  const auto n = static_cast<std::size_t>(links);
  return index < n ? fmt::format("φ_{{{}}} (rad)", index + 1)
                   : fmt::format("p_{{{}}} (kg m^2/s)", index - n + 1);
}

}  // namespace

std::string table_name(std::string_view table, std::string_view suffix) {
  return table.empty() ? std::string(suffix) : fmt::format("{}_{}", table, suffix);
}

std::string window_label(spectral_window w) {
  if (w == spectral_window::none) return "rectangular";
  std::string name(spectral_window_name(w));
  name[0] = static_cast<char>(name[0] - 'a' + 'A');
  return name;
}

cli::plot_panel spectrum_panel(series_output& files, std::string_view table, const time_series& x,
                               const power_spectrum_result& spectrum,
                               const std::vector<spectral_peak>& peaks,
                               std::optional<double> omega_max) {
  const std::string data = files.write_csv(table, std::vector<std::string>{"omega", "power"},
                                           std::vector{spectrum.omega, spectrum.power});
  std::vector<double> peak_omega, peak_power;
  for (const auto& p : peaks) {
    peak_omega.push_back(p.omega);
    peak_power.push_back(p.power);
  }
  const std::string marks =
      files.write_csv(table_name(table, "peaks"), std::vector<std::string>{"omega", "power"},
                      std::vector{peak_omega, peak_power});
  const double top = *std::max_element(spectrum.power.begin(), spectrum.power.end());
  const double limit = omega_max.value_or(plot_limit(spectrum, peaks));
  cli::plot_panel panel{.title = fmt::format("Spectral density of {} ({} window, {} segment{})",
                                             x.name, window_label(spectrum.window),
                                             spectrum.segments, spectrum.segments == 1 ? "" : "s"),
                        .xlabel = "angular frequency ω (rad/s)",
                        .ylabel = fmt::format("spectral density ρ(ω) ({})", density_unit(x)),
                        .log_y = top > 0,
                        .xrange = fmt::format("[0:{}]", limit),
                        .yrange = top > 0 ? fmt::format("[{}:{}]", top * 1e-10, top * 5) : "",
                        .curves = {{data, "1:2", "lines lw 1.5 lc rgb '#1f5fa8'", "ρ(ω)"},
                                   {marks, "1:2", "points pt 7 ps 1.3 lc rgb '#d62728'", "peaks"}}};
  // Label the strongest peaks, skipping any too close to a stronger labelled one to read
  // (a label is about 5 % of the axis wide).
  std::vector<double> labelled;
  for (const auto& p : peaks) {
    if (labelled.size() == 6) break;
    if (std::any_of(labelled.begin(), labelled.end(),
                    [&](double w) { return std::fabs(w - p.omega) < 0.08 * limit; }))
      continue;
    labelled.push_back(p.omega);
    panel.commands.push_back(
        fmt::format("set label {} \"{:.4g}\" at {},{} offset 0.8,0.6 font \",10\" tc rgb '#d62728'",
                    labelled.size(), p.omega, p.omega, p.power));
  }
  return panel;
}

cli::plot_panel mutual_information_panel(series_output& files, std::string_view table,
                                         const time_series& x,
                                         const mutual_information_result& ami) {
  const std::string data = files.write_csv(table, std::vector<std::string>{"tau", "I"},
                                           std::vector{ami.lag, ami.information});
  cli::plot_panel panel{.title = fmt::format("Average mutual information of {}", x.name),
                        .xlabel = "lag τ (s)",
                        .ylabel = "I(τ) (bit)",
                        .commands = {"set key off"},
                        .curves = {{data, "1:2", "lines lw 1.5 lc rgb '#1f5fa8'", ""}}};
  if (ami.first_minimum)
    panel.commands.push_back(
        fmt::format("set arrow from {0},graph 0 to {0},graph 1 nohead dt 2 lw 1.5 lc rgb '#d62728'",
                    *ami.first_minimum));
  return panel;
}

cli::plot_panel autocorrelation_panel(series_output& files, std::string_view table,
                                      const time_series& x, const autocorrelation_result& c) {
  const std::string data =
      files.write_csv(table, std::vector<std::string>{"tau", "C"}, std::vector{c.lag, c.value});
  cli::plot_panel panel{.title = fmt::format("Autocorrelation of {}", x.name),
                        .xlabel = "lag τ (s)",
                        .ylabel = "C_{xx}(τ)",
                        .xrange = fmt::format("[0:{}]", c.lag.back()),
                        .yrange = "[-1.05:1.05]",
                        .commands = {"set xzeroaxis lt -1 lw 1"},
                        .curves = {{data, "1:2", "lines lw 1.5 lc rgb '#1f5fa8'", "C_{xx}(τ)"}}};
  if (c.first_zero)
    panel.commands.push_back(
        fmt::format("set arrow from {0},-1.05 to {0},1.05 nohead dt 2 lc rgb '#2ca02c'\n"
                    "set label \"first zero {0:.4g} s\" at {0},0.9 offset 0.6,0 tc rgb '#2ca02c'",
                    *c.first_zero));
  if (c.first_minimum)
    panel.commands.push_back(fmt::format(
        "set arrow from {0},-1.05 to {0},1.05 nohead dt 3 lc rgb '#d62728'\n"
        "set label \"first minimum {0:.4g} s\" at {0},-0.9 offset 0.6,0 tc rgb '#d62728'",
        *c.first_minimum));
  return panel;
}

recurrence_panels recurrence_figure(series_output& files, std::string_view table,
                                    std::string_view what, std::span<const double> times,
                                    const recurrence_statistics& stats) {
  // A strictly periodic signal: equal intervals up to rounding, an interval spectrum of noise.
  const bool constant = stats.standard_deviation <= 1e-9 * stats.mean;
  std::vector<double> index, start;
  for (std::size_t j = 0; j < stats.intervals.size(); ++j) {
    index.push_back(static_cast<double>(j + 1));
    start.push_back(times[j]);
  }
  const std::string data =
      files.write_csv(table, std::vector<std::string>{"index", "time", "interval"},
                      std::vector{index, start, stats.intervals});
  const auto& h = stats.distribution;
  std::vector<double> centre, width;
  for (std::size_t b = 0; b + 1 < h.edges.size(); ++b) {
    centre.push_back(0.5 * (h.edges[b] + h.edges[b + 1]));
    width.push_back(h.edges[b + 1] - h.edges[b]);
  }
  const std::string histogram = files.write_csv(
      table_name(table, "histogram"), std::vector<std::string>{"interval", "density", "width"},
      std::vector{centre, h.density, width});
  const std::string spectrum =
      files.write_csv(table_name(table, "spectrum"), std::vector<std::string>{"omega", "power"},
                      std::vector{stats.spectrum.omega, stats.spectrum.power});
  const double top =
      constant ? 0.0 : *std::max_element(stats.spectrum.power.begin(), stats.spectrum.power.end());
  return {
      .intervals = {.title = fmt::format("Intervals between events {}", what),
                    .xlabel = "event number j",
                    .ylabel = "interval T_j (s)",
                    .yrange = constant ? fmt::format("[{}:{}]", stats.mean * (1 - 1e-3),
                                                     stats.mean * (1 + 1e-3))
                                       : "",
                    .curves = {{data, "1:3", "linespoints pt 7 ps 0.6 lw 1 lc rgb '#1f5fa8'", ""}}},
      .distribution =
          {.title = fmt::format("Distribution (mean {:.4g} s)", stats.mean),
           .xlabel = "interval T (s)",
           .ylabel = "probability density (1/s)",
           .yrange = "[0:*]",
           .commands = {"set style fill solid 0.6 border lc rgb '#1f5fa8'",
                        fmt::format("set arrow from {0},graph 0 to {0},graph 1 nohead front dt 2 "
                                    "lc rgb '#d62728'",
                                    stats.mean),
                        // One bin 1e-3 wide: a single tick at the mean instead of crowded ones;
                        // otherwise about four ticks, so that their labels do not run together.
                        constant ? fmt::format("set xtics ({:.9g}) format '%.6g'; unset mxtics",
                                               stats.mean)
                                 : fmt::format("set xtics {:.6g}",
                                               tick_step(h.edges.back() - h.edges.front(), 4))},
           .curves = {{histogram, "1:2:3", "boxes lc rgb '#1f5fa8'", ""}}},
      .spectrum = {.title = constant ? "Spectrum of the interval sequence (intervals constant)"
                                     : "Spectrum of the interval sequence",
                   .xlabel = "ω (rad per event)",
                   .ylabel = "ρ (s^2 event/rad)",
                   .log_y = top > 0,
                   .xrange = fmt::format("[0:{}]", stats.spectrum.omega.back()),
                   .yrange = top > 0 ? fmt::format("[{}:{}]", top * 1e-8, top * 5) : "[-1:1]",
                   .curves = {{spectrum, "1:2", "lines lw 1.5 lc rgb '#1f5fa8'", ""}}}};
}

cli::plot_panel delay_plot_panel(series_output& files, std::string_view table, const time_series& x,
                                 const delay_choice& tau, const delay_vectors& v) {
  const std::size_t shown = v.dimension;
  std::vector<std::string> names{"t"};
  std::vector<std::vector<double>> columns(shown + 1);
  for (std::size_t c = 0; c < shown; ++c)
    names.push_back(c == 0 ? "x(t)" : c == 1 ? "x(t-tau)" : fmt::format("x(t-{}tau)", c));
  for (std::size_t i = 0; i < v.count; ++i) {
    columns[0].push_back(x.t0 + static_cast<double>(i + (shown - 1) * v.delay) * x.dt);
    for (std::size_t c = 0; c < shown; ++c) columns[c + 1].push_back(v.points[i * shown + c]);
  }
  const std::string data = files.write_csv(table, names, columns);
  return {.title = fmt::format("Delay plot of {}, τ = {:.4g} s", x.name, tau.seconds),
          .xlabel = value_label(x, "t"),
          .ylabel = value_label(x, "t − τ"),
          .commands = {"set size square", "set key off"},
          .curves = {{data, "2:3", "lines lw 0.8 lc rgb '#1f5fa8'", ""}}};
}

cli::plot_panel embedding_dimension_panel(series_output& files, std::string_view table,
                                          const false_neighbours_result& fnn, const cao_result& cao,
                                          std::optional<std::size_t> dimension,
                                          std::string_view method) {
  const std::size_t max_dim = fnn.fraction.size();
  std::vector<double> m;
  for (std::size_t d = 1; d <= max_dim; ++d) m.push_back(static_cast<double>(d));
  const std::string criteria = files.write_csv(
      table,
      std::vector<std::string>{"m", "fnn", "fnn_distance", "fnn_attractor", "cao_e1", "cao_e2"},
      std::vector{m, fnn.fraction, fnn.fraction_distance, fnn.fraction_attractor, cao.e1, cao.e2});
  cli::plot_panel dimension_plot{
      .title = dimension ? fmt::format("Embedding dimension {} ({})", *dimension, method)
                         : fmt::format("No embedding dimension up to {} ({})", max_dim, method),
      .xlabel = "embedding dimension m",
      .ylabel = "fraction of false neighbours; Cao's E1, E2",
      .xrange = fmt::format("[0.5:{}.5]", max_dim),
      .yrange = "[0:1.6]",
      .commands = {"set xtics 1", "unset mxtics", "set key top right"},
      .curves = {{criteria, "1:2", "linespoints pt 7 lw 2 lc rgb '#1f5fa8'", "false neighbours"},
                 {criteria, "1:5", "linespoints pt 5 lw 2 lc rgb '#2ca02c'", "Cao E1"},
                 {criteria, "1:6", "linespoints pt 9 lw 1.5 dt 2 lc rgb '#7f7f7f'", "Cao E2"}}};
  if (dimension)
    dimension_plot.commands.push_back(fmt::format(
        "set arrow from {0},0 to {0},1.6 nohead dt 2 lw 1.5 lc rgb '#d62728'", *dimension));
  return dimension_plot;
}

std::pair<cli::plot_panel, cli::plot_panel> embedding_figure(
    series_output& files, std::string_view table, const time_series& x, const delay_choice& tau,
    const delay_vectors& v, const false_neighbours_result& fnn, const cao_result& cao,
    std::optional<std::size_t> dimension, std::string_view method) {
  return {delay_plot_panel(files, table, x, tau, v),
          embedding_dimension_panel(files, table_name(table, "dimension"), fnn, cao, dimension,
                                    method)};
}

cli::plot_panel poincare_panel(series_output& files, std::string_view table, const chain& c,
                               std::span<const section_crossing> crossings,
                               std::pair<std::size_t, std::size_t> projection,
                               std::string_view section) {
  const int n = c.links();
  const auto size = static_cast<std::size_t>(2 * n);
  std::vector<std::string> names{"t"};
  for (std::size_t i = 0; i < size; ++i) names.push_back(cli::coordinate_name(i, n));
  names.push_back("H");
  std::vector<std::vector<double>> columns(size + 2);
  for (const auto& x : crossings) {
    columns[0].push_back(x.t);
    for (std::size_t i = 0; i < size; ++i) columns[i + 1].push_back(x.state[i]);
    columns[size + 1].push_back(c.hamiltonian(x.state));
  }
  const std::string data = files.write_csv(table, names, columns);
  // The ranges of the points, padded, with about four ticks across and five up: the section of
  // a periodic orbit can span 1e-4 rad, where gnuplot's own ticks run into each other.
  std::vector<std::string> commands{"set key off"};
  for (const auto& [axis, index, ticks] :
       {std::tuple{'x', projection.first, 4.0}, {'y', projection.second, 5.0}}) {
    if (crossings.empty()) break;
    const auto& v = columns[index + 1];
    const auto [low, high] = std::minmax_element(v.begin(), v.end());
    const double pad =
        *high > *low ? 0.06 * (*high - *low) : std::max(1e-3, 1e-3 * std::fabs(*low));
    commands.push_back(fmt::format("set {0}range [{1:.10g}:{2:.10g}]; set {0}tics {3:.10g}", axis,
                                   *low - pad, *high + pad,
                                   tick_step(*high - *low + 2 * pad, ticks)));
  }
  return {.title = fmt::format("Poincaré section {}: {} crossing{}, projected on ({}, {})", section,
                               crossings.size(), crossings.size() == 1 ? "" : "s",
                               cli::coordinate_name(projection.first, n),
                               cli::coordinate_name(projection.second, n)),
          .xlabel = coordinate_label(projection.first, n),
          .ylabel = coordinate_label(projection.second, n),
          .commands = commands,
          .curves = {{data, fmt::format("{}:{}", projection.first + 2, projection.second + 2),
                      "points pt 7 ps 0.45 lc rgb '#1f5fa8'", ""}}};
}

cli::plot_panel time_series_panel(series_output& files, std::string_view table,
                                  const sampled_signals& signals, std::size_t signal,
                                  double t_max) {
  std::vector<std::string> names{"t"};
  names.insert(names.end(), signals.names.begin(), signals.names.end());
  std::vector<std::vector<double>> columns{{}};
  for (std::size_t j = 0; j < signals.samples(); ++j)
    columns[0].push_back(signals.t0 + static_cast<double>(j) * signals.dt);
  columns.insert(columns.end(), signals.values.begin(), signals.values.end());
  const std::string data = files.write_csv(table, names, columns);
  const int links = static_cast<int>(signals.names.size() / 2);
  const double end = t_max > 0 ? t_max : columns[0].back();
  return {.title = fmt::format("{}(t)", signals.names[signal]),
          .xlabel = "time t (s)",
          .ylabel = coordinate_label(signal, links),
          .xrange = fmt::format("[{}:{}]", signals.t0, end),
          .commands = {"set xzeroaxis lt -1 lw 1"},
          .curves = {{data, fmt::format("1:{}", signal + 2), "lines lw 1.2 lc rgb '#1f5fa8'", ""}}};
}

}  // namespace npend::app
