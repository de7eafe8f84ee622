// The Markdown index of a folder of figures (npend analyze, npend demo): a title, a few lines
// on what was computed, a table of the numbers, then each plot with what it shows and links
// to its data and gnuplot script.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace npend::app {

/// One figure of the index.
struct index_entry {
  std::string heading;            ///< section heading and alt text
  std::string image;              ///< the PNG, relative to the index ("spectrum.png")
  std::string text;               ///< what it shows (Markdown)
  std::vector<std::string> data;  ///< the CSV files it reads, relative to the index
};

struct figure_index {
  std::string title;
  std::vector<std::string> preamble;                       ///< paragraphs before the table
  std::vector<std::pair<std::string, std::string>> facts;  ///< the table's rows
  std::vector<index_entry> entries;
  std::vector<std::string> notes;  ///< shown as notes under the table

  /// The index as Markdown. '|' in table cells is escaped; the plot script of image X.png
  /// is linked as X.gp.
  std::string markdown() const;
};

}  // namespace npend::app
