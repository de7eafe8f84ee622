#include "npend/analysis/series/mutual_information.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include "analysis/detail/argument_checks.hpp"
#include "analysis/detail/curve_features.hpp"

namespace npend {

namespace {

// The lags a series typically takes to move by one of `cells` equal cells over its range:
// the cell width over the median step |x_{j+1} − x_j| (at least 1).
std::size_t cell_crossing_lags(std::span<const double> x, std::size_t cells) {
  std::vector<double> steps(x.size() - 1);
  for (std::size_t j = 0; j + 1 < x.size(); ++j) steps[j] = std::fabs(x[j + 1] - x[j]);
  auto middle = steps.begin() + static_cast<std::ptrdiff_t>(steps.size() / 2);
  std::nth_element(steps.begin(), middle, steps.end());
  const auto [lo, hi] = std::minmax_element(x.begin(), x.end());
  const double width = (*hi - *lo) / static_cast<double>(cells);
  if (!(*middle > 0)) return 1;
  return std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil(width / *middle)));
}

constexpr std::array estimator_names{
    std::pair{mutual_information_estimator::tisean, std::string_view{"tisean"}},
    std::pair{mutual_information_estimator::averaged, std::string_view{"averaged"}},
};

}  // namespace

std::string_view mutual_information_estimator_name(mutual_information_estimator e) {
  for (const auto& [estimator, name] : estimator_names)
    if (estimator == e) return name;
  throw std::invalid_argument("mutual_information_estimator_name: unknown estimator");
}

std::optional<mutual_information_estimator> mutual_information_estimator_from_name(
    std::string_view name) {
  for (const auto& [estimator, known] : estimator_names)
    if (known == name) return estimator;
  return std::nullopt;
}

mutual_information_result average_mutual_information(std::span<const double> x, double dt,
                                                     std::size_t max_lag,
                                                     const mutual_information_options& options) {
  const std::size_t n = x.size();
  if (n < 2 || max_lag > n - 2)
    throw std::invalid_argument(
        fmt::format("max_lag must be at most N − 2 = {} for the {} samples of x, got {}",
                    n < 2 ? 0 : n - 2, n, max_lag));
  detail::require_sample_spacing(dt);
  const std::size_t bins = options.bins;
  // TISEAN's single histogram is the averaged one with one grid.
  const std::size_t shifts = options.estimator == mutual_information_estimator::averaged ? 4 : 1;
  if (bins < 2) throw std::invalid_argument(fmt::format("bins must be at least 2, got {}", bins));
  detail::require_finite_series(x, "x", 2);
  detail::require_varying(x, "x", "its mutual information is undefined");
  const auto [lo_it, hi_it] = std::minmax_element(x.begin(), x.end());
  const double lo = *lo_it, hi = *hi_it;

  // Every sample's cell on the fine grid of bins·shifts cells; the grid shifted by s fine
  // cells (s = 0..shifts−1) groups fine cell f into coarse cell ⌊(f + s)/shifts⌋ (0..bins).
  const std::size_t fine = bins * shifts, coarse = bins + 1;
  std::vector<std::size_t> cell(n);
  const double scale = static_cast<double>(fine) / (hi - lo);
  for (std::size_t j = 0; j < n; ++j)
    cell[j] = std::min(fine - 1, static_cast<std::size_t>((x[j] - lo) * scale));
  // Fine-cell range [begin, end) of coarse cell c under shift s.
  const auto range = [&](std::size_t c, std::size_t s) {
    const std::size_t begin = c * shifts > s ? c * shifts - s : 0;
    const std::size_t end = std::min(fine, (c + 1) * shifts - s);
    return std::pair{begin, std::max(begin, end)};
  };

  mutual_information_result r;
  r.lag.resize(max_lag + 1);
  r.information.resize(max_lag + 1);
  // Prefix sums over the fine joint histogram (fine+1 squared) and its two marginals.
  const std::size_t stride = fine + 1;
  std::vector<double> joint(stride * stride), first(stride), second(stride);
  std::vector<double> first_coarse(coarse), second_coarse(coarse);
  for (std::size_t k = 0; k <= max_lag; ++k) {
    std::fill(joint.begin(), joint.end(), 0.0);
    std::fill(first.begin(), first.end(), 0.0);
    std::fill(second.begin(), second.end(), 0.0);
    const std::size_t pairs = n - k;
    for (std::size_t j = 0; j < pairs; ++j) {
      joint[(cell[j] + 1) * stride + cell[j + k] + 1] += 1;
      first[cell[j] + 1] += 1;
      second[cell[j + k] + 1] += 1;
    }
    for (std::size_t a = 1; a < stride; ++a) {
      first[a] += first[a - 1];
      second[a] += second[a - 1];
      for (std::size_t b = 1; b < stride; ++b)
        joint[a * stride + b] += joint[(a - 1) * stride + b] + joint[a * stride + b - 1] -
                                 joint[(a - 1) * stride + b - 1];
    }
    const auto total = static_cast<double>(pairs);
    double information = 0;
    for (std::size_t sa = 0; sa < shifts; ++sa)
      for (std::size_t sb = 0; sb < shifts; ++sb) {
        for (std::size_t c = 0; c < coarse; ++c) {
          const auto [a0, a1] = range(c, sa);
          const auto [b0, b1] = range(c, sb);
          first_coarse[c] = first[a1] - first[a0];
          second_coarse[c] = second[b1] - second[b0];
        }
        for (std::size_t ca = 0; ca < coarse; ++ca) {
          if (first_coarse[ca] == 0) continue;
          const auto [a0, a1] = range(ca, sa);
          for (std::size_t cb = 0; cb < coarse; ++cb) {
            if (second_coarse[cb] == 0) continue;
            const auto [b0, b1] = range(cb, sb);
            const double count = joint[a1 * stride + b1] - joint[a0 * stride + b1] -
                                 joint[a1 * stride + b0] + joint[a0 * stride + b0];
            if (count > 0)
              information +=
                  count * std::log2(count * total / (first_coarse[ca] * second_coarse[cb]));
          }
        }
      }
    r.lag[k] = static_cast<double>(k) * dt;
    r.information[k] = information / (total * static_cast<double>(shifts * shifts));
  }
  r.window = options.minimum_window > 0 ? options.minimum_window : cell_crossing_lags(x, fine);
  r.first_minimum = detail::first_local_minimum_within(r.information, dt, r.window);
  return r;
}

}  // namespace npend
