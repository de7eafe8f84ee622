// write_file_atomically, output_stem and the gnuplot plots every command writes.
#include <doctest/doctest.h>
#include <fmt/format.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "input_parsing.hpp"
#include "output_file.hpp"
#include "plotting.hpp"
#include "signal_cleanup.hpp"
#include "support/test_support.hpp"

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
                       doctest::Contains("cannot create a file in"), std::runtime_error);
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

// --- Paths an output must not replace, and the modes, limits and checks of what is written.

namespace {

using npend::test::run_npend;
using npend::test::run_shell;

// Every file under `dir`, recursively (hidden ones included), relative to it.
std::vector<std::string> all_files(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    out.push_back(e.path().lexically_relative(dir).string());  // links not followed
  std::sort(out.begin(), out.end());
  return out;
}

std::string quoted(const fs::path& p) { return "'" + p.string() + "'"; }

}  // namespace

TEST_CASE("npend simulate: an --out that is a link, a FIFO or a device is refused, untouched") {
  const fs::path dir = temporary_directory("out-special");
  npend::cli::write_file_atomically(dir / "target.csv", "kept\n");
  fs::create_symlink(dir / "target.csv", dir / "link.csv");
  REQUIRE(::mkfifo((dir / "pipe.csv").c_str(), 0644) == 0);
  const std::string run = "simulate --links 2 --phi 1,1 --t-end 0.1 --out ";
  const auto link = run_npend(run + quoted(dir / "link.csv"));
  CHECK(npend::test::is_input_error(link, "--out: '" + (dir / "link.csv").string() +
                                              "' is a symbolic link: give a regular file "
                                              "path"));
  CHECK(fs::is_symlink(dir / "link.csv"));
  CHECK(npend::test::read_text(dir / "target.csv") == "kept\n");
  const auto fifo = run_npend(run + quoted(dir / "pipe.csv"));
  CHECK(npend::test::is_input_error(fifo, "' is a FIFO: give a regular file path"));
  CHECK(fs::is_fifo(dir / "pipe.csv"));
  const auto device = run_npend(run + "/dev/null");
  CHECK(npend::test::is_input_error(device, "--out: '/dev/null' is a device"));
  CHECK(fs::is_character_file("/dev/null"));
  CHECK(all_files(dir) == std::vector<std::string>{"link.csv", "pipe.csv", "target.csv"});
  // The same refusal in a command whose outputs are a set (the plot's PNG is the link here).
  const auto png = run_npend("rope --links 2,4 --out " + quoted(dir / "link.csv"));
  CHECK(npend::test::is_input_error(png, "is a symbolic link: give a regular file path"));
}

TEST_CASE("npend: an output that is an input or another output of the command is refused") {
  const fs::path dir = temporary_directory("out-is-input");
  const std::string series = "t,x\n0,0\n0.1,1\n0.2,0\n0.3,-1\n0.4,0\n0.5,1\n0.6,0\n0.7,-1\n";
  npend::cli::write_file_atomically(dir / "m.csv", series);
  const auto lyapunov =
      run_npend("lyapunov --input " + quoted(dir / "m.csv") + " --out " + quoted(dir / "m.csv"));
  CHECK(npend::test::is_input_error(lyapunov,
                                    "' is also the input of --input: give the output "
                                    "another path"));
  CHECK(npend::test::read_text(dir / "m.csv") == series);
  // The same file by another name: a hard link.
  fs::create_hard_link(dir / "m.csv", dir / "hard.csv");
  const auto hard =
      run_npend("spectrum --input " + quoted(dir / "hard.csv") + " --out " + quoted(dir / "m.csv"));
  CHECK(npend::test::is_input_error(hard, "is also the input of --input"));
  const std::string chain = "{\"masses\": [1, 1], \"lengths\": [1, 1]}\n";
  npend::cli::write_file_atomically(dir / "lab.json", chain);
  const auto simulate = run_npend("simulate --links 2 --chain " + quoted(dir / "lab.json") +
                                  " --phi 1,1 --t-end 0.1 --out " + quoted(dir / "." / "lab.json"));
  CHECK(npend::test::is_input_error(simulate, "is also the input of --chain"));
  CHECK(npend::test::read_text(dir / "lab.json") == chain);
  const auto animate = run_npend("animate --links 2 --phi 1,1 --t-end 0.1 --frames-csv " +
                                 quoted(dir / "a.gif") + " --out " + quoted(dir / "a.gif"));
  CHECK(npend::test::is_input_error(
      animate, "--frames-csv: '" + (dir / "a.gif").string() +
                   "' is also the output of --out: give each output its own path"));
  CHECK(all_files(dir) == std::vector<std::string>{"hard.csv", "lab.json", "m.csv"});
}

