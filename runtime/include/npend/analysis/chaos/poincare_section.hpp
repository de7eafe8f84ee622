// Poincaré sections (paper §6.6.1, Abb. 6.8): where a trajectory crosses a hyperplane of
// state space such as φ₃ = 0, located on the integrator's own steps — bracketed by the
// sign of g at the step's ends, found on the step's dense output, and polished by Hénon's
// trick — not by sampling the output grid. The same crossings are the exact event times of
// the recurrence statistics (§6.6.3: φ_k = 0, or stretched neighbours φ_i = φ_{i+1}).
#pragma once

#include <cstddef>
#include <span>
#include <string_view>
#include <vector>

#include "npend/analysis/series/event_times.hpp"
#include "npend/chain.hpp"
#include "npend/integrators/integrate.hpp"

namespace npend {

/// The hyperplane g(x) = w·x − c = 0 of the state space x = [φ_1..φ_n, p_1..p_n].
///
/// Angles live on a circle, but the state carries them unwrapped (an arm that went over the
/// top once has φ near 2π). A `circular` section is taken on the circle: it is the family of
/// planes w·x = c + 2πj for every integer j, so φ_k = 0 is crossed whenever the arm passes
/// the downward vertical, however often it has turned. Sections of angles made by
/// coordinate() and equal_coordinates() are circular; clear the flag for the plane of the
/// unwrapped angles (the two agree while no arm flips over, the paper's regime).
struct section_plane {
  std::vector<double> normal;  ///< w (dim 2n), not all 0
  double level = 0;            ///< c, in the unit of w·x
  /// The section is w·x ≡ c (mod 2π): w must have integer entries on the angles and 0 on
  /// the momenta (φ_k = c, φ_i = φ_j). Crossing directions are those of w·x.
  bool circular = false;

  /// g(x) = w·x − c (x: dim of the normal); for a circular section reduced to [−π, π], the
  /// distance to the nearest branch. Does not check sizes.
  double value(std::span<const double> x) const;

  /// Coordinate `index` of the state (0-based: φ_k is k − 1, p_k is n + k − 1) equal to
  /// `level` (rad or kg m²/s); circular for an angle. Throws std::invalid_argument for
  /// links < 1, an index ≥ 2n or a non-finite level.
  static section_plane coordinate(int links, std::size_t index, double level);
  /// Coordinate `first` equal to coordinate `second` (e.g. φ_i = φ_{i+1}: g = x_first −
  /// x_second); circular when both are angles. Throws std::invalid_argument for links < 1,
  /// indices ≥ 2n, or first = second.
  static section_plane equal_coordinates(int links, std::size_t first, std::size_t second);

  /// The level c + 2πj of the plane a circular section is crossed on between states a and b
  /// of one step: j with 2πj between w·a − c and w·b − c (the first such j from a on; a step
  /// turns by far less than 2π). The level itself when not circular or not crossed.
  double branch_level(std::span<const double> a, std::span<const double> b) const;

