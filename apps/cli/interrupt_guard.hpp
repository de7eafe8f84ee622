// Ctrl-C (SIGINT) and SIGTERM as a flag a long run polls, so it can stop cleanly.
#pragma once

#include <csignal>

namespace npend::cli {

/// While alive, SIGINT and SIGTERM set a flag instead of killing the process; the previous
/// handlers come back on destruction. One at a time.
class interrupt_guard {
 public:
  interrupt_guard();
  ~interrupt_guard();
  interrupt_guard(const interrupt_guard&) = delete;
  interrupt_guard& operator=(const interrupt_guard&) = delete;

  /// Whether a signal arrived since construction.
  bool interrupted() const;
  /// The signal that arrived (0 if none).
  int signal() const;

 private:
  struct sigaction m_old_int {};
  struct sigaction m_old_term {};
};

}  // namespace npend::cli
