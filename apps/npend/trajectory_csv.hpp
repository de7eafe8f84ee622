// The trajectory as `npend simulate` writes it, CSV: t, φ_i, p_i, H, then the bob positions
// x_i, y_i, and with tensions the rod tensions τ_i. `npend explore` serves the same rows.
#pragma once

#include <fmt/format.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <iterator>
#include <span>
#include <string>
#include <vector>

#include "input_parsing.hpp"
#include "npend/analysis/motion/rod_tensions.hpp"
#include "npend/chain.hpp"
#include "output_file.hpp"

namespace npend::app {

/// --every K: write every K-th output step (1 when empty). Throws cli::input_error.
inline std::size_t parse_every(const std::string& text) {
  if (text.empty()) return 1;
  const double k = cli::parse_number(text, "--every");
  if (!cli::is_whole_number(k, 1, 1e15))
    throw cli::input_error(fmt::format("--every: must be a whole number >= 1, got {}", text));
  return static_cast<std::size_t>(k);
}

/// Rows to `stream`, buffered; `flush` writes what is left.
class trajectory_csv {
 public:
  // `name`: the file for messages ("stdout" for the stream of that name).
  trajectory_csv(const chain& c, std::FILE* stream, std::string name, bool tensions)
      : m_chain(c),
        m_stream(stream),
        m_name(std::move(name)),
        m_xy(static_cast<std::size_t>(2 * c.points())),
        m_tau(tensions ? static_cast<std::size_t>(c.links()) : 0) {}

  void header() {
    const int n = m_chain.links();
    m_buffer += "t";
    if (m_chain.has_cart()) m_buffer += ",x_c";
    for (int i = 1; i <= n; ++i) fmt::format_to(std::back_inserter(m_buffer), ",phi_{}", i);
    if (m_chain.has_cart()) m_buffer += ",p_x";
    for (int i = 1; i <= n; ++i) fmt::format_to(std::back_inserter(m_buffer), ",p_{}", i);
    m_buffer += ",H";
    if (m_chain.has_cart()) m_buffer += ",cart_x,cart_y";
    for (int i = 1; i <= n; ++i) fmt::format_to(std::back_inserter(m_buffer), ",x_{0},y_{0}", i);
    if (!m_tau.empty())
      for (int i = 1; i <= n; ++i) fmt::format_to(std::back_inserter(m_buffer), ",tau_{}", i);
    m_buffer += '\n';
  }

  // Numbers in the shortest form that reads back to the same double.
  void row(double t, std::span<const double> x, double energy) {
    m_chain.positions(x.first(static_cast<std::size_t>(m_chain.coordinates())), m_xy);
    auto out = std::back_inserter(m_buffer);
    fmt::format_to(out, "{}", t);
    for (double v : x) fmt::format_to(out, ",{}", v);
    fmt::format_to(out, ",{}", energy);
    for (double v : m_xy) fmt::format_to(out, ",{}", v);
    if (!m_tau.empty()) {
      rod_tensions(m_chain, x, m_tau);
      for (double v : m_tau) fmt::format_to(out, ",{}", v);
    }
    m_buffer += '\n';
    if (m_buffer.size() > (1u << 16)) flush();
  }

  // A failed write (a full disk, the file-size limit) ends the run at once, with its reason:
  // the stream's error flag alone would only show at the end, with errno long overwritten.
  void flush() {
    errno = 0;
    if (std::fwrite(m_buffer.data(), 1, m_buffer.size(), m_stream) != m_buffer.size())
      throw cli::write_error(fmt::format("writing {} failed: {}", m_name,
                                         errno != 0 ? std::strerror(errno) : "disk full?"));
    m_buffer.clear();
  }

 private:
  const chain& m_chain;
  std::FILE* m_stream;
  std::string m_name;
  std::vector<double> m_xy, m_tau;
  std::string m_buffer;
};

}  // namespace npend::app
