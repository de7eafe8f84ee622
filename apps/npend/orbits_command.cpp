// npend orbits: the nonlinear normal modes of a chain — each linear mode of the hanging chain
// continued in energy as a family of periodic orbits (exact shooting on the monodromy matrix),
// with their periods, amplitudes and stability, the frequency–energy plot, and where each
// frequency departs from the linear one by 1 % and 5 % (the paper's §6.4 question).
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <iostream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <optional>
#include <string_view>

#include "chain_options.hpp"
#include "command.hpp"
#include "input_parsing.hpp"
#include "integrator_options.hpp"
#include "npend/analysis/orbits/forced_orbit.hpp"
#include "npend/analysis/orbits/periodic_orbit.hpp"
#include "npend/analysis/stability/backbone.hpp"
#include "series_output.hpp"
#include "start_options.hpp"
#include "terminal_run.hpp"

namespace npend::app {

namespace {

struct orbits_command_options {
  cli::chain_options chain;
  std::string mode, energy_max, start_amplitude, steps, max_points, thresholds, segments;
  std::string stepper, tol;  // how the shootings integrate (gauss6 or taylor at tol)
  std::string continuation = "arclength";
  bool json = false, branches = false;
  std::string out;
};

struct mode_result {
  nnm_branch branch;
  std::vector<std::pair<double, std::optional<nnm_point>>> departures;  // shift, orbit
  std::vector<nnm_bifurcation> bifurcations;
  // With --branches: the family born at each bifurcation (empty where none), continued to
  // --energy-max.
  std::vector<nnm_branch> families;
};

// --stepper, --steps and --tol of a shooting (forced_orbit_options or
// periodic_orbit_options), checked together.
template <class Shooting>
void set_shooting_integrator(const std::string& stepper, const std::string& steps,
                             const std::string& tol, Shooting& orbit) {
  orbit.stepper = cli::parse_monodromy_integrator(stepper, !steps.empty(), tol, "the shooting",
                                                  orbit.integration_tolerance);
  if (orbit.stepper != stepper_kind::taylor && !steps.empty())
    orbit.steps = static_cast<int>(cli::parse_whole_number(steps, "--steps", 20, 1e6));
}

// How the text output names the shooting's integration, per `period` ("period" or "drive
// period").
template <class Shooting>
std::string shooting_integrator_text(const Shooting& orbit, std::string_view period) {
  if (orbit.stepper == stepper_kind::taylor)
    return fmt::format("taylor at tolerance {:g}", orbit.integration_tolerance);
  return fmt::format("{} Gauss-Legendre steps per {}", orbit.steps, period);
}

// The JSON keys of the shooting's integration; `taken`: the Taylor steps of one orbit's
// last pass (none for a family).
template <class Shooting>
nlohmann::json shooting_integrator_json(const Shooting& orbit, std::optional<int> taken = {}) {
  if (orbit.stepper != stepper_kind::taylor) return {{"stepper", "gauss6"}, {"steps", orbit.steps}};
  nlohmann::json j{{"stepper", "taylor"}, {"integration_tolerance", orbit.integration_tolerance}};
  if (taken) j["steps"] = *taken;
  return j;
}

continuation_method parse_continuation(const std::string& name) {
  if (const auto method = continuation_method_from_name(name)) return *method;
  throw cli::input_error(
      fmt::format("--continuation: arclength (the default) or natural, got '{}'", name));
}

continuation_options make_continuation(const orbits_command_options& o) {
  continuation_options opts;
  opts.energy_max = cli::parse_number(o.energy_max, "--energy-max");
  if (!(opts.energy_max > 0) || !std::isfinite(opts.energy_max))
    throw cli::input_error(
        fmt::format("--energy-max: must be a positive energy in J, got {}", o.energy_max));
  if (!o.start_amplitude.empty()) {
    opts.start_amplitude = cli::parse_number(o.start_amplitude, "--start-amplitude");
    if (!(opts.start_amplitude > 0 && opts.start_amplitude < 0.5))
      throw cli::input_error(fmt::format("--start-amplitude: a small angle in (0, 0.5) rad, got {}",
                                         o.start_amplitude));
  }
  set_shooting_integrator(o.stepper, o.steps, o.tol, opts.orbit);
  if (!o.max_points.empty())
    opts.max_points =
        static_cast<int>(cli::parse_whole_number(o.max_points, "--max-points", 2, 100000));
  if (!o.segments.empty())
    opts.orbit.segments =
        static_cast<int>(cli::parse_whole_number(o.segments, "--segments", 1, opts.orbit.steps));
  opts.method = parse_continuation(o.continuation);
  return opts;
}

std::vector<double> parse_thresholds(const std::string& text) {
  if (text.empty()) return {0.01, 0.05};
  std::vector<double> shifts = cli::parse_number_list(text, "--thresholds");
  for (double s : shifts)
    if (!(s > 0 && s < 1))
      throw cli::input_error(
          fmt::format("--thresholds: {} is not a relative shift in (0, 1) (0.01 = 1 %)", s));
  return shifts;
}

std::string multipliers_text(const nnm_point& p) {
  if (p.multipliers.empty()) return "-";
  std::string out;
  for (const auto& mu : p.multipliers)
    out += fmt::format("{}{:.6g}{:+.6g}i", out.empty() ? "" : " ", mu.real(), mu.imag());
  return out;
}

void write_orbits_files(series_output& files, const chain& c,
                        const std::vector<mode_result>& results) {
  const int n = c.links();
  std::vector<std::string> names{"mode", "energy", "period", "frequency", "ratio"};
  for (int i = 1; i <= n; ++i) names.push_back(fmt::format("amplitude_phi{}", i));
  names.insert(names.end(), {"max_multiplier", "stable", "closure", "iterations"});
  if (n == 1) names.push_back("exact_frequency");
  std::vector<std::vector<double>> table(names.size()), marks(5), changes(4);
  for (const mode_result& r : results) {
    const double mode = r.branch.mode + 1;
    for (const nnm_point& p : r.branch.points) {
      std::vector<double> row{mode, p.energy, p.period, p.frequency,
                              p.frequency / r.branch.linear_frequency};
      row.insert(row.end(), p.amplitudes.begin(), p.amplitudes.end());
      row.insert(row.end(), {p.max_multiplier, p.stable ? 1.0 : 0.0, p.closure,
                             static_cast<double>(p.iterations)});
      if (n == 1)
        row.push_back(r.branch.linear_frequency * pendulum_frequency_ratio(p.amplitudes[0]));
      for (std::size_t k = 0; k < row.size(); ++k) table[k].push_back(row[k]);
    }
    for (const nnm_bifurcation& f : r.bifurcations) {
      changes[0].push_back(mode);
      changes[1].push_back(f.energy);
      changes[2].push_back(f.stable_side.frequency);
      changes[3].push_back(static_cast<double>(f.kind));
    }
    for (const auto& [shift, orbit] : r.departures)
      if (orbit) {
        marks[0].push_back(mode);
        marks[1].push_back(shift);
        marks[2].push_back(orbit->energy);
        marks[3].push_back(orbit->frequency);
        double largest = 0;
        for (double a : orbit->amplitudes) largest = std::max(largest, a);
        marks[4].push_back(largest);
      }
  }
  const std::string data = files.write_csv("", names, table);
  const std::string departures = files.write_csv(
      "departures", std::vector<std::string>{"mode", "shift", "energy", "frequency", "max_angle"},
      marks);
  // --branches: the families born at the bifurcations, one row per orbit.
  std::vector<std::vector<double>> born(7);
  bool switched = false;
  for (const mode_result& r : results)
    for (std::size_t k = 0; k < r.families.size(); ++k) {
      switched = true;
      for (const nnm_point& p : r.families[k].points) {
        const std::vector<double> row{static_cast<double>(r.branch.mode + 1),
                                      r.bifurcations[k].energy,
                                      p.energy,
                                      p.period,
                                      p.frequency,
                                      p.max_multiplier,
                                      p.stable ? 1.0 : 0.0};
        for (std::size_t i = 0; i < row.size(); ++i) born[i].push_back(row[i]);
      }
    }
  const std::string families =
      switched ? files.write_csv(
                     "families",
                     std::vector<std::string>{"mode", "bifurcation_energy", "energy", "period",
                                              "frequency", "max_multiplier", "stable"},
                     born)
               : std::string();
  const std::string bifurcations =
      files.write_csv("bifurcations",
                      std::vector<std::string>{"mode", "energy", "frequency",
                                               "kind (0 branch point, 1 period "
                                               "doubling, 2 complex pair)"},
                      changes);
  cli::plot_panel panel{
      .title =
          fmt::format("Frequency-energy plot of the {}-link chain's nonlinear normal modes", n),
      .xlabel = "energy E (J)",
      .ylabel = "frequency ω = 2π/T (rad/s)",
      .commands = {"set logscale x", "set key outside right"}};
  // gnuplot's number of the `stable` column.
  const std::size_t stable_column = 5 + static_cast<std::size_t>(n) + 2;
  const char* colours[] = {"#440154", "#21918c", "#d62728", "#3b528b", "#5ec962", "#fde725"};
  for (std::size_t k = 0; k < results.size(); ++k) {
    const mode_result& r = results[k];
    const std::string colour = colours[k % std::size(colours)];
    const int mode = r.branch.mode + 1;
    panel.commands.push_back(fmt::format(
        "set arrow from graph 0, first {0} to graph 1, first {0} nohead dt 2 lc rgb '{1}'",
        r.branch.linear_frequency, colour));
    panel.curves.push_back({data,
                            fmt::format("($1=={} && ${}==1 ? $2 : 1/0):4", mode, stable_column),
                            fmt::format("linespoints lw 1.5 pt 7 ps 0.5 lc rgb '{}'", colour),
                            fmt::format("mode {} (ω_{} = {:.4g} rad/s, dashed), stable", mode, mode,
                                        r.branch.linear_frequency)});
    panel.curves.push_back({data,
                            fmt::format("($1=={} && ${}==0 ? $2 : 1/0):4", mode, stable_column),
                            fmt::format("points pt 6 ps 0.8 lc rgb '{}'", colour),
                            fmt::format("mode {}, unstable", mode)});
  }
  if (!marks[0].empty())
    panel.curves.push_back({departures, "3:4", "points pt 4 ps 1.6 lw 2 lc rgb 'black'",
                            "departures from ω_k (--thresholds)"});
  if (!changes[0].empty())
    panel.curves.push_back(
        {bifurcations, "2:3", "points pt 8 ps 1.8 lw 2 lc rgb '#d62728'", "changes of stability"});
  if (!families.empty())
    panel.curves.push_back({families, "3:5", "points pt 1 ps 0.7 lc rgb 'black'",
                            "families born at the bifurcations (--branches)"});
  if (n == 1)
    panel.curves.push_back({data, fmt::format("2:{}", names.size()),
                            "lines lw 1 dt 3 lc rgb 'black'", "exact: 2π / (4 K(k)/ω_0)"});
  files.write_plot(
      {.description = {fmt::format("npend orbits: frequency against energy along the nonlinear "
                                   "normal modes, {}-link chain",
                                   n),
                       fmt::format("data: {} (per mode and orbit), {} (the departures), {} "
                                   "(the changes of stability)",
                                   data, departures, bifurcations)},
       .width = 1100,
       .height = 700,
       .panels = {panel}});
}

nlohmann::json point_json(const nnm_point& p, double linear_frequency) {
  nlohmann::json mu = nlohmann::json::array();
  for (const auto& m : p.multipliers) mu.push_back({m.real(), m.imag()});
  return {{"energy", p.energy},
          {"period", p.period},
          {"frequency", p.frequency},
          {"ratio", p.frequency / linear_frequency},
          {"x0", p.x0},
          {"amplitudes", p.amplitudes},
          {"multipliers", mu},
          {"max_multiplier", p.max_multiplier},
          {"stable", p.stable},
          {"closure", p.closure},
          {"iterations", p.iterations}};
}

void print_folds(const nnm_branch& b) {
  for (const nnm_fold& f : b.folds)
    fmt::print("fold: the energy turns back at E = {:.10g} J (after orbit {})\n", f.energy,
               f.after + 1);
}

nlohmann::json folds_json(const nnm_branch& b) {
  nlohmann::json list = nlohmann::json::array();
  for (const nnm_fold& f : b.folds) list.push_back({{"after", f.after}, {"energy", f.energy}});
  return list;
}

// One line for a family born at a bifurcation (--branches): where it starts and ends.
void print_family_summary(const nnm_branch& b) {
  if (b.points.empty()) {
    fmt::print("  new family: none ({})\n", b.end_reason);
    return;
  }
  const nnm_point &first = b.points.front(), &last = b.points.back();
  const auto stable_count =
      std::count_if(b.points.begin(), b.points.end(), [](const nnm_point& p) { return p.stable; });
  fmt::print(
      "  new family: {} orbits from E = {:.8g} J (T = {:.8g} s) to E = {:.8g} J (T = {:.8g} s, "
      "max|mu| {:.4g}), {} of them stable; {}\n",
      b.points.size(), first.energy, first.period, last.energy, last.period, last.max_multiplier,
      stable_count, b.end_reason);
}

void print_results(const chain& c, const std::vector<mode_result>& results,
                   const continuation_options& opts) {
  const int n = c.links();
  fmt::print(
      "Nonlinear normal modes of the {}-link chain: periodic orbits through a turning point\n"
      "(p = 0), continued {} from each linear mode at {:g} rad; shooting with the exact\n"
      "monodromy matrix ({}{}), closure ||phi(T) - x0|| <= {:g}.\n"
      "stable: every Floquet multiplier but the trivial pair has |mu| <= 1 + {:g}.\n",
      n, opts.method == continuation_method::pseudo_arclength ? "by pseudo-arclength" : "in energy",
      opts.start_amplitude, shooting_integrator_text(opts.orbit, "period"),
      opts.orbit.segments > 1 ? fmt::format(", {} segments", opts.orbit.segments) : "",
      opts.orbit.tolerance, opts.orbit.stability_tolerance);
  for (const mode_result& r : results) {
    const nnm_branch& b = r.branch;
    fmt::print("\nMode {}: omega_{} = {:.8g} rad/s, shape ({:.4f}); {} orbits, {}\n", b.mode + 1,
               b.mode + 1, b.linear_frequency, fmt::join(b.shape, ", "), b.points.size(),
               b.end_reason);
    fmt::print("{:>12}  {:>12}  {:>14}  {:>10}  {:>12}  {:>12}  {}\n", "energy (J)", "period (s)",
               "omega (rad/s)", "omega/w_k", "max|phi|", "max|mu|", "stable");
    for (const nnm_point& p : b.points) {
      double largest = 0;
      for (double a : p.amplitudes) largest = std::max(largest, a);
      fmt::print("{:>12.6g}  {:>12.8g}  {:>14.8g}  {:>10.6f}  {:>12.6g}  {:>12.6g}  {}\n", p.energy,
                 p.period, p.frequency, p.frequency / b.linear_frequency, largest, p.max_multiplier,
                 p.stable ? "yes" : "no");
    }
    for (const auto& [shift, orbit] : r.departures) {
      if (!orbit) {
        fmt::print("{:g} % departure from omega_{}: not reached on the branch\n", 100 * shift,
                   b.mode + 1);
        continue;
      }
      fmt::print(
          "{:g} % departure from omega_{}: E = {:.10g} J, omega = {:.10g} rad/s, "
          "amplitudes ({:.8f}) rad\n",
          100 * shift, b.mode + 1, orbit->energy, orbit->frequency,
          fmt::join(orbit->amplitudes, ", "));
    }
    print_folds(b);
    for (std::size_t k = 0; k < r.bifurcations.size(); ++k) {
      const nnm_bifurcation& f = r.bifurcations[k];
      fmt::print(
          "{} at E = {:.10g} J (omega = {:.8g} rad/s): {} above; multipliers {} (stable "
          "side) and {} (unstable side)\n",
          nnm_bifurcation_name(f.kind), f.energy, f.stable_side.frequency,
          f.loses_stability ? "unstable" : "stable again", multipliers_text(f.stable_side),
          multipliers_text(f.unstable_side));
      if (k < r.families.size()) print_family_summary(r.families[k]);
    }
    if (!b.points.empty() && !b.points.back().multipliers.empty())
      fmt::print("multipliers of the last orbit: {}\n", multipliers_text(b.points.back()));
  }
}

int run_orbits(const orbits_command_options& o) {
  const chain c = o.chain.make_chain(cli::model_support::conservative, "npend orbits");
  const int n = c.links();
  if (o.energy_max.empty()) throw cli::input_error("--energy-max is required (in J)");
  std::vector<int> modes;
  if (o.mode.empty())
    for (int k = 0; k < n; ++k) modes.push_back(k);
  else
    modes.push_back(static_cast<int>(cli::parse_whole_number(o.mode, "--mode", 1, n)) - 1);
  continuation_options opts = make_continuation(o);
  const std::vector<double> shifts = parse_thresholds(o.thresholds);
  series_output files(o.out);

  cli::terminal_run control;
  std::vector<mode_result> results;
  for (std::size_t i = 0; i < modes.size(); ++i) {
    run_control_part part(&control, i, modes.size());
    opts.orbit.control = &part;
    mode_result r;
    try {
      r.branch = continue_mode(c, modes[i], opts);
    } catch (const std::invalid_argument& e) {
      throw cli::input_error(e.what());
    }
    for (double shift : shifts)
      if (!r.branch.stopped)
        r.departures.emplace_back(shift, locate_departure(c, r.branch, shift, opts.orbit));
    if (!r.branch.stopped) r.bifurcations = locate_bifurcations(c, r.branch, opts.orbit);
    if (o.branches && !r.branch.stopped)
      for (const nnm_bifurcation& f : r.bifurcations)
        r.families.push_back(switch_branch(c, f, opts.energy_max, opts));
    if (r.branch.stopped || control.interrupted()) {
      control.finish();
      fmt::print(stderr, "npend orbits: interrupted in mode {}{}\n", modes[i] + 1,
                 o.out.empty() ? "" : fmt::format("; nothing written to {}", o.out));
      return control.exit_code();
    }
    results.push_back(std::move(r));
  }
  control.finish();
  if (files.enabled()) write_orbits_files(files, c, results);
  if (!o.json) {
    print_results(c, results, opts);
    files.print();
    return 0;
  }
  nlohmann::json list = nlohmann::json::array();
  for (const mode_result& r : results) {
    nlohmann::json points = nlohmann::json::array(), departures = nlohmann::json::array();
    for (const nnm_point& p : r.branch.points) {
      nlohmann::json j = point_json(p, r.branch.linear_frequency);
      if (n == 1)
        j["exact_frequency"] =
            r.branch.linear_frequency * pendulum_frequency_ratio(p.amplitudes[0]);
      points.push_back(j);
    }
    for (const auto& [shift, orbit] : r.departures)
      departures.push_back(
          {{"shift", shift},
           {"orbit", orbit ? point_json(*orbit, r.branch.linear_frequency) : nlohmann::json()}});
    nlohmann::json changes = nlohmann::json::array();
    for (std::size_t k = 0; k < r.bifurcations.size(); ++k) {
      const nnm_bifurcation& f = r.bifurcations[k];
      nlohmann::json change{
          {"kind", std::string(nnm_bifurcation_name(f.kind))},
          {"energy", f.energy},
          {"loses_stability", f.loses_stability},
          {"stable_side", point_json(f.stable_side, r.branch.linear_frequency)},
          {"unstable_side", point_json(f.unstable_side, r.branch.linear_frequency)}};
      if (k < r.families.size()) {
        nlohmann::json family_points = nlohmann::json::array();
        for (const nnm_point& p : r.families[k].points)
          family_points.push_back(point_json(p, r.branch.linear_frequency));
        change["family"] = {{"end_reason", r.families[k].end_reason},
                            {"folds", folds_json(r.families[k])},
                            {"points", family_points}};
      }
      changes.push_back(change);
    }
    list.push_back({{"mode", r.branch.mode + 1},
                    {"bifurcations", changes},
                    {"linear_frequency", r.branch.linear_frequency},
                    {"shape", r.branch.shape},
                    {"end_reason", r.branch.end_reason},
                    {"folds", folds_json(r.branch)},
                    {"points", points},
                    {"departures", departures}});
  }
  nlohmann::json j = describe_chain(c);
  j.update(shooting_integrator_json(opts.orbit));
  j.update(nlohmann::json{{"segments", opts.orbit.segments},
                          {"continuation", o.continuation},
                          {"start_amplitude", opts.start_amplitude},
                          {"energy_max", opts.energy_max},
                          {"tolerance", opts.orbit.tolerance},
                          {"modes", list}});
  files.add_to(j);
  std::cout << j.dump(2) << "\n";
  return 0;
}

struct orbit_command_options {
  cli::chain_options chain;
  cli::start_options start;
  std::string period, phase, steps, winding, segments;
  // A driven pivot: how the shooting integrates (gauss6 or taylor, and taylor's tolerance).
  std::string stepper, tol;
  bool json = false;
  // A free orbit: its family continued in energy to `continue_to`. A driven pivot: the forced
  // orbit over `periods` drive periods, and its continuation in the drive frequency up or
  // down to `continue_to`. Either branch written to `out`.
  std::string periods, continue_to, out;
};

nlohmann::json forced_point_json(const forced_point& p) {
  return {{"frequency", p.frequency},
          {"period", p.period},
          {"x0", p.x0},
          {"amplitudes", p.amplitudes},
          {"multipliers", json_complex_list(p.multipliers)},
          {"max_multiplier", p.max_multiplier},
          {"stable", p.stable},
          {"closure", p.closure},
          {"iterations", p.iterations}};
}

std::string forced_multipliers_text(const std::vector<std::complex<double>>& multipliers) {
  std::string out;
  for (const auto& mu : multipliers)
    out += fmt::format("{}{:.6g}{:+.6g}i", out.empty() ? "" : " ", mu.real(), mu.imag());
  return out;
}

void write_drive_files(series_output& files, const chain& c, const drive_branch& branch) {
  const int n = c.links();
  std::vector<std::string> names{"omega", "a_omega", "period"};
  for (int i = 1; i <= n; ++i) names.push_back(fmt::format("amplitude_phi{}", i));
  names.insert(names.end(), {"max_multiplier", "stable", "closure", "iterations"});
  const double a = c.parameters().pivot.amplitude;
  std::vector<std::vector<double>> table(names.size()), changes(4);
  for (const forced_point& p : branch.points) {
    std::vector<double> row{p.frequency, a * p.frequency, p.period};
    row.insert(row.end(), p.amplitudes.begin(), p.amplitudes.end());
    row.insert(row.end(), {p.max_multiplier, p.stable ? 1.0 : 0.0, p.closure,
                           static_cast<double>(p.iterations)});
    for (std::size_t k = 0; k < row.size(); ++k) table[k].push_back(row[k]);
  }
  for (const drive_stability_change& s : branch.changes) {
    changes[0].push_back(s.frequency);
    changes[1].push_back(a * s.frequency);
    changes[2].push_back(s.stable_above ? 1.0 : 0.0);
    changes[3].push_back(static_cast<double>(s.kind));
  }
  const std::string data = files.write_csv("", names, table);
  const std::string marks = files.write_csv(
      "changes",
      std::vector<std::string>{"omega", "a_omega", "stable_above",
                               "kind (0 branch point, 1 period doubling, 2 complex pair)"},
      changes);
  cli::plot_panel panel{
      .title = fmt::format("Forced orbit of the {}-link chain over the drive frequency (pivot {})",
                           n, c.parameters().pivot.describe()),
      .xlabel = "drive frequency Ω (rad/s)",
      .ylabel = "largest multiplier |μ|_{max}",
      .log_y = true,
      .commands = {"set key top right", "set grid"}};
  const std::size_t stable_column = 3 + static_cast<std::size_t>(n) + 2;
  panel.curves.push_back(
      {data, fmt::format("1:{}", stable_column - 1), "lines lw 2 lc rgb '#1f77b4'", "max |μ|"});
  panel.curves.push_back(
      {data, fmt::format("(${} > 0.5 ? $1 : 1/0):{}", stable_column, stable_column - 1),
       "points pt 7 ps 0.6 lc rgb '#2ca02c'", "stable"});
  if (!branch.changes.empty())
    panel.curves.push_back(
        {marks, "1:(1)", "points pt 8 ps 1.8 lw 2 lc rgb '#d62728'", "changes of stability"});
  files.write_plot({.description = {"npend orbit --continue-to: the forced orbit's largest "
                                    "Floquet multiplier over the drive frequency",
                                    fmt::format("data: {} (per orbit), {} (the changes of "
                                                "stability)",
                                                data, marks)},
                    .panels = {panel}});
}

// One shooting of npend orbit: bad input exits 2, a guess that leads to no orbit exits 1
// with `advice`, and a signal stops it (nullopt; the exit status is the control's).
template <class Shoot>
auto shoot_for_command(cli::terminal_run& control, Shoot shoot, std::string_view advice)
    -> std::optional<decltype(shoot())> {
  decltype(shoot()) r;
  try {
    r = shoot();
  } catch (const std::invalid_argument& e) {
    throw cli::input_error(e.what());
  }
  control.finish();
  if (r.stopped) {
    fmt::print(stderr, "npend orbit: interrupted\n");
    return std::nullopt;
  }
  if (!r.converged)
    throw std::runtime_error(
        fmt::format("the shooting did not converge (closure {:.3g} at its last iterate): {}",
                    r.closure, advice));
  return r;
}

// npend orbit on a driven pivot: the forced orbit (and with --continue-to its branch).
int run_forced_orbit(const chain& c, const std::vector<double>& guess,
                     const orbit_command_options& o) {
  if (!o.period.empty())
    throw cli::input_error(
        "--period: not with a driven pivot (the forced orbit's period is the drive's, times "
        "--periods)");
  if (!o.phase.empty())
    throw cli::input_error("--phase: not with a driven pivot (the drive fixes the orbit's phase)");
  for (const auto& [given, name] :
       {std::pair{&o.winding, "--winding"}, std::pair{&o.segments, "--segments"}})
    if (!given->empty())
      throw cli::input_error(fmt::format("{}: not with a driven pivot (free orbits only)", name));
  if (!o.out.empty() && o.continue_to.empty())
    throw cli::input_error("--out: only with --continue-to (the branch's table and plot)");
  drive_continuation_options opts;
  if (!o.periods.empty())
    opts.orbit.periods = static_cast<int>(cli::parse_whole_number(o.periods, "--periods", 1, 1000));
  set_shooting_integrator(o.stepper, o.steps, o.tol, opts.orbit);
  const double a = c.parameters().pivot.amplitude;
  cli::terminal_run control;
  opts.orbit.control = &control;
  if (!o.continue_to.empty()) {
    opts.frequency_end = cli::parse_number(o.continue_to, "--continue-to");
    if (!(opts.frequency_end > 0) || !std::isfinite(opts.frequency_end))
      throw cli::input_error(
          fmt::format("--continue-to: a positive drive frequency in rad/s, got {}", o.continue_to));
    series_output files(o.out);
    drive_branch branch;
    try {
      branch = continue_drive(c, guess, opts);
    } catch (const std::invalid_argument& e) {
      throw cli::input_error(e.what());
    }
    control.finish();
    if (branch.stopped) {
      fmt::print(stderr, "npend orbit: interrupted{}\n",
                 o.out.empty() ? "" : fmt::format("; nothing written to {}", o.out));
      return control.exit_code();
    }
    if (branch.points.empty())
      throw std::runtime_error(
          "the shooting did not converge at the first drive frequency: give a start closer to "
          "the forced orbit");
    if (files.enabled()) write_drive_files(files, c, branch);
    if (o.json) {
      nlohmann::json j = describe_chain(c), points = nlohmann::json::array(),
                     changes = nlohmann::json::array();
      for (const forced_point& p : branch.points) points.push_back(forced_point_json(p));
      for (const drive_stability_change& s : branch.changes)
        changes.push_back({{"kind", std::string(nnm_bifurcation_name(s.kind))},
                           {"frequency", s.frequency},
                           {"a_omega", a * s.frequency},
                           {"bracket", s.bracket},
                           {"stable_above", s.stable_above},
                           {"stable_side", forced_point_json(s.stable_side)},
                           {"unstable_side", forced_point_json(s.unstable_side)}});
      j.update(shooting_integrator_json(opts.orbit));
      j.update(nlohmann::json{{"periods", opts.orbit.periods},
                              {"frequency_end", opts.frequency_end},
                              {"tolerance", opts.orbit.tolerance},
                              {"end_reason", branch.end_reason},
                              {"points", points},
                              {"changes", changes}});
      files.add_to(j);
      std::cout << j.dump(2) << "\n";
      return 0;
    }
    fmt::print(
        "Forced orbit of the {}-link chain (pivot {}) over {} drive period(s), continued in the "
        "drive frequency\nfrom {:g} to {:g} rad/s ({}, closure <= {:g}): {} orbits, {}\n",
        c.links(), c.parameters().pivot.describe(), opts.orbit.periods,
        branch.points.front().frequency, opts.frequency_end,
        shooting_integrator_text(opts.orbit, "drive period"), opts.orbit.tolerance,
        branch.points.size(), branch.end_reason);
    fmt::print("{:>14}  {:>12}  {:>12}  {:>10}  {:>14}  {}\n", "Omega (rad/s)", "a*Omega",
               "max|phi|", "closure", "max|mu|", "stable");
    for (const forced_point& p : branch.points) {
      double largest = 0;
      for (double v : p.amplitudes) largest = std::max(largest, v);
      fmt::print("{:>14.8g}  {:>12.6g}  {:>12.6g}  {:>10.2g}  {:>14.10g}  {}\n", p.frequency,
                 a * p.frequency, largest, p.closure, p.max_multiplier, p.stable ? "yes" : "no");
    }
    if (branch.changes.empty()) fmt::print("no change of stability on the branch\n");
    for (const drive_stability_change& s : branch.changes)
      fmt::print(
          "{} at Omega = {:.12g} rad/s (a*Omega = {:.10g} m/s, bracket {:.2g}): stable {}; "
          "multipliers {} (stable side) and {} (unstable side)\n",
          nnm_bifurcation_name(s.kind), s.frequency, a * s.frequency, s.bracket,
          s.stable_above ? "above" : "below", forced_multipliers_text(s.stable_side.multipliers),
          forced_multipliers_text(s.unstable_side.multipliers));
    files.print();
    return 0;
  }
  const std::optional<forced_orbit_result> shot = shoot_for_command(
      control, [&] { return forced_orbit(c, guess, opts.orbit); },
      "give a start closer to the forced orbit (its state at t = 0), or continue it from a "
      "drive frequency where it is known with --continue-to");
  if (!shot) return control.exit_code();
  const forced_orbit_result& r = *shot;
  if (o.json) {
    nlohmann::json j = describe_chain(c);
    j["orbit"] = forced_point_json(to_forced_point(r));
    j.update(shooting_integrator_json(opts.orbit, r.steps));
    j["periods"] = opts.orbit.periods;
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  fmt::print(
      "Forced orbit of the {}-link chain, pivot {} ({} drive period(s); {} Newton steps, {}{})\n",
      c.links(), c.parameters().pivot.describe(), opts.orbit.periods, r.iterations,
      shooting_integrator_text(opts.orbit, "drive period"),
      opts.orbit.stepper == stepper_kind::taylor ? fmt::format(", {} steps over T", r.steps) : "");
  fmt::print("start x0     ({}) at t = 0\n", fmt::join(r.x0, ", "));
  fmt::print("period       {:.15g} s (drive frequency {:.12g} rad/s)\n", r.period, r.frequency);
  fmt::print("closure      {:.3g} (max |phi(T) - x0|)\n", r.closure);
  fmt::print("amplitudes   ({:.10f}) rad\n", fmt::join(r.amplitudes, ", "));
  fmt::print("multipliers  {} (max |mu| {:.10g}: {})\n", forced_multipliers_text(r.multipliers),
             r.max_multiplier, r.stable ? "stable" : "unstable");
  return 0;
}

bool rotates(const std::vector<int>& winding) {
  return std::any_of(winding.begin(), winding.end(), [](int w) { return w != 0; });
}

// The shooting of a free orbit from the command's options: a rotating orbit (--winding) is
// on the Poincaré plane unless --phase says otherwise (and the library refuses a turning
// point for it).
periodic_orbit_options free_orbit_options(const chain& c, const orbit_command_options& o) {
  periodic_orbit_options opts;
  if (!o.winding.empty()) {
    for (const double w : cli::parse_number_list(o.winding, "--winding")) {
      if (w != std::round(w) || std::fabs(w) > 1000)
        throw cli::input_error(
            fmt::format("--winding: whole turns per period for each angle, got {}", w));
      opts.winding.push_back(static_cast<int>(w));
    }
    if (opts.winding.size() != static_cast<std::size_t>(c.links()))
      throw cli::input_error(fmt::format("--winding: {} values for the {}-link chain",
                                         opts.winding.size(), c.links()));
  }
  if (o.phase == "poincare" || (o.phase.empty() && rotates(opts.winding)))
    opts.phase = orbit_phase::poincare;
  else if (!o.phase.empty() && o.phase != "turning_point")
    throw cli::input_error(fmt::format("--phase: turning_point or poincare, got '{}'", o.phase));
  set_shooting_integrator(o.stepper, o.steps, o.tol, opts);
  if (!o.segments.empty())
    opts.segments =
        static_cast<int>(cli::parse_whole_number(o.segments, "--segments", 1, opts.steps));
  return opts;
}

void write_family_files(series_output& files, const chain& c, const nnm_branch& b) {
  const int n = c.links();
  std::vector<std::string> names{"energy", "period", "frequency"};
  for (int i = 1; i <= n; ++i) names.push_back(fmt::format("amplitude_phi{}", i));
  names.insert(names.end(), {"max_multiplier", "stable", "closure", "iterations"});
  std::vector<std::vector<double>> table(names.size());
  for (const nnm_point& p : b.points) {
    std::vector<double> row{p.energy, p.period, p.frequency};
    row.insert(row.end(), p.amplitudes.begin(), p.amplitudes.end());
    row.insert(row.end(), {p.max_multiplier, p.stable ? 1.0 : 0.0, p.closure,
                           static_cast<double>(p.iterations)});
    for (std::size_t k = 0; k < row.size(); ++k) table[k].push_back(row[k]);
  }
  const std::string data = files.write_csv("", names, table);
  const std::size_t stable_column = 3 + static_cast<std::size_t>(n) + 2;
  cli::plot_panel panel{.title = fmt::format("A family of periodic orbits of the {}-link chain", n),
                        .xlabel = "energy E (J)",
                        .ylabel = "frequency ω = 2π/T (rad/s)",
                        .commands = {"set key top right", "set grid"}};
  panel.curves.push_back({data, "1:3", "lines lw 1.5 lc rgb '#21918c'", "the family"});
  panel.curves.push_back({data, fmt::format("(${} == 1 ? $1 : 1/0):3", stable_column),
                          "points pt 7 ps 0.6 lc rgb '#21918c'", "stable"});
  panel.curves.push_back({data, fmt::format("(${} == 0 ? $1 : 1/0):3", stable_column),
                          "points pt 6 ps 0.8 lc rgb '#d62728'", "unstable"});
  files.write_plot({.description = {"npend orbit --continue-to: frequency against energy along "
                                    "the orbit's family",
                                    fmt::format("data: {} (per orbit)", data)},
                    .panels = {panel}});
}

// npend orbit --continue-to E: the family of the orbit found, continued in energy.
int run_family(const chain& c, const periodic_orbit_result& start,
               const periodic_orbit_options& shooting, const orbit_command_options& o,
               cli::terminal_run& control) {
  const double end = cli::parse_number(o.continue_to, "--continue-to");
  if (!std::isfinite(end) || end == start.energy)
    throw cli::input_error(
        fmt::format("--continue-to: an energy in J other than the orbit's ({:.10g} J), got {}",
                    start.energy, o.continue_to));
  continuation_options opts;
  opts.orbit = shooting;
  series_output files(o.out);
  opts.orbit.control = &control;
  nnm_branch b;
  try {
    b = continue_orbit(c, start, end, opts);
  } catch (const std::invalid_argument& e) {
    throw cli::input_error(e.what());
  }
  control.finish();
  if (b.stopped) {
    fmt::print(stderr, "npend orbit: interrupted{}\n",
               o.out.empty() ? "" : fmt::format("; nothing written to {}", o.out));
    return control.exit_code();
  }
  if (files.enabled()) write_family_files(files, c, b);
  if (o.json) {
    nlohmann::json points = nlohmann::json::array();
    for (const nnm_point& p : b.points) {
      nlohmann::json j = point_json(p, p.frequency);
      j.erase("ratio");
      points.push_back(j);
    }
    nlohmann::json j = describe_chain(c);
    j.update(shooting_integrator_json(opts.orbit));
    j.update(nlohmann::json{{"winding", start.winding},
                            {"segments", opts.orbit.segments},
                            {"energy_end", end},
                            {"end_reason", b.end_reason},
                            {"folds", folds_json(b)},
                            {"points", points}});
    files.add_to(j);
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  fmt::print(
      "The family of the orbit at E = {:.10g} J (period {:.10g} s{}) continued by "
      "pseudo-arclength to E = {:g} J: {} orbits, {}\n",
      start.energy, start.period,
      rotates(start.winding) ? fmt::format(", winding ({})", fmt::join(start.winding, ", ")) : "",
      end, b.points.size(), b.end_reason);
  fmt::print("{:>14}  {:>14}  {:>14}  {:>12}  {:>12}  {}\n", "energy (J)", "period (s)",
             "omega (rad/s)", "max|phi|", "max|mu|", "stable");
  for (const nnm_point& p : b.points) {
    double largest = 0;
    for (double a : p.amplitudes) largest = std::max(largest, a);
    fmt::print("{:>14.10g}  {:>14.10g}  {:>14.10g}  {:>12.6g}  {:>12.6g}  {}\n", p.energy, p.period,
               p.frequency, largest, p.max_multiplier, p.stable ? "yes" : "no");
  }
  print_folds(b);
  files.print();
  return 0;
}

// npend orbit: one periodic orbit from a guess of its start and period.
int run_orbit(const orbit_command_options& o) {
  {
    // A driven pivot: the forced orbit (damping is refused there, by the library).
    const chain driven = o.chain.make_chain(cli::model_support::any, "npend orbit");
    if (driven.parameters().pivot.moves())
      return run_forced_orbit(driven, o.start.make_state(driven), o);
    if (!o.periods.empty())
      throw cli::input_error(
          "--periods: only with a driven pivot (--pivot vertical:A:OMEGA or horizontal:A:OMEGA)");
  }
  const chain c = o.chain.make_chain(cli::model_support::conservative, "npend orbit");
  const std::vector<double> guess = o.start.make_state(c);
  if (o.period.empty()) throw cli::input_error("--period is required (a guess of T in s)");
  const double period = cli::parse_number(o.period, "--period");
  if (!(period > 0) || !std::isfinite(period))
    throw cli::input_error(fmt::format("--period: a positive time in s, got {}", o.period));
  if (!o.out.empty() && o.continue_to.empty())
    throw cli::input_error("--out: only with --continue-to (the family's table and plot)");
  periodic_orbit_options opts = free_orbit_options(c, o);
  cli::terminal_run control;
  opts.control = &control;
  const std::optional<periodic_orbit_result> shot = shoot_for_command(
      control, [&] { return periodic_orbit(c, guess, period, opts); },
      "give a start and period closer to the orbit (for a normal mode, npend orbits continues "
      "it from small amplitude)");
  if (!shot) return control.exit_code();
  const periodic_orbit_result& r = *shot;
  if (!o.continue_to.empty()) return run_family(c, r, opts, o, control);
  const nnm_point p = to_nnm_point(r);
  if (o.json) {
    nlohmann::json j = describe_chain(c);
    nlohmann::json orbit = point_json(p, p.frequency);
    orbit.erase("ratio");
    orbit["winding"] = r.winding;
    j["orbit"] = orbit;
    j.update(shooting_integrator_json(opts, r.steps));
    j["segments"] = opts.segments;
    j["phase"] = opts.phase == orbit_phase::poincare ? "poincare" : "turning_point";
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  fmt::print("Periodic orbit of the {}-link chain ({} Newton steps, {}{})\n", c.links(),
             r.iterations, shooting_integrator_text(opts, "period"),
             opts.stepper == stepper_kind::taylor ? fmt::format(", {} steps over T", r.steps) : "");
  fmt::print("start x0     ({})\n", fmt::join(r.x0, ", "));
  fmt::print("period       {:.15g} s (frequency {:.12g} rad/s)\n", r.period, p.frequency);
  fmt::print("energy       {:.15g} J\n", r.energy);
  fmt::print("closure      {:.3g} (max |phi(T) - x0 - 2 pi winding|)\n", r.closure);
  if (rotates(r.winding))
    fmt::print("winding      ({}) turns per period\n", fmt::join(r.winding, ", "));
  fmt::print("amplitudes   ({:.10f}) rad\n", fmt::join(r.amplitudes, ", "));
  fmt::print("multipliers  {} (max |mu| {:.10g}: {})\n", multipliers_text(p), r.max_multiplier,
             r.stable ? "stable" : "unstable");
  return 0;
}

}  // namespace

void add_orbits_command(CLI::App& app, command_list& commands) {
  auto o = std::make_shared<orbits_command_options>();
  CLI::App* cmd = app.add_subcommand(
      "orbits",
      "Nonlinear normal modes: each linear mode continued in energy as a family of periodic "
      "orbits (exact shooting), with period, amplitudes, Floquet stability, the frequency-energy "
      "plot and the 1 % / 5 % departures from the linear frequency");
  o->chain.add_to(*cmd);
  cmd->add_option("--mode", o->mode, "Only this mode (1 = the slowest; default: all)");
  cmd->add_option("--energy-max", o->energy_max,
                  "Continue each branch up to this energy in J (required)");
  cmd->add_option("--start-amplitude", o->start_amplitude,
                  "The largest angle of the first orbit of each branch in rad (default 0.01)");
  cmd->add_option("--steps", o->steps,
                  "Gauss-Legendre steps per period of each orbit (default 400)");
  cli::add_monodromy_options(*cmd, o->stepper, o->tol, "How each shooting", "--steps per period",
                             1e-14);
  cmd->add_option("--max-points", o->max_points,
                  "At most this many orbits per branch (default 200)");
  cmd->add_option("--segments", o->segments,
                  "Multiple shooting: cut each period into this many segments (default 1); "
                  "follows strongly unstable orbits further");
  cmd->add_option("--continuation", o->continuation,
                  "arclength (default: pseudo-arclength, turns round folds in energy) or "
                  "natural (steps in the energy)");
  cmd->add_option("--thresholds", o->thresholds,
                  "Relative frequency departures to locate on each branch (default: 0.01,0.05)");
  cmd->add_flag("--branches", o->branches,
                "Switch branches: continue the family born at each branch point or period "
                "doubling up to --energy-max");
  cmd->add_flag("--json", o->json, "Print JSON (every orbit, its start and multipliers)");
  cmd->add_option("--out", o->out,
                  "Write FILE.csv (one row per orbit), FILE_departures.csv and the "
                  "frequency-energy plot FILE.png with its gnuplot script FILE.gp");
  commands.push_back({cmd, [o] { return run_orbits(*o); }});
}

void add_orbit_command(CLI::App& app, command_list& commands) {
  auto o = std::make_shared<orbit_command_options>();
  CLI::App* cmd = app.add_subcommand(
      "orbit",
      "One periodic orbit from a guess of its start and period: Newton's method with the exact "
      "monodromy matrix at the start's energy; its period, amplitudes and Floquet multipliers. "
      "On a driven pivot the forced orbit of the drive's period, and with --continue-to its "
      "branch over the drive frequency");
  o->chain.add_to(*cmd);
  o->start.add_to(*cmd);
  cmd->add_option("--period", o->period,
                  "A guess of the period T in s (required, unless the pivot is driven)");
  cmd->add_option("--phase", o->phase,
                  "turning_point (default: the orbit's start has p = 0) or poincare (on the "
                  "plane through the guess across the flow: any orbit; the default with "
                  "--winding)");
  cmd->add_option("--winding", o->winding,
                  "A rotating orbit: whole turns of each angle per period, e.g. 1,0,0 (default: "
                  "an oscillation)");
  cmd->add_option("--segments", o->segments,
                  "Multiple shooting: cut the period into this many segments (default 1), for "
                  "strongly unstable orbits");
  cmd->add_option("--steps", o->steps,
                  "Gauss-Legendre steps per period, or per drive period on a driven pivot "
                  "(default 400)");
  cmd->add_option("--periods", o->periods,
                  "Driven pivot: the forced orbit's period in drive periods (default 1)");
  cli::add_monodromy_options(*cmd, o->stepper, o->tol, "How the shooting",
                             "--steps per period or drive period", 1e-14);
  cmd->add_option("--continue-to", o->continue_to,
                  "Continue the orbit's family by pseudo-arclength up or down to this energy "
                  "(J); on a driven pivot, the forced orbit in the drive frequency from the "
                  "--pivot OMEGA to this one (rad/s), locating its changes of stability");
  cmd->add_option("--out", o->out,
                  "With --continue-to: write FILE.csv (one row per orbit), on a driven pivot "
                  "FILE_changes.csv, and the plot FILE.png with its gnuplot script FILE.gp");
  cmd->add_flag("--json", o->json, "Print JSON");
  commands.push_back({cmd, [o] { return run_orbit(*o); }});
}

}  // namespace npend::app
