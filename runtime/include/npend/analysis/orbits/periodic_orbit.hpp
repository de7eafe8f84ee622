// Periodic orbits of an undamped, undriven chain by shooting, and the continuation of a
// linear normal mode into its nonlinear normal mode (NNM) family over the energy.
#pragma once

#include <complex>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "npend/chain.hpp"
#include "npend/integrators/stepper_kind.hpp"
#include "npend/run_control.hpp"

namespace npend {

/// Which condition picks one point of the orbit (the flow moves any periodic start along it).
enum class orbit_phase {
  /// x0 has p = 0: a turning point, where every angle is at its extreme. The natural choice
  /// for synchronous NNMs (every angle turns at the same instant); n + 1 unknowns (q0, T).
  turning_point,
  /// ⟨f(x̃0), x0 − x̃0⟩ = 0 with x̃0 the guess (a Poincaré section through it): any orbit;
  /// 2n + 1 unknowns (x0, T).
  poincare,
};

/// How the shooting gets the monodromy matrix ∂φ(T)/∂x0.
enum class monodromy_method {
  /// The exact tangent map of the steps (Gauss–Legendre or Taylor), carried along the one
  /// pass.
  exact,
  /// Forward differences of 2n + 1 passes (the start and each coordinate nudged by
  /// √ε·max(1, |x_j|)), as continuation codes without a variational system do it. Kept for
  /// the benchmark against the exact map; it converges more slowly and less far.
  finite_difference,
};

struct periodic_orbit_options {
  /// How the shooting crosses the period (stepper_use::monodromy): gauss6, `steps` fixed
  /// steps, or taylor, adaptive steps on the Taylor series of the variational equations at
  /// `integration_tolerance`.
  stepper_kind stepper = stepper_kind::gauss6;
  /// gauss6: Gauss–Legendre (order 6) steps over the period: the orbit is exact for that
  /// map, whose period differs from the flow's by about steps⁻⁶. At least 2 and at least
  /// `segments`; each segment takes ⌈steps / segments⌉. Not used by taylor.
  int steps = 400;
  /// taylor: the absolute and relative tolerance of its steps, in (0, 1e-6]: the orbit is
  /// the flow's to about this tolerance. A pass that needs more than 10,000 steps per segment
  /// (a Newton iterate that spins the chain) counts as failed.
  double integration_tolerance = 1e-14;
  /// Multiple shooting: the period is cut into this many segments, each integrated from its
  /// own start, and Newton matches each segment's end to the next start. An unstable orbit's
  /// errors then grow over T/segments instead of T. 1: single shooting.
  int segments = 1;
  /// Rotating orbits: whole turns of each angle per period (empty or all zero: an
  /// oscillation). The orbit closes as φ_i(T) = φ_i(0) + 2π·winding[i], p(T) = p(0). A
  /// rotating orbit has no turning point: it needs orbit_phase::poincare.
  std::vector<int> winding;
  /// The energy H(x0) = E (J) the orbit keeps. NaN: the guess's energy.
  double energy = std::numeric_limits<double>::quiet_NaN();
  orbit_phase phase = orbit_phase::turning_point;
  /// Converged when ‖φ(T) − x0‖∞ ≤ tolerance and |H(x0) − E| ≤ tolerance·max(1, |E|).
  double tolerance = 1e-11;
  int max_iterations = 20;
  /// Damped Newton: a correction that leaves a larger residual is retried at half its length
  /// (up to three times), and the shooting gives up when none helps. For guesses far from
  /// any orbit (close returns of a chaotic trajectory) more converge and hopeless ones end
  /// sooner; from a continuation's predictions full steps converge in fewer passes, so it is
  /// off by default.
  bool line_search = false;
  monodromy_method monodromy = monodromy_method::exact;
  /// Stable when every non-trivial multiplier has |μ| ≤ 1 + stability_tolerance.
  double stability_tolerance = 1e-6;
  run_control* control = nullptr;  ///< not owned; may be null
};

struct periodic_orbit_result {
  bool converged = false;
  std::vector<double> x0;  ///< the start (dim 2n)
  double period = 0;       ///< T (s)
  double energy = 0;       ///< H(x0) (J)
  /// ‖φ(T) − x0 − 2πw‖∞ of the last integration; with several segments the largest
  /// mismatch between a segment's end and the next start.
  double closure = 0;
  int iterations = 0;  ///< Newton corrections taken
  /// max |φ_i| (rad) over the start and the states after each step (taylor: 16 points of
  /// each step's polynomial), per angle (dim n); a rotating angle's exceeds π.
  std::vector<double> amplitudes;
  /// The integration steps of the last pass over the period, all segments together (gauss6:
  /// segments × ⌈steps / segments⌉).
  int steps = 0;
  std::vector<int> winding;  ///< the turns per period it was shot with (dim n)
  /// The monodromy's eigenvalues by descending |μ|, without the trivial pair at +1 that the
  /// flow direction and the energy give (dim 2n − 2).
  std::vector<std::complex<double>> multipliers;
  double max_multiplier = 0;  ///< max |μ| of `multipliers` (1 when there are none: n = 1)
  bool stable = false;        ///< max_multiplier ≤ 1 + stability_tolerance
  bool stopped = false;       ///< a run control stopped it
};

/// The periodic orbit near (x0_guess, T_guess) at the energy of `options`: Newton on
/// F(x0, T) = φ(T; x0) − x0 with the phase condition and H(x0) = E. φ is the Gauss–Legendre
/// flow with its exact tangent map, or Taylor's (options.stepper), which gives the monodromy
/// M = ∂φ/∂x0; ∂φ/∂T = f(φ(T)). Energy
/// conservation makes one row of [M − I, f] dependent on the others, so the square system is
/// singular; the correction is the least-squares (minimum-norm) solution of all the rows,
/// which converges quadratically since the residual vanishes at the orbit. Throws
/// std::invalid_argument for a damped chain, a moving pivot, a cart, a wrong size of
/// x0_guess, T_guess not positive and finite, steps < 2 (odd for turning_point is fine),
/// a tolerance that is not positive, a stepper other than gauss6 and taylor, an integration
/// tolerance outside (0, 1e-6], or taylor with finite-difference monodromies.
periodic_orbit_result periodic_orbit(const chain& c, std::span<const double> x0_guess,
                                     double T_guess, const periodic_orbit_options& options = {});

/// How a family of orbits is followed from one point to the next.
enum class continuation_method {
  /// Each point shot at a fixed energy from a secant prediction in the energy: ends at a
  /// fold in energy, and crawls where the period grows fast (towards the separatrix).
  natural,
  /// Pseudo-arclength (Keller): each point is the intersection of the family with the
  /// plane normal to the secant of the last two points in (start, period), at a distance
  /// along it; the energy is an unknown. Turns round folds in energy.
  pseudo_arclength,
};

/// The method a name gives, as the command line and Python take it: "arclength" or
/// "natural"; nullopt for any other.
std::optional<continuation_method> continuation_method_from_name(std::string_view name);

struct continuation_options {
  periodic_orbit_options orbit;  ///< each point's shooting (its energy is set per point)
  continuation_method method = continuation_method::pseudo_arclength;
  /// The first point: angles = start_amplitude · shape / max |shape| (rad), p = 0.
  double start_amplitude = 0.01;
  /// continue_mode: continue up to this energy (J); must exceed the first point's.
  double energy_max = 0;
  int max_points = 200;
  /// The first step in energy is the first point's energy × initial_step_ratio
  /// (continue_orbit: a twentieth of the way to the end × initial_step_ratio); a step grows
  /// by 1.5 after an easy point (≤ 4 iterations) and halves after a failure.
  double initial_step_ratio = 1.0;
  /// The branch ends when a failed step would fall below this fraction of the energy (or,
  /// along the arc, of the last point's size in (start, period)).
  double min_step_ratio = 1e-6;
  /// Each orbit takes orbit.steps × max(1, T / T₀) steps (T₀ the first point's period), so
  /// that the step size stays the first orbit's while the period grows towards a separatrix.
  bool steps_follow_period = true;
};

/// One converged point of a branch.
struct nnm_point {
  double energy = 0;     ///< H (J)
  double period = 0;     ///< T (s)
  double frequency = 0;  ///< 2π/T (rad/s)
  std::vector<double> x0;
  std::vector<double> amplitudes;  ///< max |φ_i| (rad), dim n
  std::vector<std::complex<double>> multipliers;
  double max_multiplier = 0;
  bool stable = false;
  double closure = 0;
  int iterations = 0;
};

/// Where the energy along a branch turns back (a fold: the family continues, towards lower
/// energies), bracketed by two neighbouring points.
struct nnm_fold {
  std::size_t after = 0;  ///< the index of the point before the turn
  double energy = 0;      ///< the largest (or smallest) energy of the parabola through three points
};

/// The point of a branch that a converged shooting result is.
nnm_point to_nnm_point(const periodic_orbit_result& r);

struct nnm_branch {
  int mode = 0;                 ///< k (0-based, ascending linear frequency)
  double linear_frequency = 0;  ///< ω_k of the linear mode (rad/s)
  std::vector<double> shape;    ///< its mode shape (dim n)
  /// In the order of the family: by increasing energy, except past a fold.
  std::vector<nnm_point> points;
  std::vector<nnm_fold> folds;  ///< where the energy turned back
  /// Why the branch ended: "reached energy_max", "max_points reached", "the shooting stopped
  /// converging beyond E = … (the step fell below min_step_ratio)", "the branch turned back
  /// below its first energy", "stopped".
  std::string end_reason;
  bool stopped = false;  ///< a run control stopped it
};

/// The nonlinear normal mode family of linear mode `mode` (0-based, ascending ω) of the
/// hanging chain, continued from a small amplitude up to options.energy_max (the first two
/// points at fixed energies, then by options.method, with step-size control; the last point
/// is shot at energy_max itself). Throws std::invalid_argument as periodic_orbit does, and
/// for a mode index out of range, a non-positive start_amplitude or energy_max below the
/// first point's energy.
nnm_branch continue_mode(const chain& c, int mode, const continuation_options& options);

/// The family of a converged orbit (an oscillation or a rotating orbit: `start` was shot
/// with options.orbit, whose winding and phase it keeps), continued in energy towards
/// `energy_end` (up or down) as continue_mode continues a mode; options.energy_max and
/// start_amplitude are not used. The branch's mode is −1 and its linear frequency 0. Throws
/// std::invalid_argument for an orbit that did not converge or has the wrong size, and as
/// periodic_orbit does.
nnm_branch continue_orbit(const chain& c, const periodic_orbit_result& start, double energy_end,
                          const continuation_options& options);

/// Where a branch's frequency ω first departs from the linear ω_k by the relative `shift`
/// (|ω/ω_k − 1| = shift, e.g. 0.01 for the paper's 1 %, §6.4): the orbit at that energy,
/// bracketed by the first two points of the branch on either side and located by the
/// Illinois variant of regula falsi in the energy, each orbit shot (with `options`, its energy
/// set) from the interpolation of the bracket's ends, until ||ω/ω_k − 1| − shift| ≤
/// `tolerance` · shift or the bracket is a few ulps wide. nullopt where no point of the branch
/// departs that far, or where the first point already does (nothing brackets it). Throws
/// std::invalid_argument for a shift not in (0, 1) or a non-positive tolerance.
std::optional<nnm_point> locate_departure(const chain& c, const nnm_branch& branch, double shift,
                                          const periodic_orbit_options& options = {},
                                          double tolerance = 1e-9);

/// How a branch's orbits lose or regain stability between two points: the Floquet
/// multipliers that leave the unit circle, seen on the unstable side. In a Hamiltonian
/// system they leave in pairs μ, 1/μ (or quartets), after colliding on the circle.
enum class nnm_bifurcation_kind {
  branch_point,     ///< a real pair leaves through +1 (a new family branches off)
  period_doubling,  ///< a real pair leaves through −1 (an orbit of twice the period)
  complex_pair,     ///< a complex quartet leaves the circle (a Krein collision, Neimark–Sacker)
};
/// "branch point", "period doubling" or "complex pair".
std::string_view nnm_bifurcation_name(nnm_bifurcation_kind kind);

/// A change of stability along a branch, bracketed in energy by two orbits.
struct nnm_bifurcation {
  nnm_bifurcation_kind kind = nnm_bifurcation_kind::branch_point;
  double energy = 0;            ///< the bracket's midpoint (J)
  bool loses_stability = true;  ///< stable below `energy`, unstable above (or the reverse)
  nnm_point stable_side;        ///< the bracket's stable orbit
  nnm_point unstable_side;      ///< and its unstable one
};

/// Every change of stability between consecutive points of `branch`, located by bisection in
/// the energy (each orbit shot with `options`, from the interpolation of the bracket's ends)
/// until the bracket is narrower than energy_tolerance · max(1, E), and classified by the
/// unstable side's largest multiplier. A shot that fails ends that bisection with the bracket
/// it had. Throws std::invalid_argument for a non-positive energy_tolerance.
std::vector<nnm_bifurcation> locate_bifurcations(const chain& c, const nnm_branch& branch,
                                                 const periodic_orbit_options& options = {},
                                                 double energy_tolerance = 1e-8);

/// The family that branches off at a change of stability located by locate_bifurcations,
/// continued towards energy_end as continue_orbit continues a family (options.orbit's phase
/// is replaced by the Poincaré plane: a family born at a branch point need not pass through
/// a turning point). The new direction v: at a branch point, the null direction the
/// fixed-energy shooting equations gain (the smallest singular vector of their Jacobian in
/// (x0, T) at the bracket's orbit, orthogonal to the flow); at a period doubling, the
/// monodromy's eigenvector at −1, the new orbits having twice the period. Orbits are shot at
/// energies a little to either side of the bifurcation, from its orbit moved along ±v by
/// growing distances; the first that converges away from the old family's orbit at that
/// energy (more than 1e-6 from it in x0, and for a period doubling not the old orbit run
/// twice) starts the new family. The branch is empty, with end_reason saying why, when none
/// is found or for a complex pair (no family of the same period to switch to). mode is −1.
/// Its orbits lie on Poincaré planes: locate_bifurcations on it needs options with
/// orbit_phase::poincare (a turning-point shooting would look for another family's orbits).
nnm_branch switch_branch(const chain& c, const nnm_bifurcation& at, double energy_end,
                         const continuation_options& options);

}  // namespace npend