TEST_CASE("write_file_atomically: threads writing at once keep the umask and its modes") {
  // Reading the umask used to mean setting it to 0 and back: two threads doing so at once
  // could leave it 0 for good, and every later file 0666 (in 4 of 5 runs of this test).
  const fs::path dir = temporary_directory("umask-threads");
  const mode_t saved = ::umask(077);
  std::vector<std::thread> threads;
  for (int t = 0; t < 8; ++t)
    threads.emplace_back([&dir, t] {
      for (int k = 0; k < 400; ++k)
        npend::cli::write_file_atomically(dir / fmt::format("{}_{}.csv", t, k), "x\n",
                                          npend::cli::durability::cached);
    });
  for (auto& thread : threads) thread.join();
  const mode_t after = ::umask(saved);
  CHECK(after == 077);
  int files = 0, other_modes = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    ++files;
    if (e.status().permissions() != (fs::perms::owner_read | fs::perms::owner_write)) ++other_modes;
  }
  CHECK(files == 8 * 400);
  CHECK(other_modes == 0);
}

TEST_CASE("npend map: files written by two threads get the mode the umask gives (0600)") {
  // The command-line view of the test above (which strikes the race far more often).
  for (int run = 0; run < 2; ++run) {
    const fs::path dir = temporary_directory("umask-map-" + std::to_string(run));
    const auto r = run_shell("umask 077; " + std::string(NPEND_CLI_PATH) +
                             " map --links 2 --x phi1:-3:3:16 --y phi2:-3:3:16 --t-end 2 "
                             "--tile 2 --threads 2 --out " +
                             quoted(dir / "m"));
    REQUIRE(r.exit_code == 0);
    const auto files = all_files(dir / "m");
    REQUIRE(files.size() >= 4);
    for (const auto& name : files) {
      INFO(name);
      if (fs::is_directory(dir / "m" / name)) continue;
      CHECK(fs::status(dir / "m" / name).permissions() ==
            (fs::perms::owner_read | fs::perms::owner_write));
    }
  }
}

TEST_CASE("npend: a write beyond the file-size limit fails with its reason and leaves nothing") {
  // ulimit -f counts 1024-byte blocks in bash: 8 KiB, less than any of these outputs.
  const auto limited = [](const std::string& args) {
    return run_shell("bash -c 'ulimit -f 8; exec " + std::string(NPEND_CLI_PATH) + " " + args +
                     "'");
  };
  const fs::path dir = temporary_directory("file-size-limit");
  // Before SIGXFSZ was ignored the signal killed npend (status 153 from the shell) and left
  // the hidden temporary file; the error then read "Success" (errno lost).
  const auto simulate =
      limited("simulate --links 2 --phi 1,1 --t-end 20 --out " + quoted(dir / "traj.csv"));
  CHECK(simulate.exit_code == 1);
  CHECK(simulate.err == "npend simulate: error: writing '" + (dir / "traj.csv").string() +
                            "' failed: File too large\n");
  CHECK(all_files(dir).empty());
  // rope: the CSVs and the script fit, gnuplot's PNG does not (gnuplot still exits with 0).
  const auto rope = limited("rope --links 2,4,8 --out " + quoted(dir / "r.csv"));
  CHECK(rope.exit_code == 1);
  CHECK(rope.err.find("writing '" + (dir / "r.png").string() + "' failed: the PNG is cut short") !=
        std::string::npos);
  CHECK(all_files(dir).empty());  // all files or none: the CSVs that fitted are gone too
  const auto gif = limited("animate --links 2 --phi 1,1 --t-end 2 --out " + quoted(dir / "a.gif"));
  CHECK(gif.exit_code == 1);
  CHECK(gif.err.find("writing '" + (dir / "a.gif").string() + "' failed: ") != std::string::npos);
  CHECK(all_files(dir).empty());
  const auto map = limited(
      "map --links 2 --x phi1:-3:3:40 --y phi2:-3:3:40 --t-end 0.5 "
      "--threads 2 --out " +
      quoted(dir / "m"));
  CHECK(map.exit_code == 1);
  CHECK(map.err.find("failed") != std::string::npos);
  // The tiles stay for --resume; none of the result files is there.
  for (const char* name : {"map.npy", "map.json", "map.png", "map.gp", "map.csv"})
    CHECK_FALSE(fs::exists(dir / "m" / name));
  for (const auto& name : all_files(dir / "m")) CHECK(name.find(".npend-") == std::string::npos);
}

