// Run-time parameters of an n-link chain: masses, lengths and g.
#pragma once

#include <vector>

namespace npend {

/// Standard gravity, the default g (m/s²).
inline constexpr double standard_gravity = 9.81;

/// Masses m_1..m_n (kg), rod lengths l_1..l_n (m) and gravity g (m/s²) of an n-link chain.
/// The generated kernels take them packed as [m_1..m_n, l_1..l_n, g] (dim 2n + 1).
struct chain_parameters {
  std::vector<double> masses;
  std::vector<double> lengths;
  double g = standard_gravity;

  /// n equal links: the paper's setting.
  static chain_parameters uniform(int links, double mass = 1.0, double length = 1.0,
                                  double g = standard_gravity);

  /// The link count n (= masses.size()).
  int links() const { return static_cast<int>(masses.size()); }

  /// Throws std::invalid_argument naming the problem: no links, masses and lengths of
  /// different counts, a non-finite or non-positive mass, length or g.
  void validate() const;

  /// [m_1..m_n, l_1..l_n, g] (dim 2n + 1).
  std::vector<double> packed() const;
};

}  // namespace npend
