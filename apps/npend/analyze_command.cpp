// npend analyze: every analysis of paper §6.6 for one simulated start, written to a folder
// with the data (CSV), the plots (PNG from kept gnuplot scripts) and an index (Markdown).
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>

#include "command.hpp"
#include "figure_index.hpp"
#include "input_parsing.hpp"
#include "npend/analysis/motion/motion_analysis.hpp"
#include "npend/analysis/motion/rod_tensions.hpp"
#include "npend/excitation.hpp"
#include "output_file.hpp"
#include "section_spec.hpp"
#include "series_figures.hpp"
#include "series_output.hpp"
#include "time_series_source.hpp"

namespace npend::app {

namespace {

// τ_k(t) of every rod at the samples of all coordinates (angles may be wrapped: the tensions
// depend on them through cosines only).
cli::plot_panel tension_panel(series_output& files, const chain& c,
                              const sampled_signals& signals) {
  const auto n = static_cast<std::size_t>(c.links());
  std::vector<std::string> names{"t"};
  std::vector<std::vector<double>> columns(n + 1);
  for (std::size_t k = 1; k <= n; ++k) names.push_back(fmt::format("tau_{}", k));
  std::vector<double> x(2 * n), tau(n);
  for (std::size_t j = 0; j < signals.samples(); ++j) {
    columns[0].push_back(signals.t0 + static_cast<double>(j) * signals.dt);
    for (std::size_t i = 0; i < 2 * n; ++i) x[i] = signals.values[i][j];
    rod_tensions(c, x, tau);
    for (std::size_t k = 0; k < n; ++k) columns[k + 1].push_back(tau[k]);
  }
  const std::string data = files.write_csv("", names, columns);
  cli::plot_panel panel{.title = "Rod tensions",
                        .xlabel = "time t (s)",
                        .ylabel = "tension τ_k (N)",
                        .commands = {"set key top right", "set grid", "set xzeroaxis lt -1"}};
  static const char* colours[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e"};
  for (std::size_t k = 0; k < n; ++k)
    panel.curves.push_back({data, fmt::format("1:{}", k + 2),
                            fmt::format("lines lw 1.2 lc rgb '{}'", colours[k % 5]),
                            fmt::format("τ_{}", k + 1)});
  return panel;
}

namespace fs = std::filesystem;

struct analyze_options {
  cli::series_options series;
  std::string section = "phi1=0", direction = "up", event, event_direction = "both", project;
  std::string out;
  bool json = false;
  bool unwrapped = false;
};

// What the options ask of the analysis, checked before the run.
struct analyze_plan {
  motion_analysis_options options;
  cli::angle_mode angles = cli::angle_mode::circle;
  std::string event;                               // the event's spec (default phin=0)
  std::pair<std::size_t, std::size_t> projection;  // the Poincaré plot's coordinates
  std::string section_what, event_what;            // the section and the events, in words
};

analyze_plan plan_analysis(const analyze_options& o, int n) {
  analyze_plan plan;
  motion_analysis_options& options = plan.options;
  options.coordinate = o.series.column.empty()
                           ? static_cast<std::size_t>(n - 1)
                           : cli::parse_coordinate(o.series.column, n, "--coordinate");
  plan.angles = o.unwrapped ? cli::angle_mode::unwrapped : cli::angle_mode::circle;
  options.section = cli::section_from_spec(cli::parse_section_spec(o.section, "--section"), n,
                                           "--section", plan.angles);
  options.section_direction = cli::parse_direction(o.direction, "--direction");
  plan.event = o.event.empty() ? fmt::format("phi{}=0", n) : o.event;
  options.event = cli::section_from_spec(cli::parse_section_spec(plan.event, "--event"), n,
                                         "--event", plan.angles);
  options.event_direction = cli::parse_direction(o.event_direction, "--event-direction");
  plan.projection =
      o.project.empty()
          ? std::pair<std::size_t, std::size_t>{options.coordinate,
                                                options.coordinate < static_cast<std::size_t>(n)
                                                    ? options.coordinate + n
                                                    : options.coordinate - n}
          : cli::parse_projection(o.project, n, "--project");
  plan.section_what =
      fmt::format("{} ({})", o.section, cli::direction_name(options.section_direction));
  plan.event_what =
      fmt::format("{} ({})", plan.event, cli::direction_name(options.event_direction));
  return plan;
}

// The figures of the folder, each with its text.
void add_figures(figure_folder& folder, const simulated_start& simulation, const motion_analysis& a,
                 const analyze_plan& plan) {
  const chain& c = simulation.pendulum;
  const int n = c.links();
  const time_series& x = a.series;
  const motion_analysis_options& options = plan.options;
  folder.add("series", "Time series",
             fmt::format("{}(t) over the {} samples analysed below (dt = {:g} s). Regular motion "
                         "looks like a beat of a few oscillations; chaotic motion like calm phases "
                         "and sudden flurries taking turns.",
                         x.name, x.values.size(), x.dt),
             [&](series_output& out) {
               return std::vector{time_series_panel(out, "", a.signals, options.coordinate)};
             });
  if (!c.is_physical())
    folder.add("tensions", "Rod tensions",
               fmt::format("The tension τ_k(t) of every rod (N) over the samples: Lagrange's "
                           "equations of the first kind (paper §6.3.1) at each state. At rest "
                           "τ_k is the weight below rod k; a swing adds the centripetal part, "
                           "and a rod whose tension drops below 0 pushes."),
               [&](series_output& out) { return std::vector{tension_panel(out, c, a.signals)}; });
  folder.add("spectrum", "Spectral density",
             fmt::format("ρ(ω) = |x̂(ω)|² of {} (mean removed, Hann window), on a log scale, its "
                         "peaks marked. A few sharp lines mean periodic or quasi-periodic motion "
                         "(for small oscillations: the normal modes); a broad continuous spectrum "
                         "is a sign of chaos.",
                         x.name),
             [&](series_output& out) {
               return std::vector{spectrum_panel(out, "", x, a.spectrum, a.peaks)};
             });
  folder.add("autocorrelation", "Autocorrelation",
             fmt::format("C_xx(τ) of {}, normalised to C_xx(0) = 1. It keeps oscillating for a "
                         "discrete spectrum (long memory) and decays towards 0 for chaotic motion.",
                         x.name),
             [&](series_output& out) {
               return std::vector{autocorrelation_panel(out, "", x, a.autocorrelation)};
             });
  if (!a.section.empty())
    folder.add(
        "poincare", "Poincaré section",
        fmt::format("The {} crossings of the section {} over {:g} s, projected on ({}, {}). "
                    "Periodic motion gives finitely many points, quasi-periodic motion closed "
                    "curves, chaotic motion a scattered cloud.",
                    a.section.size(), plan.section_what, simulation.integration.t_end,
                    cli::coordinate_name(plan.projection.first, n),
                    cli::coordinate_name(plan.projection.second, n)),
        [&](series_output& out) {
          return std::vector{
              poincare_panel(out, "", c, a.section, plan.projection, plan.section_what)};
        },
        {820, 760});
  if (a.recurrence)
    folder.add(
        "recurrence", "Recurrence times",
        fmt::format("The intervals between the events {} over {:g} s, their probability "
                    "density and the spectrum of the interval sequence. Periodic motion "
                    "clusters them at a few values; chaotic motion spreads them around a mean "
                    "T with a broad spectrum.",
                    plan.event_what, simulation.integration.t_end),
        [&](series_output& out) {
          const auto p = recurrence_figure(out, "", plan.event_what, a.event_times, *a.recurrence);
          return std::vector{p.intervals, p.distribution, p.spectrum};
        },
        {1500, 520, 3});
  if (a.embedded())
    folder.add(
        "embedding", "Delay embedding",
        fmt::format("{}(t) against {}(t − τ) with τ = {:.4g} s ({}), and the false-nearest-"
                    "neighbour fraction and Cao's E1, E2 against the embedding dimension m. "
                    "Too small a τ squeezes the plot onto the diagonal, too large a τ folds it.",
                    x.name, x.name, a.tau.seconds, delay_method_name(a.tau.method)),
        [&](series_output& out) {
          const auto [delay, dimension] =
              embedding_figure(out, "", x, a.tau, a.vectors, a.fnn, a.cao, a.dimension, "fnn");
          return std::vector{delay, dimension};
        },
        {1300, 620, 2});
}

// The numbers of the index, the terminal and the JSON: the index's title, preamble and table
// (its entries are the folder's figures).
figure_index index_text(const simulated_start& simulation, const motion_analysis& a,
                        const analyze_plan& plan) {
  const chain& c = simulation.pendulum;
  const int n = c.links();
  const time_series& x = a.series;
  const double duration = x.dt * static_cast<double>(x.values.size() - 1);
  const double energy = c.hamiltonian(simulation.x0);
  std::string epsilon;
  try {
    epsilon = fmt::format(" (ε = E/(m g l) = {:.4g})", epsilon_from_energy(c, energy));
  } catch (const std::invalid_argument&) {  // unequal masses or lengths: no ε
  }
  std::vector<std::string> lines;
  for (std::size_t k = 0; k < std::min<std::size_t>(a.peaks.size(), 5); ++k)
    lines.push_back(fmt::format("{:.4g}", a.peaks[k].omega));
  const auto seconds = [](const std::optional<double>& v) {
    return v ? fmt::format("{:.4g} s", *v) : std::string("none");
  };
  figure_index index;
  index.facts = {
      {"energy E", fmt::format("{:.6g} J{}", energy, epsilon)},
      {"series", fmt::format("{}, {} samples, dt = {:g} s ({:g} s)", x.name, x.values.size(), x.dt,
                             duration)},
      {"strongest spectral lines ω (rad/s)",
       lines.empty() ? "none" : fmt::format("{}", fmt::join(lines, ", "))},
      {"autocorrelation",
       fmt::format("first zero {}, first minimum {}", seconds(a.autocorrelation.first_zero),
                   seconds(a.autocorrelation.first_minimum))},
      {fmt::format("Poincaré section {}", plan.section_what),
       fmt::format("{} crossings, largest |g| {:.1e}, largest |H − E|/E {:.1e}", a.section.size(),
                   a.section_quality.max_residual, a.section_quality.max_rel_energy_error)},
      {fmt::format("events {}", plan.event_what),
       a.recurrence
           ? fmt::format("{} events, mean interval T = {:.4g} s, standard deviation "
                         "{:.3g} s",
                         a.event_times.size(), a.recurrence->mean, a.recurrence->standard_deviation)
           : fmt::format("{} events", a.event_times.size())},
      {"delay embedding",
       a.embedded() ? fmt::format("τ = {:.4g} s ({}), dimension {}", a.tau.seconds,
                                  delay_method_name(a.tau.method),
                                  a.dimension ? std::to_string(*a.dimension) : "none up to 10")
                    : "none"}};
  index.title = fmt::format("npend analyze: the {}-link chain, E = {:.6g} J", n, energy);
  index.preamble = {
      fmt::format("Masses {} kg, lengths {} m, g = {} m/s². Start x₀ = [φ₁..φ_{}, p₁..p_{}] = "
                  "[{}] (rad, kg m²/s).",
                  fmt::join(c.parameters().masses, ", "), fmt::join(c.parameters().lengths, ", "),
                  c.parameters().g, n, n, fmt::join(simulation.x0, ", ")),
      fmt::format("Integrated by {} with dt = {:g} s from t = 0 to {:g} s: the first {} samples "
                  "are the time series, the whole run gives the Poincaré section and the events "
                  "(located on the integrator's steps, not on the samples).",
                  stepper_name(simulation.integration.stepper), simulation.integration.dt,
                  simulation.integration.t_end, x.values.size())};
  return index;
}

void print_analyze_json(const analyze_options& o, const fs::path& dir, const fs::path& index,
                        const std::vector<std::string>& files, const simulated_start& simulation,
                        const motion_analysis& a, const analyze_plan& plan,
                        const std::vector<std::string>& notes) {
  const time_series& x = a.series;
  nlohmann::json peaks = nlohmann::json::array();
  for (const auto& p : a.peaks) peaks.push_back({{"omega", p.omega}, {"power", p.power}});
  const auto optional = [](const auto& v) { return v ? nlohmann::json(*v) : nlohmann::json(); };
  nlohmann::json j{
      {"out", dir.string()},
      {"index", index.string()},
      {"files", files},
      {"links", simulation.pendulum.links()},
      {"initial_state", simulation.x0},
      {"energy", simulation.pendulum.hamiltonian(simulation.x0)},
      {"stepper", std::string(stepper_name(simulation.integration.stepper))},
      {"dt", simulation.integration.dt},
      {"t_end", simulation.integration.t_end},
      {"signal", x.name},
      {"samples", x.values.size()},
      {"peaks", peaks},
      {"first_zero", optional(a.autocorrelation.first_zero)},
      {"first_minimum", optional(a.autocorrelation.first_minimum)},
      {"section", o.section},
      {"angles", cli::angle_mode_name(plan.angles)},
      {"crossings", a.section.size()},
      {"max_section_residual", a.section_quality.max_residual},
      {"max_rel_energy_error", a.section_quality.max_rel_energy_error},
      {"event", plan.event},
      {"events", a.event_times.size()},
      {"mean_interval", a.recurrence ? nlohmann::json(a.recurrence->mean) : nlohmann::json()},
      {"tau", a.embedded() ? nlohmann::json(a.tau.seconds) : nlohmann::json()},
      {"dimension", optional(a.dimension)},
      {"notes", notes}};
  std::cout << j.dump(2) << "\n";
}

int run_analyze(const analyze_options& o) {
  const fs::path dir = cli::output_folder(o.out, "--out");
  const auto simulation = o.series.simulation(64);
  const analyze_plan plan = plan_analysis(o, simulation->pendulum.links());
  motion_analysis a;
  try {
    a = cli::on_terminal(
        *simulation, [&](const simulated_start& run) { return analyze_motion(run, plan.options); });
  } catch (const std::invalid_argument& e) {  // the options were checked: the start is at fault
    throw cli::input_error(e.what());
  }
  figure_folder folder(dir, "npend analyze: ", " of " + a.series.source);
  // Every file or none: the figures, their data and the index appear together at the end.
  cli::output_batch batch;
  add_figures(folder, *simulation, a, plan);
  figure_index text = index_text(*simulation, a, plan);
  std::vector<std::string> notes = a.notes;
  notes.insert(notes.end(), folder.notes().begin(), folder.notes().end());
  folder.index() = {text.title, text.preamble, text.facts, folder.index().entries, notes};
  const fs::path index = folder.write_index();
  batch.commit_all();
  const std::vector<std::string>& files = folder.files();
  for (const auto& note : notes) fmt::print(stderr, "note: {}\n", note);

  if (o.json) {
    print_analyze_json(o, dir, index, files, *simulation, a, plan, notes);
    return 0;
  }
  fmt::print("{}\n\n", text.title);
  for (const auto& [name, value] : text.facts) fmt::print("{:<40} {}\n", name, value);
  fmt::print("\nWrote {} files to {}/; open {}\n", files.size(), dir.string(), index.string());
  return 0;
}

}  // namespace

void add_analyze_command(CLI::App& app, command_list& commands) {
  auto o = std::make_shared<analyze_options>();
  CLI::App* cmd = app.add_subcommand(
      "analyze",
      "Every analysis of one simulated start (time series, spectrum, autocorrelation, Poincare "
      "section, recurrence times, delay embedding) into a folder with plots and an index");
  o->series.add_to(*cmd, cli::series_use::whole);
  cmd->add_option("--section", o->section,
                  "The Poincare section: NAME=VALUE or NAME=NAME over phi1..phin, p1..pn")
      ->capture_default_str();
  cmd->add_option("--direction", o->direction, "Crossings of the section: up, down or both")
      ->capture_default_str();
  cmd->add_option("--event", o->event,
                  "The recurrence event, like --section (default: phin=0, the paper's)");
  cmd->add_option("--event-direction", o->event_direction, "Events counted: up, down or both")
      ->capture_default_str();
  cmd->add_option("--project", o->project,
                  "The two coordinates of the Poincare plot, e.g. phi3,p3 (default: the analysed "
                  "coordinate and its partner)");
  cmd->add_option("--out", o->out,
                  "The folder to write (created if missing; files in it are replaced)")
      ->required();
  cmd->add_flag("--unwrapped", o->unwrapped,
                "Sections and events of angles on the unwrapped angle instead of on the circle "
                "(the default: every passage of the arm)");
  cmd->add_flag("--json", o->json, "Print a JSON summary instead of the table");
  commands.push_back({cmd, [o] { return run_analyze(*o); }});
}

}  // namespace npend::app
