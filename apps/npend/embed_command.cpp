// npend embed: delay coordinates (paper §6.6.4, Abb. 6.13) — the delay τ and the minimal
// embedding dimension of a time series, and its delay vectors.
#include "command.hpp"
#include "input_parsing.hpp"
#include "series_figures.hpp"
#include "series_output.hpp"
#include "time_series_source.hpp"

#include "npend/analysis/delay_embedding.hpp"
#include "npend/analysis/embedding_dimension.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <iostream>

namespace npend::app {

namespace {

constexpr std::size_t min_samples = 64;

struct embed_options {
  cli::series_options series;
  std::string tau = "auto", dim = "auto", dim_method = "fnn", theiler;
  std::size_t max_dim = 10;
  bool json = false;
  std::string out;
};

// τ from --tau: a method name, or a delay in seconds.
delay_choice delay_from_option(const std::string& text, const cli::time_series& x) {
  if (const auto method = delay_method_from_name(text)) {
    const delay_choice c = choose_delay(x.values, x.dt, *method);
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

int run_embed(const embed_options& o) {
  if (o.dim_method != "fnn" && o.dim_method != "cao")
    throw cli::input_error(fmt::format("--dim-method: '{}' is not fnn or cao", o.dim_method));
  if (o.max_dim < 2 || o.max_dim > 20)
    throw cli::input_error(fmt::format("--max-dim: must be 2..20, got {}", o.max_dim));
  std::optional<std::size_t> fixed_dim;
  if (o.dim != "auto") {
    const double k = cli::parse_number(o.dim, "--dim");
    if (k != std::floor(k) || k < 1 || k > 20)
      throw cli::input_error(fmt::format("--dim: '{}' is not auto or a dimension 1..20", o.dim));
    fixed_dim = static_cast<std::size_t>(k);
  }
  series_output files(o.out);
  const cli::time_series x = o.series.load_one(min_samples);
  const delay_choice tau = delay_from_option(o.tau, x);
  std::size_t theiler = tau.samples;
  if (!o.theiler.empty()) {
    const double seconds = cli::parse_number(o.theiler, "--theiler");
    if (!(seconds >= 0)) throw cli::input_error("--theiler: must be at least 0");
    theiler = static_cast<std::size_t>(std::round(seconds / x.dt));
  }

  false_neighbours_result fnn;
  cao_result cao;
  try {
    fnn = false_nearest_neighbours(x.values, tau.samples, o.max_dim, {.theiler_window = theiler});
    cao = cao_embedding(x.values, tau.samples, o.max_dim, {.theiler_window = theiler});
  } catch (const std::invalid_argument& e) {
    // The one data-dependent failure: too short a series for --max-dim at this τ.
    throw cli::input_error(fmt::format("--max-dim: {}", e.what()));
  }
  const bool by_cao = o.dim_method == "cao";
  const bool found = fixed_dim || (by_cao ? cao.found : fnn.found);
  const std::size_t dimension = fixed_dim ? *fixed_dim
                                : found   ? (by_cao ? cao.dimension : fnn.dimension)
                                          : 0;
  // The delay vectors written and plotted: in the dimension found, at least 2 for the plot.
  const std::size_t shown = std::max<std::size_t>(2, found ? dimension : o.max_dim);
  const delay_vectors v = delay_embedding(x.values, tau.samples, shown);

  if (files.enabled()) {
    const auto [delay_plot, dimension_plot] = embedding_figure(
        files, "", x, tau, v, fnn, cao, found ? std::optional(dimension) : std::nullopt,
        fixed_dim ? "given" : o.dim_method);
    files.write_plot(
        {.description = {fmt::format("npend embed: delay coordinates of {}", series_summary(x)),
                         fmt::format("data: {} (delay vectors), {} (dimension criteria)",
                                     files.file_name(""), files.file_name("dimension"))},
         .width = 1300,
         .height = 620,
         .columns = 2,
         .panels = {delay_plot, dimension_plot}});
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
         {"false_neighbours", fnn.fraction},
         {"cao_e1", cao.e1},
         {"cao_e2", cao.e2},
         {"vectors", v.count}});
    files.add_to(j);
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  fmt::print("Delay embedding of {}\n\n", series_summary(x));
  fmt::print("delay tau = {:.6g} s ({} samples; {})\n", tau.seconds, tau.samples,
             delay_method_from_name(o.tau)
                 ? fmt::format("{} estimate {:.6g} s", delay_method_name(tau.method), tau.estimate)
                 : std::string("given"));
  fmt::print("\n{:>4}  {:>16}  {:>10}  {:>10}\n", "m", "false neighbours", "Cao E1", "Cao E2");
  for (std::size_t d = 0; d < o.max_dim; ++d)
    fmt::print("{:>4}  {:>16.4f}  {:>10.4f}  {:>10.4f}\n", d + 1, fnn.fraction[d], cao.e1[d],
               cao.e2[d]);
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
  cmd->add_option("--max-dim", o->max_dim, "Largest dimension tested")->capture_default_str();
  cmd->add_option("--theiler", o->theiler,
                  "Neighbours closer in time than this (s) are ignored (default: tau)");
  cmd->add_flag("--json", o->json, "Print JSON");
  cmd->add_option("--out", o->out,
                  "Write FILE.csv (t and the delay vectors), FILE_dimension.csv and the plot "
                  "FILE.png with its gnuplot script FILE.gp");
  commands.push_back({cmd, [o] { return run_embed(*o); }});
}

}  // namespace npend::app
