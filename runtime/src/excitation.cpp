#include "npend/excitation.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace npend {

namespace {

std::vector<double> checked_direction(const chain& c, std::span<const double> direction,
                                      double default_entry(const chain&, int)) {
  const int n = c.links();
  if (direction.empty()) {
    std::vector<double> out;
    for (int i = 0; i < n; ++i) out.push_back(default_entry(c, i));
    return out;
  }
  if (direction.size() != static_cast<std::size_t>(n))
    throw std::invalid_argument(fmt::format("direction has {} entries; the {}-link chain needs {}",
                                            direction.size(), n, n));
  bool nonzero = false;
  for (double v : direction) {
    if (!std::isfinite(v)) throw std::invalid_argument("direction has a non-finite entry");
    nonzero = nonzero || v != 0;
  }
  if (!nonzero) throw std::invalid_argument("direction is zero: it must have a non-zero entry");
  return {direction.begin(), direction.end()};
}

void check_energy(double energy) {
  if (!std::isfinite(energy))
    throw std::invalid_argument(fmt::format("energy {} J is not finite", energy));
  if (energy < 0)
    throw std::invalid_argument(fmt::format(
        "energy {} J is below the minimum 0 J of the potential (the chain hanging at rest)",
        energy));
}

// The common mass and length of a chain whose links are all alike.
std::pair<double, double> uniform_link(const chain& c) {
  const auto& m = c.parameters().masses;
  const auto& l = c.parameters().lengths;
  const auto all_equal = [](const std::vector<double>& v) {
    return std::all_of(v.begin(), v.end(), [&](double x) { return x == v.front(); });
  };
  if (!all_equal(m) || !all_equal(l))
    throw std::invalid_argument(
        "epsilon = E/(m g l) is defined for equal masses and equal lengths only");
  return {m.front(), l.front()};
}

double potential_along(const chain& c, const std::vector<double>& u, double s) {
  std::vector<double> phi(u);
  for (double& v : phi) v *= s;
  return c.potential_energy(phi);
}

double max_deflection_scale(const std::vector<double>& u) {
  double largest = 0;
  for (double v : u) largest = std::max(largest, std::fabs(v));
  return std::numbers::pi / largest;
}

}  // namespace

std::string_view excitation_name(excitation style) {
  return style == excitation::deflection ? "deflection" : "kick";
}

excitation parse_excitation(std::string_view name) {
  if (name == "deflection") return excitation::deflection;
  if (name == "kick") return excitation::kick;
  throw std::invalid_argument(
      fmt::format("unknown excitation '{}': choose one of deflection, kick", name));
}

double energy_from_epsilon(const chain& c, double epsilon) {
  if (!std::isfinite(epsilon)) throw std::invalid_argument("epsilon is not finite");
  const auto [m, l] = uniform_link(c);
  return epsilon * m * c.parameters().g * l;
}

double epsilon_from_energy(const chain& c, double energy) {
  if (!std::isfinite(energy)) throw std::invalid_argument("energy is not finite");
  const auto [m, l] = uniform_link(c);
  return energy / (m * c.parameters().g * l);
}

double max_deflection_energy(const chain& c, std::span<const double> direction) {
  const auto u = checked_direction(c, direction, [](const chain&, int) { return 1.0; });
  return potential_along(c, u, max_deflection_scale(u));
}

std::vector<double> deflected_state(const chain& c, double energy,
                                    std::span<const double> direction) {
  check_energy(energy);
  const auto u = checked_direction(c, direction, [](const chain&, int) { return 1.0; });
  double hi = max_deflection_scale(u);
  const double reachable = potential_along(c, u, hi);
  // The top itself counts, whichever way rounding went in computing it.
  if (energy > reachable * (1 + 1e-12))
    throw std::invalid_argument(fmt::format(
        "energy {} J is out of reach of a deflection from rest: at most {:.6g} J, with an arm "
        "pointing straight up; use a kick for higher energies",
        energy, reachable));
  // Bisection on [0, s_max] to adjacent doubles: V(s·u) is monotonic there.
  double lo = 0;
  while (energy < reachable) {
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    (potential_along(c, u, mid) < energy ? lo : hi) = mid;
  }
  const double s =
      std::fabs(potential_along(c, u, lo) - energy) <= std::fabs(potential_along(c, u, hi) - energy)
          ? lo
          : hi;
  std::vector<double> x(u);
  for (double& v : x) v *= s;
  x.resize(static_cast<std::size_t>(c.state_size()), 0.0);
  return x;
}

std::vector<double> kicked_state(const chain& c, double energy, std::span<const double> direction) {
  check_energy(energy);
  const auto d = checked_direction(c, direction, [](const chain& ch, int i) {
    return ch.parameters().lengths[static_cast<std::size_t>(i)];
  });
  const auto n = static_cast<std::size_t>(c.links());
  std::vector<double> x(2 * n, 0.0);
  std::copy(d.begin(), d.end(), x.begin() + static_cast<std::ptrdiff_t>(n));
  const double unit = c.hamiltonian(x);  // ½ dᵀA(0)⁻¹d > 0: A is positive definite
  const double s = std::sqrt(energy / unit);
  for (std::size_t i = n; i < 2 * n; ++i) x[i] *= s;
  return x;
}

std::vector<double> excited_state(const chain& c, double energy, excitation style) {
  return style == excitation::deflection ? deflected_state(c, energy) : kicked_state(c, energy);
}

}  // namespace npend
