// Average mutual information between x(t) and x(t + τ) (Fraser & Swinney 1986), whose first
// minimum is a common choice of the embedding delay.
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

namespace npend {

/// How I(τ) is estimated from the pairs (x_j, x_{j+k}).
enum class mutual_information_estimator {
  /// TISEAN's `mutual`: one histogram of bins × bins equal-width boxes over [min x, max x]
  /// (a sample at max x in the last box). Its first minimum is where TISEAN's is. On a clean
  /// periodic signal it zigzags from lag to lag by more than it falls, and its first minimum
  /// may be a dip of that zigzag (0.107 s on a 1.3 Hz sine sampled at 1 ms, a quarter period
  /// is 0.192 s): there the averaged estimator serves better.
  tisean,
  /// Averaged shifted histograms (Scott 1985): the mean over 4 × 4 grids offset by quarters
  /// of a bin on each axis. It removes most of the grid-alignment noise a single histogram
  /// shows on smooth signals (a sine's pairs lie on a curve, and its single-grid I(τ) zigzags
  /// by ~0.1 bit from lag to lag), but it also smooths away shallow first dips: on the weak
  /// triple pendulum's x3 at 16 bins its first minimum lies at 0.55 s, TISEAN's at 0.36 s.
  averaged,
};

/// "tisean", "averaged".
std::string_view mutual_information_estimator_name(mutual_information_estimator e);
/// The estimator of that name, if there is one.
std::optional<mutual_information_estimator> mutual_information_estimator_from_name(
    std::string_view name);

struct mutual_information_options {
  std::size_t bins = 16;  ///< equal-width bins per axis spanning [min x, max x], at least 2
  mutual_information_estimator estimator = mutual_information_estimator::tisean;
  /// The first minimum is the first lag whose I is below the previous lag's and the smallest
  /// within ± this many lags: Fraser & Swinney's first local minimum, made deaf to the
  /// histogram estimate's jitter (1: the plain first local minimum). 0, the default: the
  /// lags the series takes to move by one histogram cell, (max − min)/bins (a quarter of
  /// that for the averaged estimator, whose grids are offset by quarter bins) divided by the
  /// median |x_{j+1} − x_j| — the estimate cannot resolve a change of lag that moves no
  /// sample to another cell, and on oversampled data it steps up and down on that scale.
  std::size_t minimum_window = 0;
};

struct mutual_information_result {
  std::vector<double> lag;          ///< τ_k = k dt in s, k = 0..max_lag
  std::vector<double> information;  ///< I(τ_k) in bits
  /// The first local minimum of I (s; Fraser & Swinney): the first τ_k with I(τ_k) below
  /// I(τ_{k−1}) and the smallest on [τ_{k−h}, τ_{k+h}], h = `window`. None if there is none
  /// among the lags evaluated.
  std::optional<double> first_minimum;
  std::size_t window = 1;  ///< h in lags: options.minimum_window, or as found for 0
};

/// I(τ) = Σ_ab p_ab log₂(p_ab / (p_a p_b)) for the pairs (x_j, x_{j+k}), j = 0..N−1−k, with
/// p_a, p_b the marginals of the same pairs (so I ≥ 0), estimated by histograms as set in
/// `options`, for k = 0..max_lag; x_j = x(t₀ + j dt) (dim N, dt > 0 in s). In bits: TISEAN's
/// `mutual` prints the same in nats (ln 2 times this). Cost O(max_lag · (N + bins²)) (16 bins²
/// averaged). Throws std::invalid_argument for max_lag > N − 2 (each lag needs two pairs),
/// dt ≤ 0, bins < 2, a non-finite sample or a constant series.
mutual_information_result average_mutual_information(
    std::span<const double> x, double dt, std::size_t max_lag,
    const mutual_information_options& options = {});

}  // namespace npend
