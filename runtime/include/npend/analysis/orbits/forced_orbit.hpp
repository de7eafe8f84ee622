// Forced periodic orbits of a chain whose pivot is driven periodically (the orbit has the
// drive's period, or k times it), by shooting, and their continuation in the drive frequency:
// Kapitza's branch of the inverted pendulum and its stability threshold.
#pragma once

#include <complex>
#include <span>
#include <string>
#include <vector>

#include "npend/analysis/orbits/periodic_orbit.hpp"
#include "npend/chain.hpp"
#include "npend/integrators/stepper_kind.hpp"
#include "npend/run_control.hpp"

namespace npend {

struct forced_orbit_options {
  /// The orbit's period in drive periods: T = periods · 2π/Ω (k ≥ 1; 2 for a subharmonic
  /// response).
  int periods = 1;
  /// How each pass crosses the period: gauss6 (the default: `steps` per drive period) or
  /// taylor (adaptive steps on the Taylor series of the variational equations at
  /// `integration_tolerance`); no other stepper (stepper_use::monodromy).
  stepper_kind stepper = stepper_kind::gauss6;
  /// gauss6: steps per drive period (at least 2): the orbit is exact for that map, which
  /// differs from the flow's by about steps⁻⁶.
  int steps = 400;
  /// taylor: the absolute and relative tolerance of its steps, in (0, 1e-6]: the orbit is
  /// the flow's to about this (keep it well below `tolerance`).
  double integration_tolerance = 1e-14;
  /// Converged when ‖φ(T) − x0‖∞ ≤ tolerance.
  double tolerance = 1e-11;
  int max_iterations = 20;
  /// Stable when every multiplier has |μ| ≤ 1 + stability_tolerance.
  double stability_tolerance = 1e-6;
  run_control* control = nullptr;  ///< not owned; may be null
};

struct forced_orbit_result {
  bool converged = false;
  std::vector<double> x0;  ///< the state at t = 0 (dim 2n)
  double frequency = 0;    ///< the drive's Ω (rad/s)
  double period = 0;       ///< T = periods · 2π/Ω (s)
  double closure = 0;      ///< ‖φ(T) − x0‖∞ of the last integration
  int iterations = 0;      ///< Newton corrections taken
  int steps = 0;           ///< the steps of the last pass over T
  /// max |φ_i| (rad) over the start and the states after each step, per angle (dim n); with
  /// taylor, over 16 points of each step's polynomial, its end included.
  std::vector<double> amplitudes;
  /// All 2n eigenvalues of the monodromy over T, by descending |μ|: a forced orbit has no
  /// trivial pair (the drive fixes the phase, and H is not conserved).
  std::vector<std::complex<double>> multipliers;
  double max_multiplier = 0;  ///< max |μ|
  bool stable = false;        ///< max_multiplier ≤ 1 + stability_tolerance
  bool stopped = false;       ///< a run control stopped it
};

/// The forced orbit near x0_guess (dim 2n, the state at t = 0) of a chain whose pivot is
/// driven with a built-in periodic drive (pivot_motion::vertical or horizontal, frequency
/// Ω): the T-periodic solution, T = options.periods · 2π/Ω, found by Newton's method on
/// F(x0) = φ(T; x0) − x0 = 0 (2n equations, 2n unknowns; no phase condition, since the drive
/// fixes the time origin). φ is the Gauss–Legendre flow from t = 0 with its exact tangent map
/// M = ∂φ/∂x0 (or Taylor's, options.stepper), so the Newton matrix is M − I, regular unless a
/// multiplier is +1 (where the orbit bifurcates); the correction is a complete orthogonal
/// (least-squares) solve, which stays bounded there. Throws std::invalid_argument for a damped
/// chain (damping is excluded: its orbits are attracting, not a Hamiltonian family, and its
/// multipliers are not reciprocal), a fixed pivot (see periodic_orbit for free orbits), a custom
/// pivot path (no period), a cart, a wrong size of x0_guess, periods < 1, steps < 2, a tolerance
/// that is not positive, a stepper other than gauss6 and taylor, or an integration tolerance
/// outside (0, 1e-6].
forced_orbit_result forced_orbit(const chain& c, std::span<const double> x0_guess,
                                 const forced_orbit_options& options = {});

/// The chain c with its pivot's drive frequency set to `frequency` (rad/s), everything else
/// kept. Throws std::invalid_argument as forced_orbit does for a chain without a built-in
/// drive, and for a frequency that is not positive and finite.
chain with_drive_frequency(const chain& c, double frequency);

struct drive_continuation_options {
  forced_orbit_options orbit;  ///< each point's shooting
  /// Continue from the chain's Ω to this drive frequency (rad/s; above or below it).
  double frequency_end = 0;
  /// The first step |ΔΩ| (rad/s); 0: max_step.
  double initial_step = 0;
  /// The largest step |ΔΩ| (rad/s), so that the table resolves the branch; 0: |Ω_end − Ω_0|/20.
  double max_step = 0;
  /// The step grows by 1.5 after an easy point (≤ 3 iterations), halves after a failure; the
  /// branch ends when a failed step would fall below min_step_ratio · Ω.
  double min_step_ratio = 1e-7;
  int max_points = 500;
  /// Each change of stability is located by bisection in Ω until the bracket is narrower
  /// than frequency_tolerance · Ω.
  double frequency_tolerance = 1e-8;
};

/// One converged orbit of a drive-frequency branch.
struct forced_point {
  double frequency = 0;  ///< Ω (rad/s)
  double period = 0;     ///< T (s)
  std::vector<double> x0;
  std::vector<double> amplitudes;  ///< max |φ_i| (rad), dim n
  std::vector<std::complex<double>> multipliers;
  double max_multiplier = 0;
  bool stable = false;
  double closure = 0;
  int iterations = 0;
};

/// The point a converged forced_orbit result is.
forced_point to_forced_point(const forced_orbit_result& r);

/// A change of stability along the branch, located in Ω.
struct drive_stability_change {
  /// How the unstable side's largest multiplier left the unit circle (through +1: a branch
  /// point, such as Kapitza's threshold; through −1: period doubling; a complex quartet).
  nnm_bifurcation_kind kind = nnm_bifurcation_kind::branch_point;
  double frequency = 0;  ///< the final bracket's midpoint (rad/s)
  /// Whether the orbit is stable above `frequency` (and unstable below it).
  bool stable_above = false;
  forced_point stable_side;    ///< the bracket's stable orbit
  forced_point unstable_side;  ///< and its unstable one
  /// The width of the final bracket (rad/s): below frequency_tolerance · Ω unless a shot in
  /// the bisection failed.
  double bracket = 0;
};

struct drive_branch {
  std::vector<forced_point> points;             ///< in the order of the continuation (Ω_0 first)
  std::vector<drive_stability_change> changes;  ///< in the order of the continuation
  /// Why it ended: "reached frequency_end", "max_points reached", "the first orbit did not
  /// converge", "the shooting stopped converging beyond Omega = … rad/s (a fold of the
  /// response curve or a bifurcation: …)", "stopped".
  std::string end_reason;
  bool stopped = false;  ///< a run control stopped it
};

/// The forced orbit through x0_start (dim 2n, a guess at the chain's own Ω) continued in
/// the drive frequency Ω from the chain's Ω to options.frequency_end (natural-parameter
/// continuation: each point is forced_orbit from the secant prediction of the last two,
/// with step control; the drive's amplitude and everything else stay). Every change of
/// stability between consecutive points is then located by bisection in Ω, each orbit shot
/// from the interpolation of the bracket's ends. For the inverted pendulum on a vertical
/// drive the upright state (π, 0) is an exact orbit at every Ω, and the change is Kapitza's
/// threshold, (aΩ)² ≈ 2 g l for small a/l. The control of options.orbit hears the progress
/// in Ω and may stop it (the branch then has what was found, flagged stopped). Throws
/// std::invalid_argument as forced_orbit does, for a frequency_end that is not positive and
/// finite or equal to the chain's Ω, negative steps, or a non-positive frequency_tolerance.
drive_branch continue_drive(const chain& c, std::span<const double> x0_start,
                            const drive_continuation_options& options);

}  // namespace npend
