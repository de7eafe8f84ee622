// What the time-series commands share: describing the analysed series, and their --out files
// (CSV tables plus a plot, next to each other).
#pragma once

#include <complex>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <span>
#include <string>
#include <vector>

#include "plotting.hpp"
#include "time_series_source.hpp"

namespace npend::app {

/// {"links", "masses", "lengths", "g"} of the chain, the start of every chain command's JSON.
nlohmann::json describe_chain(const chain& c);

/// A row-major matrix with `cols` columns as a JSON list of rows.
nlohmann::json json_rows(const std::vector<double>& m, std::size_t cols);

/// Complex numbers (eigenvalues, multipliers) as a JSON list of [re, im].
nlohmann::json json_complex_list(const std::vector<std::complex<double>>& values);

/// {"source", "signal", "samples", "t0", "dt"} of the analysed series.
nlohmann::json describe_series(const time_series& s);

/// "'x' from data.csv: 16384 samples, dt = 0.001 s (16.384 s)".
std::string series_summary(const time_series& s);

/// The files a command writes for --out FILE.csv: FILE.csv, FILE_<table>.csv, FILE.gp and
/// FILE.png. Constructed before the analysis runs, so a bad --out fails first and nothing is
/// written; every file is written atomically.
class series_output {
 public:
  /// `out` empty: no files. Throws cli::input_error for a bad --out.
  explicit series_output(const std::string& out);

  bool enabled() const { return !m_stem.empty(); }
  /// The name (without folder) of FILE.csv (`table` empty) or FILE_<table>.csv.
  std::string file_name(std::string_view table) const;
  /// Writes FILE.csv (`table` empty) or FILE_<table>.csv; returns the file name for plots.
  std::string write_csv(std::string_view table, std::span<const std::string> names,
                        std::span<const std::vector<double>> columns);
  /// Writes FILE.gp and renders FILE.png; a plot that cannot be rendered is noted, not fatal.
  void write_plot(const cli::figure& f);

  /// The files written so far, and the notes on plots that could not be drawn.
  const std::vector<std::string>& files() const { return m_files; }
  const std::vector<std::string>& notes() const { return m_notes; }

  /// Adds "files" (and "notes" if any) to `j`; notes also go to stderr.
  void add_to(nlohmann::json& j) const;
  /// Prints the files written and any notes.
  void print() const;

 private:
  std::filesystem::path m_stem;
  std::vector<std::string> m_files, m_notes;
};

}  // namespace npend::app
