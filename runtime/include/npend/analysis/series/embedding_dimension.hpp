// The minimal embedding dimension of a scalar series: false nearest neighbours (Kennel,
// Brown & Abarbanel 1992) and Cao's method (Cao 1997). Neighbours are found with a k-d tree.
//
// Both test the vectors y_j(m) = (x_j, x_{j+τ}, …, x_{j+(m−1)τ}) by the coordinate that
// dimension m + 1 adds, x_{j+mτ}, as Kennel et al. and Cao do. This is the same set of points
// as the paper's (x(t), x(t−τ), …) up to the order of coordinates; what matters is that the
// added coordinate lies in the future, where neighbours separate at the largest Lyapunov
// exponent. (Adding x(t − mτ) instead makes true neighbours of a dissipative flow separate at
// its most negative exponent run backwards — e^{14.5 t} for Lorenz — and flags them false.)
#pragma once

#include <cstddef>
#include <span>
#include <vector>

namespace npend {

struct false_neighbours_options {
  double distance_ratio = 15;  ///< R_tol: false if the new coordinate's gap exceeds R_tol · R_m
  double attractor_ratio = 2;  ///< A_tol: false if R_{m+1} exceeds A_tol · σ_x
  /// Neighbours closer in time than this many samples (|i − j| ≤ w) are not considered.
  std::size_t theiler_window = 0;
  double threshold = 0.01;  ///< the dimension is the first m whose fraction is below this
  /// Test at most this many evenly spaced points (0: all); all points remain candidate
  /// neighbours. On oversampled data every search must step over the 2w points of its
  /// Theiler window, so testing all N points costs O(N w) per dimension.
  std::size_t reference_points = 4000;
};

struct false_neighbours_result {
  /// Entry m−1 (m = 1..max_dimension): the fraction of points whose nearest neighbour in m
  /// dimensions is false in m + 1 by either criterion, and by each one alone.
  std::vector<double> fraction, fraction_distance, fraction_attractor;
  std::size_t dimension = 0;  ///< first m with fraction < threshold (0 if none)
  bool found = false;
};

/// False nearest neighbours of the delay vectors of x (dim N) with delay τ = `delay` samples,
/// for m = 1..max_dimension. For each vector y_j(m) (j + mτ < N, so that x_{j+mτ} exists;
/// the reference points of the options) and its nearest neighbour y_n(m) at Euclidean
/// distance R_m > 0 outside the Theiler window: false if |x_{j+mτ} − x_{n+mτ}| > R_tol R_m
/// (criterion 1) or R_{m+1} > A_tol σ_x (criterion 2, σ_x the standard deviation of x). Throws
/// std::invalid_argument for delay 0, max_dimension 0, options out of range, a non-finite sample, a
/// constant series, or a series too short: N − max_dimension·τ must be at least 2w + 3.
false_neighbours_result false_nearest_neighbours(std::span<const double> x, std::size_t delay,
                                                 std::size_t max_dimension,
                                                 const false_neighbours_options& options = {});

struct cao_options {
  std::size_t theiler_window = 0;  ///< as for false_nearest_neighbours
  /// E1 has saturated at d when E1(d) ≥ saturation and |E1(d+1) − E1(d)| ≤ change · E1(d):
  /// close to 1 and no longer changing (the two conditions of Cao's paper; with the maximum
  /// norm E1 creeps towards 1 on smooth flows, so a threshold alone is fragile). In (0, 1].
  double saturation = 0.85;
  double change = 0.1;
  std::size_t reference_points = 4000;  ///< as for false_nearest_neighbours
};

struct cao_result {
  /// Entry d−1 (d = 1..max_dimension): E1(d) = E(d+1)/E(d), which approaches 1 once d
  /// embeds the attractor, and E2(d) = E*(d+1)/E*(d), which stays near 1 for all d only for
  /// random data.
  std::vector<double> e1, e2;
  std::size_t dimension = 0;  ///< first d < max_dimension where E1 has saturated (0 if none)
  bool found = false;
};

/// Cao's method on the delay vectors of x (dim N) with delay τ = `delay` samples, for
/// d = 1..max_dimension: E(d) = mean over j of ‖y_j(d+1) − y_n(d+1)‖ / ‖y_j(d) − y_n(d)‖
/// with y_n the nearest neighbour of y_j in d dimensions, E*(d) = mean |x_{j+dτ} − x_{n+dτ}|;
/// distances in the maximum norm, as in Cao's paper (the k-d tree is Euclidean, so the search
/// is exact but visits a ball √d times wider: slower than false_nearest_neighbours). Throws
/// std::invalid_argument as false_nearest_neighbours, with N − (max_dimension+1)·τ ≥ 2w + 3.
cao_result cao_embedding(std::span<const double> x, std::size_t delay, std::size_t max_dimension,
                         const cao_options& options = {});

}  // namespace npend
