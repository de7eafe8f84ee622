// The command line's run control: a progress bar on stderr, and Ctrl-C as a stop request.
#pragma once

#include <npend/run_control.hpp>
#include <stdexcept>
#include <string>

#include "interrupt_guard.hpp"
#include "progress_bar.hpp"

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

  /// The progress reports that follow come at another pace (progress_bar::new_pace).
  void new_pace() { m_bar.new_pace(); }
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

/// The share [from, to] (fractions, 0 ≤ from < to ≤ 1) of the parent's work that one phase
/// of a run takes, when the phases cost unequally (npend animate: integrating is quick,
/// drawing the frames slow; run_control_part splits equally): maps the phase's progress
/// into it and passes stop requests through. A null parent gives a control that does
/// nothing.
class run_control_share final : public run_control {
 public:
  run_control_share(run_control* parent, double from, double to)
      : m_parent(parent), m_from(from), m_to(to) {}

  void progress(double done, double total) override {
    if (m_parent != nullptr && total > 0)
      m_parent->progress(m_from + (m_to - m_from) * done / total, 1);
  }
  bool stop_requested() override { return npend::stop_requested(m_parent); }

 private:
  run_control* m_parent;
  double m_from, m_to;
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
