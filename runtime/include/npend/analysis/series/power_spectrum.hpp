// Spectral density ρ(ω) = |x̂(ω)|² of a sampled time series (paper §6.6.2), windowed and
// optionally Welch-averaged, via FFTW3.
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

namespace npend {

/// Data windows (periodic forms, as used for spectral estimation).
enum class spectral_window {
  none,      ///< rectangular: narrowest lines, high leakage (sidelobes −13 dB)
  hann,      ///< 0.5 − 0.5 cos(2πj/L): sidelobes −31 dB, falling 18 dB per octave
  hamming,   ///< 0.54 − 0.46 cos(2πj/L): first sidelobe −43 dB
  blackman,  ///< 0.42 − 0.5 cos(2πj/L) + 0.08 cos(4πj/L): −58 dB, widest main lobe
};

/// "none", "hann", "hamming", "blackman".
std::string_view spectral_window_name(spectral_window w);
/// The window named `name` (as spectral_window_name prints it), none if unknown.
std::optional<spectral_window> spectral_window_from_name(std::string_view name);
/// The window's coefficients w_j, j = 0..length−1.
std::vector<double> window_coefficients(spectral_window w, std::size_t length);

struct spectrum_options {
  spectral_window window = spectral_window::hann;
  /// Welch segment length L in samples (2 ≤ L ≤ N); 0 means one segment: the whole series.
  std::size_t segment_length = 0;
  /// Fraction of a segment shared with the next one, in [0, 1); used only when segments < N.
  double overlap = 0.5;
};

/// One-sided spectral density on the bins ω_k = k Δω, k = 0..L/2.
struct power_spectrum_result {
  std::vector<double> omega;  ///< ω_k in rad/s (dim L/2 + 1)
  /// ρ(ω_k) in [x]²·s/rad: the segments' |X_k|² (mean removed, windowed), averaged and scaled
  /// so that Σ_k ρ_k Δω is the windowed mean square Σ(w_j x_j)²/Σw_j² — the variance of x
  /// for the rectangular window (Parseval).
  std::vector<double> power;
  double resolution = 0;           ///< bin spacing Δω = 2π/(L dt) in rad/s
  std::size_t segment_length = 0;  ///< L
  std::size_t segments = 0;        ///< number of averaged segments
  spectral_window window = spectral_window::hann;
};

/// The spectral density of x_j = x(t₀ + j dt) (dim N ≥ 2; dt > 0 in s). Each segment of L
/// samples has its own mean removed before the window is applied; segments start every
/// max(1, round(L (1 − overlap))) samples, and samples after the last whole segment are not
/// used. Throws std::invalid_argument naming the argument for N < 2, dt ≤ 0 or not finite,
/// a non-finite sample, a segment length outside [2, N], or an overlap outside [0, 1).
power_spectrum_result power_spectrum(std::span<const double> x, double dt,
                                     const spectrum_options& options = {});

}  // namespace npend
