#include "workload.hpp"

#include <numbers>
#include <random>

namespace npend::bench {

chain_parameters random_parameters(int links, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> dist(0.5, 2.0);
  chain_parameters params;
  for (int i = 0; i < links; ++i) {
    params.masses.push_back(dist(rng));
    params.lengths.push_back(dist(rng));
  }
  params.g = standard_gravity;
  return params;
}

state_pool::state_pool(int links, std::size_t count_, unsigned seed)
    : state_size(2 * static_cast<std::size_t>(links)), count(count_) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> angle(-std::numbers::pi, std::numbers::pi);
  std::uniform_real_distribution<double> momentum(-3.0, 3.0);
  values.reserve(count * state_size);
  for (std::size_t s = 0; s < count; ++s) {
    for (int i = 0; i < links; ++i) values.push_back(angle(rng));
    for (int i = 0; i < links; ++i) values.push_back(momentum(rng));
  }
}

}  // namespace npend::bench
