// Unstable periodic orbits (UPOs) in a chaotic sea: the close returns of a chaotic trajectory
// on the Poincaré section φ_1 = 0 are candidate orbits, each refined by shooting at the
// trajectory's energy; the distinct orbits up to a period bound, with their Floquet
// multipliers and the largest multiplier's rate ln|μ_max|/T beside the trajectory's maximal
// Lyapunov exponent.
#pragma once

#include <complex>
#include <cstddef>
#include <limits>
#include <span>
#include <vector>

#include "npend/analysis/orbits/periodic_orbit.hpp"
#include "npend/chain.hpp"
#include "npend/run_control.hpp"

namespace npend {

struct unstable_orbit_search_options {
  /// Orbits up to this period are looked for (s); required, positive and finite.
  double period_max = 0;
  /// And from this period on (s): 0 ≤ period_min < period_max.
  double period_min = 0;
  /// The length of the chaotic trajectory whose close returns are the candidates (s).
  double search_time = 500;
  /// The Gauss–Legendre (order 6) step of the trajectory and of the Lyapunov run (s).
  double dt = 0.005;
  /// A close return: two crossings of the section at most period_max apart whose states
  /// differ by at most this, per coordinate, in units of that coordinate's range over all
  /// crossings (angles compared on the circle): the distance is
  /// max_k |Δx_k| / range_k over the coordinates other than φ_1 (which is 0 on the section).
  double return_tolerance = 0.1;
  /// At most this many candidates are shot.
  int max_candidates = 100;
  /// Stop once this many distinct orbits are found (0: no limit). The candidates are tried
  /// by the number of section crossings between their ends, then by their distance, so the
  /// orbits found first are the topologically shortest.
  int max_orbits = 0;
  /// The shooting of each candidate: phase (poincare), energy (the start's) and winding (the
  /// candidate's turns) are set here; segments is raised to ⌈T / segment_time⌉ and steps to
  /// ⌈T / shooting_dt⌉ (a multiple of the segments) where that is more. The other fields
  /// (tolerance, max_iterations, stability_tolerance, …) are used as given. Damped Newton
  /// (line_search) is on: at 50 J on the triple pendulum it let 22 of 90 close returns
  /// converge instead of 12.
  periodic_orbit_options shooting = [] {
    periodic_orbit_options o;
    o.line_search = true;
    return o;
  }();
  /// The longest Gauss–Legendre step of the shooting (s): its map's orbit must be the flow's
  /// to well below 1e-9 after the amplification e^{λT} of an unstable orbit.
  double shooting_dt = 0.002;
  /// The longest segment of the multiple shooting (s): an unstable orbit's errors grow over a
  /// segment, e^{λ·segment_time}, not over the whole period. Infinity: single shooting.
  double segment_time = 0.5;
  /// Two orbits are one when their periods agree to this relative tolerance and a section
  /// point of one lies within same_orbit_tolerance (∞-norm, angles on the circle) of a
  /// section point of the other. The same test finds an orbit that is another traversed
  /// several times: it is reported once, at its prime period.
  double period_tolerance = 1e-6;
  double same_orbit_tolerance = 1e-6;
  /// Also compute the trajectory's maximal Lyapunov exponent (maximal_lyapunov_exponent with
  /// gauss6 at dt over lyapunov_time) for comparison with the orbits' rates.
  bool lyapunov = true;
  /// The length of that run (s); NaN: search_time.
  double lyapunov_time = std::numeric_limits<double>::quiet_NaN();
  /// Progress (the trajectory, the Lyapunov run, then the candidates) and stop requests.
  run_control* control = nullptr;  ///< not owned; may be null
};

/// One distinct periodic orbit.
struct unstable_orbit {
  std::vector<double> x0;  ///< the start (dim 2n), angles as the shooting left them
  double period = 0;       ///< T (s), the prime period
  double energy = 0;       ///< H(x0) (J)
  double closure = 0;      ///< ‖φ(T) − x0‖∞ of the shooting's last integration
  int iterations = 0;      ///< Newton corrections of the shooting
  /// The monodromy's eigenvalues by descending |μ|, without the trivial pair (dim 2n − 2).
  std::vector<std::complex<double>> multipliers;
  double max_multiplier = 0;  ///< max |μ| (1 for n = 1)
  /// ln(max_multiplier) / T (1/s): the orbit's rate of separation, to compare with the
  /// maximal Lyapunov exponent of the chaotic trajectory.
  double lyapunov_rate = 0;
  bool stable = false;  ///< max_multiplier ≤ 1 + shooting.stability_tolerance
  /// Whole turns of each angle per period (dim n): all 0 for an oscillation; a rotating
  /// orbit's arms turn over.
  std::vector<int> winding;
  /// How many distinct orbits this one and its images under the chain's symmetries are (1, 2
  /// or 4): time reversal (φ, p, t) → (φ, −p, −t), and where no spring has a rest angle the
  /// mirror (φ, p) → (−φ, −p). The images share the period and multipliers; the search lists
  /// one of them.
  int copies = 1;
  /// The crossings of φ_1 = 0 (upwards) in one period, in time order: their states (dim 2n
  /// each, angles in [−π, π]) and times from x0 (s, in (−T/2, T/2]: traced half a period
  /// each way). Empty for an orbit that does not cross the section.
  std::vector<std::vector<double>> section_points;
  std::vector<double> section_times;
};

struct unstable_orbit_search_result {
  /// The distinct converged orbits with period_min ≤ T ≤ period_max, by ascending period.
  std::vector<unstable_orbit> orbits;
  double energy = 0;             ///< H of the start (J): every orbit's energy
  std::size_t crossings = 0;     ///< crossings of the section by the trajectory
  std::size_t candidates = 0;    ///< close returns to shoot (before max_candidates)
  std::size_t rotating = 0;      ///< of the candidates, those along which an arm turned over
  std::size_t tried = 0;         ///< candidates shot
  std::size_t converged = 0;     ///< shootings that converged
  std::size_t repeats = 0;       ///< converged to an orbit traversed several times
  std::size_t duplicates = 0;    ///< converged to an orbit found (or a symmetry image of one)
  std::size_t out_of_range = 0;  ///< converged to a prime period outside the bounds
  /// The trajectory's maximal Lyapunov exponent (1/s); NaN without options.lyapunov.
  double lyapunov_exponent = std::numeric_limits<double>::quiet_NaN();
  double lyapunov_time = 0;  ///< the length of the Lyapunov run (s)
  bool stopped = false;      ///< a run control stopped it (the orbits are those found so far)
};

/// The periodic orbits near the close returns of the trajectory from `start` (dim 2n), at
/// its energy E = H(start). The trajectory (gauss6, step options.dt, for search_time) is cut
/// by the section φ_1 = 0 (on the circle, upwards: φ_1' > 0; crossings located as
/// poincare_section does). Each pair of crossings i < j with period_min ≤ t_j − t_i ≤
/// period_max whose states are within return_tolerance (see the options) is a close return;
/// a return (i, j) is skipped when (i, j') is one for some j' < j with j − i a multiple of
/// j' − i (it shadows the shorter orbit repeatedly), and when it overlaps the stretch of a
/// candidate that converged with the same number of crossings (the trajectory shadows that
/// orbit). The others, by crossings then distance, are shot with periodic_orbit
/// (orbit_phase::poincare at energy E, multiple shooting, from x_i with its angles on the
/// circle, T = t_j − t_i and the whole turns each angle made from i to j as the winding). A
/// converged orbit is traced half a period each way with the shooting's steps for its
/// section points; if one of them recurs within the period, the orbit is a repeat, shot again
/// at its prime period. It is kept when that period is within the bounds and it is none of
/// the orbits already found nor their images under the symmetries (unstable_orbit::copies). Throws
/// std::invalid_argument for a damped chain, a moving pivot, a cart, a start of the wrong size or
/// not finite, a period_max not positive and finite, period_min outside [0, period_max),
/// search_time, dt, shooting_dt, segment_time, return_tolerance, period_tolerance,
/// same_orbit_tolerance or lyapunov_time not positive (and finite, but for segment_time), dt not
/// below search_time, max_candidates < 1 or max_orbits < 0, and as periodic_orbit does for bad
/// shooting options; npend::integration_error when the trajectory cannot be integrated (a smaller
/// dt).
unstable_orbit_search_result find_unstable_orbits(const chain& c, std::span<const double> start,
                                                  const unstable_orbit_search_options& options);

}  // namespace npend
