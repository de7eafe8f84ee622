// parse_csv, signals_from_csv and select_signal: the reading of users' time series.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include "csv_table.hpp"
#include "input_parsing.hpp"
#include "time_series_source.hpp"

using npend::cli::input_error;
using npend::cli::parse_csv;
using npend::cli::select_signal;
using npend::cli::signals_from_csv;

namespace {

std::string error_of(auto f) {
  try {
    f();
  } catch (const input_error& e) {
    return e.what();
  }
  return "no input_error";
}

}  // namespace

TEST_CASE("parse_csv: header, comments, blank lines, CRLF, spaces and quotes") {
  const auto t = parse_csv(
      "# measured 2024\r\n\"t\", angle \r\n\r\n0, 1.5\r\n0.1,-2e-3\n  # note\n0.2 ,+3\n", "a.csv");
  CHECK(t.names == std::vector<std::string>{"t", "angle"});
  REQUIRE(t.columns.size() == 2);
  CHECK(t.columns[0] == std::vector<double>{0, 0.1, 0.2});
  CHECK(t.columns[1] == std::vector<double>{1.5, -2e-3, 3});
  CHECK(t.lines == std::vector<std::size_t>{4, 5, 7});
}

TEST_CASE("parse_csv: a first line of numbers is data, not a header") {
  const auto t = parse_csv("1,2\n3,4", "b.csv");
  CHECK(t.names.empty());
  CHECK(t.columns[1] == std::vector<double>{2, 4});
}

TEST_CASE("parse_csv: whitespace-separated files read as their comma-separated twins") {
  // TISEAN's and most data loggers' format: runs of spaces and tabs, with or without a
  // header, comments allowed.
  const auto comma = parse_csv("t,x,y\n0,1.5,-2\n0.1,-2e-3,4\n0.2,3,5\n", "c.csv");
  const auto spaced =
      parse_csv("# logger v2\n t   x \t y\n0 1.5  -2\n0.1\t-2e-3\t4\n  0.2 3 5  \r\n", "w.dat");
  CHECK(spaced.names == comma.names);
  CHECK(spaced.columns == comma.columns);
  const auto bare = parse_csv("0 1.5 -2\n0.1 -2e-3 4\n0.2 3 5\n", "b.dat");
  CHECK(bare.names.empty());
  CHECK(bare.columns == comma.columns);
  CHECK(bare.lines == std::vector<std::size_t>{1, 2, 3});
  // A single column has no separator at all: the same either way.
  CHECK(parse_csv("x\n1\n2\n", "s.dat").columns == std::vector<std::vector<double>>{{1, 2}});
  CHECK(error_of([] { parse_csv("1 2 3\n4 5\n", "d.dat"); }) ==
        "d.dat:2: 2 cells, but the first line has 3");
  CHECK(error_of([] { parse_csv("t x\n0 1\n0.1 abc\n", "d.dat"); }) ==
        "d.dat:3: column 'x': 'abc' is not a number");
}

TEST_CASE("parse_csv: every malformed input gets a one-line message with its line") {
  CHECK(error_of([] { parse_csv("t,x\n0,1\n0.1,abc\n", "d.csv"); }) ==
        "d.csv:3: column 'x': 'abc' is not a number");
  CHECK(error_of([] { parse_csv("1,2\n3\n", "d.csv"); }) ==
        "d.csv:2: 1 cells, but the first line has 2");
  CHECK(error_of([] { parse_csv("1,,2\n", "d.csv"); }) == "d.csv:1: column 2: empty cell");
  CHECK(error_of([] { parse_csv("t,x\n# nothing\n", "d.csv"); }) == "d.csv: no data rows");
  CHECK(error_of([] { parse_csv("", "d.csv"); }) == "d.csv: no data rows");
  CHECK(error_of([] { parse_csv("x,x\n1,2\n", "d.csv"); }) ==
        "d.csv:1: column name 'x' appears twice");
  CHECK(error_of([] { parse_csv("t,,x\n1,2,3\n", "d.csv"); }) == "d.csv:1: header cell 2 is empty");
  CHECK(error_of([] { parse_csv("t,x\n0,1e999\n", "d.csv"); }) ==
        "d.csv:2: column 'x': '1e999' is out of the range of a double");
}

TEST_CASE("format_csv: a header and shortest round-trip numbers") {
  const std::vector<std::string> names{"a", "b"};
  const std::vector<std::vector<double>> columns{{0.1, 1e-300}, {2, -3.25}};
  const std::string text = npend::cli::format_csv(names, columns);
  CHECK(text == "a,b\n0.1,2\n1e-300,-3.25\n");
  const auto back = parse_csv(text, "round trip");
  CHECK(back.columns == columns);
}

