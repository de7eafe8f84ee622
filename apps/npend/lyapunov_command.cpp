// npend lyapunov: the Lyapunov spectrum (or the maximal exponent) of a trajectory, with its
// convergence (paper §6.5.1).
#include "chain_options.hpp"
#include "command.hpp"
#include "input_parsing.hpp"
#include "integrator_options.hpp"
#include "interrupt_guard.hpp"
#include "progress_bar.hpp"
#include "series_output.hpp"
#include "start_options.hpp"

#include "npend/analysis/lyapunov.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <iostream>

namespace npend::app {

namespace {

struct lyapunov_command_options {
  cli::chain_options chain;
  cli::start_options start;
  cli::integrator_options integrator;
  std::string transient, renormalise, fraction;
  bool maximal = false;
  bool json = false;
  std::string out;
};

lyapunov_options make_options(const lyapunov_command_options& o) {
  lyapunov_options l;
  l.integration = o.integrator.make();
  if (l.integration.stepper == stepper_kind::rosenbrock4)
    throw cli::input_error(
        "--stepper: rosenbrock4 cannot integrate the variational equations (it would need "
        "second derivatives of f); use gauss6 (default), gauss4, rk4, dopri5, rkf78 or bs");
  if (!o.transient.empty()) {
    l.transient = cli::parse_number(o.transient, "--transient");
    if (l.transient < 0)
      throw cli::input_error(fmt::format("--transient: must be >= 0, got {}", l.transient));
    if (l.transient >= l.integration.t_end)
      throw cli::input_error(
          fmt::format("--transient: {} s leaves no time to average before --t-end {} s",
                      l.transient, l.integration.t_end));
  }
  if (!o.renormalise.empty()) {
    l.renormalisation_interval = cli::parse_number(o.renormalise, "--renormalise-every");
    if (l.renormalisation_interval <= 0)
      throw cli::input_error(
          fmt::format("--renormalise-every: must be positive, got {}", l.renormalisation_interval));
  }
  if (!o.fraction.empty()) {
    l.convergence_fraction = cli::parse_number(o.fraction, "--convergence-fraction");
    if (!(l.convergence_fraction > 0 && l.convergence_fraction <= 1))
      throw cli::input_error(
          fmt::format("--convergence-fraction: must be in (0, 1], got {}", l.convergence_fraction));
  }
  return l;
}

// JSON numbers, with NaN (a spread that could not be estimated) as null.
nlohmann::json numbers(const std::vector<double>& values) {
  nlohmann::json out = nlohmann::json::array();
  for (double v : values) out.push_back(std::isfinite(v) ? nlohmann::json(v) : nlohmann::json());
  return out;
}

// λ_i + λ_{2n+1−i} for i = 1..n.
std::vector<double> pair_sums(const std::vector<double>& lambda) {
  std::vector<double> out;
  for (std::size_t i = 0; i < lambda.size() / 2; ++i)
    out.push_back(lambda[i] + lambda[lambda.size() - 1 - i]);
  return out;
}

void write_files(series_output& files, const lyapunov_result& r, const chain& c, bool maximal) {
  std::vector<std::string> names{"t"};
  std::vector<std::vector<double>> columns{r.history_t};
  for (std::size_t i = 0; i < r.exponents.size(); ++i) {
    names.push_back(fmt::format("lambda_{}", i + 1));
    std::vector<double> column;
    for (const auto& h : r.history) column.push_back(h[i]);
    columns.push_back(std::move(column));
  }
  const std::string data = files.write_csv("", names, columns);
  cli::plot_panel panel{
      .title = fmt::format("Running Lyapunov {} of the {}-link chain ({}, re-orthonormalised every "
                           "{:.3g} s)",
                           maximal ? "exponent" : "exponents", c.links(), r.method,
                           r.renormalisation_interval),
      .xlabel = "averaging time t (s)",
      .ylabel = "λ_i(t) (1/s)",
      .log_x = true,
      .commands = {"set xzeroaxis lt -1 lw 1", "set key outside right top"}};
  // The y range of the second half of the run, where the values converge: the first
  // renormalisations swing far wider.
  double largest = 0;
  for (std::size_t j = 0; j < r.history_t.size(); ++j)
    if (r.history_t[j] - r.transient >= 0.5 * r.averaging_time)
      for (double v : r.history[j]) largest = std::max(largest, std::fabs(v));
  if (largest > 0) panel.yrange = fmt::format("[{}:{}]", -1.6 * largest, 1.6 * largest);
  for (std::size_t i = 0; i < r.exponents.size(); ++i)
    panel.curves.push_back({data, fmt::format("($1-{}):{}", r.transient, i + 2), "lines lw 1.5",
                            fmt::format("λ_{{{}}} = {:.4g}", i + 1, r.exponents[i])});
  files.write_plot(
      {.description = {fmt::format("npend lyapunov: running exponents of the {}-link chain",
                                   c.links()),
                       fmt::format("data: {} (t, lambda_1..)", data)},
       .panels = {panel}});
}

int run_lyapunov(const lyapunov_command_options& o) {
  const chain c = o.chain.make_chain();
  const std::vector<double> x0 = o.start.make_state(c);
  const lyapunov_options options = make_options(o);
  series_output files(o.out);

  cli::interrupt_guard interrupt;
  cli::progress_bar progress(options.integration.t_start, options.integration.t_end);
  const auto observer = [&](double t, std::span<const double>) {
    progress.update(t);
    return interrupt.interrupted() ? observer_action::stop : observer_action::proceed;
  };
  lyapunov_result r;
  try {
    r = o.maximal ? maximal_lyapunov_exponent(c, x0, options, observer)
                  : lyapunov_spectrum(c, x0, options, observer);
  } catch (const std::invalid_argument& e) {
    // What the options above cannot see, e.g. a transient that rounds up to --t-end.
    throw cli::input_error(e.what());
  }
  progress.finish();
  if (r.stopped) {
    fmt::print(stderr, "npend lyapunov: interrupted at t = {} s\n", r.t);
    return 128 + interrupt.signal();
  }
  if (files.enabled()) write_files(files, r, c, o.maximal);

  const double window = options.convergence_fraction * r.averaging_time;
  if (o.json) {
    nlohmann::json j;
    j["links"] = c.links();
    j["masses"] = c.parameters().masses;
    j["lengths"] = c.parameters().lengths;
    j["g"] = c.parameters().g;
    j["initial_state"] = x0;
    j["energy"] = c.hamiltonian(x0);
    j["stepper"] = std::string(stepper_name(options.integration.stepper));
    j["method"] = r.method;
    j["dt"] = options.integration.dt;
    j["t_end"] = r.t;
    j["transient"] = r.transient;
    j["renormalisation_interval"] = r.renormalisation_interval;
    j["renormalisations"] = r.renormalisations;
    j["exponents"] = r.exponents;
    j["maximal_exponent"] = r.exponents.front();
    if (!o.maximal) {
      j["sum"] = r.sum;
      j["pair_sums"] = pair_sums(r.exponents);
    }
    j["spread"] = numbers(r.spread);
    j["convergence_window"] = window;
    j["max_rel_energy_error"] = r.max_rel_energy_error;
    files.add_to(j);
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  fmt::print("{} of the {}-link chain from x0 = [{:.6g}] (E = {:.6g} J)\n",
             o.maximal ? "Maximal Lyapunov exponent" : "Lyapunov spectrum", c.links(),
             fmt::join(x0, ", "), c.hamiltonian(x0));
  fmt::print("{}, dt = {} s, averaged over t = {} ... {} s; {}, re-orthonormalised every {} s\n\n",
             stepper_name(options.integration.stepper), options.integration.dt, r.transient, r.t,
             r.method, r.renormalisation_interval);
  fmt::print("{:>4}  {:>16}  {:>22}\n", "i", "lambda_i (1/s)",
             fmt::format("spread (last {:.3g} s)", window));
  for (std::size_t i = 0; i < r.exponents.size(); ++i)
    fmt::print("{:>4}  {:>16.6g}  {:>22.3g}\n", i + 1, r.exponents[i], r.spread[i]);
  if (!o.maximal) {
    fmt::print("\nsum = {:.3g} (0 for a Hamiltonian flow: div f = 0)\n", r.sum);
    fmt::print("pairs lambda_i + lambda_(2n+1-i) = {::.3g}\n", pair_sums(r.exponents));
  }
  fmt::print("max |H - H0| / H0 = {:.2g}\n", r.max_rel_energy_error);
  files.print();
  return 0;
}

}  // namespace

void add_lyapunov_command(CLI::App& app, command_list& commands) {
  auto o = std::make_shared<lyapunov_command_options>();
  CLI::App* cmd = app.add_subcommand(
      "lyapunov", "Lyapunov spectrum (or the maximal exponent) of a trajectory, with convergence");
  o->chain.add_to(*cmd);
  o->start.add_to(*cmd);
  o->integrator.add_to(*cmd);
  cmd->add_option("--transient", o->transient,
                  "Integrate this long (s) before averaging starts (default: 0)");
  cmd->add_option("--renormalise-every", o->renormalise,
                  "Re-orthonormalise the tangent vectors every this many s, rounded to whole "
                  "steps (default: 0.1)");
  cmd->add_option("--convergence-fraction", o->fraction,
                  "The spread of the running values is taken over this last fraction of the "
                  "averaging time (default: 0.25)");
  cmd->add_flag("--maximal", o->maximal,
                "Only the maximal exponent, from one tangent vector (cheaper)");
  cmd->add_flag("--json", o->json, "Print JSON");
  cmd->add_option("--out", o->out,
                  "Write the running values to FILE.csv (t, lambda_1..) and their plot FILE.png "
                  "with its gnuplot script FILE.gp");
  commands.push_back({cmd, [o] { return run_lyapunov(*o); }});
}

}  // namespace npend::app
