// write_file_atomically, output_stem and the gnuplot plots every command writes.
#include "input_parsing.hpp"
#include "output_file.hpp"
#include "plotting.hpp"
#include "signal_cleanup.hpp"
#include "support/test_support.hpp"

#include <doctest/doctest.h>

#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <sys/wait.h>
#include <unistd.h>

namespace fs = std::filesystem;
using npend::test::temporary_directory;

namespace {

// Runs `body` with PATH set to `path`, restoring it afterwards.
template <class F>
void with_path(const std::string& path, F body) {
  const std::string saved = std::getenv("PATH") ? std::getenv("PATH") : "";
  ::setenv("PATH", path.c_str(), 1);
  try {
    body();
  } catch (...) {
    ::setenv("PATH", saved.c_str(), 1);
    throw;
  }
  ::setenv("PATH", saved.c_str(), 1);
}

bool is_png(const fs::path& p) { return npend::test::read_text(p).rfind("\x89PNG", 0) == 0; }

}  // namespace

TEST_CASE("write_file_atomically: writes and replaces, leaving only the file") {
  const fs::path dir = temporary_directory("atomic");
  npend::cli::write_file_atomically(dir / "a.csv", "first\n");
  npend::cli::write_file_atomically(dir / "a.csv", "second\n");
  CHECK(npend::test::read_text(dir / "a.csv") == "second\n");
  CHECK(npend::test::directory_listing(dir) == std::vector<std::string>{"a.csv"});
  // The mode of a plain new file (umask applied), not mkstemp's private 0600.
  CHECK((fs::status(dir / "a.csv").permissions() & fs::perms::owner_read) != fs::perms::none);
}

TEST_CASE("write_file_atomically: a failure leaves the target and no temporary") {
  const fs::path dir = temporary_directory("atomic-fail");
  CHECK_THROWS_WITH_AS(npend::cli::write_file_atomically(dir / "missing" / "a.csv", "x"),
                       doctest::Contains("cannot create a file in"),
                       std::runtime_error);
  {
    // A folder appearing under the name while the output is written: the rename fails.
    npend::cli::atomic_output_file file(dir / "busy.csv");
    std::fputs("x", file.stream());
    fs::create_directories(dir / "busy.csv" / "inside");
    CHECK_THROWS_WITH_AS(file.commit(), doctest::Contains("cannot rename the output to"),
                         std::runtime_error);
  }
  CHECK(fs::is_directory(dir / "busy.csv" / "inside"));
  CHECK(npend::test::directory_listing(dir) == std::vector<std::string>{"busy.csv"});
  // A folder there from the start is refused before any work is done.
  CHECK_THROWS_WITH_AS(npend::cli::write_file_atomically(dir / "busy.csv", "x"),
                       doctest::Contains("names a directory, not a file"), std::runtime_error);
  CHECK(npend::test::directory_listing(dir) == std::vector<std::string>{"busy.csv"});
}

namespace {

// Forks a child that opens an atomic output in `dir`, writes to it and dies of SIGINT before
// committing; returns the child's wait status.
int die_while_writing(const fs::path& dir, bool with_cleanup) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    if (with_cleanup) npend::cli::remove_temporaries_on_signal();
    npend::cli::atomic_output_file file(dir / "out.csv");
    std::fputs("t,x\n0,1\n", file.stream());
    std::fflush(file.stream());
    ::raise(SIGINT);
    ::_exit(0);  // not reached: the signal kills the child
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  return status;
}

}  // namespace

TEST_CASE("remove_temporaries_on_signal: a SIGINT while writing leaves no file at all") {
  const fs::path dir = temporary_directory("signal-cleanup");
  const int status = die_while_writing(dir, true);
  REQUIRE(WIFSIGNALED(status));
  CHECK(WTERMSIG(status) == SIGINT);  // it still dies of the signal, as the shell expects
  CHECK(npend::test::directory_listing(dir).empty());
  // Without the handler the same death leaves the hidden temporary behind (so the check above
  // is what the handler does, not what dying does anyway).
  const fs::path other = temporary_directory("signal-no-cleanup");
  REQUIRE(WIFSIGNALED(die_while_writing(other, false)));
  const auto left = npend::test::directory_listing(other);
  REQUIRE(left.size() == 1);
  CHECK(left[0].rfind(".out.csv.npend-", 0) == 0);
}

