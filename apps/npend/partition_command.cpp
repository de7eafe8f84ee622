// npend partition: the chain's canonical ensemble (paper §6.3.2) — Z, F, ⟨E⟩, C and ⟨cos φ_i⟩
// at one temperature or over a range, with error estimates.
#include <fmt/format.h>

#include <cmath>
#include <iostream>
#include <nlohmann/json.hpp>

#include "chain_options.hpp"
#include "command.hpp"
#include "input_parsing.hpp"
#include "npend/analysis/statistical/partition_function.hpp"
#include "series_output.hpp"
#include "terminal_run.hpp"

namespace npend::app {

namespace {

struct partition_command_options {
  cli::chain_options chain;
  std::string temperature, scan, rule = "auto", out;
  int grid = 0, points = 65536, replicas = 16;
  std::string seed;
  const CLI::App* command = nullptr;
  double kb = 1;
  bool json = false;
};

// Log-spaced temperatures FROM:TO:COUNT, both ends included.
std::vector<double> parse_temperature_scan(const std::string& text) {
  const auto parts = cli::split_list(text, ':');
  if (parts.size() != 3)
    throw cli::input_error(fmt::format("--scan: expected T_FROM:T_TO:COUNT, got '{}'", text));
  const double from = cli::parse_number(parts[0], "--scan (from)"),
               to = cli::parse_number(parts[1], "--scan (to)"),
               count = cli::parse_number(parts[2], "--scan (count)");
  if (!(from > 0) || !(to > from))
    throw cli::input_error(
        fmt::format("--scan: temperatures must satisfy 0 < from < to, got {}:{}", from, to));
  if (!cli::is_whole_number(count, 2, 1000))
    throw cli::input_error(
        fmt::format("--scan: the count must be a whole number 2..1000, got {}", parts[2]));
  std::vector<double> out;
  const int n = static_cast<int>(count);
  for (int i = 0; i < n; ++i)
    out.push_back(i == n - 1 ? to : from * std::pow(to / from, static_cast<double>(i) / (n - 1)));
  return out;
}

partition_rule parse_rule(const std::string& text) {
  if (text == "auto") return partition_rule::automatic;
  if (text == "trapezoid") return partition_rule::trapezoid;
  if (text == "qmc") return partition_rule::quasi_monte_carlo;
  throw cli::input_error(fmt::format("--rule: one of auto, trapezoid, qmc, got '{}'", text));
}

nlohmann::json state_json(const canonical_state& s) {
  return {{"temperature", s.temperature},
          {"partition_function", std::isfinite(s.partition_function)
                                     ? nlohmann::json(s.partition_function)
                                     : nlohmann::json(nullptr)},
          {"log_partition_function", s.log_partition_function},
          {"free_energy", s.free_energy},
          {"mean_energy", s.mean_energy},
          {"mean_potential", s.mean_potential},
          {"heat_capacity", s.heat_capacity},
          {"mean_cos", s.mean_cos},
          {"error_estimate",
           {{"log_partition_function", s.log_partition_error},
            {"free_energy", s.free_energy_error},
            {"mean_energy", s.mean_energy_error},
            {"heat_capacity", s.heat_capacity_error}}}};
}

void write_files(series_output& files, const chain& c, const partition_result& r, double kb) {
  const auto n = static_cast<std::size_t>(c.links());
  std::vector<std::string> names{"T", "log_Z", "F", "E", "E_error", "C", "C_error"};
  for (std::size_t i = 1; i <= n; ++i) names.push_back(fmt::format("cos_phi_{}", i));
  std::vector<std::vector<double>> columns(names.size());
  for (const canonical_state& s : r.states) {
    const double row[] = {s.temperature,        s.log_partition_function, s.free_energy,
                          s.mean_energy,        s.mean_energy_error,      s.heat_capacity,
                          s.heat_capacity_error};
    for (std::size_t j = 0; j < 7; ++j) columns[j].push_back(row[j]);
    for (std::size_t i = 0; i < n; ++i) columns[7 + i].push_back(s.mean_cos[i]);
  }
  const std::string data = files.write_csv("", names, columns);
  const double links = static_cast<double>(n);
  cli::plot_panel capacity{
      .title = "Heat capacity",
      .xlabel = "temperature T",
      .ylabel = kb == 1 ? "C / k" : "C (J/K)",
      .log_x = true,
      .commands = {"set key bottom right", "set grid",
                   fmt::format("set arrow from graph 0, first {0} to graph 1, first {0} nohead "
                               "dt 2 lc rgb '#888888'",
                               links * kb),
                   fmt::format("set arrow from graph 0, first {0} to graph 1, first {0} nohead "
                               "dt 2 lc rgb '#888888'",
                               links * kb / 2)},
      .curves = {{data, "1:6:7", "yerrorlines lw 2 pt 7 ps 0.6 lc rgb '#d62728'",
                  "C (dashed: n k and n k/2)"}}};
  cli::plot_panel energy{
      .title = "Mean energy per link over k T",
      .xlabel = "temperature T",
      .ylabel = "<E> / (n k T)",
      .log_x = true,
      .commands = {"set key top right", "set grid"},
      .curves = {{data, fmt::format("1:($4/({}*{}*$1))", links, kb),
                  "linespoints lw 2 pt 7 ps 0.6 lc rgb '#1f77b4'", "<E>/(n k T)"}}};
  cli::plot_panel order{.title = "Order: <cos phi_i>",
                        .xlabel = "temperature T",
                        .ylabel = "<cos φ_i>",
                        .log_x = true,
                        .commands = {"set key bottom left", "set grid"}};
  static const char* colours[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e"};
  for (std::size_t i = 0; i < n; ++i)
    order.curves.push_back(
        {data, fmt::format("1:{}", 8 + i),
         fmt::format("linespoints lw 1.5 pt 7 ps 0.5 lc rgb '{}'", colours[i % 5]),
         fmt::format("<cos φ_{}>", i + 1)});
  files.write_plot({.description = {"npend partition: the canonical ensemble over the "
                                    "temperature: heat capacity, mean energy, <cos phi_i>",
                                    fmt::format("data: {}", data)},
                    .width = 1500,
                    .height = 520,
                    .columns = 3,
                    .panels = {capacity, energy, order}});
}

int run_partition(const partition_command_options& o) {
  const chain c = o.chain.make_chain(cli::model_support::canonical, "npend partition");
  if (o.temperature.empty() == o.scan.empty())
    throw cli::input_error("give one of --temperature T and --scan T_FROM:T_TO:COUNT");
  const std::vector<double> temperatures =
      o.scan.empty() ? std::vector<double>{cli::parse_number(o.temperature, "--temperature")}
                     : parse_temperature_scan(o.scan);
  if (!o.out.empty() && o.scan.empty())
    throw cli::input_error("--out: only with --scan (the curves' data and plot)");
  partition_options options;
  options.rule = parse_rule(o.rule);
  options.grid = o.grid;
  options.points = o.points;
  options.replicas = o.replicas;
  // Options of the other rule would be ignored: refuse them.
  const bool trapezoid =
      chosen_partition_rule(options.rule, c.links()) == partition_rule::trapezoid;
  const char* rule_name = trapezoid ? "trapezoid" : "qmc";
  for (const char* name : {"--points", "--replicas", "--seed", "--grid"}) {
    const bool of_trapezoid = std::string_view(name) == "--grid";
    if (o.command->count(name) > 0 && of_trapezoid != trapezoid)
      throw cli::input_error(fmt::format(
          "{}: only for the {} rule; this run uses the {} rule{}", name,
          of_trapezoid ? "trapezoid" : "qmc", rule_name,
          o.rule == "auto" ? " (auto: trapezoid for n <= 3, qmc beyond; choose with --rule)" : ""));
  }
  if (!o.seed.empty()) {
    options.seed = static_cast<std::uint64_t>(cli::parse_whole_number(o.seed, "--seed", 0, 9.0e15));
  }
  options.boltzmann = o.kb;
  series_output files(o.out);
  cli::terminal_run control;
  options.control = &control;
  partition_result r;
  try {
    r = canonical_ensemble(c, temperatures, options);
  } catch (const std::invalid_argument& e) {
    throw cli::input_error(e.what());
  }
  control.finish();
  if (r.stopped) {
    fmt::print(stderr, "npend partition: interrupted{}\n",
               o.out.empty() ? "" : fmt::format("; nothing written to {}", o.out));
    return control.exit_code();
  }
  if (files.enabled()) write_files(files, c, r, o.kb);
  // A rule that has not resolved the Boltzmann factor's peak (low T) says so.
  for (const canonical_state& s : r.states)
    if (s.heat_capacity_error > 1e-3 * s.heat_capacity)
      fmt::print(stderr,
                 "npend partition: note: at T = {:g} the rule has not converged (C = {:.6g} +- "
                 "{:.2g}); raise {}\n",
                 s.temperature, s.heat_capacity, s.heat_capacity_error,
                 r.rule == "trapezoid" ? "--grid" : "--points");

  if (o.json) {
    nlohmann::json j = describe_chain(c);
    j["boltzmann"] = o.kb;
    j["rule"] = r.rule;
    j["evaluations"] = r.evaluations;
    if (r.rule == "trapezoid")
      j["grid"] = r.grid;
    else
      j["points"] = r.points, j["replicas"] = r.replicas, j["seed"] = options.seed;
    if (o.scan.empty()) {
      j.update(state_json(r.states.front()));
    } else {
      nlohmann::json list = nlohmann::json::array();
      for (const canonical_state& s : r.states) list.push_back(state_json(s));
      j["states"] = list;
    }
    files.add_to(j);
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  fmt::print(
      "{}-link chain, canonical ensemble (k = {}), {} rule: {}\n", c.links(), o.kb, r.rule,
      r.rule == "trapezoid"
          ? fmt::format("{} points per angle, error from the grid of every other point", r.grid)
          : fmt::format("{} Sobol points x {} random shifts, standard errors", r.points,
                        r.replicas));
  fmt::print("{:>12} {:>14} {:>14} {:>24} {:>24}", "T", "ln Z", "F", "<E>", "C");
  for (int i = 1; i <= c.links(); ++i) fmt::print(" {:>10}", fmt::format("<cos phi{}>", i));
  fmt::print("\n");
  for (const canonical_state& s : r.states) {
    fmt::print("{:>12.6g} {:>14.8g} {:>14.8g} {:>24} {:>24}", s.temperature,
               s.log_partition_function, s.free_energy,
               fmt::format("{:.8g} +- {:.1e}", s.mean_energy, s.mean_energy_error),
               fmt::format("{:.8g} +- {:.1e}", s.heat_capacity, s.heat_capacity_error));
    for (const double v : s.mean_cos) fmt::print(" {:>10.6f}", v);
    fmt::print("\n");
  }
  files.print();
  return 0;
}

}  // namespace

void add_partition_command(CLI::App& app, command_list& commands) {
  auto o = std::make_shared<partition_command_options>();
  CLI::App* cmd = app.add_subcommand(
      "partition",
      "The canonical ensemble: partition function Z, free energy, mean energy, heat capacity "
      "and <cos phi_i> at a temperature or over a range, with error estimates");
  o->command = cmd;
  o->chain.add_to(*cmd);
  cmd->add_option("--temperature", o->temperature,
                  "The temperature T (in energy units, J, with the default --kb 1)");
  cmd->add_option("--scan", o->scan,
                  "T_FROM:T_TO:COUNT: COUNT temperatures, log-spaced, both ends included");
  cmd->add_option("--rule", o->rule,
                  "The angle integral's rule: trapezoid (periodic, exponentially convergent; "
                  "n <= 3 by default), qmc (randomised Sobol quasi-Monte Carlo) or auto "
                  "(default)");
  cmd->add_option(
      "--grid", o->grid,
      "trapezoid only: points per angle, even (default 256, 128, 64 for 1, 2, 3 links)");
  cmd->add_option("--points", o->points, "qmc only: Sobol points per shift (default 65536)");
  cmd->add_option("--replicas", o->replicas, "qmc only: random shifts (default 16)");
  cmd->add_option("--seed", o->seed,
                  "qmc only: seed of the random shifts, a whole number 0..9e15 (default 1)");
  cmd->add_option("--kb", o->kb,
                  "Boltzmann's constant k in J/K (default 1: T in J; 1.380649e-23 for kelvin)");
  cmd->add_option("--out", o->out,
                  "With --scan: write S.csv and the plot S.gp/S.png (C, <E>/(n k T), "
                  "<cos phi_i> over T)");
  cmd->add_flag("--json", o->json, "Print JSON");
  commands.push_back({cmd, [o] { return run_partition(*o); }});
}

}  // namespace npend::app
