// Floquet analysis of a periodically driven chain: the monodromy matrix of a T-periodic
// orbit (an equilibrium of the undriven chain, carried along by the drive) and its
// multipliers, from the exact Jacobian.
#pragma once

#include <complex>
#include <span>
#include <vector>

#include "npend/chain.hpp"
#include "npend/run_control.hpp"

namespace npend {

struct floquet_options {
  /// Gauss–Legendre steps per period (order 6: the monodromy's error falls like steps⁻⁶).
  int steps = 400;
  /// A multiplier counts as stable while |μ| ≤ 1 + tolerance.
  double tolerance = 1e-6;
  run_control* control = nullptr;  ///< not owned; may be null
};

struct floquet_result {
  double period = 0;  ///< T (s)
  /// M = ∂x(T)/∂x(0), row-major (2n × 2n).
  std::vector<double> monodromy;
  /// The eigenvalues μ of M, by descending |μ|.
  std::vector<std::complex<double>> multipliers;
  double max_modulus = 0;  ///< max |μ|
  bool stable = false;     ///< max |μ| ≤ 1 + tolerance
  /// |x(T) − x(0)|∞: whether the start is on a T-periodic orbit (0 up to the integration
  /// error for an equilibrium the drive keeps, such as φ = 0 or π on a vertical drive).
  double closure = 0;
  bool stopped = false;  ///< a run control stopped it (the result is then incomplete)
};

/// The Floquet multipliers of the orbit through x0 (dim 2n) over one period of the pivot's
/// drive (`period`: the drive's, if 0). The monodromy matrix is the derivative of the
/// Gauss–Legendre (order 6) flow over the period, built from the exact Jacobian step by step
/// (gauss_legendre::do_step_with_tangent). An undamped chain has multipliers in reciprocal
/// pairs (det M = 1); a damped one has det M = exp(∫₀ᵀ tr J dt). Throws
/// std::invalid_argument for a chain without a periodic drive and no period given, a wrong
/// size of x0, or steps < 1.
floquet_result floquet_analysis(const chain& c, std::span<const double> x0,
                                const floquet_options& options = {}, double period = 0);

}  // namespace npend
