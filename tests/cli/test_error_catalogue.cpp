// docs/errors.md, the catalogue of bad input, run row by row: each row's command gives the
// row's exit status and exactly the row's one-line message, and leaves no file behind.
#include <doctest/doctest.h>

#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "support/test_support.hpp"

namespace fs = std::filesystem;

namespace {

struct catalogue_row {
  int line;
  std::string what, args, message;
  int exit_code;
};

// "`text`" -> "text"; "" when the cell is not one code span.
std::string code_span(const std::string& cell) {
  if (cell.size() < 2 || cell.front() != '`' || cell.back() != '`') return "";
  return cell.substr(1, cell.size() - 2);
}

std::vector<std::string> table_cells(const std::string& line) {
  std::vector<std::string> cells;
  std::string inner = line.substr(2, line.size() - 4);  // without the outer "| " and " |"
  for (std::size_t start = 0;;) {
    const std::size_t bar = inner.find(" | ", start);
    cells.push_back(
        inner.substr(start, bar == std::string::npos ? std::string::npos : bar - start));
    if (bar == std::string::npos) break;
    start = bar + 3;
  }
  return cells;
}

// The catalogue's rows: table lines whose second cell is a `npend ...` command.
std::vector<catalogue_row> read_catalogue(const std::string& text) {
  std::vector<catalogue_row> rows;
  std::istringstream in(text);
  int number = 0;
  for (std::string line; std::getline(in, line);) {
    ++number;
    if (line.rfind("| ", 0) != 0 || line.size() < 4 || line.substr(line.size() - 2) != " |")
      continue;
    const auto cells = table_cells(line);
    if (cells.size() != 4) continue;
    const std::string command = code_span(cells[1]);
    if (command.rfind("npend ", 0) != 0) continue;
    rows.push_back({number, cells[0], command.substr(6), code_span(cells[3]), std::stoi(cells[2])});
  }
  return rows;
}

// Whether `text` is `pattern`, where each "…" in the pattern stands for any text.
bool matches(const std::string& text, const std::string& pattern) {
  const std::string ellipsis = "…";
  std::vector<std::string> pieces;
  for (std::size_t start = 0;;) {
    const std::size_t at = pattern.find(ellipsis, start);
    pieces.push_back(
        pattern.substr(start, at == std::string::npos ? std::string::npos : at - start));
    if (at == std::string::npos) break;
    start = at + ellipsis.size();
  }
  if (pieces.size() == 1) return text == pattern;
  if (text.rfind(pieces.front(), 0) != 0) return false;
  std::size_t position = pieces.front().size();
  for (std::size_t k = 1; k + 1 < pieces.size(); ++k) {
    const std::size_t at = text.find(pieces[k], position);
    if (at == std::string::npos) return false;
    position = at + pieces[k].size();
  }
  const std::string& last = pieces.back();
  return text.size() >= position + last.size() &&
         text.compare(text.size() - last.size(), last.size(), last) == 0;
}

}  // namespace

TEST_CASE("matches: an ellipsis stands for any text, everything else must be equal") {
  CHECK(matches("at t = 0.5 (step 2)", "at t = … (step …)"));
  CHECK(matches("abc", "abc"));
  CHECK_FALSE(matches("abcd", "abc"));
  CHECK_FALSE(matches("at t = 0.5 (step 2", "at t = … (step …)"));
  CHECK_FALSE(matches("x at t = 0.5 (step 2)", "at t = … (step …)"));
}

TEST_CASE("error catalogue: every row of docs/errors.md") {
  const fs::path fixtures = fs::path(NPEND_SOURCE_DIR) / "tests" / "data" / "errors";
  const auto rows = read_catalogue(npend::test::read_text(NPEND_SOURCE_DIR "/docs/errors.md"));
  // The classes of bad input the hardening issue lists are all there (a truncated or
  // reformatted table would silently test nothing).
  REQUIRE(rows.size() >= 50);

  int index = 0;
  for (const auto& row : rows) {
    CAPTURE(row.line);
    CAPTURE(row.what);
    CAPTURE(row.args);
    const std::string dir =
        npend::test::temporary_directory("catalogue-" + std::to_string(index++));
    for (const auto& e : fs::directory_iterator(fixtures))
      fs::copy_file(e.path(), fs::path(dir) / e.path().filename());
    const auto before = npend::test::directory_listing(dir);

    const auto r = npend::test::run_shell("cd '" + dir + "' && " + NPEND_CLI_PATH + " " + row.args);
    CHECK(r.exit_code == row.exit_code);
    CHECK(r.out.empty());
    const bool one_line =
        !r.err.empty() && r.err.back() == '\n' && r.err.find('\n') == r.err.size() - 1;
    CHECK_MESSAGE(one_line, r.err);
    const std::string message = one_line ? r.err.substr(0, r.err.size() - 1) : r.err;
    CHECK_MESSAGE(matches(message, row.message), message);
    CHECK(npend::test::directory_listing(dir) == before);
    fs::remove_all(dir);
  }
}
