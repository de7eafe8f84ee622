// The inputs every benchmark and agreement check uses: a chain with unequal masses and
// lengths, and a pool of random states, all from fixed seeds so that runs compare.
#pragma once

#include <cstddef>
#include <vector>

#include "npend/parameters.hpp"

namespace npend::bench {

/// Masses uniform in [0.5, 2] kg, lengths uniform in [0.5, 2] m, g = 9.81 m/s².
chain_parameters random_parameters(int links, unsigned seed);

/// `count` states of dim 2n, stored one after another: angles uniform in [−π, π] rad,
/// momenta uniform in [−3, 3] kg m²/s.
struct state_pool {
  state_pool(int links, std::size_t count, unsigned seed);

  const double* state(std::size_t i) const { return values.data() + i * state_size; }

  std::size_t state_size;
  std::size_t count;
  std::vector<double> values;
};

}  // namespace npend::bench
