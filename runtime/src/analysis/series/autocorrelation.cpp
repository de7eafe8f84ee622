#include "npend/analysis/series/autocorrelation.hpp"

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "analysis/detail/argument_checks.hpp"
#include "analysis/detail/curve_features.hpp"
#include "analysis/detail/real_fft.hpp"

namespace npend {

namespace {
constexpr std::array estimator_names{
    std::pair{autocorrelation_estimator::biased, std::string_view{"biased"}},
    std::pair{autocorrelation_estimator::unbiased, std::string_view{"unbiased"}},
};
}  // namespace

std::string_view autocorrelation_estimator_name(autocorrelation_estimator e) {
  for (const auto& [estimator, name] : estimator_names)
    if (estimator == e) return name;
  throw std::invalid_argument("autocorrelation_estimator_name: unknown estimator");
}

std::optional<autocorrelation_estimator> autocorrelation_estimator_from_name(
    std::string_view name) {
  for (const auto& [estimator, known] : estimator_names)
    if (known == name) return estimator;
  return std::nullopt;
}

autocorrelation_result autocorrelation(std::span<const double> x, double dt, std::size_t max_lag,
                                       autocorrelation_estimator estimator) {
  const std::size_t n = x.size();
  detail::require_finite_series(x, "x", 2);
  detail::require_sample_spacing(dt);
  detail::require_varying(x, "x", "its autocorrelation is undefined");
  if (max_lag == 0) max_lag = n - 1;
  if (max_lag >= n)
    throw std::invalid_argument(
        fmt::format("max_lag must be below the {} samples, got {}", n, max_lag));
  double mean = 0;
  for (const double v : x) mean += v;
  mean /= static_cast<double>(n);

  // Zero padding to ≥ 2N − 1 makes the circular correlation of the padded series equal the
  // linear one for every lag 0..N−1.
  detail::real_fft fft(detail::fast_fft_size(2 * n - 1));
  const auto y = fft.real();
  std::fill(y.begin(), y.end(), 0.0);
  for (std::size_t j = 0; j < n; ++j) y[j] = x[j] - mean;
  fft.forward();
  for (auto& c : fft.spectrum()) c = std::norm(c);
  fft.backward();
  const double zero_lag = y[0];

  autocorrelation_result r;
  r.lag.resize(max_lag + 1);
  r.value.resize(max_lag + 1);
  for (std::size_t k = 0; k <= max_lag; ++k) {
    r.lag[k] = static_cast<double>(k) * dt;
    r.value[k] = y[k] / zero_lag;
    if (estimator == autocorrelation_estimator::unbiased)
      r.value[k] *= static_cast<double>(n) / static_cast<double>(n - k);
  }
  r.first_zero = detail::first_zero_crossing(r.value, dt);
  r.first_minimum = detail::first_local_minimum(r.value, dt);
  return r;
}

}  // namespace npend
