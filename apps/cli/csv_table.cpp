#include "csv_table.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <optional>
#include <stdexcept>

#include "input_parsing.hpp"

namespace npend::cli {

namespace {

// Comma-separated, or — as TISEAN and most data loggers write — separated by runs of spaces
// and tabs. The first line that is neither blank nor a comment decides for the whole file.
enum class separator { comma, whitespace };

separator separator_of(std::string_view first_line) {
  return first_line.find(',') == std::string_view::npos ? separator::whitespace : separator::comma;
}

std::vector<std::string_view> split_on_whitespace(std::string_view line) {
  std::vector<std::string_view> cells;
  constexpr std::string_view blanks = " \t";
  for (std::size_t start = line.find_first_not_of(blanks); start != std::string_view::npos;) {
    const std::size_t end = line.find_first_of(blanks, start);
    cells.push_back(line.substr(start, end == std::string_view::npos ? end : end - start));
    start = end == std::string_view::npos ? end : line.find_first_not_of(blanks, end);
  }
  return cells;
}

std::vector<std::string_view> split_cells(std::string_view line, separator sep) {
  if (sep == separator::whitespace) return split_on_whitespace(line);
  std::vector<std::string_view> cells;
  for (std::size_t start = 0;;) {
    const std::size_t comma = line.find(',', start);
    cells.push_back(
        trim(line.substr(start, comma == std::string_view::npos ? comma : comma - start)));
    if (comma == std::string_view::npos) return cells;
    start = comma + 1;
  }
}

// A cell without the double or single quotes around it ("1.5", 'x').
std::string_view unquote(std::string_view cell) {
  if (cell.size() >= 2 && (cell.front() == '"' || cell.front() == '\'') &&
      cell.back() == cell.front())
    return trim(cell.substr(1, cell.size() - 2));
  return cell;
}

// How a cell reads as a number.
enum class cell_kind { number, out_of_range, text };

// A cell's number: quotes stripped, a Fortran exponent D or d (1.0D-3, as TISEAN's example
// files and Fortran programs write) read as E, a leading '+' allowed. NaN and infinities are
// numbers here: only the columns an analysis uses must be finite, and those are checked
// where a column is chosen.
cell_kind read_cell(std::string_view cell, double& value) {
  std::string digits(unquote(cell));
  if (digits.size() > 1 && digits.front() == '+' && digits[1] != '-') digits.erase(0, 1);
  const auto exponent = digits.find_first_of("Dd");
  if (exponent != std::string::npos && exponent > 0 &&
      (std::isdigit(static_cast<unsigned char>(digits[exponent - 1])) != 0 ||
       digits[exponent - 1] == '.'))
    digits[exponent] = 'e';
  if (digits.empty()) return cell_kind::text;
  const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  if (ec == std::errc::result_out_of_range) return cell_kind::out_of_range;
  if (ec != std::errc{} || end != digits.data() + digits.size()) return cell_kind::text;
  return cell_kind::number;
}

// A header cell: text that is not a number (an empty cell is a defect of a data row).
bool is_name(std::string_view cell) {
  double value = 0;
  return !cell.empty() && read_cell(cell, value) != cell_kind::number;
}

// A byte no text table holds: NUL and the control characters other than tab, line feed and
// carriage return. Bytes from 0x80 on may be UTF-8 (names like φ3) and pass.
bool is_binary_byte(char c) {
  const auto b = static_cast<unsigned char>(c);
  return (b < 0x20 && b != '\t' && b != '\n' && b != '\r') || b == 0x7f;
}

}  // namespace

csv_table parse_csv(std::string_view text, std::string_view source) {
  csv_table table;
  std::size_t width = 0;
  bool first = true;
  separator sep = separator::comma;
  std::size_t line_number = 0;
  if (const auto binary = find_binary_byte(text))
    throw input_error(binary_data_message(text, *binary, source));
  // A UTF-8 byte order mark, as spreadsheet programs write one, is no part of the header.
  if (text.starts_with("\xEF\xBB\xBF")) text.remove_prefix(3);
  for (std::size_t start = 0; start <= text.size();) {
    std::size_t end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = text.substr(start, end - start);
    start = end + 1;
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    const std::string_view content = trim(line);
    if (content.empty() || content.front() == '#') continue;

    if (first) sep = separator_of(content);
    const auto cells = split_cells(line, sep);
    if (first) {
      first = false;
      width = cells.size();
      table.columns.resize(width);
      if (std::any_of(cells.begin(), cells.end(), is_name)) {
        for (std::size_t c = 0; c < width; ++c) {
          std::string name(unquote(cells[c]));
          if (name.empty())
            throw input_error(
                fmt::format("{}:{}: header cell {} is empty", source, line_number, c + 1));
          if (std::find(table.names.begin(), table.names.end(), name) != table.names.end())
            throw input_error(
                fmt::format("{}:{}: column name '{}' appears twice", source, line_number, name));
          table.names.push_back(std::move(name));
        }
        continue;
      }
    }
    if (cells.size() != width)
      throw input_error(fmt::format("{}:{}: {} cells, but the first line has {}", source,
                                    line_number, cells.size(), width));
    for (std::size_t c = 0; c < width; ++c) {
      const std::string column = table.names.empty() ? fmt::format("column {}", c + 1)
                                                     : fmt::format("column '{}'", table.names[c]);
      if (cells[c].empty())
        throw input_error(fmt::format("{}:{}: {}: empty cell", source, line_number, column));
      double value = 0;
      switch (read_cell(cells[c], value)) {
        case cell_kind::number:
          break;
        case cell_kind::out_of_range:
          throw input_error(fmt::format("{}:{}: {}: '{}' is out of the range of a double", source,
                                        line_number, column, excerpt(cells[c])));
        case cell_kind::text:
          throw input_error(fmt::format("{}:{}: {}: '{}' is not a number", source, line_number,
                                        column, excerpt(cells[c])));
      }
      table.columns[c].push_back(value);
    }
    table.lines.push_back(line_number);
  }
  if (table.lines.empty()) throw input_error(fmt::format("{}: no data rows", source));
  return table;
}

std::optional<std::size_t> find_binary_byte(std::string_view text) {
  const auto found = std::find_if(text.begin(), text.end(), is_binary_byte);
  if (found == text.end()) return std::nullopt;
  return static_cast<std::size_t>(found - text.begin());
}

std::string binary_data_message(std::string_view text, std::size_t position,
                                std::string_view source) {
  const auto line =
      1 + std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(position), '\n');
  return fmt::format("{}:{}: binary data (byte 0x{:02x}), not a table of numbers", source, line,
                     static_cast<unsigned char>(text[position]));
}

std::string format_csv(std::span<const std::string> names,
                       std::span<const std::vector<double>> columns) {
  if (names.size() != columns.size() || columns.empty())
    throw std::invalid_argument("format_csv: one name per column, at least one column");
  for (const auto& c : columns)
    if (c.size() != columns.front().size())
      throw std::invalid_argument("format_csv: columns of different lengths");
  std::string out = fmt::format("{}\n", fmt::join(names, ","));
  for (std::size_t row = 0; row < columns.front().size(); ++row) {
    for (std::size_t c = 0; c < columns.size(); ++c) {
      if (c > 0) out += ',';
      fmt::format_to(std::back_inserter(out), "{}", columns[c][row]);
    }
    out += '\n';
  }
  return out;
}

}  // namespace npend::cli