TEST_CASE("signals_from_csv: the time column gives t0 and dt, the others are signals") {
  const auto t = parse_csv("x,Time (s),y\n1,2.0,5\n2,2.5,6\n3,3.0,7\n4,3.5,8\n", "c.csv");
  const auto s = signals_from_csv(t, "c.csv", std::nullopt, 4);
  CHECK(s.dt == 0.5);
  CHECK(s.t0 == 2.0);
  CHECK(s.time_name == "Time (s)");
  CHECK(s.names == std::vector<std::string>{"x", "y"});
  CHECK(s.numbers == std::vector<std::size_t>{1, 3});
  CHECK(s.samples() == 4);
  // --dt agreeing with the time column is accepted, a different one is not.
  CHECK(signals_from_csv(t, "c.csv", 0.5, 4).dt == 0.5);
  CHECK(error_of([&] { signals_from_csv(t, "c.csv", 0.1, 4); }) ==
        "--dt: 0.1 s disagrees with the time column 'Time (s)' of c.csv (dt = 0.5 s)");
  CHECK(error_of([&] { signals_from_csv(t, "c.csv", std::nullopt, 5); }) ==
        "c.csv: 4 samples; at least 5 are needed");
}

TEST_CASE("signals_from_csv: without a time column --dt is required") {
  const auto t = parse_csv("1,5\n2,6\n3,7\n", "n.csv");
  CHECK(error_of([&] { signals_from_csv(t, "n.csv", std::nullopt, 2); }) ==
        "n.csv has no time column (a header named t or time); give the sample spacing with --dt");
  const auto s = signals_from_csv(t, "n.csv", 0.25, 2);
  CHECK(s.dt == 0.25);
  CHECK(s.t0 == 0);
  CHECK(s.names == std::vector<std::string>{"1", "2"});
}

TEST_CASE("signals_from_csv: a non-uniform or non-increasing time column is refused") {
  const auto jitter = parse_csv("t,x\n0,1\n0.1,2\n0.25,3\n0.3,4\n", "j.csv");
  CHECK(error_of([&] { signals_from_csv(jitter, "j.csv", std::nullopt, 2); }) ==
        "j.csv:4: time column 't' is not uniformly spaced: t = 0.25 is 0.5 steps off the grid t_0 "
        "+ j "
        "dt with dt = 0.1 s (resample the data first)");
  const auto backwards = parse_csv("t,x\n0,1\n0.1,2\n0.1,3\n", "b.csv");
  CHECK(error_of([&] { signals_from_csv(backwards, "b.csv", std::nullopt, 2); }) ==
        "b.csv:4: time column 't' does not increase (0.1 after 0.1)");
  // Rounding in the last printed digit (well under 1% of a step) is fine.
  const auto rounded = parse_csv("t,x\n0,1\n0.333,2\n0.667,3\n1,4\n", "r.csv");
  CHECK(signals_from_csv(rounded, "r.csv", std::nullopt, 2).dt == doctest::Approx(1.0 / 3));
}

TEST_CASE("select_signal: by name, by column number, and helpful refusals") {
  const auto t = parse_csv("t,phi1,phi2\n0,1,4\n1,2,5\n2,3,6\n", "s.csv");
  const auto s = signals_from_csv(t, "s.csv", std::nullopt, 2);
  CHECK(select_signal(s, "", "--column").name == "phi1");
  CHECK(select_signal(s, "phi2", "--column").values == std::vector<double>{4, 5, 6});
  CHECK(select_signal(s, "3", "--column").name == "phi2");
  CHECK(select_signal(s, "2", "--column").dt == 1);
  CHECK(error_of([&] { select_signal(s, "phi3", "--column"); }) ==
        "--column: s.csv has no column 'phi3'; its signals are phi1 (2), phi2 (3)");
  CHECK(error_of([&] { select_signal(s, "1", "--column"); }) ==
        "--column: '1' is the time column of s.csv; choose a signal");
  CHECK(error_of([&] { select_signal(s, "t", "--column"); }) ==
        "--column: 't' is the time column of s.csv; choose a signal");
}

TEST_CASE("parse_csv: a byte order mark, quoted numbers and Fortran D exponents") {
  // A spreadsheet's UTF-8 BOM is no part of the first header name.
  const auto bom = parse_csv("\xEF\xBB\xBFt,x\n0,1\n0.5,2\n", "b.csv");
  CHECK(bom.names == std::vector<std::string>{"t", "x"});
  // "1.5" and '1.5' are numbers; quoted names are names.
  const auto quoted = parse_csv("\"t\",'x'\n\"0\",'1.5'\n\"0.1\", \"-2\"\n", "q.csv");
  CHECK(quoted.names == std::vector<std::string>{"t", "x"});
  CHECK(quoted.columns[1] == std::vector<double>{1.5, -2});
  const auto data = parse_csv("'0','1.5'\n'0.1','2'\n", "q.csv");
  CHECK(data.names.empty());
  CHECK(data.columns[1] == std::vector<double>{1.5, 2});
  // TISEAN's and Fortran's exponents: 1.0D-3 is 1.0e-3, a data row and not a header.
  const auto fortran = parse_csv("1.0D-3 2.5d+2\n-4.D1 +1D0\n", "f.dat");
  CHECK(fortran.names.empty());
  CHECK(fortran.columns[0] == std::vector<double>{1.0e-3, -40});
  CHECK(fortran.columns[1] == std::vector<double>{250, 1});
  // A name with a d stays a name.
  CHECK(parse_csv("dx,d\n1,2\n", "n.csv").names == std::vector<std::string>{"dx", "d"});
}

