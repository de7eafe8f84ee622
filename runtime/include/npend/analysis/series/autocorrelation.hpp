// Autocorrelation C_xx(τ) of a sampled time series via the Wiener–Khinchin theorem
// (paper §6.6.2, Abb. 6.10).
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

namespace npend {

/// How the lagged products are averaged.
enum class autocorrelation_estimator {
  /// Σ_{j<N−k} y_j y_{j+k} / N: the usual estimate of textbooks (Box & Jenkins), a positive
  /// semi-definite sequence whose magnitude shrinks by (1 − k/N); what Wiener–Khinchin gives.
  biased,
  /// Σ_{j<N−k} y_j y_{j+k} / (N − k): no (1 − k/N) taper, at the price of a variance that
  /// grows as the overlap N − k shrinks. TISEAN's `corr` and `autocor` divide so.
  unbiased,
};

/// "biased", "unbiased".
std::string_view autocorrelation_estimator_name(autocorrelation_estimator e);
/// The estimator of that name, if there is one.
std::optional<autocorrelation_estimator> autocorrelation_estimator_from_name(std::string_view name);

struct autocorrelation_result {
  std::vector<double> lag;    ///< τ_k = k dt in s, k = 0..max_lag
  std::vector<double> value;  ///< C_xx(τ_k), normalised: C_xx(0) = 1
  /// First τ where C_xx falls to 0 (s; linear interpolation between lags), if it does.
  std::optional<double> first_zero;
  /// First local minimum of C_xx (s; parabola through three lags), if there is one.
  std::optional<double> first_minimum;
};

/// C_xx(τ_k) = Σ_{j<N−k} y_j y_{j+k} / Σ_j y_j² for y = x − mean(x), x_j = x(t₀ + j dt)
/// (dim N ≥ 2, dt > 0 in s), for k = 0..max_lag (max_lag = 0: N − 1) — the biased estimate;
/// the unbiased one multiplies lag k by N/(N − k). Both come from the linear (not circular)
/// correlation, the inverse FFT of |ŷ|² with y zero-padded to at least 2N − 1 samples; for a
/// sine of many periods the biased one is cos(ωτ)(1 − τ/(N dt)), the unbiased one cos(ωτ).
/// Throws std::invalid_argument naming the argument for N < 2, dt ≤ 0, a non-finite sample,
/// a constant series, or max_lag ≥ N.
autocorrelation_result autocorrelation(
    std::span<const double> x, double dt, std::size_t max_lag = 0,
    autocorrelation_estimator estimator = autocorrelation_estimator::biased);

}  // namespace npend
