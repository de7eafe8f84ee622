// A whole-number option in a range, shared by `npend backbone` and `npend corrections`.
#pragma once

#include <fmt/format.h>

#include <cmath>
#include <string>

#include "input_parsing.hpp"

namespace npend::app {

/// The whole number in [low, high] typed for `option`; throws cli::input_error naming the
/// option and the range otherwise.
inline double whole_number(const std::string& text, const char* option, double low, double high) {
  const double k = cli::parse_number(text, option);
  if (k != std::floor(k) || k < low || k > high)
    throw cli::input_error(
        fmt::format("{}: must be a whole number in {:g}..{:g}, got {}", option, low, high, text));
  return k;
}

}  // namespace npend::app