TEST_CASE("parse_csv: NaN and infinities are kept, the column analysed must be finite") {
  const auto t = parse_csv("t,x,y\n0,1,nan\n0.1,2,-inf\n0.2,3,4\n", "d.csv");
  CHECK(std::isnan(t.columns[2][0]));
  CHECK(t.columns[2][1] == -INFINITY);
  const auto s = signals_from_csv(t, "d.csv", std::nullopt, 2);
  // A NaN in y blocks nothing when x is analysed.
  CHECK(select_signal(s, "x", "--column").values == std::vector<double>{1, 2, 3});
  CHECK(error_of([&] { select_signal(s, "y", "--column"); }) ==
        "--column: column 'y' of d.csv is nan at t = 0 s (data row 1); the columns analysed "
        "must be finite");
  // The time column is always used.
  CHECK(error_of([] {
          signals_from_csv(parse_csv("t,x\n0,1\nnan,2\n", "d.csv"), "d.csv", std::nullopt, 2);
        }) == "d.csv:3: time column 't': nan is not a finite number");
  // A constant column has nothing to analyse.
  const auto c =
      signals_from_csv(parse_csv("t,x,y\n0,1,5\n1,2,5\n", "c.csv"), "c.csv", std::nullopt, 2);
  CHECK(error_of([&] { select_signal(c, "y", "--column"); }) ==
        "--column: 'y' of c.csv is constant (5 in every sample): nothing varies to analyse");
  CHECK(error_of([] {
          signals_from_csv(parse_csv("t,x\n0,1\n", "o.csv"), "o.csv", std::nullopt, 2);
        }) == "o.csv: 1 sample; at least 2 are needed");
}

TEST_CASE("parse_csv: binary data is refused without echoing its bytes") {
  // A NUL or another control character: a binary file, named by its first such byte.
  CHECK(error_of([] { parse_csv(std::string_view("t,x\n0,1\n\x89PNG\x00\x1a", 14), "p.csv"); }) ==
        "p.csv:3: binary data (byte 0x00), not a table of numbers");
  // Bytes that are no UTF-8 but no control characters either: a cell that is not a number,
  // quoted short and escaped.
  const std::string garbage = "t,x\n0," + std::string(400, '\xff') + "\n";
  const std::string message = error_of([&] { parse_csv(garbage, "g.csv"); });
  std::string escaped;
  for (int k = 0; k < 40; ++k) escaped += "\\xff";
  CHECK(message == "g.csv:2: column 'x': '" + escaped + "...' is not a number");
  CHECK(message.size() < 250);
  // UTF-8 text is quoted as it is.
  CHECK(error_of([] { parse_csv("t,x\n0,φ\n", "u.csv"); }) ==
        "u.csv:2: column 'x': 'φ' is not a number");
}

TEST_CASE("read_text_file: a directory, more than the cap, binary data at once") {
  const auto dir = std::filesystem::temp_directory_path() / "npend-read-text-file";
  std::filesystem::create_directories(dir);
  CHECK(error_of([&] { npend::cli::read_text_file(dir.string(), "--input"); }) ==
        "--input: '" + dir.string() + "' is a directory, not a file");
  const auto big = (dir / "big.csv").string();
  {
    std::ofstream out(big);
    out << "t,x\n";
    for (int j = 0; j < 200; ++j) out << j << "," << j * j << "\n";
  }
  CHECK(npend::cli::read_text_file(big, "--input").size() == std::filesystem::file_size(big));
  CHECK(error_of([&] { npend::cli::read_text_file(big, "--input", 1000); }) ==
        "--input: '" + big +
            "' holds more than 1000 bytes, the most npend reads as a table of "
            "numbers");
  // An endless device of random bytes: refused at its first binary byte, not read on.
  const std::string urandom =
      error_of([] { npend::cli::read_text_file("/dev/urandom", "--input"); });
  CHECK(urandom.starts_with("/dev/urandom:"));
  CHECK(urandom.find(": binary data (byte 0x") != std::string::npos);
  std::filesystem::remove_all(dir);
}
