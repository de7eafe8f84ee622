// A folder of figures with its Markdown index (npend analyze, npend demo): a title, a few
// lines on what was computed, a table of the numbers, then each plot with what it shows and
// links to its data and gnuplot script.
#pragma once

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "plotting.hpp"
#include "series_output.hpp"

namespace npend::app {

/// One figure of the index.
struct index_entry {
  std::string heading;            ///< section heading and alt text
  std::string image;              ///< the PNG, relative to the index ("spectrum.png")
  std::string text;               ///< what it shows (Markdown)
  std::vector<std::string> data;  ///< the CSV files it reads, relative to the index
  bool scripted = true;  ///< whether a gnuplot script X.gp draws it (an animation has none)
};

struct figure_index {
  std::string title;
  std::vector<std::string> preamble;                       ///< paragraphs before the table
  std::vector<std::pair<std::string, std::string>> facts;  ///< the table's rows
  std::vector<index_entry> entries;
  std::vector<std::string> notes;  ///< shown as notes under the table

  /// The index as Markdown. '|' in table cells is escaped; the plot script of image X.png
  /// is linked as X.gp (if it has one).
  std::string markdown() const;
};

/// The size and layout of a figure's PNG.
struct figure_size {
  int width = 960, height = 640;
  int columns = 1;  ///< panels side by side
};

/// The figures of one folder, the files written, the notes on plots that could not be
/// drawn, and the index that lists them.
class figure_folder {
 public:
  /// Figures go to `dir` (which must exist); each gnuplot script is described as
  /// "<description_prefix><heading><description_suffix>". With `echo`, each figure's heading,
  /// text and path are printed to stdout as it is written.
  figure_folder(std::filesystem::path dir, std::string description_prefix,
                std::string description_suffix = {}, bool echo = false);

  const std::filesystem::path& dir() const { return m_dir; }

  /// A figure STEM.png with its script STEM.gp, whose tables STEM_<table>.csv the panels
  /// write through the series_output handed to `panels` (which returns the panels);
  /// `also_reads` lists tables of other figures its panels read. Returns the path of the PNG.
  template <class Panels>
  std::string add(const std::string& stem, const std::string& heading, const std::string& text,
                  Panels&& panels, figure_size size = {},
                  const std::vector<std::string>& also_reads = {}) {
    series_output out((m_dir / (stem + ".csv")).string());
    std::vector<cli::plot_panel> list = panels(out);
    return finish(out, stem, heading, text, std::move(list), size, also_reads);
  }

  figure_index& index() { return m_index; }
  const std::vector<std::string>& files() const { return m_files; }
  const std::vector<std::string>& notes() const { return m_notes; }
  /// Records a file written to the folder by other means.
  void record(const std::string& path) { m_files.push_back(path); }

  /// Writes the index as index.md (atomically), records it, and returns its path.
  std::filesystem::path write_index();

 private:
  std::string finish(series_output& out, const std::string& stem, const std::string& heading,
                     const std::string& text, std::vector<cli::plot_panel> panels, figure_size size,
                     const std::vector<std::string>& also_reads);

  std::filesystem::path m_dir;
  std::string m_prefix, m_suffix;
  bool m_echo;
  figure_index m_index;
  std::vector<std::string> m_files, m_notes;
};

}  // namespace npend::app
