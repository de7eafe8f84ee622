// npend lyapunov: the Lyapunov spectrum (or the maximal exponent) of a trajectory, with its
// uncertainty (paper §6.5.1) — or, with --input, the maximal exponent of a measured time series
// by Kantz's method.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cmath>
#include <iostream>
#include <nlohmann/json.hpp>
#include <numeric>
#include <optional>

#include "chain_options.hpp"
#include "command.hpp"
#include "csv_table.hpp"
#include "input_parsing.hpp"
#include "integrator_options.hpp"
#include "npend/analysis/chaos/lyapunov.hpp"
#include "npend/analysis/series/delay_embedding.hpp"
#include "npend/analysis/series/series_lyapunov.hpp"
#include "series_output.hpp"
#include "start_options.hpp"
#include "terminal_run.hpp"
#include "time_series_source.hpp"
#include "work_estimate.hpp"

namespace npend::app {

namespace {

struct lyapunov_command_options {
  cli::chain_options chain;
  cli::start_options start;
  cli::integrator_options integrator;
  std::string transient, renormalise, fraction;
  std::string ensemble, ensemble_radius, seed, blocks, exponents;
  bool maximal = false;
  bool json = false;
  std::string out;
  // A measured series (--input).
  std::string input, column, tau = "auto", dim, theiler, horizon, fit, radii;
  const CLI::App* command = nullptr;
};

constexpr std::size_t min_series_samples = 64;

bool given(const lyapunov_command_options& o, const char* name) {
  const CLI::Option* option = o.command->get_option_no_throw(name);
  return option != nullptr && option->count() > 0;
}

lyapunov_options make_options(const lyapunov_command_options& o) {
  lyapunov_options l;
  l.integration = o.integrator.make();
  if (!serves(l.integration.stepper, stepper_use::variational))
    throw cli::input_error(fmt::format(
        "--stepper: {} cannot integrate the variational equations ({}); use one of {} (default "
        "gauss6)",
        stepper_name(l.integration.stepper), variational_refusal(l.integration.stepper),
        stepper_names(stepper_use::variational)));
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
  if (!o.blocks.empty())
    l.blocks = static_cast<std::size_t>(cli::parse_whole_number(o.blocks, "--blocks", 2, 1000));
  return l;
}

// JSON numbers, with NaN (a spread that could not be estimated) as null.
nlohmann::json numbers(const std::vector<double>& values) {
  nlohmann::json out = nlohmann::json::array();
  for (double v : values) out.push_back(std::isfinite(v) ? nlohmann::json(v) : nlohmann::json());
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

// What the run will cost, before it starts: integrating k tangent vectors of dimension d = 2n
// along the trajectory, and re-orthonormalising them. Gauss–Legendre (s stages) solves its
// implicit stages with dense (s d) x (s d) Newton matrices, O(d³) per step whatever k; the
// explicit steppers evaluate J W per stage, O(n k) on the loop kernels (which apply J to a
// vector without forming it) and O(d² k) on the unrolled ones.
cli::work_estimate lyapunov_cost(const chain& c, const lyapunov_options& l, double k,
                                 double members) {
  const double n = c.links(), d = 2 * n;
  const integration_options& o = l.integration;
  const double steps = std::ceil(o.t_end / o.dt - 1e-9);
  const double chunk = std::max(1.0, std::round(l.renormalisation_interval / o.dt));
  const double qr = 4 * d * k * k;  // Householder QR of W and its Q, per chunk
  double bytes = 0, step = 0;
  if (o.stepper == stepper_kind::gauss4 || o.stepper == stepper_kind::gauss6) {
    const double s = o.stepper == stepper_kind::gauss6 ? 3 : 2, S = s * d;
    bytes = 8 * (4 * S * S + d * d + 4 * d * k);
    step = 2 * (2.0 / 3.0) * S * S * S + 2 * S * S * k + s * d * d * (1 + 2 * k);
  } else {
    const double stages = o.stepper == stepper_kind::rk4      ? 4
                          : o.stepper == stepper_kind::dopri5 ? 7
                          : o.stepper == stepper_kind::rkf78  ? 13
                                                              : 30;
    bytes = 8 * ((c.runs_on_loops() ? 0 : d * d) + (stages + 4) * d * (k + 1));
    step = stages * (c.runs_on_loops() ? 100 * n * (k + 1) : d * d * (1 + 2 * k));
  }
  return {.bytes = bytes,
          .flops = members * (steps * step + steps / chunk * qr),
          .flops_per_step = std::max(step, qr)};
}

// "± x (what it is)" for the text output.
std::string uncertainty_label(bool ensemble, std::size_t count, double length) {
  return ensemble ? fmt::format(
                        "standard error of the mean over an ensemble of {} nearby starts "
                        "on the same energy surface",
                        count)
                  : fmt::format(
                        "standard error from {} blocks of {:.4g} s of the run (block "
                        "exponents' standard deviation / sqrt({}))",
                        count, length, count);
}

// What run_equations computes: the maximal exponent, the K largest or the spectrum, of one
// start or of an ensemble of nearby ones.
struct exponent_request {
  std::optional<int> count;  // --exponents K
  bool full = false;         // the whole spectrum
  std::optional<lyapunov_ensemble_options> ensemble;
};

// --exponents, --ensemble, --ensemble-radius and --seed, checked against each other.
exponent_request parse_exponent_request(const lyapunov_command_options& o, const chain& c) {
  exponent_request q;
  if (!o.exponents.empty()) {
    if (o.maximal) throw cli::input_error("--exponents: give --exponents K or --maximal, not both");
    if (!o.ensemble.empty())
      throw cli::input_error(
          "--exponents: not with --ensemble (an ensemble takes the full "
          "spectrum or --maximal)");
    q.count =
        static_cast<int>(cli::parse_whole_number(o.exponents, "--exponents", 1, 2.0 * c.links()));
  }
  q.full = !o.maximal && !q.count;
  if (!o.ensemble.empty()) {
    auto& ensemble = q.ensemble.emplace();
    ensemble.members =
        static_cast<std::size_t>(cli::parse_whole_number(o.ensemble, "--ensemble", 2, 10000));
    ensemble.maximal = o.maximal;
    if (!o.ensemble_radius.empty()) {
      ensemble.radius = cli::parse_number(o.ensemble_radius, "--ensemble-radius");
      if (!(ensemble.radius > 0 && ensemble.radius <= 0.1))
        throw cli::input_error(
            fmt::format("--ensemble-radius: must be in (0, 0.1] rad, got {}", o.ensemble_radius));
    }
    if (!o.seed.empty())
      ensemble.seed =
          static_cast<std::uint64_t>(cli::parse_whole_number(o.seed, "--seed", 0, 9.0e15));
  } else {
    for (const char* name : {"--ensemble-radius", "--seed"})
      if (given(o, name)) throw cli::input_error(fmt::format("{}: only with --ensemble K", name));
  }
  return q;
}

// Refuses a run too large for the machine before it starts (cli::require_feasible).
void check_exponent_cost(const lyapunov_command_options& o, const chain& c,
                         const lyapunov_options& options, const exponent_request& q) {
  const double vectors = o.maximal ? 1.0 : q.count ? *q.count : 2.0 * c.links();
  cli::require_feasible(
      lyapunov_cost(c, options, vectors, q.ensemble ? static_cast<double>(q.ensemble->members) : 1),
      fmt::format("{} of {} links by {}{}",
                  o.maximal ? "the maximal exponent"
                  : q.count ? fmt::format("the {} largest exponents", *q.count)
                            : fmt::format("the spectrum ({} exponents)", 2 * c.links()),
                  c.links(), stepper_name(options.integration.stepper),
                  q.ensemble ? fmt::format(" for {} starts", q.ensemble->members) : ""),
      "for a long chain take --maximal or --exponents K with an explicit stepper (--stepper "
      "rk4), which costs O(n K) per step");
}

// The run's exponents and their uncertainty, as reported: an ensemble's mean and standard
// error, or one run's with its blocks' standard error.
struct exponent_report {
  std::vector<double> exponents, errors;
  std::size_t blocks = 0;
  double block_length = 0, window = 0;
  std::string label;
};

exponent_report report_of(const lyapunov_result& r, const lyapunov_ensemble_result& e,
                          const exponent_request& q, const lyapunov_options& options) {
  exponent_report out;
  out.exponents = q.ensemble ? e.mean : r.exponents;
  out.errors = q.ensemble ? e.standard_error : r.block_standard_error;
  out.blocks = r.block_exponents.size();
  out.block_length = out.blocks > 0 ? r.averaging_time / static_cast<double>(out.blocks) : 0;
  out.label = q.ensemble ? uncertainty_label(true, e.runs.size(), 0)
                         : uncertainty_label(false, out.blocks, out.block_length);
  out.window = options.convergence_fraction * r.averaging_time;
  return out;
}

void print_exponents_json(const chain& c, const std::vector<double>& x0,
                          const lyapunov_options& options, const lyapunov_result& r,
                          const lyapunov_ensemble_result& e, const exponent_request& q,
                          const exponent_report& p, const series_output& files) {
  nlohmann::json j = describe_chain(c);
  j["initial_state"] = x0;
  j["energy"] = c.hamiltonian(x0);
  j["stepper"] = std::string(stepper_name(options.integration.stepper));
  j["method"] = r.method;
  j["dt"] = options.integration.dt;
  j["t_end"] = r.t;
  j["transient"] = r.transient;
  j["renormalisation_interval"] = r.renormalisation_interval;
  j["renormalisations"] = r.renormalisations;
  j["exponents"] = p.exponents;
  j["maximal_exponent"] = p.exponents.front();
  j["standard_errors"] = numbers(p.errors);
  j["uncertainty"] =
      std::isfinite(p.errors.front()) ? nlohmann::json(p.errors.front()) : nlohmann::json();
  j["uncertainty_method"] = q.ensemble ? "ensemble standard error" : "block standard error";
  j["uncertainty_description"] = p.label;
  if (q.full) {
    j["sum"] = std::accumulate(p.exponents.begin(), p.exponents.end(), 0.0);
    j["pair_sums"] = pair_sums(p.exponents);
  }
  j["spread"] = numbers(r.spread);
  j["convergence_window"] = p.window;
  j["blocks"] = {{"count", p.blocks},
                 {"length", p.block_length},
                 {"exponents", r.block_exponents},
                 {"standard_errors", numbers(r.block_standard_error)}};
  if (q.ensemble) {
    nlohmann::json runs = nlohmann::json::array();
    for (const auto& run : e.runs) runs.push_back(run.exponents);
    j["ensemble"] = {{"members", e.runs.size()},
                     {"radius", q.ensemble->radius},
                     {"seed", q.ensemble->seed},
                     {"starts", e.starts},
                     {"exponents", runs},
                     {"mean", e.mean},
                     {"standard_deviation", numbers(e.standard_deviation)},
                     {"standard_error", numbers(e.standard_error)}};
  }
  j["max_rel_energy_error"] = r.max_rel_energy_error;
  files.add_to(j);
  std::cout << j.dump(2) << "\n";
}

void print_exponents_text(const lyapunov_command_options& o, const chain& c,
                          const std::vector<double>& x0, const lyapunov_options& options,
                          const lyapunov_result& r, const lyapunov_ensemble_result& e,
                          const exponent_request& q, const exponent_report& p,
                          const series_output& files) {
  fmt::print("{} of the {}-link chain from x0 = [{:.6g}] (E = {:.6g} J)\n",
             o.maximal ? "Maximal Lyapunov exponent"
             : q.count ? fmt::format("The {} largest Lyapunov exponents", *q.count)
                       : std::string("Lyapunov spectrum"),
             c.links(), fmt::join(x0, ", "), c.hamiltonian(x0));
  fmt::print("{}, dt = {} s, averaged over t = {} ... {} s; {}, re-orthonormalised every {} s\n",
             stepper_name(options.integration.stepper), options.integration.dt, r.transient, r.t,
             r.method, r.renormalisation_interval);
  if (q.ensemble)
    fmt::print(
        "ensemble: {} starts (x0 and {} others, angles moved by {:g} rad, back on H = H(x0)); "
        "lambda_i is their mean\n",
        e.runs.size(), e.runs.size() - 1, q.ensemble->radius);
  fmt::print("+- is the {}\n\n", p.label);
  fmt::print("{:>4}  {:>16}  {:>12}  {:>22}\n", "i", "lambda_i (1/s)", "+-",
             fmt::format("spread{} (last {:.3g} s)", q.ensemble ? " of x0's run" : "", p.window));
  for (std::size_t i = 0; i < p.exponents.size(); ++i)
    fmt::print("{:>4}  {:>16.6g}  {:>12.3g}  {:>22.3g}\n", i + 1, p.exponents[i], p.errors[i],
               r.spread[i]);
  if (q.ensemble)
    fmt::print("\nsingle runs scatter by (standard deviation): [{::.3g}]\n", e.standard_deviation);
  if (q.full) {
    fmt::print("\nsum = {:.3g} (0 for a Hamiltonian flow: div f = 0)\n",
               std::accumulate(p.exponents.begin(), p.exponents.end(), 0.0));
    fmt::print("pairs lambda_i + lambda_(2n+1-i) = {::.3g}\n", pair_sums(p.exponents));
  }
  fmt::print("max |H - H0| / H0 = {:.2g}\n", r.max_rel_energy_error);
  files.print();
}

int run_equations(const lyapunov_command_options& o) {
  for (const char* name :
       {"--column", "--tau", "--dim", "--theiler", "--horizon", "--fit", "--radius"})
    if (given(o, name))
      throw cli::input_error(
          fmt::format("{}: only for a measured series (--input F.csv), not with --links", name));
  if (o.integrator.t_end.empty())
    throw cli::input_error("--t-end is required with --links (see npend lyapunov --help)");
  const chain c =
      o.chain.make_chain(cli::model_support::conservative, "npend lyapunov", /*takes_cart=*/true);
  const std::vector<double> x0 = o.start.make_state(c);
  lyapunov_options options = make_options(o);
  const exponent_request q = parse_exponent_request(o, c);
  check_exponent_cost(o, c, options, q);
  series_output files(o.out);

  cli::terminal_run control;
  options.integration.control = &control;
  lyapunov_result r;
  lyapunov_ensemble_result e;
  try {
    if (q.ensemble) {
      e = lyapunov_ensemble(c, x0, options, *q.ensemble);
      if (!e.stopped) r = e.runs.front();
    } else {
      r = o.maximal ? maximal_lyapunov_exponent(c, x0, options)
          : q.count ? largest_lyapunov_exponents(c, x0, options, *q.count)
                    : lyapunov_spectrum(c, x0, options);
    }
  } catch (const std::invalid_argument& error) {
    // What the options above cannot see, e.g. a transient that rounds up to --t-end.
    throw cli::input_error(error.what());
  }
  control.finish();
  if (r.stopped || e.stopped) {
    fmt::print(stderr, "npend lyapunov: interrupted at t = {} s{}\n", r.stopped ? r.t : 0.0,
               e.stopped ? fmt::format(" of ensemble member {}", e.runs.size() + 1) : "");
    return control.exit_code();
  }
  if (files.enabled()) write_files(files, r, c, r.exponents.size() == 1);
  const exponent_report p = report_of(r, e, q, options);
  if (o.json)
    print_exponents_json(c, x0, options, r, e, q, p, files);
  else
    print_exponents_text(o, c, x0, options, r, e, q, p, files);
  return 0;
}

// --fit a:b (s).
std::pair<double, double> fit_range(const std::string& text) {
  const auto colon = text.find(':');
  if (colon == std::string::npos)
    throw cli::input_error(fmt::format("--fit: '{}' is not FROM:TO (seconds)", text));
  const double from = cli::parse_number(text.substr(0, colon), "--fit");
  const double to = cli::parse_number(text.substr(colon + 1), "--fit");
  if (!(from >= 0 && to > from))
    throw cli::input_error(fmt::format("--fit: '{}' needs 0 <= FROM < TO", text));
  return {from, to};
}

// --column: one selector, or several separated by commas (none: the default signal).
std::vector<std::string> column_list(const std::string& text) {
  std::vector<std::string> out;
  for (const std::string_view piece : cli::split_list(text)) out.emplace_back(piece);
  if (out.size() > 1)
    for (const auto& c : out)
      if (c.empty()) throw cli::input_error(fmt::format("--column: an empty name in '{}'", text));
  return out;
}

// The options of the equations, refused with --input.
void refuse_equation_options(const lyapunov_command_options& o) {
  for (const char* name : {"--masses",
                           "--lengths",
                           "--g",
                           "--phi",
                           "--p",
                           "--dphi",
                           "--energy",
                           "--excitation",
                           "--t-end",
                           "--stepper",
                           "--abs-tol",
                           "--rel-tol",
                           "--tol",
                           "--transient",
                           "--renormalise-every",
                           "--convergence-fraction",
                           "--maximal",
                           "--exponents",
                           "--ensemble",
                           "--ensemble-radius",
                           "--seed",
                           "--blocks"})
    if (given(o, name))
      throw cli::input_error(
          fmt::format("{}: only for the equations (--links N), not with --input", name));
}

// What --input's options ask for, checked before the file is read.
struct series_request {
  std::optional<double> spacing;       // --dt
  std::vector<std::string> selectors;  // --column
  std::optional<std::size_t> dimension;
  std::optional<std::pair<double, double>> fit;
  std::vector<double> radii;
};

series_request parse_series_request(const lyapunov_command_options& o) {
  series_request q;
  if (!o.integrator.dt.empty()) {
    q.spacing = cli::parse_number(o.integrator.dt, "--dt");
    if (!(*q.spacing > 0))
      throw cli::input_error(fmt::format("--dt: must be positive, got {}", o.integrator.dt));
  }
  q.selectors = column_list(o.column);
  if (!o.dim.empty())
    q.dimension = static_cast<std::size_t>(cli::parse_whole_number(o.dim, "--dim", 1, 20));
  if (!o.fit.empty()) q.fit = fit_range(o.fit);
  if (!o.radii.empty()) {
    q.radii = cli::parse_number_list(o.radii, "--radius");
    for (double r : q.radii)
      if (!(r > 0)) throw cli::input_error(fmt::format("--radius: must be positive, got {}", r));
  }
  return q;
}

// The measured series: the first selected column, and with several columns all of them
// standardised side by side (observables in different units: each in units of its standard
// deviation).
struct measured_series {
  time_series x;
  std::vector<std::vector<double>> observables;  // empty for one column
};

measured_series load_measured_series(const lyapunov_command_options& o, const series_request& q) {
  const std::string text = cli::read_text_file(o.input, "--input");
  const sampled_signals signals =
      cli::signals_from_csv(cli::parse_csv(text, o.input), o.input, q.spacing, min_series_samples);
  std::vector<time_series> chosen;
  for (const auto& selector : q.selectors)
    chosen.push_back(cli::select_signal(signals, selector, "--column"));
  measured_series m{chosen.front(), {}};
  if (chosen.size() > 1) {
    for (const auto& c : chosen) m.observables.push_back(c.values);
    try {
      m.observables = standardised_series(m.observables);
    } catch (const std::invalid_argument& e) {
      throw cli::input_error(fmt::format("--column: {}", e.what()));
    }
    std::vector<std::string> names;
    for (const auto& c : chosen) names.push_back(c.name);
    m.x.name = fmt::format("{}", fmt::join(names, ","));
  }
  return m;
}

// τ in samples and how it was found: a rule of npend embed, or seconds.
std::pair<std::size_t, std::string> series_delay(const std::string& text, const time_series& x) {
  const double dt = x.dt;
  if (const auto method = delay_method_from_name(text)) {
    const delay_choice choice = choose_delay(x.values, dt, *method);
    if (!choice.found)
      throw cli::input_error(fmt::format(
          "--tau {}: the series has no such feature (no spectral peak, zero or minimum within "
          "the lags searched); choose another method or give tau in seconds",
          text));
    return {choice.samples, std::string(delay_method_name(choice.method))};
  }
  double seconds = 0;
  try {
    seconds = cli::parse_number(text, "--tau");
  } catch (const cli::input_error&) {
    throw cli::input_error(fmt::format(
        "--tau: '{}' is not auto, T/4, acf-zero, acf-min, ami or a delay in seconds", text));
  }
  const double samples = std::round(seconds / dt);
  if (!(samples >= 1 && samples < static_cast<double>(x.values.size())))
    throw cli::input_error(
        fmt::format("--tau: {} s is not between dt = {:.6g} s and the series' length", text, dt));
  return {static_cast<std::size_t>(samples), "given"};
}

// The library's Kantz options with the choices made on the command line (the library fills
// in the rest).
series_lyapunov_options series_options(const lyapunov_command_options& o, const series_request& q,
                                       const measured_series& m, std::size_t tau) {
  const double dt = m.x.dt;
  kantz_choices choices{.delay = tau, .dimension = q.dimension, .radii = q.radii};
  if (!o.theiler.empty()) {
    const double seconds = cli::parse_number(o.theiler, "--theiler");
    if (!(seconds >= 0)) throw cli::input_error("--theiler: must be at least 0");
    choices.theiler_window = static_cast<std::size_t>(std::round(seconds / dt));
  }
  if (!o.horizon.empty()) {
    const double seconds = cli::parse_number(o.horizon, "--horizon");
    if (!(seconds >= dt))
      throw cli::input_error(fmt::format("--horizon: must be at least dt = {:.6g} s", dt));
    choices.horizon = static_cast<std::size_t>(std::round(seconds / dt));
  }
  const std::size_t columns = std::max<std::size_t>(1, m.observables.size());
  series_lyapunov_options options = kantz_options(m.x.values.size(), columns, choices);
  if (q.fit) {
    const double horizon = static_cast<double>(options.stretching.horizon) * dt;
    if (q.fit->second > horizon * (1 + 1e-12))
      throw cli::input_error(fmt::format("--fit: {} s lies beyond the horizon {:.6g} s (--horizon)",
                                         q.fit->second, horizon));
    options.fit_from = q.fit->first;
    options.fit_to = q.fit->second;
  }
  return options;
}

// The stretching curves (CSV) and their plot with the fitted line.
void write_series_files(series_output& files, const time_series& x, const series_lyapunov_result& r,
                        const std::vector<double>& t, const stretching_options& s) {
  std::vector<std::string> names{"t"};
  std::vector<std::vector<double>> columns{t};
  for (const auto& c : r.stretching.curves) {
    names.push_back(fmt::format("S_eps_{:.4g}", c.radius));
    columns.push_back(c.s);
  }
  const std::string data = files.write_csv("", names, columns);
  cli::plot_panel panel{
      .title = fmt::format("Stretching curve of {} (Kantz; m = {}, tau = {:.4g} s): slope {:.4g} "
                           "+- {:.2g} 1/s over {:.4g} ... {:.4g} s",
                           x.name, s.dimension, static_cast<double>(s.delay) * x.dt,
                           r.maximal_exponent, r.uncertainty, r.fit_from, r.fit_to),
      .xlabel = "Δt (s)",
      .ylabel = "S(Δt) = <ln mean distance>",
      .commands = {fmt::format("set arrow from {0},graph 0 to {0},graph 1 nohead dt 2", r.fit_from),
                   fmt::format("set arrow from {0},graph 0 to {0},graph 1 nohead dt 2", r.fit_to),
                   "set key left top"}};
  for (std::size_t q = 0; q < r.stretching.curves.size(); ++q) {
    panel.curves.push_back({data, fmt::format("1:{}", q + 2), "lines lw 1.5",
                            fmt::format("ε = {:.3g}", r.stretching.curves[q].radius)});
  }
  const auto& f = r.fits[r.fits.size() / 2];
  panel.commands.push_back(fmt::format("f(x) = {} + {} * x", f.intercept, f.slope));
  panel.curves.push_back(
      {data, fmt::format("1:(($1 >= {} && $1 <= {}) ? f($1) : 1/0)", r.fit_from, r.fit_to),
       "lines lw 3 dt 3", fmt::format("fit, slope {:.4g} /s", f.slope)});
  files.write_plot(
      {.description = {fmt::format("npend lyapunov: stretching curves of {}", series_summary(x)),
                       fmt::format("data: {} (t, S for each radius)", data)},
       .panels = {panel}});
}

// How the exponent was measured, for the JSON and the text.
struct series_run {
  const time_series& x;
  const std::vector<std::string>& selectors;
  std::size_t observables;
  const std::string& tau_method;
  const stretching_options& s;
};

void print_series_json(const series_run& run, const series_lyapunov_result& r,
                       const std::vector<double>& t, series_output& files) {
  const stretching_options& s = run.s;
  const double dt = run.x.dt;
  nlohmann::json j = describe_series(run.x);
  j["method"] = "Kantz";
  // Without a linear region the slope is no estimate of the exponent: null, not a number.
  j["maximal_exponent"] = r.linear_region ? nlohmann::json(r.maximal_exponent) : nlohmann::json();
  j["uncertainty"] = r.linear_region ? nlohmann::json(r.uncertainty) : nlohmann::json();
  j["linear_region"] = r.linear_region;
  j["fit_slope"] = r.maximal_exponent;
  j["growth_before_fit"] = r.growth_before_fit;
  j["growth_in_fit"] = r.growth_in_fit;
  j["columns"] = run.selectors;
  j["uncertainty_parts"] = {{"statistical", std::isfinite(r.statistical_uncertainty)
                                                ? nlohmann::json(r.statistical_uncertainty)
                                                : nlohmann::json()},
                            {"radius", r.radius_uncertainty},
                            {"range", r.range_uncertainty}};
  j["fit_range"] = {r.fit_from, r.fit_to};
  j["fit_range_method"] = r.automatic_range ? "automatic" : "given";
  j["tau"] = static_cast<double>(s.delay) * dt;
  j["tau_samples"] = s.delay;
  j["tau_method"] = run.tau_method;
  j["dimension"] = s.dimension;
  j["theiler_window"] = static_cast<double>(s.theiler_window) * dt;
  j["horizon"] = static_cast<double>(s.horizon) * dt;
  j["rise"] = r.rise;
  nlohmann::json fits = nlohmann::json::array(), curve_s = nlohmann::json::array();
  for (std::size_t q = 0; q < r.fits.size(); ++q) {
    const auto& f = r.fits[q];
    const auto& c = r.stretching.curves[q];
    fits.push_back(
        {{"radius", f.radius},
         {"slope", f.slope},
         {"standard_error",
          std::isfinite(f.standard_error) ? nlohmann::json(f.standard_error) : nlohmann::json()},
         {"group_standard_error", std::isfinite(f.group_standard_error)
                                      ? nlohmann::json(f.group_standard_error)
                                      : nlohmann::json()},
         {"references", c.references},
         {"mean_neighbours", c.mean_neighbours}});
    curve_s.push_back(numbers(c.s));
  }
  j["fits"] = fits;
  nlohmann::json radii_json = nlohmann::json::array();
  for (const auto& c : r.stretching.curves) radii_json.push_back(c.radius);
  j["curve"] = {{"t", t}, {"radii", radii_json}, {"s", curve_s}};
  if (!r.warnings.empty()) j["warnings"] = r.warnings;
  files.add_to(j);
  std::cout << j.dump(2) << "\n";
}

void print_series_text(const series_run& run, const series_lyapunov_result& r) {
  const stretching_options& s = run.s;
  const double dt = run.x.dt;
  fmt::print("Maximal Lyapunov exponent of {} (Kantz's method)\n\n", series_summary(run.x));
  fmt::print(
      "delay embedding{}: m = {}, tau = {:.6g} s ({} samples; {}), Theiler window {:.6g} s\n",
      run.observables == 0
          ? std::string()
          : fmt::format(" of {} standardised columns side by side", run.observables),
      s.dimension, static_cast<double>(s.delay) * dt, s.delay, run.tau_method,
      static_cast<double>(s.theiler_window) * dt);
  fmt::print(
      "stretching curve S(dt) up to {:.6g} s; slope fitted over {:.6g} ... {:.6g} s ({})\n\n",
      static_cast<double>(s.horizon) * dt, r.fit_from, r.fit_to,
      r.automatic_range ? "chosen automatically" : "given");
  fmt::print("{:>12}  {:>12}  {:>12}  {:>11}\n", "radius", "slope (1/s)", "references",
             "neighbours");
  for (std::size_t q = 0; q < r.fits.size(); ++q)
    fmt::print("{:>12.4g}  {:>12.5g}  {:>12}  {:>11.3g}\n", r.fits[q].radius, r.fits[q].slope,
               r.stretching.curves[q].references, r.stretching.curves[q].mean_neighbours);
  if (r.linear_region)
    fmt::print("\nmaximal exponent = {:.5g} +- {:.2g} 1/s\n", r.maximal_exponent, r.uncertainty);
  else
    fmt::print(
        "\nno estimate of the maximal exponent (the slope over the fit range is {:.5g} "
        "1/s, but the range is no linear region)\n",
        r.maximal_exponent);
  fmt::print(
      "+- = sqrt(statistical^2 + radius^2 + range^2) = sqrt({:.2g}^2 + {:.2g}^2 + {:.2g}^2): the "
      "slopes' standard error over {} groups of reference points, half the slopes' range over "
      "the radii, and half the difference of the slopes over the two halves of the fit range\n",
      r.statistical_uncertainty, r.radius_uncertainty, r.range_uncertainty, s.groups);
  for (const auto& note : r.warnings) fmt::print("warning: {}\n", note);
}

int run_series(const lyapunov_command_options& o) {
  refuse_equation_options(o);
  const series_request request = parse_series_request(o);
  series_output files(o.out);
  const measured_series m = load_measured_series(o, request);
  const auto [tau, tau_method] = series_delay(o.tau, m.x);
  const series_lyapunov_options options = series_options(o, request, m, tau);
  series_lyapunov_result r;
  try {
    r = m.observables.empty() ? series_lyapunov_exponent(m.x.values, m.x.dt, options)
                              : series_lyapunov_exponent(m.observables, m.x.dt, options);
  } catch (const std::invalid_argument& e) {
    throw cli::input_error(e.what());
  }
  std::vector<double> t;
  for (std::size_t k : r.stretching.steps) t.push_back(static_cast<double>(k) * m.x.dt);
  if (files.enabled()) write_series_files(files, m.x, r, t, options.stretching);
  const series_run run{m.x, request.selectors, m.observables.size(), tau_method,
                       options.stretching};
  if (o.json) {
    print_series_json(run, r, t, files);
    return 0;
  }
  print_series_text(run, r);
  files.print();
  return 0;
}

int run_lyapunov(const lyapunov_command_options& o) {
  const bool from_file = !o.input.empty();
  if (from_file && o.chain.links != 0)
    throw cli::input_error(
        "--input and --links exclude each other: a measured series or the equations");
  if (from_file) return run_series(o);
  if (!given(o, "--links"))
    throw cli::input_error(
        "--links is required (or --input F.csv for a measured series; see npend lyapunov "
        "--help)");
  return run_equations(o);
}

}  // namespace

void add_lyapunov_command(CLI::App& app, command_list& commands) {
  auto o = std::make_shared<lyapunov_command_options>();
  CLI::App* cmd = app.add_subcommand(
      "lyapunov",
      "Lyapunov spectrum (or the maximal exponent) of a trajectory with its uncertainty, or the "
      "maximal exponent of a measured series (--input)");
  o->command = cmd;
  o->chain.add_to(*cmd, false);
  o->start.add_to(*cmd);
  cmd->add_option("--t-end", o->integrator.t_end, "Integrate from t = 0 to this time in s");
  cmd->add_option("--dt", o->integrator.dt,
                  "Output step in s (default: 0.001); with --input the sample spacing (needed "
                  "without a time column)");
  o->integrator.add_stepper_options(*cmd);
  cmd->add_option("--transient", o->transient,
                  "Integrate this long (s) before averaging starts (default: 0)");
  cmd->add_option("--renormalise-every", o->renormalise,
                  "Re-orthonormalise the tangent vectors every this many s, rounded to whole "
                  "steps (default: 0.1)");
  cmd->add_option("--convergence-fraction", o->fraction,
                  "The spread of the running values is taken over this last fraction of the "
                  "averaging time (default: 0.25)");
  cmd->add_option("--blocks", o->blocks,
                  "Cut the averaging time into this many blocks; the uncertainty without "
                  "--ensemble is their standard error (default: 10)");
  cmd->add_option("--ensemble", o->ensemble,
                  "Run K starts (the given one and K - 1 nearby on the same energy surface); "
                  "report their mean and its standard error");
  cmd->add_option("--ensemble-radius", o->ensemble_radius,
                  "How far (rad) the ensemble's starts are moved from the given one (default: "
                  "1e-6)");
  cmd->add_option("--seed", o->seed, "Seed of the ensemble's random starts (default: 1)");
  cmd->add_flag("--maximal", o->maximal,
                "Only the maximal exponent, from one tangent vector (cheaper)");
  cmd->add_option("--exponents", o->exponents,
                  "Only the K largest exponents, from K tangent vectors (for long chains, where "
                  "all 2n cost O(n) vectors; default: all 2n)");
  cmd->add_option("--input", o->input,
                  "A measured time series: a CSV file (a column per signal, header names, a "
                  "column t or time for the sample times); its maximal exponent by Kantz's "
                  "method");
  cmd->add_option("--column", o->column,
                  "With --input: the signal, a column name or number (default: the first "
                  "signal); several separated by commas embed them together, each standardised "
                  "(then --dim defaults to 1: the observables themselves as coordinates)");
  cmd->add_option("--tau", o->tau,
                  "With --input: the embedding delay, auto, T/4, acf-zero, acf-min, ami or "
                  "seconds (default: auto, as npend embed)");
  cmd->add_option("--dim", o->dim,
                  "With --input: the embedding dimension per column (default: 6; 1 for several "
                  "columns)");
  cmd->add_option("--theiler", o->theiler,
                  "With --input: neighbours closer in time than this (s) are not used "
                  "(default: max(1, dim - 1) tau)");
  cmd->add_option("--horizon", o->horizon,
                  "With --input: the stretching curve's longest time in s (default: 40 tau, at "
                  "most a quarter of the series)");
  cmd->add_option("--fit", o->fit,
                  "With --input: fit the slope over FROM:TO (s) (default: chosen on the curve)");
  cmd->add_option("--radius", o->radii,
                  "With --input: neighbourhood radii eps1,eps2,.. in the signal's unit (default: "
                  "1, 2, 4 times the median nearest-neighbour distance)");
  cmd->add_flag("--json", o->json, "Print JSON");
  cmd->add_option("--out", o->out,
                  "Write the running values (with --input: the stretching curves) to FILE.csv "
                  "and their plot FILE.png with its gnuplot script FILE.gp");
  commands.push_back({cmd, [o] { return run_lyapunov(*o); }});
}

}  // namespace npend::app
