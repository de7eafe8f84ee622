// Lines in a spectral density: local maxima that stand out, strongest first.
#pragma once

#include <cstddef>
#include <vector>

#include "npend/analysis/series/power_spectrum.hpp"

namespace npend {

struct spectral_peak {
  double omega = 0;       ///< refined peak frequency in rad/s
  double power = 0;       ///< refined peak density, in the spectrum's units
  double prominence = 0;  ///< height above the higher of its two bases, same units
  std::size_t bin = 0;    ///< index k of the local maximum in the spectrum
};

struct peak_options {
  /// Keep peaks whose density is at least this fraction of the strongest local maximum's.
  double threshold = 1e-3;
  /// Keep peaks whose prominence is at least this fraction of their own density (0.5: the
  /// peak rises at least 3 dB above the higher of its bases), in [0, 1].
  double min_prominence = 0.5;
  /// Report at most this many (0: all).
  std::size_t max_peaks = 10;
};

/// The peaks of `spectrum` (a power_spectrum result with at least 3 bins), strongest first.
/// A peak is an interior bin k with ρ_{k−1} < ρ_k ≥ ρ_{k+1}; its prominence is ρ_k minus
/// the higher of the lowest densities between k and the nearest higher bin on either side (or
/// the end of the spectrum). Its frequency and density are refined by the parabola through
/// ln ρ at k−1, k, k+1 (exact for Gaussian lobes; within a few hundredths of a bin for a Hann
/// window) — except next to the DC bin (emptied by the mean removal), next to a zero bin, and
/// where the refined density would exceed ρ_k by more than the window's scalloping bound
/// |W(0)/W(½)|² (2.47 rectangular, 1.39 Hann): there the bin's own ω_k and ρ_k stand. Throws
/// std::invalid_argument for fewer than 3 bins, omega and power of different sizes, or options out
/// of range.
std::vector<spectral_peak> find_spectral_peaks(const power_spectrum_result& spectrum,
                                               const peak_options& options = {});

}  // namespace npend
