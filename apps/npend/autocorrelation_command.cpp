// npend autocorrelation: the autocorrelation of a time series, its first zero and minimum
// (paper §6.6.2, Abb. 6.10).
#include <fmt/format.h>

#include <cmath>
#include <iostream>
#include <nlohmann/json.hpp>

#include "command.hpp"
#include "input_parsing.hpp"
#include "npend/analysis/series/autocorrelation.hpp"
#include "series_figures.hpp"
#include "series_output.hpp"
#include "time_series_source.hpp"

namespace npend::app {

namespace {

constexpr std::size_t min_autocorrelation_samples = 16;

struct autocorrelation_options {
  cli::series_options series;
  std::string max_lag;
  std::string estimator = "biased";
  bool json = false;
  std::string out;
};

int run_autocorrelation(const autocorrelation_options& o) {
  series_output files(o.out);
  const time_series x = o.series.load_one(min_autocorrelation_samples);
  const std::size_t n = x.values.size();
  std::size_t lags = n / 2;
  if (!o.max_lag.empty()) {
    const double seconds = cli::parse_number(o.max_lag, "--max-lag");
    const double samples = std::round(seconds / x.dt);
    if (!(samples >= 1 && samples < static_cast<double>(n)))
      throw cli::input_error(
          fmt::format("--max-lag: must be between dt = {:.6g} s and the series' "
                      "length {:.6g} s, got {}",
                      x.dt, x.dt * static_cast<double>(n - 1), o.max_lag));
    lags = static_cast<std::size_t>(samples);
  }
  const auto estimator = autocorrelation_estimator_from_name(o.estimator);
  if (!estimator)
    throw cli::input_error(
        fmt::format("--estimator: unknown estimator '{}': choose biased or unbiased", o.estimator));
  const auto c = autocorrelation(x.values, x.dt, lags, *estimator);

  if (files.enabled())
    files.write_plot({.description = {fmt::format("npend autocorrelation of {}", series_summary(x)),
                                      fmt::format("data: {}", files.file_name(""))},
                      .panels = {autocorrelation_panel(files, "", x, c)}});

  if (o.json) {
    nlohmann::json j = describe_series(x);
    j.update(
        {{"max_lag", c.lag.back()},
         {"estimator", o.estimator},
         {"first_zero", c.first_zero ? nlohmann::json(*c.first_zero) : nlohmann::json()},
         {"first_minimum", c.first_minimum ? nlohmann::json(*c.first_minimum) : nlohmann::json()}});
    files.add_to(j);
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  fmt::print("Autocorrelation C_xx(tau) of {}, lags up to {:.6g} s, {} estimate\n\n",
             series_summary(x), c.lag.back(), o.estimator);
  if (c.first_zero)
    fmt::print("first zero:    tau = {:.6g} s\n", *c.first_zero);
  else
    fmt::print("first zero:    none (C_xx stays positive)\n");
  if (c.first_minimum)
    fmt::print("first minimum: tau = {:.6g} s\n", *c.first_minimum);
  else
    fmt::print("first minimum: none\n");
  files.print();
  return 0;
}

}  // namespace

void add_autocorrelation_command(CLI::App& app, command_list& commands) {
  auto o = std::make_shared<autocorrelation_options>();
  CLI::App* cmd = app.add_subcommand(
      "autocorrelation", "Autocorrelation C_xx(tau) of a time series, its first zero and minimum");
  o->series.add_to(*cmd);
  cmd->add_option("--max-lag", o->max_lag, "Largest lag in s (default: half the series)");
  cmd->add_option("--estimator", o->estimator,
                  "biased (lag k summed over N - k products, divided by N; the default, "
                  "tapered by 1 - k/N) or unbiased (divided by N - k, as TISEAN's corr and "
                  "autocor: no taper, noisier at long lags)")
      ->capture_default_str();
  cmd->add_flag("--json", o->json, "Print JSON");
  cmd->add_option("--out", o->out,
                  "Write FILE.csv (tau, C) and the plot FILE.png with its gnuplot script FILE.gp");
  commands.push_back({cmd, [o] { return run_autocorrelation(*o); }});
}

}  // namespace npend::app
