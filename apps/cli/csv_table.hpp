// Numeric CSV tables: the parser users' measured time series go through (a pure function of
// the text, the fuzzers' target) and the writer of every CSV the commands produce.
#pragma once

#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace npend::cli {

/// A table of numbers, column-major.
struct csv_table {
  std::vector<std::string> names;            ///< header cells; empty if there is no header
  std::vector<std::vector<double>> columns;  ///< one vector per column, all of equal length
  std::vector<std::size_t> lines;            ///< 1-based source line of each data row
};

/// Parses a table of numbers, comma-separated or — when the first line that is neither blank
/// nor a comment has no comma — separated by runs of spaces and tabs (TISEAN's and most data
/// loggers' format). Lines may end in \n or \r\n; blank lines and lines whose first
/// non-blank character is '#' are skipped; cells are trimmed of spaces and tabs. The
/// first remaining line is a header when any of its cells is not a number (header cells may
/// be double-quoted). Every data row must have as many cells as the first line, each a finite
/// number. Throws input_error naming `source`, the line and the column, e.g.
/// "data.csv:17: column 'x': 'abc' is not a number"; also for no data rows, empty or
/// duplicate header names.
csv_table parse_csv(std::string_view text, std::string_view source);

/// CSV text: a header row of `names`, then one row per index of the equally long `columns`,
/// numbers in their shortest round-trip form. Throws std::invalid_argument if the sizes
/// disagree.
std::string format_csv(std::span<const std::string> names,
                       std::span<const std::vector<double>> columns);

}  // namespace npend::cli