TEST_CASE("output_stem: a .csv name in an existing directory") {
  const fs::path dir = temporary_directory("stem");
  CHECK(npend::cli::output_stem((dir / "s.csv").string(), "--out") == dir / "s");
  CHECK_THROWS_WITH_AS(npend::cli::output_stem((dir / "s.png").string(), "--out"),
                       doctest::Contains("must be a file name ending in .csv"),
                       npend::cli::input_error);
  CHECK_THROWS_WITH_AS(npend::cli::output_stem((dir / "no" / "s.csv").string(), "--out"),
                       doctest::Contains("--out: directory '"), npend::cli::input_error);
}

TEST_CASE("gnuplot_string: quotes and backslashes are escaped") {
  CHECK(npend::cli::gnuplot_string(R"(a "b" \c)") == R"("a \"b\" \\c")");
}

TEST_CASE("write_plot: a PNG from the kept script, which re-renders it") {
  const fs::path dir = temporary_directory("plot");
  npend::cli::write_file_atomically(dir / "p.csv", "x,y\n0,1\n1,3\n2,2\n");
  npend::cli::figure f;
  f.description = {"a test figure"};
  f.panels.push_back({.title = "title_with_underscores",
                      .xlabel = "x (s)",
                      .ylabel = "y (m)",
                      .curves = {{"p.csv", "1:2", "linespoints", "y"}}});
  const auto outcome = npend::cli::write_plot(dir / "p", f);
  CHECK(outcome.rendered);
  CHECK(outcome.message.find("p.png") != std::string::npos);
  CHECK(is_png(dir / "p.png"));
  CHECK(npend::test::directory_listing(dir) == std::vector<std::string>{"p.csv", "p.gp", "p.png"});
  const std::string script = npend::test::read_text(dir / "p.gp");
  CHECK(script.rfind("# a test figure\n", 0) == 0);
  CHECK(script.find("npend_output = \"p.png\"") != std::string::npos);
  CHECK(script.find("plot \"p.csv\" using 1:2 with linespoints title \"y\"") != std::string::npos);
  // The user's way: gnuplot on the script, in its folder, rewrites the PNG.
  fs::remove(dir / "p.png");
  const std::string command = "cd '" + dir.string() + "' && gnuplot p.gp 2>/dev/null";
  REQUIRE(std::system(command.c_str()) == 0);
  CHECK(is_png(dir / "p.png"));
}

TEST_CASE("write_plot: without gnuplot the script is kept and the outcome says why") {
  const fs::path dir = temporary_directory("no-gnuplot");
  npend::cli::figure f;
  f.panels.push_back({.title = "t", .curves = {{"q.csv", "1:2", "lines", ""}}});
  npend::cli::plot_outcome outcome;
  with_path(temporary_directory("empty-path"),
            [&] { outcome = npend::cli::write_plot(dir / "q", f); });
  CHECK_FALSE(outcome.rendered);
  CHECK(outcome.message.find("gnuplot is not installed") == 0);
  CHECK(npend::test::directory_listing(dir) == std::vector<std::string>{"q.gp"});
}

TEST_CASE("write_plot: a failing script is reported, not thrown, and leaves no PNG") {
  const fs::path dir = temporary_directory("bad-plot");
  npend::cli::figure f;
  f.panels.push_back({.title = "t",
                      .commands = {"set no_such_setting"},
                      .curves = {{"r.csv", "1:2", "lines", ""}}});
  const auto outcome = npend::cli::write_plot(dir / "r", f);
  CHECK_FALSE(outcome.rendered);
  CHECK(outcome.message.find("gnuplot failed") == 0);
  CHECK(npend::test::directory_listing(dir) == std::vector<std::string>{"r.gp"});
}
