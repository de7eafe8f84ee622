// Plots for every command: a gnuplot script kept next to the CSV data it reads (so users can
// restyle and re-run it), rendered to PNG when gnuplot is installed.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace npend::cli {

/// One curve of a panel, read from a CSV file next to the script.
struct plot_curve {
  std::string data;     ///< CSV file name, relative to the script's folder
  std::string columns;  ///< gnuplot `using` columns, e.g. "1:2"
  std::string style;    ///< gnuplot `with` style, e.g. "lines lw 2", "points pt 7", "boxes"
  std::string title;    ///< legend entry; empty for none
  /// Read options between the file name and `using`, e.g. gnuplot's
  /// "binary skip=128 array=(64,48) format='%float64'" for a raw array; empty for CSV.
  std::string source_options = {};
};

struct plot_panel {
  std::string title;           ///< shown verbatim (no enhanced-text markup)
  std::string xlabel, ylabel;  ///< gnuplot enhanced text: "C_{xx}(τ)", units in parentheses
  bool log_x = false, log_y = false;
  std::string xrange, yrange;         ///< gnuplot ranges such as "[0:10]"; empty: automatic
  std::vector<std::string> commands;  ///< further gnuplot commands before `plot`
  std::vector<plot_curve> curves;
};

struct figure {
  std::vector<std::string> description;  ///< comment lines opening the script: what it shows
  int width = 960, height = 640;         ///< pixels
  int columns = 1;                       ///< panels per row (multiplot layout)
  std::vector<plot_panel> panels;
};

/// The gnuplot script drawing `f` into `png_name` (unless the variable npend_output is set,
/// as `gnuplot -e "npend_output='x.png'" script.gp` does): pngcairo if this gnuplot has it,
/// else the libgd png terminal. Data paths are relative to the script's folder.
std::string gnuplot_script(const figure& f, std::string_view png_name);

struct plot_outcome {
  bool rendered = false;
  std::string message;  ///< what happened: the PNG written, or why not
};

/// Writes stem.gp (atomically), then runs gnuplot in its folder to render stem.png (into a
/// temporary file renamed into place). A missing gnuplot or a failed run is reported in the
/// outcome, never thrown: the data and the script stay, and the user can render later.
/// Throws std::runtime_error if the script cannot be written, or if gnuplot ends with
/// status 0 but the PNG is missing or cut short (a full disk, the file-size limit).
plot_outcome write_plot(const std::filesystem::path& stem, const figure& f);

/// `text` as a gnuplot double-quoted string literal.
std::string gnuplot_string(std::string_view text);

}  // namespace npend::cli
