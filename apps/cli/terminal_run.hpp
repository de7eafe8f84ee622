// The command line's run control: a progress bar on stderr, and Ctrl-C as a stop request.
#pragma once

#include "interrupt_guard.hpp"
#include "progress_bar.hpp"

#include <npend/run_control.hpp>

#include <stdexcept>
#include <string>

namespace npend::cli {

/// What every long-running command hands to the library as its run control: while alive,
/// SIGINT and SIGTERM stop the computation at its next safe point instead of killing the
/// process (so temporary output files are cleaned up), and the progress shows as a bar on
/// stderr when that is a terminal. One at a time (it owns the signal handlers).
class terminal_run final : public run_control {
 public:
  terminal_run() = default;

  void progress(double done, double total) override { m_bar.update(done, total); }
  bool stop_requested() override { return m_interrupt.interrupted(); }

  /// Erases the progress bar (call before printing results).
  void finish() { m_bar.finish(); }
  /// Whether a signal stopped the run.
  bool interrupted() const { return m_interrupt.interrupted(); }
  /// The exit status of a command stopped by a signal: 128 + the signal's number.
  int exit_code() const { return 128 + m_interrupt.signal(); }

 private:
  interrupt_guard m_interrupt;
  progress_bar m_bar;
};

/// A command stopped by a signal in a computation that has nothing useful to return
/// half-done: `npend` prints "npend <command>: <what>" and exits with exit_code().
class interrupted : public std::runtime_error {
 public:
  interrupted(const std::string& what, int exit_code)
      : std::runtime_error(what), m_exit_code(exit_code) {}
  int exit_code() const { return m_exit_code; }

 private:
  int m_exit_code;
};

}  // namespace npend::cli
