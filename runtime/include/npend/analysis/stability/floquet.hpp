// Floquet analysis of a periodically driven chain: the monodromy matrix of a T-periodic
// orbit (an equilibrium of the undriven chain, carried along by the drive) and its
// multipliers, from the exact Jacobian.
#pragma once

#include <complex>
#include <span>
#include <utility>
#include <vector>

#include "npend/chain.hpp"
#include "npend/integrators/stepper_kind.hpp"
#include "npend/run_control.hpp"

namespace npend {

struct floquet_options {
  /// How the state and its tangent map cross the period: gauss6 (the default: `steps`
  /// Gauss–Legendre steps, the exact derivative of each step) or taylor (adaptive steps on the
  /// Taylor series of the variational equations at `tolerance`); no other stepper.
  stepper_kind stepper = stepper_kind::gauss6;
  /// gauss6: steps per period (order 6: the monodromy's error falls like steps⁻⁶); a second
  /// run at half of them (⌊steps/2⌋) gives the error estimate. At least 2.
  int steps = 400;
  /// taylor: the absolute and the relative tolerance of its steps; a second run at 100 times
  /// it gives the error estimate. In (0, 1e-6].
  double tolerance = 1e-13;
  run_control* control = nullptr;  ///< not owned; may be null
};

/// How the multipliers judge the orbit, against their error (floquet_result::modulus_error).
enum class floquet_verdict {
  stable,    ///< damped: max |μ| < 1 − err; undamped: max |μ| ≤ 1 + err (all on the circle)
  marginal,  ///< damped, and max |μ| within err of 1: the integration cannot tell
  unstable,  ///< max |μ| > 1 + err
};

/// "stable", "marginal" or "unstable".
const char* verdict_name(floquet_verdict v);

struct floquet_result {
  double period = 0;  ///< T (s)
  int steps = 0;      ///< the steps over the period (taylor: of the run at `tolerance`)
  /// M = ∂x(T)/∂x(0), row-major (2n × 2n).
  std::vector<double> monodromy;
  /// The eigenvalues μ of M, by descending |μ|.
  std::vector<std::complex<double>> multipliers;
  double max_modulus = 0;  ///< max |μ|
  /// The error estimate of max |μ|: its change from the second run (gauss6: at half the
  /// steps, order 6, so the full run's own error is about 1/63 of it; taylor: at 100 times
  /// the tolerance) — an upper bound once the rule converges — plus rounding: the
  /// eigenvalues' (each one's condition number × d ε ‖M‖) and that of the K steps of the
  /// tangent map (K ε ‖M‖).
  double modulus_error = 0;
  floquet_verdict verdict = floquet_verdict::unstable;
  bool stable = false;  ///< verdict == floquet_verdict::stable
  /// |x(T) − x(0)|∞: whether the start is on a T-periodic orbit (0 up to the integration
  /// error for an equilibrium the drive keeps, such as φ = 0 or π on a vertical drive).
  double closure = 0;
  bool stopped = false;  ///< a run control stopped it (the result is then incomplete)
};

/// The Floquet multipliers of the orbit through x0 (dim 2n) over one period of the pivot's
/// drive (`period`: the drive's, if 0). The monodromy matrix is the derivative of the
/// Gauss–Legendre (order 6) flow over the period, built from the exact Jacobian step by step
/// (gauss_legendre::do_step_with_tangent), or with options.stepper = taylor the solution of
/// the variational equations w' = J w from w(0) = e_1..e_2n, their Taylor series from the
/// generated recurrences on dual numbers (taylor_tangents). An undamped chain has multipliers in
/// reciprocal pairs (det M = 1), so that its best is max |μ| = 1 (linearly stable: every multiplier
/// on the unit circle); a damped one has det M = exp(∫₀ᵀ tr J dt) and is stable only when every
/// multiplier is inside the circle by more than the error estimate — when max |μ| is within it of 1
/// (a slow instability or a slow decay) the verdict is marginal. Throws std::invalid_argument for a
/// chain without a periodic drive and no period given, a wrong size of x0, steps < 2, a stepper
/// other than gauss6 and taylor, a tolerance outside (0, 1e-6], and taylor on a chain without
/// Taylor kernels; npend::integration_error where the state becomes non-finite or taylor's steps
/// collapse (more than floquet_taylor_max_steps in one period).
floquet_result floquet_analysis(const chain& c, std::span<const double> x0,
                                const floquet_options& options = {}, double period = 0);

/// One drive frequency of floquet_frequency_scan: the floquet_analysis there, in brief.
struct floquet_scan_point {
  double frequency = 0;      ///< Ω (rad/s)
  double max_modulus = 0;    ///< max |μ|
  double modulus_error = 0;  ///< its error estimate (floquet_result::modulus_error)
  floquet_verdict verdict = floquet_verdict::unstable;
  bool stable = false;  ///< verdict == floquet_verdict::stable
};

/// A stability chart over the drive frequency.
struct floquet_scan_result {
  std::vector<floquet_scan_point> points;  ///< one per frequency, in the order given
  /// The runs of consecutive stable points, as [first, last] frequencies (rad/s): where the
  /// drive holds the orbit, to the scan's resolution.
  std::vector<std::pair<double, double>> stable_windows;
  /// A run control stopped it at the frequency `stopped_at` (rad/s); `points` holds the
  /// frequencies before it and `stable_windows` is empty.
  bool stopped = false;
  double stopped_at = 0;
};

/// floquet_analysis of the orbit through x0 (dim 2n) for each drive frequency Ω of
/// `frequencies` (rad/s, dim K ≥ 1), the chain c otherwise unchanged: Kapitza's and Acheson's
/// stability charts. The chain needs a built-in periodic drive (pivot_motion::vertical or
/// horizontal), whose amplitude stays; each analysis takes one drive period 2π/Ω. The
/// control of `options` hears the scan's progress, each frequency an equal part. Throws
/// std::invalid_argument for a chain without a built-in periodic drive, no frequencies, a
/// frequency that is not positive and finite, and as floquet_analysis does.
floquet_scan_result floquet_frequency_scan(const chain& c, std::span<const double> x0,
                                           std::span<const double> frequencies,
                                           const floquet_options& options = {});

}  // namespace npend
