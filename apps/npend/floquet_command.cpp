// npend floquet: Floquet multipliers of a driven chain's periodic orbit (Kapitza's inverted
// pendulum, Acheson's stabilised double and triple pendulums), and stability charts over the
// drive frequency.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cmath>
#include <iostream>
#include <nlohmann/json.hpp>
#include <numbers>

#include "chain_options.hpp"
#include "command.hpp"
#include "input_parsing.hpp"
#include "integrator_options.hpp"
#include "npend/analysis/stability/floquet.hpp"
#include "npend/integrators/integrate.hpp"
#include "series_output.hpp"
#include "terminal_run.hpp"

namespace npend::app {

namespace {

struct floquet_command_options {
  cli::chain_options chain;
  std::string at = "pi", p, scan, out, stepper = "gauss6", tol;
  int steps = 400;
  bool steps_given = false;
  bool json = false;
};

struct frequency_scan {
  double from = 0, to = 0;
  int count = 0;
};

frequency_scan parse_scan(const std::string& text) {
  const auto parts = cli::split_list(text, ':');
  if (parts.size() != 3)
    throw cli::input_error(
        fmt::format("--scan: expected OMEGA_FROM:OMEGA_TO:COUNT, got '{}'", text));
  frequency_scan s{cli::parse_number(parts[0], "--scan (from)"),
                   cli::parse_number(parts[1], "--scan (to)"), 0};
  const double count = cli::parse_number(parts[2], "--scan (count)");
  if (!cli::is_whole_number(count, 2, 100000))
    throw cli::input_error(
        fmt::format("--scan: the count must be a whole number 2..100000, got {}", parts[2]));
  if (!(s.from > 0) || !(s.to > s.from))
    throw cli::input_error(fmt::format(
        "--scan: frequencies must satisfy 0 < from < to (rad/s), got {}:{}", s.from, s.to));
  s.count = static_cast<int>(count);
  return s;
}

std::vector<double> start_state(const chain& c, const floquet_command_options& o) {
  const int n = c.links();
  std::vector<double> x = cli::parse_angle_list(o.at, "--at", n);
  if (o.p.empty()) {
    x.resize(static_cast<std::size_t>(2 * n), 0.0);
  } else {
    const auto p = cli::parse_number_list(o.p, "--p", static_cast<std::size_t>(n),
                                          fmt::format("p_1..p_{}", n));
    x.insert(x.end(), p.begin(), p.end());
  }
  return x;
}

int run_single(const chain& c, const floquet_command_options& o, const floquet_options& options) {
  const std::vector<double> x0 = start_state(c, o);
  cli::terminal_run control;
  floquet_options opts = options;
  opts.control = &control;
  const floquet_result r = floquet_analysis(c, x0, opts);
  control.finish();
  if (r.stopped) {
    fmt::print(stderr, "npend floquet: interrupted\n");
    return control.exit_code();
  }
  const bool periodic = r.closure < 1e-6 * std::max(1.0, std::fabs(x0[0]));
  if (o.json) {
    nlohmann::json j = describe_chain(c);
    j["at"] = x0;
    j["period"] = r.period;
    j["stepper"] = stepper_name(options.stepper);
    j["steps"] = r.steps;
    if (options.stepper == stepper_kind::taylor) j["tolerance"] = options.tolerance;
    j["multipliers"] = json_complex_list(r.multipliers);
    j["max_modulus"] = r.max_modulus;
    j["modulus_error"] = r.modulus_error;
    j["verdict"] = verdict_name(r.verdict);
    j["stable"] = r.stable;
    j["closure"] = r.closure;
    j["periodic"] = periodic;
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  const bool taylor = options.stepper == stepper_kind::taylor;
  fmt::print("{}-link chain, pivot {}, period T = {:.6g} s, {}\n", c.links(),
             c.parameters().pivot.describe(), r.period,
             taylor ? fmt::format("{} Taylor steps at tolerance {:g}", r.steps, options.tolerance)
                    : fmt::format("{} Gauss-Legendre steps", r.steps));
  fmt::print("start x0 = {}\n", x0);
  fmt::print("{:>4} {:>22} {:>22} {:>14}\n", "k", "Re mu", "Im mu", "|mu|");
  for (std::size_t k = 0; k < r.multipliers.size(); ++k)
    fmt::print("{:>4} {:>22.15g} {:>22.15g} {:>14.10f}\n", k + 1, r.multipliers[k].real(),
               r.multipliers[k].imag(), std::abs(r.multipliers[k]));
  const char* verdict = r.verdict == floquet_verdict::stable     ? "stable (linearly)"
                        : r.verdict == floquet_verdict::marginal ? "marginal"
                                                                 : "unstable";
  fmt::print(
      "{}: max |mu| = {:.10f}, max |mu| - 1 = {:.3g} +- {:.2g} (the change from {}, and "
      "rounding)\n",
      verdict, r.max_modulus, r.max_modulus - 1, r.modulus_error,
      taylor ? fmt::format("tolerance {:g}", 100 * options.tolerance)
             : fmt::format("{} steps per period", options.steps / 2));
  if (r.verdict == floquet_verdict::marginal)
    fmt::print(
        "marginal: max |mu| is within its error of 1, so the integration cannot tell a slow "
        "decay from a slow growth; {} shrink the error\n",
        taylor ? "a smaller --tol may" : "more --steps");
  if (!periodic)
    fmt::print(stderr,
               "npend floquet: warning: the start is not on a T-periodic orbit (|x(T) - x(0)| = "
               "{:.3g}): the multipliers are those of the period map there, not of an orbit\n",
               r.closure);
  return 0;
}

// The chart's data (CSV) and its plot.
void write_scan_files(series_output& files, const floquet_scan_result& scan,
                      const std::vector<double>& x0, const pivot_motion& drive) {
  std::vector<double> omega, a_omega, modulus, stable_flag, modulus_error;
  for (const auto& p : scan.points) {
    omega.push_back(p.frequency);
    a_omega.push_back(drive.amplitude * p.frequency);
    modulus.push_back(p.max_modulus);
    stable_flag.push_back(p.stable ? 1.0 : 0.0);
    modulus_error.push_back(p.modulus_error);
  }
  const std::string data = files.write_csv(
      "", std::vector<std::string>{"omega", "a_omega", "max_modulus", "stable", "modulus_error"},
      std::vector{omega, a_omega, modulus, stable_flag, modulus_error});
  cli::plot_panel panel{
      .title = fmt::format("Floquet stability of {} over the drive frequency ({} drive, a = {} m)",
                           fmt::join(x0, ","),
                           drive.type == pivot_motion::kind::vertical ? "vertical" : "horizontal",
                           drive.amplitude),
      .xlabel = "drive frequency Ω (rad/s)",
      .ylabel = "largest multiplier |μ|_{max}",
      .log_y = true,
      .commands = {"set key top right", "set grid"}};
  panel.curves.push_back({data, "1:3", "lines lw 2 lc rgb '#1f77b4'", "max |μ|"});
  panel.curves.push_back(
      {data, "($4 > 0.5 ? $1 : 1/0):3", "points pt 7 ps 0.6 lc rgb '#2ca02c'", "stable"});
  files.write_plot({.description = {"npend floquet --scan: the largest Floquet multiplier over "
                                    "the drive frequency; stable where it is 1",
                                    fmt::format("data: {}", data)},
                    .panels = {panel}});
}

int run_scan(const chain& base, const floquet_command_options& o, const floquet_options& options) {
  const frequency_scan range = parse_scan(o.scan);
  const pivot_motion& drive = base.parameters().pivot;
  const std::vector<double> x0 = start_state(base, o);
  series_output files(o.out);
  std::vector<double> frequencies;
  for (int k = 0; k < range.count; ++k)
    frequencies.push_back(range.from + (range.to - range.from) * k / (range.count - 1));
  cli::terminal_run control;
  floquet_options opts = options;
  opts.control = &control;
  const floquet_scan_result scan = floquet_frequency_scan(base, x0, frequencies, opts);
  control.finish();
  if (scan.stopped) {
    fmt::print(stderr, "npend floquet: interrupted at Omega = {} rad/s{}\n", scan.stopped_at,
               o.out.empty() ? "" : fmt::format("; nothing written to {}", o.out));
    return control.exit_code();
  }
  if (files.enabled()) write_scan_files(files, scan, x0, drive);
  if (o.json) {
    nlohmann::json j = describe_chain(base);
    j["at"] = x0;
    nlohmann::json rows = nlohmann::json::array(), list = nlohmann::json::array();
    for (const auto& p : scan.points)
      rows.push_back({{"omega", p.frequency},
                      {"a_omega", drive.amplitude * p.frequency},
                      {"max_modulus", p.max_modulus},
                      {"modulus_error", p.modulus_error},
                      {"verdict", verdict_name(p.verdict)},
                      {"stable", p.stable}});
    for (const auto& [lo, hi] : scan.stable_windows) list.push_back({lo, hi});
    j["scan"] = rows;
    j["stable_windows"] = list;
    files.add_to(j);
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  fmt::print("{}-link chain at {}, drive amplitude {} m: {} frequencies {}..{} rad/s\n",
             base.links(), x0, drive.amplitude, range.count, range.from, range.to);
  fmt::print("{:>12} {:>12} {:>16} {:>10} {:>9}\n", "Omega", "a*Omega", "max |mu|", "+-",
             "verdict");
  for (const auto& p : scan.points)
    fmt::print("{:>12.6g} {:>12.6g} {:>16.10g} {:>10.2g} {:>9}\n", p.frequency,
               drive.amplitude * p.frequency, p.max_modulus, p.modulus_error,
               verdict_name(p.verdict));
  if (scan.stable_windows.empty()) fmt::print("no stable frequency in the scan\n");
  for (const auto& [lo, hi] : scan.stable_windows)
    fmt::print("stable for Omega in [{:.6g}, {:.6g}] rad/s (a*Omega in [{:.6g}, {:.6g}] m/s)\n", lo,
               hi, drive.amplitude * lo, drive.amplitude * hi);
  files.print();
  return 0;
}

// --stepper, --steps and --tol, checked together, and taylor against the chain.
floquet_options integrator_of(const chain& c, const floquet_command_options& o) {
  floquet_options options;
  options.steps = o.steps;
  options.stepper = cli::parse_monodromy_integrator(o.stepper, o.steps_given, o.tol,
                                                    "Floquet analysis", options.tolerance);
  if (options.stepper != stepper_kind::taylor) return options;
  try {
    check_stepper_fits(c, stepper_kind::taylor);
  } catch (const std::invalid_argument& e) {
    throw cli::input_error(fmt::format("--stepper: {}", e.what()));
  }
  return options;
}

int run_floquet(const floquet_command_options& o) {
  const chain c = o.chain.make_chain(cli::model_support::any, "npend floquet");
  const pivot_motion& drive = c.parameters().pivot;
  if (drive.type != pivot_motion::kind::vertical && drive.type != pivot_motion::kind::horizontal)
    throw cli::input_error(
        "npend floquet needs a periodic drive: --pivot vertical:A:OMEGA or horizontal:A:OMEGA");
  if (o.steps < 8 || o.steps > 1000000)
    throw cli::input_error(fmt::format("--steps: must be 8..1000000, got {}", o.steps));
  if (!o.out.empty() && o.scan.empty())
    throw cli::input_error("--out: only with --scan (the chart's data and plot)");
  const floquet_options options = integrator_of(c, o);
  try {
    return o.scan.empty() ? run_single(c, o, options) : run_scan(c, o, options);
  } catch (const std::invalid_argument& e) {
    throw cli::input_error(e.what());
  }
}

}  // namespace

void add_floquet_command(CLI::App& app, command_list& commands) {
  auto o = std::make_shared<floquet_command_options>();
  CLI::App* cmd = app.add_subcommand(
      "floquet",
      "Floquet multipliers of a periodically driven chain (the monodromy matrix over one drive "
      "period, from the exact Jacobian); with --scan a stability chart over the drive frequency");
  o->chain.add_to(*cmd);
  cmd->add_option("--at", o->at,
                  "Start angles phi_1,..,phi_n (numbers or pi; one value for all links; default "
                  "pi: the inverted chain)");
  cmd->add_option("--p", o->p, "Start momenta p_1,..,p_n (default: 0)");
  CLI::Option* steps = cmd->add_option(
      "--steps", o->steps,
      "Gauss-Legendre (order 6) steps per drive period (default: 400); a second run at half of "
      "them gives the error estimate the verdict weighs");
  cli::add_monodromy_options(*cmd, o->stepper, o->tol, "How the monodromy matrix",
                             "--steps fixed steps", 1e-13,
                             "; a second run at 100 times it gives the error estimate");
  cmd->add_option("--scan", o->scan,
                  "OMEGA_FROM:OMEGA_TO:COUNT: scan the drive frequency (rad/s) at the --pivot "
                  "amplitude and list where the start is stable");
  cmd->add_option("--out", o->out,
                  "With --scan: write the chart as FILE.csv with a plot FILE.gp/FILE.png");
  cmd->add_flag("--json", o->json, "Print JSON");
  commands.push_back({cmd, [o, steps] {
                        o->steps_given = steps->count() > 0;
                        return run_floquet(*o);
                      }});
}

}  // namespace npend::app
