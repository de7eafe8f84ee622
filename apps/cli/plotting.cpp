#include "plotting.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

#include "child_process.hpp"
#include "output_file.hpp"

namespace npend::cli {

namespace {

// Settings every panel starts from (multiplot panels begin with `reset`).
constexpr std::string_view panel_defaults =
    "set datafile separator comma\n"
    "set datafile columnheaders\n"
    "set grid lc rgb '#dddddd'\n"
    "set key top right Left reverse opaque box lc rgb '#bbbbbb'\n"
    "set border lw 1.2\n"
    "set tics nomirror out\n"
    "set mxtics; set mytics\n";

// Runs gnuplot in `dir` on `script`, fed through its stdin; a failure to start it at all (no
// pipe, no fork) comes back as status -1 with the reason, like a failed run. Named as the
// file /dev/stdin, the script is loaded as a file is: gnuplot stops at the first error and
// names it last (reading plain stdin it would go on, and end with some later line).
program_result run_gnuplot(const std::filesystem::path& dir, const std::string& script) {
  try {
    child_process gnuplot({"gnuplot", "/dev/stdin"}, dir, true);
    gnuplot.write(script);
    return gnuplot.finish();
  } catch (const std::runtime_error& e) {
    return {-1, e.what()};
  }
}

}  // namespace

std::string gnuplot_string(std::string_view text) {
  std::string out = "\"";
  for (const char c : text) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

std::string gnuplot_script(const figure& f, std::string_view png_name) {
  std::string s;
  for (const auto& line : f.description) s += fmt::format("# {}\n", line);
  s += fmt::format(
      "# Written by npend; edit freely. Re-render in this folder with: gnuplot <this file>\n"
      "if (!exists(\"npend_output\")) npend_output = {}\n"
      "set encoding utf8\n"
      "if (strstrt(GPVAL_TERMINALS, \"pngcairo\") > 0) {{\n"
      "  set terminal pngcairo size {},{} enhanced font \"DejaVu Sans,12\" linewidth 1.2\n"
      "}} else {{\n"
      "  set terminal png size {},{} enhanced\n"
      "}}\n"
      "set output npend_output\n",
      gnuplot_string(png_name), f.width, f.height, f.width, f.height);
  const bool multi = f.panels.size() > 1;
  if (multi) {
    const int rows = static_cast<int>((f.panels.size() + static_cast<std::size_t>(f.columns) - 1) /
                                      static_cast<std::size_t>(f.columns));
    s += fmt::format("set multiplot layout {},{}\n", rows, f.columns);
  }
  for (const auto& p : f.panels) {
    s += "\nreset\n";
    s += panel_defaults;
    s += fmt::format("set title {} noenhanced\n", gnuplot_string(p.title));
    s += fmt::format("set xlabel {}\nset ylabel {}\n", gnuplot_string(p.xlabel),
                     gnuplot_string(p.ylabel));
    if (p.log_x) s += "set logscale x\nset format x '10^{%T}'\n";
    if (p.log_y) s += "set logscale y\nset format y '10^{%T}'\n";
    if (!p.xrange.empty()) s += fmt::format("set xrange {}\n", p.xrange);
    if (!p.yrange.empty()) s += fmt::format("set yrange {}\n", p.yrange);
    if (std::none_of(p.curves.begin(), p.curves.end(),
                     [](const plot_curve& c) { return !c.title.empty(); }))
      s += "set key off\n";
    for (const auto& c : p.commands) s += c + "\n";
    s += "plot ";
    for (std::size_t k = 0; k < p.curves.size(); ++k) {
      const auto& c = p.curves[k];
      s += fmt::format(
          "{}{}{} using {} with {} {}", k ? ", \\\n     " : "", gnuplot_string(c.data),
          c.source_options.empty() ? "" : " " + c.source_options, c.columns, c.style,
          c.title.empty() ? std::string("notitle") : "title " + gnuplot_string(c.title));
    }
    s += "\n";
  }
  if (multi) s += "unset multiplot\n";
  s += "set output\n";
  return s;
}

plot_outcome write_plot(const std::filesystem::path& stem, const figure& f) {
  const std::filesystem::path script = stem.string() + ".gp";
  const std::filesystem::path png = stem.string() + ".png";
  write_file_atomically(script, gnuplot_script(f, png.filename().string()));
  const auto dir = script.has_parent_path() ? script.parent_path() : std::filesystem::path(".");
  // gnuplot renders the kept script, reading each data file by the name it has now: in an
  // output_batch that is still its temporary name (as the script's is, so it goes by stdin).
  figure rendered = f;
  for (auto& panel : rendered.panels)
    for (auto& curve : panel.curves) {
      const std::filesystem::path data(curve.data);
      curve.data =
          (data.parent_path() / output_batch::readable_name(dir / data).filename()).string();
    }
  atomic_output_file image(png);
  const program_result run =
      run_gnuplot(dir, gnuplot_script(rendered, image.temporary_path().filename().string()));
  const int status = run.status;
  if (status == 0) {
    // A full disk or the file-size limit cuts the PNG short while gnuplot exits with 0.
    check_written_image(image.temporary_path(), png, image_format::png);
    image.commit();
    return {true, fmt::format("plot: {} (from {})", png.string(), script.string())};
  }
  if (status == 127)
    return {false, fmt::format("gnuplot is not installed: the data and {} are written; render "
                               "the plot later with `gnuplot {}` in {}",
                               script.string(), script.filename().string(), dir.string())};
  // gnuplot ends its complaint with the reason; report that line.
  const std::string reason = run.last_line();
  return {false, fmt::format("gnuplot failed (status {}){}{}: the data and {} are written", status,
                             reason.empty() ? "" : ": ", reason, script.string())};
}

}  // namespace npend::cli
