// Lyapunov exponents of a chain's motion (paper §6.5.1): the full spectrum by the method of
// Benettin et al., and the maximal exponent alone.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "npend/chain.hpp"
#include "npend/integrators/integrate.hpp"

namespace npend {

/// How a Lyapunov computation runs.
///
/// The state and k tangent vectors (k = 2n for the spectrum, 1 for the maximal exponent) are
/// advanced together from integration.t_start to integration.t_end in steps of
/// integration.dt, and every `renormalisation_interval` the tangent vectors W are
/// re-orthonormalised (W = QR, Householder; W ← Q) and ln|R_ii| is added to sum_i. After the
/// `transient` the running estimates are λ_i(t) = sum_i / (t − t_start − transient).
///
/// The tangent vectors follow the linearised flow dW/dt = J(x(t)) W with the generated exact
/// Jacobian J:
/// - gauss4, gauss6: the exact derivative of each Gauss–Legendre step
///   (gauss_legendre::do_step_with_tangent), so the discrete map is symplectic and the
///   exponents come in ± pairs to round-off, with sum 0;
/// - rk4, dopri5, rkf78, bs: the variational equations integrated with the state as one
///   system of dimension 2n(k + 1) (npend::integrate_system) — for the explicit Runge–Kutta
///   methods also the exact derivative of the discrete step, but not a symplectic one;
///   the adaptive ones control the error of the tangent vectors too;
/// - taylor: the Taylor series of the state and the variational equations together, from the
///   generated recurrences on dual numbers (taylor_tangents), each renormalisation interval
///   stepped adaptively under abs_tol and rel_tol (dt only sets the interval's grid);
/// - rosenbrock4 is refused (variational_refusal says why).
struct lyapunov_options {
  integration_options integration;
  /// Time (s) between re-orthonormalisations, rounded to a whole number ≥ 1 of steps dt.
  /// Short enough that the tangent vectors stay far from parallel in floating point:
  /// exp((λ_1 − λ_k)·interval) ≪ 1e8.
  double renormalisation_interval = 0.1;
  /// Time (s) integrated before averaging starts (the tangent vectors settle onto the
  /// Lyapunov directions); rounded up to a whole number of renormalisation intervals.
  double transient = 0;
  /// The convergence estimate is the spread (max − min) of each running value over the last
  /// `convergence_fraction` of the averaging time, in (0, 1].
  double convergence_fraction = 0.25;
  /// At most this many running values are kept in the result (evenly spaced, ≥ 2).
  std::size_t max_history = 1000;
  /// The averaging time is cut into this many blocks of (nearly) equal length, whole
  /// renormalisation intervals each (≥ 2, at most the number of renormalisations): each
  /// block gives its own exponents, and their standard deviation / √blocks is the
  /// block_standard_error of the result.
  std::size_t blocks = 10;

