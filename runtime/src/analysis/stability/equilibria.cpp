#include "npend/analysis/stability/equilibria.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <numbers>
#include <stdexcept>

#include "npend/analysis/stability/normal_modes.hpp"

namespace npend {

equilibrium classify_equilibrium(const chain& c, std::vector<double> angles) {
  equilibrium e;
  e.angles = std::move(angles);
  // At p = 0 the Jacobian is [[0, A⁻¹], [−K, 0]]; its eigenvalues λ satisfy λ² = −ω² for
  // the ω² of K v = ω² M v: a pair ±iω per stable mode, ±κ per unstable one.
  for (const normal_mode& mode : normal_modes(c, e.angles).modes) {
    if (mode.omega_squared > 0) {
      e.eigenvalues.emplace_back(0.0, mode.frequency);
      e.eigenvalues.emplace_back(0.0, -mode.frequency);
    } else {
      e.eigenvalues.emplace_back(mode.growth_rate, 0.0);
      e.eigenvalues.emplace_back(-mode.growth_rate, 0.0);
      ++e.unstable_directions;
    }
  }
  e.energy = c.potential_energy(e.angles);
  std::sort(e.eigenvalues.begin(), e.eigenvalues.end(), [](auto a, auto b) {
    return a.real() != b.real() ? a.real() > b.real() : a.imag() > b.imag();
  });
  e.stable = e.unstable_directions == 0;
  return e;
}

std::vector<equilibrium> find_equilibria(const chain& c) {
  const int n = c.links();
  if (c.has_cart())
    throw std::invalid_argument(
        "find_equilibria: the chain is on a cart; the 2^n equilibria are those of a chain on a "
        "fixed pivot (the cart adds a free coordinate)");
  if (n > max_equilibria_links)
    throw std::invalid_argument(fmt::format(
        "find_equilibria: {} links have 2^{} equilibria; at most {} links are supported", n, n,
        max_equilibria_links));
  std::vector<equilibrium> out;
  for (unsigned mask = 0; mask < (1u << n); ++mask) {
    std::vector<double> angles;
    for (int i = 0; i < n; ++i)
      angles.push_back((mask >> (n - 1 - i)) & 1u ? std::numbers::pi : 0.0);
    out.push_back(classify_equilibrium(c, std::move(angles)));
  }
  return out;
}

}  // namespace npend
