// Event times located in a sampled series: where an event function g changes sign (paper
// §6.6.3: g = φ_k − c for crossings, g = φ_i − φ_{i+1} for "stretched neighbours").
#pragma once

#include <span>
#include <vector>

namespace npend {

enum class crossing_direction {
  up,    ///< g goes from < 0 to ≥ 0
  down,  ///< g goes from ≥ 0 to < 0
  both,
};

enum class event_interpolation {
  linear,  ///< the straight line between the two samples around the sign change
  cubic,   ///< the cubic through four samples around it (error O(dt⁴) for smooth g)
};

struct event_options {
  crossing_direction direction = crossing_direction::both;
  event_interpolation interpolation = event_interpolation::cubic;
  double t0 = 0;  ///< time of the first sample, s
};

/// The times at which g changes sign, ascending, from its samples g_j = g(t₀ + j dt)
/// (dim N ≥ 2, dt > 0 in s). The time of each sign change between samples j and j+1 is the
/// root there of the linear or cubic interpolant (the cubic uses samples j−1..j+2, shifted
/// inwards at the ends, and falls back to linear for N < 4). This is for sampled data; a
/// simulated trajectory's events are better located on its dense output, and any list of
/// event times can go straight to recurrence_times. Throws std::invalid_argument for N < 2,
/// dt ≤ 0 or not finite, or a non-finite sample.
std::vector<double> event_times(std::span<const double> g, double dt,
                                const event_options& options = {});

}  // namespace npend