  /// Throws std::invalid_argument naming the field (see integration_options::validate too).
  void validate() const;
};

/// What a Lyapunov computation found.
struct lyapunov_result {
  /// The exponents (1/s), descending: 2n for lyapunov_spectrum, 1 for
  /// maximal_lyapunov_exponent.
  std::vector<double> exponents;
  /// Σ exponents (1/s): 0 for the chain (div f = 0) up to the integration error.
  double sum = 0;
  /// λ_i + λ_{2n+1−i} for i = 1..n (full spectrum only; empty for the maximal exponent): 0
  /// for a Hamiltonian flow, to round-off with the symplectic tangent map.
  std::vector<double> pair_sums;
  /// Per exponent, in the order of `exponents`: max − min of its running value over the
  /// last convergence_fraction of the averaging time (1/s) — the convergence estimate; NaN
  /// when fewer than two running values fall there.
  std::vector<double> spread;
  /// The exponents of each block of the averaging time (block b: Σ ln|R_ii| over its
  /// renormalisations / its length), in the order of `exponents`: blocks × k values. The
  /// exponents are their length-weighted mean. Only complete blocks (all when the run was
  /// not stopped).
  std::vector<std::vector<double>> block_exponents;
  /// The blocks' start and end times (s), blocks + 1 values.
  std::vector<double> block_edges;
  /// Per exponent: the standard deviation of the block exponents / √blocks (1/s) — the
  /// standard error of the exponent if the blocks were independent finite-time samples. For
  /// chaotic motion with quiet and wild phases they are correlated and this underestimates
  /// the error; lyapunov_ensemble gives an independent estimate. NaN with fewer than two
  /// complete blocks.
  std::vector<double> block_standard_error;
  /// The running values: times (s) and, per time, the estimates in the order of
  /// `exponents` (at most max_history + 1 of them, the last at `t`).
  std::vector<double> history_t;
  std::vector<std::vector<double>> history;
  /// The time reached (s): t_end, or earlier if the observer stopped the run.
  double t = 0;
  /// Length of the averaging, t − t_start − transient (s).
  double averaging_time = 0;
  /// The renormalisation interval and transient actually used (whole numbers of steps).
  double renormalisation_interval = 0;
  double transient = 0;
  /// Re-orthonormalisations after the transient.
  std::size_t renormalisations = 0;
  /// max |H − H0| / |H0| at the renormalisation times (|H − H0| for H0 = 0).
  double max_rel_energy_error = 0;
  /// "tangent map" (Gauss–Legendre), "Taylor series of the variational equations" (taylor) or
  /// "variational equations" (the other steppers).
  std::string method;
  /// The state at `t` (dim 2n).
  std::vector<double> state;
  /// True if the observer stopped the run; the estimates are those at `t`.
  bool stopped = false;
};

/// Called after every re-orthonormalisation with the time t (s) and the running estimates
/// (in the order the tangent vectors are kept, k values; empty during the transient). It
/// may stop the run (observer_action::stop): for progress bars and interrupts.
using lyapunov_observer = std::function<observer_action(double t, std::span<const double> running)>;

/// λ_i + λ_{d+1−i} for i = 1..d/2 of a descending spectrum of d exponents (1/s): 0 for a
/// Hamiltonian flow, whose exponents come in pairs ±λ.
std::vector<double> pair_sums(std::span<const double> exponents);

/// The full spectrum of 2n Lyapunov exponents of the trajectory from x0 (dim 2n =
/// [φ, p]), by the method of Benettin et al. with 2n tangent vectors starting as the unit
/// vectors ordered (φ_1..φ_n, p_n..p_1) (see lyapunov_options). That order is kept by any
/// symplectic tangent map and makes λ_k + λ_{2n+1−k} = 0 hold at every finite time with the
/// Gauss–Legendre steppers (to round-off), not only in the limit. Throws std::invalid_argument for
/// a start state of the wrong size or non-finite, bad options or the rosenbrock4 stepper, and
/// npend::integration_error when the integration cannot go on.
lyapunov_result lyapunov_spectrum(const chain& c, std::span<const double> x0,
                                  const lyapunov_options& options,
                                  const lyapunov_observer& observer = {});

/// The maximal Lyapunov exponent alone: one tangent vector (the normalised (1, …, 1), which
/// almost surely has a component along the most expanding direction), renormalised to
/// length 1 — 2n times cheaper in the tangent work than the spectrum. Same arguments and
/// errors as lyapunov_spectrum.
lyapunov_result maximal_lyapunov_exponent(const chain& c, std::span<const double> x0,
                                          const lyapunov_options& options,
                                          const lyapunov_observer& observer = {});

/// The `count` largest Lyapunov exponents (1 ≤ count ≤ 2n): Benettin's method with `count`
/// tangent vectors, the first `count` of lyapunov_spectrum's frame, so that count = 2n is
/// the full spectrum. For long chains, where the whole spectrum costs O(n) tangent vectors
/// of dimension 2n: with the explicit steppers each vector costs one Jacobian–vector
/// product, O(n) on the loop kernels. Same errors as lyapunov_spectrum, and
/// std::invalid_argument for a count outside 1..2n.
lyapunov_result largest_lyapunov_exponents(const chain& c, std::span<const double> x0,
                                           const lyapunov_options& options, int count,
                                           const lyapunov_observer& observer = {});

/// `count` start states near x0 on its energy surface: the first is x0 itself; each other is
/// x0 with its angles moved by a random vector of Euclidean length `radius` (rad; a uniformly
/// random direction from a std::mt19937_64 seeded with `seed`), then moved along ∇H (Newton
/// on the line x + s ∇H) until H equals H(x0) to a few units of round-off. Throws
/// std::invalid_argument for x0 of the wrong size or non-finite, count = 0, a radius that is
/// not positive and finite, an x0 where ∇H = 0 (an equilibrium: no nearby state has its
/// energy), and when the projection does not converge.
std::vector<std::vector<double>> energy_surface_neighbours(const chain& c,
                                                           std::span<const double> x0,
                                                           std::size_t count, double radius,
                                                           std::uint64_t seed = 1);

/// How an ensemble of Lyapunov runs is set up.
struct lyapunov_ensemble_options {
  /// Members K ≥ 2: x0 and K − 1 starts near it (energy_surface_neighbours).
  std::size_t members = 8;
  /// How far the starts are moved (rad, Euclidean length of the change of the angles). For
  /// chaotic motion the runs part after ~ln(1/radius)/λ_1 and their exponents become
  /// independent finite-time samples.
  double radius = 1e-6;
  std::uint64_t seed = 1;
  /// Each member computes only the maximal exponent (maximal_lyapunov_exponent).
  bool maximal = false;
};

/// K Lyapunov computations from nearby starts on one energy surface, and the statistics of
/// their exponents.
struct lyapunov_ensemble_result {
  std::vector<std::vector<double>> starts;  ///< K × 2n; starts[0] = x0
  std::vector<lyapunov_result> runs;        ///< one per start (their exponents descending)
  /// Per exponent (2n, or 1 with maximal), over the K runs: the mean, the sample standard
  /// deviation (what a single run's finite-time value scatters by) and the standard error
  /// of the mean, standard deviation / √K (1/s).
  std::vector<double> mean, standard_deviation, standard_error;
  /// True if the observer stopped the run (the statistics then cover the runs finished, and
  /// are NaN with fewer than two).
  bool stopped = false;
};

/// Called like lyapunov_observer, with the member's index (0-based) in front.
using lyapunov_ensemble_observer =
    std::function<observer_action(std::size_t member, double t, std::span<const double> running)>;

/// The ensemble: energy_surface_neighbours(c, x0, members, radius, seed), each followed by
/// lyapunov_spectrum (or maximal_lyapunov_exponent) with `options`, one after the other.
/// Throws what those throw, and std::invalid_argument for members < 2.
lyapunov_ensemble_result lyapunov_ensemble(const chain& c, std::span<const double> x0,
                                           const lyapunov_options& options,
                                           const lyapunov_ensemble_options& ensemble,
                                           const lyapunov_ensemble_observer& observer = {});

}  // namespace npend
