// npend embed: delay coordinates (paper §6.6.4, Abb. 6.13) — the delay τ and the minimal
// embedding dimension of a time series, and its delay vectors.
#include <fmt/format.h>

#include <cmath>
#include <iostream>
#include <nlohmann/json.hpp>

#include "command.hpp"
#include "input_parsing.hpp"
#include "npend/analysis/series/delay_embedding.hpp"
#include "npend/analysis/series/embedding_dimension.hpp"
#include "series_figures.hpp"
#include "series_output.hpp"
#include "time_series_source.hpp"

namespace npend::app {

namespace {

constexpr std::size_t min_embed_samples = 64;

struct embed_options {
  cli::series_options series;
  std::string tau = "auto", dim = "auto", dim_method = "fnn", theiler;
  std::size_t max_dim = 10;
  std::size_t bins = 16;
  std::string mi_estimator = "tisean";
  double rtol = 15, atol = 2;
  std::size_t references = 4000;
  bool json = false;
  std::string out;
  const CLI::App* command = nullptr;

  bool given(const char* name) const { return command->count(name) > 0; }
};

// τ from --tau: a method name, or a delay in seconds.
delay_choice delay_from_option(const std::string& text, const time_series& x,
                               const mutual_information_options& information) {
  if (const auto method = delay_method_from_name(text)) {
    const delay_choice c = choose_delay(x.values, x.dt, *method, information);
    if (!c.found)
      throw cli::input_error(fmt::format(
          "--tau {}: the series has no such feature (no spectral peak, zero or minimum within "
          "the lags searched); choose another method or give tau in seconds",
          text));
    return c;
  }
  double seconds = 0;
  try {
    seconds = cli::parse_number(text, "--tau");
  } catch (const cli::input_error&) {
    throw cli::input_error(fmt::format(
        "--tau: '{}' is not auto, T/4, acf-zero, acf-min, ami or a delay in seconds", text));
  }
  const double samples = std::round(seconds / x.dt);
  if (!(samples >= 1 && samples < static_cast<double>(x.values.size())))
    throw cli::input_error(
        fmt::format("--tau: {} s is not between dt = {:.6g} s and the series' length", text, x.dt));
  delay_choice c;
  c.found = true;
  c.estimate = seconds;
  c.samples = static_cast<std::size_t>(samples);
  c.seconds = samples * x.dt;
  return c;
}

// The options checked before any work is done.
std::optional<std::size_t> checked_fixed_dimension(const embed_options& o) {
  if (o.dim_method != "fnn" && o.dim_method != "cao")
    throw cli::input_error(fmt::format("--dim-method: '{}' is not fnn or cao", o.dim_method));
  if (o.max_dim < 2 || o.max_dim > 20)
    throw cli::input_error(fmt::format("--max-dim: must be 2..20, got {}", o.max_dim));
  if (o.bins < 2 || o.bins > 1024)
    throw cli::input_error(fmt::format("--bins: must be 2..1024, got {}", o.bins));
  if (!mutual_information_estimator_from_name(o.mi_estimator))
    throw cli::input_error(
        fmt::format("--mi-estimator: '{}' is not tisean or averaged", o.mi_estimator));
  if (!(o.rtol > 0) || !std::isfinite(o.rtol))
    throw cli::input_error(fmt::format("--rtol: must be positive, got {}", o.rtol));
  if (!(o.atol > 0) || !std::isfinite(o.atol))
    throw cli::input_error(fmt::format("--atol: must be positive, got {}", o.atol));
  // Options that cannot take effect are refused rather than silently ignored.
  const auto method = delay_method_from_name(o.tau);
  const bool information_used =
      method ? *method == delay_method::automatic || *method == delay_method::mutual_information
             : o.tau.empty() || o.tau.find_first_of("0123456789") == std::string::npos;
  if (!information_used)
    for (const char* name : {"--bins", "--mi-estimator"})
      if (o.given(name))
        throw cli::input_error(fmt::format(
            "{}: only for the mutual-information delay (--tau ami or auto), not with --tau {}",
            name, o.tau));
  if (o.dim == "auto") return std::nullopt;
  const double k = cli::parse_number(o.dim, "--dim");
  if (!cli::is_whole_number(k, 1, 20))
    throw cli::input_error(fmt::format("--dim: '{}' is not auto or a dimension 1..20", o.dim));
  for (const char* name :
       {"--max-dim", "--dim-method", "--rtol", "--atol", "--references", "--theiler"})
    if (o.given(name))
      throw cli::input_error(fmt::format(
          "{}: only for the dimension scan (--dim auto), not with --dim {}", name, o.dim));
  return static_cast<std::size_t>(k);
}

std::string delay_description(const embed_options& o, const delay_choice& tau) {
  return delay_method_from_name(o.tau)
             ? fmt::format("{} estimate {:.6g} s", delay_method_name(tau.method), tau.estimate)
             : std::string("given");
}

nlohmann::json nullable(bool present, const std::vector<double>& values) {
  return present ? nlohmann::json(values) : nlohmann::json();
}

int run_embed(const embed_options& o) {
  const std::optional<std::size_t> fixed_dim = checked_fixed_dimension(o);
  series_output files(o.out);
  const time_series x = o.series.load_one(min_embed_samples);
  const delay_choice tau = delay_from_option(
      o.tau, x,
      {.bins = o.bins, .estimator = *mutual_information_estimator_from_name(o.mi_estimator)});
  std::size_t theiler = tau.samples;
  if (!o.theiler.empty()) {
    const double seconds = cli::parse_number(o.theiler, "--theiler");
    if (!(seconds >= 0)) throw cli::input_error("--theiler: must be at least 0");
    theiler = static_cast<std::size_t>(std::round(seconds / x.dt));
  }
  // What the delay step found is part of every later error: a failing dimension step must
  // not lose it (finding it may have taken the longest).
  const std::string tau_found =
      delay_method_from_name(o.tau)
          ? fmt::format("; tau = {:.6g} s ({}) was found: pass --tau {:.6g} to keep it",
                        tau.seconds, delay_description(o, tau), tau.seconds)
          : std::string();

  // A given dimension needs no scan over dimensions.
  const bool scanned = !fixed_dim;
  false_neighbours_result fnn;
  cao_result cao;
  if (scanned) {
    try {
      fnn = false_nearest_neighbours(x.values, tau.samples, o.max_dim,
                                     {.distance_ratio = o.rtol,
                                      .attractor_ratio = o.atol,
                                      .theiler_window = theiler,
                                      .reference_points = o.references});
      cao = cao_embedding(x.values, tau.samples, o.max_dim,
                          {.theiler_window = theiler, .reference_points = o.references});
    } catch (const std::invalid_argument& e) {
      // The one data-dependent failure: too short a series for --max-dim at this τ.
      throw cli::input_error(fmt::format("--max-dim: {}{}", e.what(), tau_found));
    }
  }
  const bool by_cao = o.dim_method == "cao";
  const bool found = fixed_dim || (by_cao ? cao.found : fnn.found);
  const std::size_t dimension = fixed_dim ? *fixed_dim
                                : found   ? (by_cao ? cao.dimension : fnn.dimension)
                                          : 0;
  // The delay vectors written and plotted: in the dimension found, at least 2 for the plot.
  const std::size_t shown = std::max<std::size_t>(2, found ? dimension : o.max_dim);
  if (x.values.size() <= (shown - 1) * tau.samples)
    throw cli::input_error(fmt::format(
        "--dim: delay vectors of dimension {} at tau = {} samples need more than {} samples, "
        "the series has {}{}",
        shown, tau.samples, (shown - 1) * tau.samples, x.values.size(), tau_found));
  const delay_vectors v = delay_embedding(x.values, tau.samples, shown);
  const bool has_information = !tau.mutual_information.lag.empty();

  if (files.enabled()) {
    cli::figure figure{
        .description = {fmt::format("npend embed: delay coordinates of {}", series_summary(x)),
                        fmt::format("data: {} (delay vectors)", files.file_name(""))},
        .width = 650,
        .height = 620,
        .columns = 1,
        .panels = {delay_plot_panel(files, "", x, tau, v)}};
    if (scanned) {
      figure.panels.push_back(
          embedding_dimension_panel(files, "dimension", fnn, cao,
                                    found ? std::optional(dimension) : std::nullopt, o.dim_method));
      figure.description.push_back(
          fmt::format("dimension criteria: {}", files.file_name("dimension")));
    }
    if (has_information) {
      figure.panels.push_back(mutual_information_panel(files, "ami", x, tau.mutual_information));
      figure.description.push_back(fmt::format("mutual information: {}", files.file_name("ami")));
    }
    figure.columns = static_cast<int>(figure.panels.size());
    figure.width = 650 * figure.columns;
    files.write_plot(figure);
  }

  if (o.json) {
    nlohmann::json j = describe_series(x);
    j.update(
        {{"tau", tau.seconds},
         {"tau_samples", tau.samples},
         {"tau_method", delay_method_from_name(o.tau) ? delay_method_name(tau.method) : "given"},
         {"dimension", found ? nlohmann::json(dimension) : nlohmann::json()},
         {"dimension_method", fixed_dim ? "given" : o.dim_method},
         {"theiler_window", static_cast<double>(theiler) * x.dt},
         {"false_neighbours", nullable(scanned, fnn.fraction)},
         {"false_neighbours_distance", nullable(scanned, fnn.fraction_distance)},
         {"false_neighbours_attractor", nullable(scanned, fnn.fraction_attractor)},
         {"false_neighbours_options",
          {{"rtol", o.rtol}, {"atol", o.atol}, {"reference_points", o.references}}},
         {"cao_e1", nullable(scanned, cao.e1)},
         {"cao_e2", nullable(scanned, cao.e2)},
         {"vectors", v.count}});
    if (has_information) {
      const auto& ami = tau.mutual_information;
      j["mutual_information"] = {
          {"bins", o.bins},
          {"estimator", o.mi_estimator},
          {"minimum_window", ami.window},
          {"tau", ami.lag},
          {"information", ami.information},
          {"first_minimum",
           ami.first_minimum ? nlohmann::json(*ami.first_minimum) : nlohmann::json()}};
    }
    files.add_to(j);
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  fmt::print("Delay embedding of {}\n\n", series_summary(x));
  fmt::print("delay tau = {:.6g} s ({} samples; {})\n", tau.seconds, tau.samples,
             delay_description(o, tau));
  if (has_information)
    fmt::print("mutual information ({} bins, {} estimator): evaluated on lags up to {:.6g} s{}\n",
               o.bins, o.mi_estimator, tau.mutual_information.lag.back(),
               tau.mutual_information.first_minimum
                   ? fmt::format(", first local minimum at {:.6g} s",
                                 *tau.mutual_information.first_minimum)
                   : std::string(", no local minimum"));
  if (scanned) {
    fmt::print("\n{:>4}  {:>16}  {:>10}  {:>10}  {:>10}  {:>10}\n", "m", "false neighbours",
               "by R_tol", "by A_tol", "Cao E1", "Cao E2");
    for (std::size_t d = 0; d < o.max_dim; ++d)
      fmt::print("{:>4}  {:>16.4f}  {:>10.4f}  {:>10.4f}  {:>10.4f}  {:>10.4f}\n", d + 1,
                 fnn.fraction[d], fnn.fraction_distance[d], fnn.fraction_attractor[d], cao.e1[d],
                 cao.e2[d]);
  }
  if (fixed_dim)
    fmt::print("\nembedding dimension {} (given)\n", dimension);
  else if (found)
    fmt::print("\nembedding dimension {} ({})\n", dimension,
               by_cao ? "first m where Cao's E1 >= 0.85 has stopped changing"
                      : "first m with fewer than 1% false neighbours");
  else
    fmt::print(
        "\nno embedding dimension up to {} by {}: the series may be noisy or high-dimensional\n",
        o.max_dim, o.dim_method);
  fmt::print("delay vectors: {} of dimension {}\n", v.count, shown);
  files.print();
  return 0;
}

}  // namespace

void add_embed_command(CLI::App& app, command_list& commands) {
  auto o = std::make_shared<embed_options>();
  CLI::App* cmd = app.add_subcommand(
      "embed",
      "Delay embedding: the delay tau, the minimal embedding dimension, the delay vectors");
  o->command = cmd;
  o->series.add_to(*cmd);
  cmd->add_option(
         "--tau", o->tau,
         "Delay: auto (ami, else acf-zero, else T/4), T/4 (quarter of the dominant period), "
         "acf-zero, acf-min, ami (first minimum of the mutual information), or seconds")
      ->capture_default_str();
  cmd->add_option("--dim", o->dim, "Embedding dimension: auto or a number")->capture_default_str();
  cmd->add_option("--dim-method", o->dim_method,
                  "fnn (false nearest neighbours: first m with fewer than 1%) or cao (first m "
                  "where E1 >= 0.85 changes by less than 10%)")
      ->capture_default_str();
  cmd->add_option("--max-dim", o->max_dim, "Largest dimension tested (not with a given --dim)")
      ->capture_default_str();
  cmd->add_option("--bins", o->bins,
                  "Mutual information (--tau ami or auto): equal-width histogram bins per axis")
      ->capture_default_str();
  cmd->add_option("--mi-estimator", o->mi_estimator,
                  "Mutual information (--tau ami or auto): tisean (one histogram of bins x bins "
                  "boxes over the data's range, as TISEAN's mutual) or averaged (the mean over "
                  "4 x 4 grids shifted by quarter bins: smoother, but it can smooth away a "
                  "shallow first minimum)")
      ->capture_default_str();
  cmd->add_option("--rtol", o->rtol,
                  "False neighbours: R_tol, false if the added coordinate's gap exceeds R_tol "
                  "times the distance")
      ->capture_default_str();
  cmd->add_option("--atol", o->atol,
                  "False neighbours: A_tol, false if the distance in m + 1 dimensions exceeds "
                  "A_tol times the series' standard deviation")
      ->capture_default_str();
  cmd->add_option("--references", o->references,
                  "False neighbours and Cao: test at most this many evenly spaced points (0: all)")
      ->capture_default_str();
  cmd->add_option("--theiler", o->theiler,
                  "Neighbours closer in time than this (s) are ignored (default: tau)");
  cmd->add_flag("--json", o->json, "Print JSON");
  cmd->add_option("--out", o->out,
                  "Write FILE.csv (t and the delay vectors), FILE_dimension.csv and the plot "
                  "FILE.png with its gnuplot script FILE.gp");
  commands.push_back({cmd, [o] { return run_embed(*o); }});
}

}  // namespace npend::app
