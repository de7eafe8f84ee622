// Delay coordinates (paper §6.6.4, Abb. 6.13): vectors (x(t), x(t−τ), …, x(t−(m−1)τ)), and
// the choice of the delay τ.
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "npend/analysis/series/mutual_information.hpp"

namespace npend {

/// The delay vectors of a series, row-major.
struct delay_vectors {
  std::size_t dimension = 0;  ///< m
  std::size_t delay = 0;      ///< τ in samples
  std::size_t count = 0;      ///< rows: N − (m−1)τ
  /// Row i is (x_j, x_{j−τ}, …, x_{j−(m−1)τ}) for j = i + (m−1)τ (dim count × m).
  std::vector<double> points;
};

/// The delay vectors of x (dim N) with delay τ = `delay` samples (≥ 1) in `dimension` m ≥ 1
/// coordinates. Throws std::invalid_argument for delay 0, dimension 0, or N ≤ (m−1)τ (no
/// complete vector).
delay_vectors delay_embedding(std::span<const double> x, std::size_t delay, std::size_t dimension);

/// How the delay is chosen.
enum class delay_method {
  automatic,           ///< mutual_information, else acf_zero, else quarter_period
  quarter_period,      ///< T/4, T = 2π/ω of the strongest spectral peak (Hann window)
  acf_zero,            ///< first zero of the autocorrelation C_xx
  acf_minimum,         ///< first minimum of C_xx
  mutual_information,  ///< first local minimum of the average mutual information
};

/// "auto", "T/4", "acf-zero", "acf-min", "ami" (the command line's names).
std::string_view delay_method_name(delay_method m);
/// The method named `name` as delay_method_name prints it; none if unknown.
std::optional<delay_method> delay_method_from_name(std::string_view name);

struct delay_choice {
  bool found = false;  ///< false if the method's feature does not exist in the data
  delay_method method = delay_method::automatic;  ///< the method that gave τ
  double estimate = 0;                            ///< the method's unrounded delay in s
  std::size_t samples = 0;  ///< τ in samples: round(estimate / dt), at least 1
  double seconds = 0;       ///< samples · dt
  /// The mutual information I(τ) as evaluated, when the method tried it (ami, auto): on lags
  /// 0..63, doubled until its first minimum lies inside, at most N/2. Empty otherwise.
  mutual_information_result mutual_information;
};

/// The delay for embedding x_j = x(t₀ + j dt) (dim N ≥ 4, dt > 0 in s) by `method`. The
/// mutual information (with the histogram of `information`) is evaluated on lags up to N/2,
/// the autocorrelation on all lags.
/// When the feature is absent (no zero, no minimum, no spectral peak) found is false; for
/// automatic only when all three fail. Throws std::invalid_argument for N < 4, dt ≤ 0, a
/// non-finite sample or a constant series.
delay_choice choose_delay(std::span<const double> x, double dt,
                          delay_method method = delay_method::automatic,
                          const mutual_information_options& information = {});

}  // namespace npend
