#include "npend/parameters.hpp"

#include "npend/chain_kernels.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

namespace npend {

chain_parameters chain_parameters::uniform(int links, double mass, double length, double g) {
  if (links < 1)
    throw std::invalid_argument(fmt::format("links must be at least 1, got {}", links));
  chain_parameters p;
  p.masses.assign(static_cast<std::size_t>(links), mass);
  p.lengths.assign(static_cast<std::size_t>(links), length);
  p.g = g;
  return p;
}

void chain_parameters::validate() const {
  if (masses.empty()) throw std::invalid_argument("a chain needs at least one link");
  if (lengths.size() != masses.size())
    throw std::invalid_argument(fmt::format("{} masses but {} lengths: give one of each per link",
                                            masses.size(), lengths.size()));
  const auto check = [](const std::vector<double>& values, const char* what) {
    for (std::size_t i = 0; i < values.size(); ++i)
      if (!std::isfinite(values[i]) || values[i] <= 0)
        throw std::invalid_argument(fmt::format("{} {} is {}: it must be a positive finite number",
                                                what, i + 1, values[i]));
  };
  check(masses, "mass");
  check(lengths, "length");
  if (!std::isfinite(g) || g <= 0)
    throw std::invalid_argument(fmt::format("g is {}: it must be a positive finite number", g));
}

std::vector<double> chain_parameters::packed() const {
  const int n = links();
  std::vector<double> out(static_cast<std::size_t>(chain_layout::param_size(n)));
  for (int i = 0; i < n; ++i) {
    out[static_cast<std::size_t>(chain_layout::mass_index(n, i))] = masses[static_cast<std::size_t>(i)];
    out[static_cast<std::size_t>(chain_layout::length_index(n, i))] =
        lengths[static_cast<std::size_t>(i)];
  }
  out[static_cast<std::size_t>(chain_layout::gravity_index(n))] = g;
  return out;
}

}  // namespace npend