  /// Throws std::invalid_argument naming the problem: a normal whose size is not
  /// `state_size`, a non-finite entry or level, a normal that is all 0, a circular normal
  /// with a non-integer angle entry or a momentum entry.
  void validate(std::size_t state_size) const;
};

/// One crossing of a section.
struct section_crossing {
  double t = 0;               ///< s
  std::vector<double> state;  ///< [φ, p] on the section (dim 2n)
  /// True when polished by Hénon's trick (the state is then as accurate as the step's end
  /// states and on the section to rounding); false when the crossing was too close to
  /// tangential for it, and the state is the dense output's (see crossing_locator).
  bool refined = true;
};

/// Finds the crossings of a section in the steps of an integration. Pass it as
/// npend::integrate's step observer, by reference (std::ref(locator)), so that the crossings
/// collect here.
///
/// A step crosses upwards when g goes from < 0 at its start to ≥ 0 at its end, downwards
/// from > 0 to ≤ 0 (along the integration, i.e. forwards in time for dt > 0); a start
/// exactly on the section is not a crossing, and two crossings within one step cancel
/// (with the default dt = 1 ms of the pendulum that means a grazing touch). For a crossing
/// step:
/// 1. the crossing time t* is the root of g(x(t)) on the step's dense output
///    (integration_step::state_at), by the Illinois variant of regula falsi;
/// 2. Hénon's trick (M. Hénon, Physica D 5, 412, 1982) then integrates dx/dg = f/(w·f),
///    dt/dg = 1/(w·f) — g as the independent variable — from the nearer end of the step to
///    g = 0 with odeint's controlled Runge–Kutta–Fehlberg 7(8) at tolerances 1e-14. That
///    lands on the section up to rounding (w·x changes by exactly Δg along it), with the
///    accuracy of the step's end state rather than of the interpolant, and keeps the energy.
///    It needs w·f ≠ 0 between that end and the crossing; when w·f at the chosen end has
///    the wrong sign, or the result strays from the dense-output estimate (by more than
///    1e-3 of the step), the crossing keeps the dense output's state, marked not refined.
class crossing_locator {
 public:
  /// The chain must outlive the locator. `max_crossings` > 0 stops the integration after
  /// that many. Throws std::invalid_argument for a section that fails validate(2n).
  crossing_locator(const chain& c, section_plane section,
                   crossing_direction direction = crossing_direction::up,
                   std::size_t max_crossings = 0);

  /// Looks for a crossing in `step`; stop once max_crossings are found.
  observer_action operator()(const integration_step& step);

  const std::vector<section_crossing>& crossings() const { return m_crossings; }
  const section_plane& section() const { return m_section; }

 private:
  bool polish(const integration_step& step, double g_begin, double g_end,
              section_crossing& crossing);

  const chain* m_chain;
  section_plane m_section;
  crossing_direction m_direction;
  std::size_t m_max_crossings;
  std::vector<section_crossing> m_crossings;
  std::vector<double> m_buffer, m_f;
};

struct poincare_options {
  /// Which crossings count. A Poincaré map uses one direction; both give the event times of
  /// every passage.
  crossing_direction direction = crossing_direction::up;
  /// Stop the integration after this many crossings (0: integrate to t_end).
  std::size_t max_crossings = 0;
};

struct poincare_result {
  std::vector<section_crossing> crossings;  ///< in the order of time
  integration_result integration;           ///< how the integration ended
};

/// The crossings of `section` by the trajectory of chain `c` from x0 (dim 2n) integrated
/// with `integration` (any stepper; see crossing_locator for how each crossing is located).
/// Throws std::invalid_argument for a bad section (size ≠ 2n, non-finite, all 0) and as
/// npend::integrate does; npend::integration_error when the integration cannot go on.
poincare_result poincare_section(const chain& c, std::span<const double> x0,
                                 const section_plane& section,
                                 const integration_options& integration,
                                 const poincare_options& options = {});

/// What to tell a user whose run took an arm over the top, when sections of unwrapped angles
/// are asked for (the command line's --unwrapped).
inline constexpr std::string_view unwrapped_angles_note =
    "an arm passed the upright position (|phi| > pi) and the section is of the unwrapped "
    "angles (--unwrapped), so phi = c and phi = c + 2 pi are different planes";

/// The times of the crossings (s), for recurrence_times.
std::vector<double> crossing_times(std::span<const section_crossing> crossings);

/// How good a set of crossings is: how far they lie off the section and off the energy
/// surface.
struct section_quality {
  double max_residual = 0;          ///< largest |g(x)| of a crossing (section.value)
  double max_rel_energy_error = 0;  ///< largest relative_energy_error of H against h0
  std::size_t unrefined = 0;        ///< crossings without Hénon's step (dense output only)
};

/// The quality of `crossings` of `section` by chain `c` started with energy h0 (J); all 0
/// for no crossing. Does not check sizes.
section_quality crossing_quality(const chain& c, const section_plane& section,
                                 std::span<const section_crossing> crossings, double h0);

}  // namespace npend
