// A progress bar on stderr for long runs.
#pragma once

#include <chrono>
#include <cstdio>

namespace npend::cli {

/// Shows the progress of a run on a terminal: nothing when the stream is not a terminal,
/// nothing during the first second, then one line (percentage and time left) redrawn at
/// most ten times a second, erased by finish() (or the destructor).
class progress_bar {
 public:
  explicit progress_bar(std::FILE* stream = stderr);
  ~progress_bar();
  progress_bar(const progress_bar&) = delete;
  progress_bar& operator=(const progress_bar&) = delete;

  /// The run has done `done` of `total`. Cheap: it looks at the clock about every 10 ms,
  /// counting calls in between (a fixed count would never show the bar of a run whose calls
  /// are few and slow, like a Lyapunov spectrum's re-orthonormalisations).
  void update(double done, double total);
  /// The calls that follow come at another pace (the next phase of a run, e.g. drawing
  /// frames after integrating): look at the clock at the next call and adapt from there,
  /// instead of counting out the previous phase's many quick calls first.
  void new_pace();
  /// Erases the bar if it was shown.
  void finish();

 private:
  void draw(double fraction, std::chrono::steady_clock::time_point now);

  std::FILE* m_stream;
  bool m_enabled;
  bool m_shown = false;
  unsigned long m_calls = 0, m_next_check = 1, m_stride = 1;
  std::chrono::steady_clock::time_point m_started, m_last_draw, m_last_check;
};

}  // namespace npend::cli
