// The mean of independent estimates and its standard error (private to the runtime): block
// means of a run, replicas of a randomised rule.
#pragma once

#include <cmath>
#include <span>

namespace npend::detail {

struct mean_with_error {
  double mean = 0;
  double standard_error = 0;  ///< s / √m, s the sample standard deviation of the m values
};

/// Needs at least two values.
inline mean_with_error mean_and_standard_error(std::span<const double> values) {
  const double m = static_cast<double>(values.size());
  double mean = 0;
  for (const double v : values) mean += v;
  mean /= m;
  double squares = 0;
  for (const double v : values) squares += (v - mean) * (v - mean);
  return {mean, std::sqrt(squares / (m - 1) / m)};
}

}  // namespace npend::detail
