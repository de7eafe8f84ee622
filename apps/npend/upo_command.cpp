// npend upo: unstable periodic orbits in the chaotic sea — the close returns of a chaotic
// trajectory on the section phi_1 = 0, each refined by shooting at the trajectory's energy;
// the distinct orbits up to a period bound with their Floquet multipliers, and the largest
// multiplier's rate ln|mu|/T beside the trajectory's maximal Lyapunov exponent.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <nlohmann/json.hpp>

#include "chain_options.hpp"
#include "command.hpp"
#include "input_parsing.hpp"
#include "integrator_options.hpp"
#include "npend/analysis/orbits/unstable_orbits.hpp"
#include "series_output.hpp"
#include "start_options.hpp"
#include "terminal_run.hpp"

namespace npend::app {

namespace {

struct upo_command_options {
  cli::chain_options chain;
  cli::start_options start;
  std::string period_max, period_min, time, dt, tolerance, candidates, max_orbits;
  std::string stepper, tol;  // how the shootings integrate (gauss6 or taylor at tol)
  bool json = false;
  std::string out;
};

double positive_time(const std::string& text, const char* option) {
  const double v = cli::parse_number(text, option);
  if (!(v > 0) || !std::isfinite(v))
    throw cli::input_error(fmt::format("{}: a positive time in s, got {}", option, text));
  return v;
}

unstable_orbit_search_options make_search(const upo_command_options& o) {
  unstable_orbit_search_options opts;
  if (o.period_max.empty())
    throw cli::input_error("--period-max is required (the longest period in s)");
  opts.period_max = positive_time(o.period_max, "--period-max");
  if (!o.period_min.empty()) {
    opts.period_min = cli::parse_number(o.period_min, "--period-min");
    if (!(opts.period_min >= 0 && opts.period_min < opts.period_max))
      throw cli::input_error(fmt::format("--period-min: a time in [0, --period-max = {}) s, got {}",
                                         opts.period_max, o.period_min));
  }
  if (!o.time.empty()) opts.search_time = positive_time(o.time, "--time");
  if (!o.dt.empty()) opts.dt = positive_time(o.dt, "--dt");
  if (!(opts.dt < opts.search_time))
    throw cli::input_error(fmt::format("--dt: the step ({} s) must be shorter than --time ({} s)",
                                       opts.dt, opts.search_time));
  if (!o.tolerance.empty()) {
    opts.return_tolerance = cli::parse_number(o.tolerance, "--tolerance");
    if (!(opts.return_tolerance > 0 && opts.return_tolerance <= 1))
      throw cli::input_error(fmt::format(
          "--tolerance: a fraction of each coordinate's range in (0, 1], got {}", o.tolerance));
  }
  if (!o.candidates.empty())
    opts.max_candidates =
        static_cast<int>(cli::parse_whole_number(o.candidates, "--candidates", 1, 1e6));
  if (!o.max_orbits.empty())
    opts.max_orbits =
        static_cast<int>(cli::parse_whole_number(o.max_orbits, "--max-orbits", 1, 1e6));
  opts.shooting.stepper = cli::parse_monodromy_integrator(o.stepper, false, o.tol, "the shooting",
                                                          opts.shooting.integration_tolerance);
  return opts;
}

std::string winding_text(const unstable_orbit& u) {
  return fmt::format("{}", fmt::join(u.winding, ","));
}

nlohmann::json orbit_json(const unstable_orbit& u) {
  return {{"period", u.period},
          {"energy", u.energy},
          {"x0", u.x0},
          {"winding", u.winding},
          {"multipliers", json_complex_list(u.multipliers)},
          {"max_multiplier", u.max_multiplier},
          {"lyapunov_rate", u.lyapunov_rate},
          {"stable", u.stable},
          {"closure", u.closure},
          {"iterations", u.iterations},
          {"copies", u.copies},
          {"section_points", u.section_points}};
}

void write_upo_files(series_output& files, const chain& c, const unstable_orbit_search_result& r) {
  const int n = c.links();
  std::vector<std::string> names{"period", "energy",  "max_multiplier", "lyapunov_rate",
                                 "stable", "closure", "copies"};
  for (int i = 1; i <= n; ++i) names.push_back(fmt::format("winding{}", i));
  for (int i = 1; i <= n; ++i) names.push_back(fmt::format("phi{}", i));
  for (int i = 1; i <= n; ++i) names.push_back(fmt::format("p{}", i));
  std::vector<std::vector<double>> table(names.size());
  for (const unstable_orbit& u : r.orbits) {
    std::vector<double> row{u.period,
                            u.energy,
                            u.max_multiplier,
                            u.lyapunov_rate,
                            u.stable ? 1.0 : 0.0,
                            u.closure,
                            static_cast<double>(u.copies)};
    for (int w : u.winding) row.push_back(w);
    row.insert(row.end(), u.x0.begin(), u.x0.end());
    for (std::size_t k = 0; k < row.size(); ++k) table[k].push_back(row[k]);
  }
  const std::string data = files.write_csv("", names, table);
  cli::plot_panel panel;
  panel.title = fmt::format("Periodic orbits of the {}-link chain at E = {:.6g} J", n, r.energy);
  panel.xlabel = "period T (s)";
  panel.ylabel = "ln|μ_{max}| / T (1/s)";
  panel.commands = {"set key outside right"};
  // From 0 to above the fastest rate and the Lyapunov exponent's line.
  double top = std::isfinite(r.lyapunov_exponent) ? r.lyapunov_exponent : 0.0;
  for (const unstable_orbit& u : r.orbits) top = std::max(top, u.lyapunov_rate);
  if (top > 0) panel.yrange = fmt::format("[0:{}]", 1.15 * top);
  if (std::isfinite(r.lyapunov_exponent))
    panel.commands.push_back(fmt::format(
        "set arrow from graph 0, first {0} to graph 1, first {0} nohead dt 2 lc rgb 'black'",
        r.lyapunov_exponent));
  panel.curves.push_back(
      {data, "($5==0 ? $1 : 1/0):4", "points pt 7 ps 1.2 lc rgb '#d62728'", "unstable orbits"});
  panel.curves.push_back(
      {data, "($5==1 ? $1 : 1/0):4", "points pt 6 ps 1.4 lc rgb '#21918c'", "stable orbits"});
  files.write_plot(
      {.description = {fmt::format("npend upo: the periodic orbits' rates ln|mu_max|/T against "
                                   "their periods, {}-link chain; dashed: the maximal Lyapunov "
                                   "exponent of the trajectory",
                                   n),
                       fmt::format("data: {} (one row per orbit)", data)},
       .panels = {panel}});
}

// How the shootings integrate, for the text output.
std::string shooting_text(const unstable_orbit_search_options& opts) {
  if (opts.shooting.stepper == stepper_kind::taylor)
    return fmt::format("taylor at tolerance {:g}", opts.shooting.integration_tolerance);
  return fmt::format("Gauss-Legendre steps of at most {:g} s", opts.shooting_dt);
}

void print_results(const chain& c, const unstable_orbit_search_result& r,
                   const unstable_orbit_search_options& opts) {
  fmt::print(
      "Periodic orbits of the {}-link chain at E = {:.10g} J with {:g} <= T <= {:g} s: the close\n"
      "returns (within {:g} of each coordinate's range) of a {:g} s trajectory on the section\n"
      "phi1 = 0 (upwards), refined by multiple shooting (closure <= {:g}; {}).\n",
      c.links(), r.energy, opts.period_min, opts.period_max, opts.return_tolerance,
      opts.search_time, opts.shooting.tolerance, shooting_text(opts));
  fmt::print(
      "{} crossings, {} candidates ({} rotating), {} shot, {} converged: {} repeats of a shorter "
      "orbit, {} found before (or a symmetry image), {} outside the period range\n",
      r.crossings, r.candidates, r.rotating, r.tried, r.converged, r.repeats, r.duplicates,
      r.out_of_range);
  if (std::isfinite(r.lyapunov_exponent))
    fmt::print("maximal Lyapunov exponent of the trajectory: {:.6g} 1/s (over {:g} s)\n",
               r.lyapunov_exponent, r.lyapunov_time);
  if (r.orbits.empty()) {
    fmt::print(
        "\nNo periodic orbit converged: try a longer --time, a larger --tolerance or "
        "--period-max, or a start in the chaotic sea.\n");
    return;
  }
  fmt::print("\n{:>14}  {:>14}  {:>12}  {:>11}  {:>6}  {:>9}  {:>8}  {:>6}\n", "period (s)",
             "energy (J)", "max|mu|", "ln|mu|/T", "stable", "closure", "winding", "copies");
  for (const unstable_orbit& u : r.orbits)
    fmt::print("{:>14.10f}  {:>14.10g}  {:>12.6g}  {:>11.6f}  {:>6}  {:>9.2g}  {:>8}  {:>6}\n",
               u.period, u.energy, u.max_multiplier, u.lyapunov_rate, u.stable ? "yes" : "no",
               u.closure, winding_text(u), u.copies);
  fmt::print(
      "copies: the orbit and its images under time reversal (and the mirror phi -> -phi) are "
      "this many distinct orbits, of one period and one set of multipliers.\n");
}

int run_upo(const upo_command_options& o) {
  const chain c = o.chain.make_chain(cli::model_support::conservative, "npend upo");
  const std::vector<double> start = o.start.make_state(c);
  unstable_orbit_search_options opts = make_search(o);
  series_output files(o.out);
  cli::terminal_run control;
  opts.control = &control;
  unstable_orbit_search_result r;
  try {
    r = find_unstable_orbits(c, start, opts);
  } catch (const std::invalid_argument& e) {
    throw cli::input_error(e.what());
  }
  control.finish();
  if (r.stopped) {
    fmt::print(stderr, "npend upo: interrupted{}\n",
               o.out.empty() ? "" : fmt::format("; nothing written to {}", o.out));
    return control.exit_code();
  }
  if (files.enabled()) write_upo_files(files, c, r);
  if (!o.json) {
    print_results(c, r, opts);
    files.print();
    return 0;
  }
  nlohmann::json orbits = nlohmann::json::array();
  for (const unstable_orbit& u : r.orbits) orbits.push_back(orbit_json(u));
  nlohmann::json j = describe_chain(c);
  j.update(nlohmann::json{
      {"energy", r.energy},
      {"start", start},
      {"period_min", opts.period_min},
      {"period_max", opts.period_max},
      {"search_time", opts.search_time},
      {"return_tolerance", opts.return_tolerance},
      {"stepper", stepper_name(opts.shooting.stepper)},
      {"crossings", r.crossings},
      {"candidates", r.candidates},
      {"rotating", r.rotating},
      {"tried", r.tried},
      {"converged", r.converged},
      {"repeats", r.repeats},
      {"duplicates", r.duplicates},
      {"out_of_range", r.out_of_range},
      {"lyapunov_exponent",
       std::isfinite(r.lyapunov_exponent) ? nlohmann::json(r.lyapunov_exponent) : nlohmann::json()},
      {"lyapunov_time", r.lyapunov_time},
      {"orbits", orbits}});
  if (opts.shooting.stepper == stepper_kind::taylor)
    j["integration_tolerance"] = opts.shooting.integration_tolerance;
  files.add_to(j);
  std::cout << j.dump(2) << "\n";
  return 0;
}

}  // namespace

void add_upo_command(CLI::App& app, command_list& commands) {
  auto o = std::make_shared<upo_command_options>();
  CLI::App* cmd = app.add_subcommand(
      "upo",
      "Unstable periodic orbits in the chaotic sea: close returns of a chaotic trajectory on the "
      "section phi1 = 0 refined by multiple shooting at its energy; the distinct orbits up to "
      "--period-max with their Floquet multipliers and ln|mu|/T against the Lyapunov exponent");
  o->chain.add_to(*cmd);
  o->start.add_to(*cmd);
  cmd->add_option("--period-max", o->period_max, "The longest period in s (required)");
  cmd->add_option("--period-min", o->period_min, "The shortest period in s (default 0)");
  cmd->add_option("--time", o->time,
                  "The length of the trajectory whose close returns are the candidates, in s "
                  "(default 500)");
  cmd->add_option("--dt", o->dt,
                  "The Gauss-Legendre step of the trajectory and the Lyapunov run in s "
                  "(default 0.005)");
  cmd->add_option("--tolerance", o->tolerance,
                  "A close return: every coordinate within this fraction of its range over the "
                  "section points (default 0.1)");
  cli::add_monodromy_options(*cmd, o->stepper, o->tol, "How each shooting",
                             "steps of at most 0.002 s", 1e-14);
  cmd->add_option("--candidates", o->candidates,
                  "Shoot at most this many candidates (default 100)");
  cmd->add_option("--max-orbits", o->max_orbits,
                  "Stop after this many distinct orbits (default: no limit)");
  cmd->add_flag("--json", o->json,
                "Print JSON (every orbit, its start, multipliers, section points)");
  cmd->add_option("--out", o->out,
                  "Write FILE.csv (one row per orbit) and the plot FILE.png of ln|mu|/T against "
                  "the period with its gnuplot script FILE.gp");
  commands.push_back({cmd, [o] { return run_upo(*o); }});
}

}  // namespace npend::app
