// Running the external programs the commands draw and encode with (gnuplot, ffmpeg): one
// way to start them, feed them, collect what they print and stop them when a run is
// interrupted.
#pragma once

#include <sys/types.h>

#include <csignal>
#include <cstdio>
#include <filesystem>
#include <npend/run_control.hpp>
#include <string>
#include <string_view>
#include <vector>

namespace npend::cli {

/// How a program ended.
struct program_result {
  /// Its exit status; 127 when it could not be started (not installed), -1 when a signal
  /// ended it (or it could not be started at all).
  int status = -1;
  /// What it printed on stdout and stderr.
  std::string output;

  /// The last non-empty line of the output: where gnuplot and ffmpeg put their reason.
  std::string last_line() const;
};

/// A program started in `dir` with argv (argv[0] looked up in PATH). Its stdout and stderr
/// go to an anonymous temporary file, read back by finish(): a pipe that nobody drains
/// while we are writing to the program's stdin would block both sides. With `piped_input`
/// its stdin is a pipe that write() feeds (gnuplot reading a script as it is written, so
/// the writer sees how far it got); otherwise /dev/null.
class child_process {
 public:
  /// Throws std::runtime_error if the pipe, the temporary file or the fork fails; a program
  /// that is not installed shows as status 127 from finish().
  child_process(const std::vector<std::string>& argv, const std::filesystem::path& dir,
                bool piped_input);
  /// Kills (SIGTERM) and reaps a program still running.
  ~child_process();
  child_process(const child_process&) = delete;
  child_process& operator=(const child_process&) = delete;

  /// Writes `text` to the program's stdin. Returns false if the program no longer reads
  /// (it ended or closed its stdin), or if `control` asks to stop while the write waits.
  bool write(std::string_view text, run_control* control = nullptr);

  /// Closes its stdin and waits for it to end. If `control` asks to stop meanwhile, the
  /// program is sent SIGTERM (its status then reads -1).
  program_result finish(run_control* control = nullptr);

 private:
  void close_input() noexcept;

  pid_t m_pid = -1;
  int m_input = -1;               ///< write end of the stdin pipe, or -1
  std::FILE* m_output = nullptr;  ///< the anonymous file holding stdout and stderr
  struct sigaction m_old_sigpipe {};
};

/// Runs the program to its end (stdin /dev/null) and returns its status and output.
program_result run_program(const std::vector<std::string>& argv,
                           const std::filesystem::path& dir = ".", run_control* control = nullptr);

}  // namespace npend::cli
