#include "progress_bar.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <string>

namespace npend::cli {

progress_bar::progress_bar(std::FILE* stream)
    : m_stream(stream),
      m_enabled(::isatty(::fileno(stream)) == 1),
      m_started(std::chrono::steady_clock::now()),
      m_last_draw(m_started),
      m_last_check(m_started) {}

progress_bar::~progress_bar() { finish(); }

void progress_bar::update(double done, double total) {
  if (!m_enabled || ++m_calls < m_next_check) return;
  const auto now = std::chrono::steady_clock::now();
  // Adapt the number of calls between two looks at the clock to about 10 ms.
  const auto since = now - m_last_check;
  if (since < std::chrono::milliseconds(5) && m_stride < (1ul << 20))
    m_stride *= 2;
  else if (since > std::chrono::milliseconds(20) && m_stride > 1)
    m_stride /= 2;
  m_next_check = m_calls + m_stride;
  m_last_check = now;
  if (now - m_started < std::chrono::seconds(1)) return;
  if (m_shown && now - m_last_draw < std::chrono::milliseconds(100)) return;
  draw(total > 0 ? std::clamp(done / total, 0.0, 1.0) : 0.0, now);
}

void progress_bar::new_pace() {
  m_stride = 1;
  m_next_check = m_calls + 1;
}

void progress_bar::draw(double fraction, std::chrono::steady_clock::time_point now) {
  const double elapsed = std::chrono::duration<double>(now - m_started).count();
  const double remaining = fraction > 0 ? elapsed * (1 - fraction) / fraction : 0;
  constexpr int width = 30;
  const int filled = static_cast<int>(fraction * width);
  fmt::print(m_stream, "\r[{}{}] {:5.1f}%  ~{:.0f} s left ",
             std::string(static_cast<std::size_t>(filled), '#'),
             std::string(static_cast<std::size_t>(width - filled), ' '), 100 * fraction, remaining);
  std::fflush(m_stream);
  m_shown = true;
  m_last_draw = now;
}

void progress_bar::finish() {
  if (!m_shown) return;
  fmt::print(m_stream, "\r\033[K");
  std::fflush(m_stream);
  m_shown = false;
}

}  // namespace npend::cli
