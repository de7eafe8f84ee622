// npend spectrum: the spectral density of a time series with its lines (paper §6.6.2,
// Abb. 6.9).
#include <fmt/format.h>

#include <cmath>
#include <iostream>
#include <nlohmann/json.hpp>
#include <numbers>

#include "command.hpp"
#include "input_parsing.hpp"
#include "npend/analysis/series/power_spectrum.hpp"
#include "npend/analysis/series/spectral_peaks.hpp"
#include "series_figures.hpp"
#include "series_output.hpp"
#include "time_series_source.hpp"

namespace npend::app {

namespace {

constexpr std::size_t min_spectrum_samples = 16;
constexpr double two_pi = 2 * std::numbers::pi;

struct spectrum_options {
  cli::series_options series;
  std::string window = "hann";
  std::size_t segment = 0;
  double overlap = 0.5;
  std::size_t peaks = 10;
  double threshold = 1e-3;
  double prominence = 0.5;
  std::string omega_max;
  bool json = false;
  std::string out;
};

int run_spectrum(const spectrum_options& o) {
  const auto window = spectral_window_from_name(o.window);
  if (!window)
    throw cli::input_error(
        fmt::format("--window: '{}' is not one of none, hann, hamming, blackman", o.window));
  if (!(o.overlap >= 0 && o.overlap < 1))
    throw cli::input_error(fmt::format("--overlap: must be in [0, 1), got {}", o.overlap));
  if (!(o.threshold >= 0 && o.threshold <= 1))
    throw cli::input_error(fmt::format("--threshold: must be in [0, 1], got {}", o.threshold));
  if (!(o.prominence >= 0 && o.prominence <= 1))
    throw cli::input_error(fmt::format("--prominence: must be in [0, 1], got {}", o.prominence));
  std::optional<double> omega_max;
  if (!o.omega_max.empty()) {
    omega_max = cli::parse_number(o.omega_max, "--omega-max");
    if (!(*omega_max > 0)) throw cli::input_error("--omega-max: must be positive");
  }
  series_output files(o.out);
  const time_series x = o.series.load_one(min_spectrum_samples);
  if (o.segment != 0 && (o.segment < min_spectrum_samples || o.segment > x.values.size()))
    throw cli::input_error(
        fmt::format("--segment: must be 0 (the whole series) or {}..{} samples, got {}",
                    min_spectrum_samples, x.values.size(), o.segment));

  const auto spectrum = power_spectrum(
      x.values, x.dt, {.window = *window, .segment_length = o.segment, .overlap = o.overlap});
  const auto peaks = find_spectral_peaks(
      spectrum, {.threshold = o.threshold, .min_prominence = o.prominence, .max_peaks = o.peaks});

  if (files.enabled())
    files.write_plot(
        {.description = {fmt::format("npend spectrum: spectral density of {}", series_summary(x)),
                         fmt::format("data: {} (all bins), {} (the peaks)", files.file_name(""),
                                     files.file_name("peaks"))},
         .panels = {spectrum_panel(files, "", x, spectrum, peaks, omega_max)}});

  if (o.json) {
    nlohmann::json list = nlohmann::json::array();
    for (const auto& p : peaks)
      list.push_back({{"omega", p.omega},
                      {"power", p.power},
                      {"frequency", p.omega / two_pi},
                      {"period", two_pi / p.omega},
                      {"prominence", p.prominence}});
    nlohmann::json j = describe_series(x);
    j.update({{"window", spectral_window_name(spectrum.window)},
              {"segment_length", spectrum.segment_length},
              {"segments", spectrum.segments},
              {"resolution", spectrum.resolution},
              {"nyquist", spectrum.omega.back()},
              {"peaks", list}});
    files.add_to(j);
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  fmt::print("Spectral density of {}\n", series_summary(x));
  fmt::print(
      "{} window, {} segment{} of {} samples; resolution {:.6g} rad/s, Nyquist {:.6g} rad/s\n\n",
      window_label(spectrum.window), spectrum.segments, spectrum.segments == 1 ? "" : "s",
      spectrum.segment_length, spectrum.resolution, spectrum.omega.back());
  if (peaks.empty()) {
    fmt::print("No peaks above the threshold.\n");
  } else {
    fmt::print("{:>4}  {:>14}  {:>12}  {:>12}  {:>14}\n", "peak", "omega (rad/s)", "f (Hz)",
               "period (s)", "power");
    for (std::size_t k = 0; k < peaks.size(); ++k)
      fmt::print("{:>4}  {:>14.6g}  {:>12.6g}  {:>12.6g}  {:>14.6g}\n", k + 1, peaks[k].omega,
                 peaks[k].omega / two_pi, two_pi / peaks[k].omega, peaks[k].power);
  }
  files.print();
  return 0;
}

}  // namespace

void add_spectrum_command(CLI::App& app, command_list& commands) {
  auto o = std::make_shared<spectrum_options>();
  CLI::App* cmd = app.add_subcommand(
      "spectrum", "Spectral density rho(omega) = |x(omega)|^2 of a time series, and its peaks");
  o->series.add_to(*cmd);
  cmd->add_option("--window", o->window, "Data window: none, hann, hamming or blackman")
      ->capture_default_str();
  cmd->add_option("--segment", o->segment,
                  "Welch averaging: segment length in samples (0: one segment, the whole series)")
      ->capture_default_str();
  cmd->add_option("--overlap", o->overlap, "Welch averaging: overlap of segments, in [0, 1)")
      ->capture_default_str();
  cmd->add_option("--peaks", o->peaks, "Report at most this many peaks (0: all)")
      ->capture_default_str();
  cmd->add_option("--threshold", o->threshold,
                  "Peaks below this fraction of the strongest are dropped")
      ->capture_default_str();
  cmd->add_option("--prominence", o->prominence,
                  "Peaks must rise this fraction of their height above their higher base")
      ->capture_default_str();
  cmd->add_option("--omega-max", o->omega_max, "Upper end of the plot's frequency axis in rad/s");
  cmd->add_flag("--json", o->json, "Print JSON");
  cmd->add_option("--out", o->out,
                  "Write FILE.csv (omega, power), FILE_peaks.csv and the plot FILE.png with its "
                  "gnuplot script FILE.gp");
  commands.push_back({cmd, [o] { return run_spectrum(*o); }});
}

}  // namespace npend::app
