// npend poincare: the Poincaré section of a simulated start (paper §6.6.1, Abb. 6.8) — the
// crossings of a hyperplane such as phi1=0, located on the integrator's steps, and their
// projection onto two coordinates.
#include <fmt/format.h>

#include <cmath>
#include <functional>
#include <iostream>
#include <nlohmann/json.hpp>
#include <numbers>

#include "chain_options.hpp"
#include "command.hpp"
#include "input_parsing.hpp"
#include "integrator_options.hpp"
#include "npend/analysis/chaos/poincare_section.hpp"
#include "npend/analysis/motion/energy_drift.hpp"
#include "section_spec.hpp"
#include "series_figures.hpp"
#include "series_output.hpp"
#include "start_options.hpp"
#include "terminal_run.hpp"

namespace npend::app {

namespace {

struct poincare_options {
  cli::chain_options chain;
  cli::start_options start;
  cli::integrator_options integrator;
  std::string section, direction = "up", project, max_points, out;
  bool json = false;
  bool unwrapped = false;
};

// The crossings as reported: on a circular section with every angle on the circle, [−π, π].
std::vector<section_crossing> reported(std::vector<section_crossing> crossings,
                                       const section_plane& section, int links) {
  if (!section.circular) return crossings;
  for (auto& x : crossings)
    for (int i = 0; i < links; ++i)
      x.state[static_cast<std::size_t>(i)] = wrapped_angle(x.state[static_cast<std::size_t>(i)]);
  return crossings;
}

// (phin, pn), or (phi(n−1), p(n−1)) when the section involves phin (its points would all
// share that coordinate).
std::pair<std::size_t, std::size_t> default_projection(const section_plane& s, int links) {
  const auto n = static_cast<std::size_t>(links);
  const std::size_t k = links > 1 && s.normal[n - 1] != 0 ? n - 2 : n - 1;
  return {k, n + k};
}

int run_poincare(const poincare_options& o) {
  const chain c = o.chain.make_chain(cli::model_support::conservative, "npend poincare");
  const int n = c.links();
  const cli::angle_mode angles = o.unwrapped ? cli::angle_mode::unwrapped : cli::angle_mode::circle;
  const section_plane section = cli::section_from_spec(
      cli::parse_section_spec(o.section, "--section"), n, "--section", angles);
  const crossing_direction direction = cli::parse_direction(o.direction, "--direction");
  const auto projection = o.project.empty() ? default_projection(section, n)
                                            : cli::parse_projection(o.project, n, "--project");
  std::size_t max_points = 0;
  if (!o.max_points.empty()) {
    const double k = cli::parse_number(o.max_points, "--max-points");
    if (!cli::is_whole_number(k, 1, 1e9))
      throw cli::input_error(
          fmt::format("--max-points: must be a whole number >= 1, got {}", o.max_points));
    max_points = static_cast<std::size_t>(k);
  }
  const std::vector<double> x0 = o.start.make_state(c);
  integration_options options = o.integrator.make_for(c);
  series_output files(o.out);

  // Ctrl-C stops the run at its next output step; nothing is written then.
  cli::terminal_run control;
  options.control = &control;
  crossing_locator locator(c, section, direction, max_points);
  double largest_angle = 0;
  // The energy error of the run itself, at its grid points: the crossings' alone would be
  // 0 for a run without any.
  const double energy = c.hamiltonian(x0);
  energy_drift drift(c, energy);
  const integration_result run = integrate(
      c, x0, options,
      [&](double, std::span<const double> x) {
        drift.add(x);
        for (int i = 0; i < n; ++i)
          largest_angle = std::max(largest_angle, std::fabs(x[static_cast<std::size_t>(i)]));
        return observer_action::proceed;
      },
      std::ref(locator));
  control.finish();
  if (control.interrupted()) {
    fmt::print(stderr, "npend poincare: interrupted at t = {} s{}\n", run.t,
               o.out.empty() ? "" : fmt::format("; nothing written to {}", o.out));
    return control.exit_code();
  }

  const std::vector<section_crossing> crossings = reported(locator.crossings(), section, n);
  const auto [residual, crossing_energy_error, unrefined] =
      crossing_quality(c, section, crossings, energy);
  const double energy_error = std::max(crossing_energy_error, drift.max_relative_error());
  const std::string what = fmt::format("{} ({})", o.section, cli::direction_name(direction));
  const std::string projected = fmt::format("{},{}", cli::coordinate_name(projection.first, n),
                                            cli::coordinate_name(projection.second, n));
  // A section of unwrapped angles: say so when an arm went over the top.
  const bool flipped = largest_angle > std::numbers::pi && o.unwrapped;
  const std::string flip_note(unwrapped_angles_note);

  if (files.enabled()) {
    cli::plot_panel panel = poincare_panel(files, "", c, crossings, projection, what);
    files.write_plot(
        {.description = {fmt::format("npend poincare: section {} of the {}-link chain from "
                                     "x0 = [{}], E = {:.6g} J, t = 0 .. {} s",
                                     what, n, fmt::join(x0, ", "), energy, run.t),
                         fmt::format("data: {} (t, the state at each crossing, H)",
                                     files.file_name(""))},
         .width = 820,
         .height = 760,
         .panels = {panel}});
  }

  if (o.json) {
    nlohmann::json points = nlohmann::json::array();
    for (const auto& x : crossings) points.push_back({{"t", x.t}, {"state", x.state}});
    nlohmann::json j = describe_chain(c);
    j.update(nlohmann::json{
        {"initial_state", x0},
        {"energy", energy},
        {"stepper", std::string(stepper_name(options.stepper))},
        {"dt", options.dt},
        {"t_end", run.t},
        {"section", o.section},
        {"normal", section.normal},
        {"level", section.level},
        {"angles", cli::angle_mode_name(angles)},
        {"direction", cli::direction_name(direction)},
        {"projection",
         {cli::coordinate_name(projection.first, n), cli::coordinate_name(projection.second, n)}},
        {"count", crossings.size()},
        {"points", points},
        {"max_section_residual", residual},
        {"max_rel_energy_error", energy_error},
        {"unrefined", unrefined}});
    if (flipped) j["notes"].push_back(flip_note);
    files.add_to(j);
    if (flipped) fmt::print(stderr, "note: {}\n", flip_note);
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  fmt::print(
      "Poincare section {} of the {}-link chain, E = {:.6g} J, t = 0 .. {:g} s ({}, dt = "
      "{:g} s)\n\n",
      what, n, energy, run.t, stepper_name(options.stepper), options.dt);
  fmt::print("crossings: {}{}\n", crossings.size(),
             max_points != 0 && crossings.size() == max_points ? " (--max-points reached)" : "");
  if (crossings.empty()) fmt::print("largest |H - H0| / H0 over the run: {:.2g}\n", energy_error);
  if (!crossings.empty()) {
    fmt::print(
        "largest |g(x)| on the section: {:.2g}; largest |H - H0| / H0 (run and crossings): "
        "{:.2g}\n",
        residual, energy_error);
    if (unrefined > 0)
      fmt::print("{} crossing{} too close to tangential for Henon's step (dense output only)\n",
                 unrefined, unrefined == 1 ? " was" : "s were");
    fmt::print("\n{:>14}", "t (s)");
    for (std::size_t i = 0; i < static_cast<std::size_t>(2 * n); ++i)
      fmt::print("  {:>13}", cli::coordinate_name(i, n));
    fmt::print("\n");
    for (const auto& x : crossings) {
      fmt::print("{:>14.8f}", x.t);
      for (const double v : x.state) fmt::print("  {:>13.8f}", v);
      fmt::print("\n");
    }
  }
  if (flipped) fmt::print(stderr, "note: {}\n", flip_note);
  files.print();
  return 0;
}

}  // namespace

void add_poincare_command(CLI::App& app, command_list& commands) {
  auto o = std::make_shared<poincare_options>();
  CLI::App* cmd = app.add_subcommand(
      "poincare", "Poincare section: the crossings of a hyperplane such as phi1=0, to rounding");
  o->chain.add_to(*cmd);
  o->start.add_to(*cmd);
  o->integrator.add_to(*cmd);
  cmd->add_option("--section", o->section,
                  "The hyperplane: NAME=VALUE (a coordinate at a level: phi1=0, p2=0.5) or "
                  "NAME=NAME (two coordinates equal: phi2=phi3); names phi1..phin, p1..pn")
      ->required();
  cmd->add_option("--direction", o->direction,
                  "Crossings counted: up (LEFT - RIGHT of the section increasing through 0), down "
                  "or both")
      ->capture_default_str();
  cmd->add_option("--project", o->project,
                  "The two coordinates of the plot, e.g. phi3,p3 (default: phin,pn, or "
                  "phi(n-1),p(n-1) when the section involves phin)");
  cmd->add_option("--max-points", o->max_points, "Stop after this many crossings");
  cmd->add_flag("--unwrapped", o->unwrapped,
                "Take a section of angles on the unwrapped angle (phi3=0 and phi3=2pi differ) "
                "instead of on the circle (every passage of the arm; the default; the angles "
                "of the crossings are then reported in [-pi, pi])");
  cmd->add_flag("--json", o->json,
                "Print JSON: points (t and the state of each crossing), count, residuals, ...");
  cmd->add_option("--out", o->out,
                  "Write FILE.csv (t, phi1..phin, p1..pn, H of each crossing) and the plot "
                  "FILE.png of the projection with its gnuplot script FILE.gp");
  commands.push_back({cmd, [o] { return run_poincare(*o); }});
}

}  // namespace npend::app