TEST_CASE("check_written_image: complete files pass, files cut short are refused") {
  const fs::path dir = temporary_directory("written-images");
  const auto write = [&](const std::string& name, const std::string& bytes) {
    std::ofstream(dir / name, std::ios::binary) << bytes;
    return dir / name;
  };
  using npend::cli::check_written_image;
  using npend::cli::image_format;
  // A PNG: the signature, then chunks; the last is IEND (length 0, its fixed CRC).
  const std::string png_start = "\x89PNG\r\n\x1a\n";
  const std::string iend("\0\0\0\0IEND\xae\x42\x60\x82", 12);
  CHECK_NOTHROW(check_written_image(write("a.png", png_start + iend), "a.png", image_format::png));
  CHECK_THROWS_WITH_AS(
      check_written_image(write("b.png", png_start + iend.substr(0, 11)), "b.png",
                          image_format::png),
      "writing 'b.png' failed: the PNG is cut short (no IEND chunk at its end) (disk full, or over "
      "the file-size limit?)",
      npend::cli::write_error);
  CHECK_THROWS_AS(check_written_image(write("c.png", ""), "c.png", image_format::png),
                  npend::cli::write_error);
  CHECK_THROWS_AS(check_written_image(dir / "missing.png", "m.png", image_format::png),
                  npend::cli::write_error);
  // A GIF ends with the trailer byte 0x3B.
  const std::string gif = std::string("GIF89a") + std::string(10, '\0') + "\x3b";
  CHECK_NOTHROW(check_written_image(write("a.gif", gif), "a.gif", image_format::gif));
  CHECK_THROWS_AS(check_written_image(write("b.gif", gif.substr(0, gif.size() - 1)), "b.gif",
                                      image_format::gif),
                  npend::cli::write_error);
  // An MP4: boxes (32-bit big-endian size, 4-letter type) that fill the file exactly.
  const auto box = [](const std::string& type, const std::string& body) {
    const std::size_t n = 8 + body.size();
    return std::string{static_cast<char>(n >> 24), static_cast<char>(n >> 16),
                       static_cast<char>(n >> 8), static_cast<char>(n)} +
           type + body;
  };
  const std::string mp4 = box("ftyp", "isom0000") + box("moov", "xxxx") + box("mdat", "data");
  CHECK_NOTHROW(check_written_image(write("a.mp4", mp4), "a.mp4", image_format::mp4));
  CHECK_THROWS_WITH_AS(check_written_image(write("b.mp4", mp4.substr(0, mp4.size() - 1)), "b.mp4",
                                           image_format::mp4),
                       doctest::Contains("the MP4 is incomplete: its mdat box is cut short"),
                       npend::cli::write_error);
  CHECK_THROWS_WITH_AS(check_written_image(write("c.mp4", box("ftyp", "isom") + box("mdat", "")),
                                           "c.mp4", image_format::mp4),
                       doctest::Contains("it has no moov box"), npend::cli::write_error);
}

TEST_CASE("output_batch: the files appear together at commit_all, or none of them") {
  const fs::path dir = temporary_directory("output-batch");
  {
    npend::cli::output_batch batch;
    npend::cli::write_file_atomically(dir / "a.csv", "a\n");
    npend::cli::write_file_atomically(dir / "b.csv", "b\n");
    // Not there yet, but readable under the name the batch gives.
    CHECK_FALSE(fs::exists(dir / "a.csv"));
    CHECK(npend::test::read_text(npend::cli::output_batch::readable_name(dir / "a.csv")) == "a\n");
    batch.commit_all();
  }
  CHECK(all_files(dir) == std::vector<std::string>{"a.csv", "b.csv"});
  {
    npend::cli::output_batch batch;
    npend::cli::write_file_atomically(dir / "a.csv", "new\n");
    npend::cli::write_file_atomically(dir / "c.csv", "c\n");
  }  // no commit_all: an error or an interrupt
  CHECK(all_files(dir) == std::vector<std::string>{"a.csv", "b.csv"});
  CHECK(npend::test::read_text(dir / "a.csv") == "a\n");
}

TEST_CASE("npend: an output nobody can create is refused before the computation (exit 2)") {
  // /proc takes no new files, not even from root (which every permission bit lets through).
  for (const std::string& args :
       {std::string("floquet --links 1 --pivot vertical:0.05:100 --scan 50:100:400"),
        std::string("partition --links 2 --scan 0.5:20:40"),
        std::string("lyapunov --links 2 --phi 1,1 --t-end 200")}) {
    INFO(args);
    const auto r = run_npend(args + " --out /proc/npend-out.csv");
    CHECK(npend::test::is_input_error(r, "--out: cannot create a file in '/proc': "));
  }
}

TEST_CASE("npend: an input that is a folder is refused, naming the option") {
  const fs::path dir = temporary_directory("input-folder");
  CHECK(npend::test::is_input_error(
      run_npend("eval --links 2 --chain " + quoted(dir) + " --state 0,0,0,0"),
      "--chain: '" + dir.string() + "' is a directory, not a file"));
  CHECK(npend::test::is_input_error(run_npend("spectrum --input " + quoted(dir)),
                                    "--input: '" + dir.string() + "' is a directory, not a file"));
  // A tile of a resumed map that is a folder.
  const std::string map =
      "map --links 2 --x phi1:-3:3:4 --y phi2:-3:3:4 --t-end 0.2 --tile 2 --out " +
      quoted(dir / "m");
  REQUIRE(run_npend(map + " --part 1/2").exit_code == 0);
  const auto tiles = all_files(dir / "m" / "tiles");
  REQUIRE(std::find(tiles.begin(), tiles.end(), "tile_000001.bin") == tiles.end());
  fs::create_directories(dir / "m" / "tiles" / "tile_000001.bin");
  const auto r = run_npend(map + " --resume");
  CHECK(npend::test::is_input_error(r, "tile_000001.bin is a directory, not a tile file"));
}
