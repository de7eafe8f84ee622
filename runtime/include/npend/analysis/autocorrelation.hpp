// Autocorrelation C_xx(τ) of a sampled time series via the Wiener–Khinchin theorem
// (paper §6.6.2, Abb. 6.10).
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <vector>

namespace npend {

struct autocorrelation_result {
  std::vector<double> lag;    ///< τ_k = k dt in s, k = 0..max_lag
  std::vector<double> value;  ///< C_xx(τ_k), normalised: C_xx(0) = 1
  /// First τ where C_xx falls to 0 (s; linear interpolation between lags), if it does.
  std::optional<double> first_zero;
  /// First local minimum of C_xx (s; parabola through three lags), if there is one.
  std::optional<double> first_minimum;
};

/// C_xx(τ_k) = Σ_{j<N−k} y_j y_{j+k} / Σ_j y_j² for y = x − mean(x), x_j = x(t₀ + j dt)
/// (dim N ≥ 2, dt > 0 in s), for k = 0..max_lag (max_lag = 0: N − 1). This is the usual
/// biased estimate: the linear (not circular) correlation, obtained as the inverse FFT of
/// |ŷ|² with y zero-padded to at least 2N − 1 samples; for a sine of many periods it is
/// cos(ωτ)(1 − τ/(N dt)). Throws std::invalid_argument naming the argument for N < 2,
/// dt ≤ 0, a non-finite sample, a constant series, or max_lag ≥ N.
autocorrelation_result autocorrelation(std::span<const double> x, double dt,
                                       std::size_t max_lag = 0);

}  // namespace npend
