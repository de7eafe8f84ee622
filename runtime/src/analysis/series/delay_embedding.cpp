#include "npend/analysis/series/delay_embedding.hpp"

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "analysis/detail/argument_checks.hpp"
#include "npend/analysis/series/autocorrelation.hpp"
#include "npend/analysis/series/mutual_information.hpp"
#include "npend/analysis/series/power_spectrum.hpp"
#include "npend/analysis/series/spectral_peaks.hpp"

namespace npend {

namespace {

constexpr std::array method_names{
    std::pair{delay_method::automatic, std::string_view{"auto"}},
    std::pair{delay_method::quarter_period, std::string_view{"T/4"}},
    std::pair{delay_method::acf_zero, std::string_view{"acf-zero"}},
    std::pair{delay_method::acf_minimum, std::string_view{"acf-min"}},
    std::pair{delay_method::mutual_information, std::string_view{"ami"}},
};

std::optional<double> quarter_period(std::span<const double> x, double dt) {
  const auto peaks = find_spectral_peaks(power_spectrum(x, dt), {.max_peaks = 1});
  if (peaks.empty() || !(peaks.front().omega > 0)) return std::nullopt;
  return 0.25 * 2 * std::numbers::pi / peaks.front().omega;
}

// First minimum of the mutual information, widening the lag range (doubling) until the
// minimum lies inside it, up to N/2.
mutual_information_result mutual_information_to_minimum(std::span<const double> x, double dt,
                                                        const mutual_information_options& options) {
  const std::size_t limit = x.size() / 2;
  for (std::size_t lags = std::min<std::size_t>(64, limit);; lags = std::min(2 * lags, limit)) {
    auto ami = average_mutual_information(x, dt, lags, options);
    if (ami.first_minimum || lags == limit) return ami;
  }
}

std::optional<double> estimate(std::span<const double> x, double dt, delay_method method,
                               const mutual_information_options& information,
                               delay_choice& choice) {
  switch (method) {
    case delay_method::quarter_period:
      return quarter_period(x, dt);
    case delay_method::acf_zero:
      return autocorrelation(x, dt).first_zero;
    case delay_method::acf_minimum:
      return autocorrelation(x, dt).first_minimum;
    case delay_method::mutual_information:
      choice.mutual_information = mutual_information_to_minimum(x, dt, information);
      return choice.mutual_information.first_minimum;
    case delay_method::automatic:
      break;
  }
  throw std::invalid_argument("estimate: automatic is not a single method");
}

}  // namespace

delay_vectors delay_embedding(std::span<const double> x, std::size_t delay, std::size_t dimension) {
  if (delay == 0) throw std::invalid_argument("delay must be at least 1 sample");
  if (dimension == 0) throw std::invalid_argument("dimension must be at least 1");
  const std::size_t span = (dimension - 1) * delay;
  if (x.size() <= span)
    throw std::invalid_argument(
        fmt::format("x has {} samples; dimension {} at delay {} needs more than {}", x.size(),
                    dimension, delay, span));
  delay_vectors v;
  v.dimension = dimension;
  v.delay = delay;
  v.count = x.size() - span;
  v.points.resize(v.count * dimension);
  for (std::size_t i = 0; i < v.count; ++i)
    for (std::size_t c = 0; c < dimension; ++c)
      v.points[i * dimension + c] = x[i + span - c * delay];
  return v;
}

std::string_view delay_method_name(delay_method m) {
  for (const auto& [method, name] : method_names)
    if (method == m) return name;
  throw std::invalid_argument("delay_method_name: unknown method");
}

std::optional<delay_method> delay_method_from_name(std::string_view name) {
  for (const auto& [method, known] : method_names)
    if (known == name) return method;
  return std::nullopt;
}

delay_choice choose_delay(std::span<const double> x, double dt, delay_method method,
                          const mutual_information_options& information) {
  detail::require_finite_series(x, "x", 4);
  detail::require_sample_spacing(dt);
  detail::require_varying(x, "x", "it has no delay structure");

  std::vector<delay_method> tries{method};
  if (method == delay_method::automatic)
    tries = {delay_method::mutual_information, delay_method::acf_zero,
             delay_method::quarter_period};
  delay_choice choice;
  choice.method = method;
  for (const delay_method m : tries) {
    const auto value = estimate(x, dt, m, information, choice);
    if (!value) continue;
    choice.found = true;
    choice.method = m;
    choice.estimate = *value;
    choice.samples = std::max<std::size_t>(1, static_cast<std::size_t>(std::lround(*value / dt)));
    choice.seconds = static_cast<double>(choice.samples) * dt;
    break;
  }
  return choice;
}

}  // namespace npend
