// A progress bar on stderr for long runs.
#pragma once

#include <chrono>
#include <cstdio>

namespace npend::cli {

/// Shows the progress of a run from t_start to t_end on a terminal: nothing when the
/// stream is not a terminal, nothing during the first second, then one line redrawn at
/// most ten times a second, erased by finish() (or the destructor).
class progress_bar {
 public:
  progress_bar(double t_start, double t_end, std::FILE* stream = stderr);
  ~progress_bar();
  progress_bar(const progress_bar&) = delete;
  progress_bar& operator=(const progress_bar&) = delete;

  /// The run has reached time t. Cheap: it looks at the clock about every 10 ms, counting
  /// calls in between (a fixed count would never show the bar of a run whose calls are few
  /// and slow, like a Lyapunov spectrum's re-orthonormalisations).
  void update(double t);
  /// Erases the bar if it was shown.
  void finish();

 private:
  void draw(double t, std::chrono::steady_clock::time_point now);

  double m_t_start, m_t_end;
  std::FILE* m_stream;
  bool m_enabled;
  bool m_shown = false;
  unsigned long m_calls = 0, m_next_check = 1, m_stride = 1;
  std::chrono::steady_clock::time_point m_started, m_last_draw, m_last_check;
};

}  // namespace npend::cli
