// Numeric CSV tables: the parser users' measured time series go through (a pure function of
// the text, the fuzzers' target) and the writer of every CSV the commands produce.
#pragma once

#include <optional>
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
/// loggers' format). A UTF-8 byte order mark at the start is skipped; lines may end in \n or
/// \r\n; blank lines and lines whose first non-blank character is '#' are skipped; cells are
/// trimmed of spaces and tabs. The first remaining line is a header when any of its cells is
/// not a number. Cells may be quoted ("1.5", 'x'); numbers may have a Fortran exponent D or d
/// (1.0D-3). Every data row must have as many cells as the first line, each a number; NaN and
/// infinities are kept (the columns an analysis uses are checked for them where they are
/// chosen: a bad cell in a column nobody reads blocks nothing). Throws input_error naming
/// `source`, the line and the column, e.g. "data.csv:17: column 'x': 'abc' is not a number"
/// (the cell quoted by excerpt); also for no data rows, empty or duplicate header names, and
/// for binary data (binary_data_message).
csv_table parse_csv(std::string_view text, std::string_view source);

/// The position of the first byte in `text` that no text table holds (NUL, a control
/// character other than tab, line feed and carriage return), if any.
std::optional<std::size_t> find_binary_byte(std::string_view text);

/// "data.csv:3: binary data (byte 0x00), not a table of numbers" for the byte at `position`
/// of `text` (the line counted from its start): the file's bytes are never echoed.
std::string binary_data_message(std::string_view text, std::size_t position,
                                std::string_view source);

/// CSV text: a header row of `names`, then one row per index of the equally long `columns`,
/// numbers in their shortest round-trip form. Throws std::invalid_argument if the sizes
/// disagree.
std::string format_csv(std::span<const std::string> names,
                       std::span<const std::vector<double>> columns);

}  // namespace npend::cli
