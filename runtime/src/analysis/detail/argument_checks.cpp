#include "argument_checks.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace npend::detail {

void require_finite_start(std::span<const double> x0, std::string_view prefix) {
  for (std::size_t i = 0; i < x0.size(); ++i)
    if (!std::isfinite(x0[i]))
      throw std::invalid_argument(
          fmt::format("{}start state entry {} is not finite", prefix, i + 1));
}

void require_finite_series(std::span<const double> series, std::string_view name,
                           std::size_t minimum) {
  if (series.size() < minimum)
    throw std::invalid_argument(
        fmt::format("{} has {} samples; at least {} are needed", name, series.size(), minimum));
  for (std::size_t j = 0; j < series.size(); ++j)
    if (!std::isfinite(series[j]))
      throw std::invalid_argument(fmt::format("{}[{}] is not finite ({})", name, j, series[j]));
}

void require_sample_spacing(double dt) {
  if (!(dt > 0) || !std::isfinite(dt))
    throw std::invalid_argument(fmt::format("dt must be positive and finite, got {}", dt));
}

void require_varying(std::span<const double> series, std::string_view name,
                     std::string_view consequence) {
  if (std::all_of(series.begin(), series.end(), [&](double v) { return v == series[0]; }))
    throw std::invalid_argument(fmt::format("{} is constant: {}", name, consequence));
}

}  // namespace npend::detail
