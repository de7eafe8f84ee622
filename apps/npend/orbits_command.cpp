// npend orbits: the nonlinear normal modes of a chain — each linear mode of the hanging chain
// continued in energy as a family of periodic orbits (exact shooting on the monodromy matrix),
// with their periods, amplitudes and stability, the frequency–energy plot, and where each
// frequency departs from the linear one by 1 % and 5 % (the paper's §6.4 question).
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cmath>
#include <complex>
#include <iostream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <optional>

#include "chain_options.hpp"
#include "command.hpp"
#include "input_parsing.hpp"
#include "npend/analysis/orbits/periodic_orbit.hpp"
#include "npend/analysis/stability/backbone.hpp"
#include "series_output.hpp"
#include "start_options.hpp"
#include "terminal_run.hpp"

namespace npend::app {

namespace {

struct orbits_command_options {
  cli::chain_options chain;
  std::string mode, energy_max, start_amplitude, steps, max_points, thresholds;
  bool json = false;
  std::string out;
};

struct mode_result {
  nnm_branch branch;
  std::vector<std::pair<double, std::optional<nnm_point>>> departures;  // shift, orbit
  std::vector<nnm_bifurcation> bifurcations;
};

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
  if (!o.steps.empty())
    opts.orbit.steps = static_cast<int>(cli::parse_whole_number(o.steps, "--steps", 20, 1e6));
  if (!o.max_points.empty())
    opts.max_points =
        static_cast<int>(cli::parse_whole_number(o.max_points, "--max-points", 2, 100000));
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

void print_results(const chain& c, const std::vector<mode_result>& results,
                   const continuation_options& opts) {
  const int n = c.links();
  fmt::print(
      "Nonlinear normal modes of the {}-link chain: periodic orbits through a turning point\n"
      "(p = 0), continued in energy from each linear mode at {:g} rad; shooting with the exact\n"
      "monodromy matrix (Gauss-Legendre, {} steps per period), closure ||phi(T) - x0|| <= {:g}.\n"
      "stable: every Floquet multiplier but the trivial pair has |mu| <= 1 + {:g}.\n",
      n, opts.start_amplitude, opts.orbit.steps, opts.orbit.tolerance,
      opts.orbit.stability_tolerance);
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
    for (const nnm_bifurcation& f : r.bifurcations)
      fmt::print(
          "{} at E = {:.10g} J (omega = {:.8g} rad/s): {} above; multipliers {} (stable "
          "side) and {} (unstable side)\n",
          nnm_bifurcation_name(f.kind), f.energy, f.stable_side.frequency,
          f.loses_stability ? "unstable" : "stable again", multipliers_text(f.stable_side),
          multipliers_text(f.unstable_side));
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
    for (const nnm_bifurcation& f : r.bifurcations)
      changes.push_back(
          {{"kind", std::string(nnm_bifurcation_name(f.kind))},
           {"energy", f.energy},
           {"loses_stability", f.loses_stability},
           {"stable_side", point_json(f.stable_side, r.branch.linear_frequency)},
           {"unstable_side", point_json(f.unstable_side, r.branch.linear_frequency)}});
    list.push_back({{"mode", r.branch.mode + 1},
                    {"bifurcations", changes},
                    {"linear_frequency", r.branch.linear_frequency},
                    {"shape", r.branch.shape},
                    {"end_reason", r.branch.end_reason},
                    {"points", points},
                    {"departures", departures}});
  }
  nlohmann::json j = describe_chain(c);
  j.update(nlohmann::json{{"steps", opts.orbit.steps},
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
  std::string period, phase = "turning_point", steps;
  bool json = false;
};

// npend orbit: one periodic orbit from a guess of its start and period.
int run_orbit(const orbit_command_options& o) {
  const chain c = o.chain.make_chain(cli::model_support::conservative, "npend orbit");
  const std::vector<double> guess = o.start.make_state(c);
  if (o.period.empty()) throw cli::input_error("--period is required (a guess of T in s)");
  const double period = cli::parse_number(o.period, "--period");
  if (!(period > 0) || !std::isfinite(period))
    throw cli::input_error(fmt::format("--period: a positive time in s, got {}", o.period));
  periodic_orbit_options opts;
  if (o.phase == "poincare")
    opts.phase = orbit_phase::poincare;
  else if (o.phase != "turning_point")
    throw cli::input_error(fmt::format("--phase: turning_point or poincare, got '{}'", o.phase));
  if (!o.steps.empty())
    opts.steps = static_cast<int>(cli::parse_whole_number(o.steps, "--steps", 20, 1e6));
  cli::terminal_run control;
  opts.control = &control;
  periodic_orbit_result r;
  try {
    r = periodic_orbit(c, guess, period, opts);
  } catch (const std::invalid_argument& e) {
    throw cli::input_error(e.what());
  }
  control.finish();
  if (r.stopped) {
    fmt::print(stderr, "npend orbit: interrupted\n");
    return control.exit_code();
  }
  if (!r.converged)
    throw std::runtime_error(fmt::format(
        "the shooting did not converge (closure {:.3g} at its last iterate): give a start and "
        "period closer to the orbit (for a normal mode, npend orbits continues it from small "
        "amplitude)",
        r.closure));
  const nnm_point p = to_nnm_point(r);
  if (o.json) {
    nlohmann::json j = describe_chain(c);
    nlohmann::json orbit = point_json(p, p.frequency);
    orbit.erase("ratio");
    j["orbit"] = orbit;
    j["steps"] = opts.steps;
    j["phase"] = o.phase;
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  fmt::print(
      "Periodic orbit of the {}-link chain ({} Newton steps, {} Gauss-Legendre steps per "
      "period)\n",
      c.links(), r.iterations, opts.steps);
  fmt::print("start x0     ({})\n", fmt::join(r.x0, ", "));
  fmt::print("period       {:.15g} s (frequency {:.12g} rad/s)\n", r.period, p.frequency);
  fmt::print("energy       {:.15g} J\n", r.energy);
  fmt::print("closure      {:.3g} (max |phi(T) - x0|)\n", r.closure);
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
  cmd->add_option("--max-points", o->max_points,
                  "At most this many orbits per branch (default 200)");
  cmd->add_option("--thresholds", o->thresholds,
                  "Relative frequency departures to locate on each branch (default: 0.01,0.05)");
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
      "monodromy matrix at the start's energy; its period, amplitudes and Floquet multipliers");
  o->chain.add_to(*cmd);
  o->start.add_to(*cmd);
  cmd->add_option("--period", o->period, "A guess of the period T in s (required)");
  cmd->add_option("--phase", o->phase,
                  "turning_point (default: the orbit's start has p = 0) or poincare (on the "
                  "plane through the guess across the flow: any orbit)");
  cmd->add_option("--steps", o->steps, "Gauss-Legendre steps per period (default 400)");
  cmd->add_flag("--json", o->json, "Print JSON");
  commands.push_back({cmd, [o] { return run_orbit(*o); }});
}

}  // namespace npend::app
