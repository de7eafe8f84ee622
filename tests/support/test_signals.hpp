// Signals with known answers for the time-series analyses: sums of sines, the Hénon map, the
// Lorenz system, and a chain trajectory (classic RK4 until the runtime's integrators land).
#pragma once

#include <cstddef>
#include <vector>

#include "npend/chain.hpp"

namespace npend::test {

struct sine_component {
  double amplitude, omega, phase;  // a sin(ω t + phase), ω in rad/s
};

/// x_j = offset + Σ a sin(ω t_j + phase), t_j = j dt.
std::vector<double> sum_of_sines(const std::vector<sine_component>& components, std::size_t n,
                                 double dt, double offset = 0);

/// The x-coordinate of the Hénon map x' = 1 − 1.4 x² + y, y' = 0.3 x (after a transient).
std::vector<double> henon_x(std::size_t n);

/// x(t) of the Lorenz system (σ = 10, ρ = 28, β = 8/3) sampled every dt, integrated by RK4
/// with step dt after a transient of 20 time units.
std::vector<double> lorenz_x(std::size_t n, double dt);

/// The chain's state x(t_j), t_j = j dt, j = 0..n−1 (rows of 2n), by classic RK4 with step dt.
std::vector<std::vector<double>> rk4_trajectory(const chain& c, std::vector<double> x0,
                                                std::size_t n, double dt);

}  // namespace npend::test
