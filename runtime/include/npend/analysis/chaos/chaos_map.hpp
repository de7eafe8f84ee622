// The per-cell quantities of a chaos map (npend map): the time to the first flip of an arm
// (J. Heyl, "The double pendulum fractal", 2008) and the maximal Lyapunov exponent, for one
// start state each. The grid is map_grid.hpp's; its tiles, threads and files map_run.hpp's.
#pragma once

#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "npend/analysis/chaos/chaos_indicators.hpp"
#include "npend/analysis/chaos/lyapunov.hpp"
#include "npend/chain.hpp"
#include "npend/integrators/stepper_kind.hpp"
#include "npend/run_control.hpp"

namespace npend {

/// Whether the energy of x0 forbids a flip — an arm passing the upright position — so that
/// the cell needs no integration. Arm k upright (φ_k = π) needs V ≥ 2 g G_k, the least V with
/// φ_k = π (the others hanging: V is a sum of g G_j (1 − cos φ_j), G_j = m_j c_j + l_j μ_{j+1}
/// the moment gravity acts on, c = l for point masses). `link` = 0: any arm (the least of
/// those bounds); k ≥ 1: arm k. The bound also holds with joint springs (their energy is
/// never negative) and damping (H only falls); a moving pivot feeds energy in, so a driven
/// chain is never ruled out (false). Throws std::invalid_argument for an arm not 0..n.
bool energy_forbids_flip(const chain& c, std::span<const double> x0, int link = 0);

/// How the cells of a map are integrated: rk4 at a fixed step dt (the default), dopri5
/// (Dormand–Prince 5(4), adaptive, under abs_tol and rel_tol, first trial step dt), as
/// npend::integrate runs them, gauss4 and gauss6; or, for the chaos indicators only, taylor
/// (chaos_indicators on Taylor's method at the one tolerance abs_tol = rel_tol, cell by cell).
struct map_stepping {
  stepper_kind stepper = stepper_kind::rk4;
  double abs_tol = 1e-10;  ///< dopri5 and taylor only
  double rel_tol = 1e-10;  ///< dopri5 and taylor only

  /// Throws std::invalid_argument ("<what>: …") for a stepper that is not a map's
  /// (is_map_stepper), or (dopri5, taylor) tolerances that are negative, not finite, or both
  /// zero, or (taylor) not equal.
  void validate(std::string_view what) const;
};

/// How far the energy may have drifted, relative to the start's, when a flip is seen: at the
/// end of the step in which an arm passes the upright, |H − H(x0)| ≤ flip_energy_tolerance ·
/// H(x0) (H = T + V with V from the hanging chain, a sum of non-negative terms, and H(x0) ≥
/// 2 g G_k > 0 wherever a flip is possible, so no cancellation). Beyond it the flip is a
/// numerical artefact — a step too long for a stiff chain (a nearly massless link, a long
/// chain) blowing the state up — and the cell failed (flip_time throws integration_error,
/// the maps give NaN). A damped chain is held to H − H(x0) ≤ the same (its H only falls);
/// a driven one, fed energy by its pivot, is not checked.
inline constexpr double flip_energy_tolerance = 1e-2;

struct flip_options {
  double t_end = 100;  ///< give up after this time (s): the cell is +inf
  double dt = 0.01;    ///< rk4's step (s); dopri5's first trial step
  int link = 0;        ///< 0: any arm; k ≥ 1: arm k only
  map_stepping stepping = {};
  /// Polled for a stop request inside each cell's steps (may be null). Once it asks to
  /// stop, the cells not yet finished end at once as NaN: the caller, who asked, drops the
  /// values. Only stop_requested() is called, from every thread that runs cells at once.
  run_control* control = nullptr;
};

/// The time (s) at which an arm (or arm `link`) of the chain started at x0 first passes the
/// upright position, |φ_k| ≥ π (the angles are not wrapped), located inside the first step
/// at whose end an arm is upright. With rk4, gauss4 and gauss6 (fixed steps of `dt`): where
/// the step's cubic Hermite interpolant of φ_k — from the angles and their rates f at the
/// step's two ends — reaches ±π, found on its monotone pieces by bisection down to adjacent
/// doubles; as accurate as the trajectory (O(dt⁴)). With dopri5: by bisection on the
/// stepper's dense output. An arm that passes π and falls back within one step is missed.
/// +inf if it does not by t_end, or if energy_forbids_flip (then without integrating); NaN if
/// options.control asked to stop first. Throws std::invalid_argument for bad options (also
/// more than 2^53 steps of dt up to t_end, too many to count exactly) or a non-conservative
/// chain, npend::integration_error if the state becomes non-finite (or dopri5's step
/// collapses) or if the energy at the end of the flip's step is off by more than
/// flip_energy_tolerance (the flip is then an artefact).
double flip_time(const chain& c, std::span<const double> x0, const flip_options& options);

/// flip_time of many start states at once: `starts` holds count = starts.size() / 2n states,
/// one after another (dim count × 2n); returns the count flip times. On a point-mass chain
/// with batch kernels (batch_lanes > 0) the rk4 steps run on batch_lanes lanes, blocks of
/// the batch kernels' W (npend/batch_math.hpp), a lane refilled from the queue of starts as
/// soon as its cell is done; otherwise flip_time cell by cell. Each value depends on its own
/// start only, never on its slot or on the other starts. The lanes take the same steps as
/// flip_time (odeint's runge_kutta4, or its dopri5 with each lane's own step control and
/// dense output, the same sums in the same order) with SLEEF's sines and cosines (within 1
/// ulp) for std::sin's, and locate the flip and check its energy as flip_time does (the
/// rates at the step's ends from the lanes' rhs), so a cell's time equals flip_time's up to
/// round-off (bit for bit where SLEEF's sines equal std::sin's). Where flip_time would
/// throw integration_error (the state became non-finite, an untrusted flip) the value is
/// NaN. Throws
/// std::invalid_argument as flip_time, and for a size that is not a multiple of 2n.
std::vector<double> flip_times(const chain& c, std::span<const double> starts,
                               const flip_options& options);

/// Lanes flip_times and map_cells step at once for chain `c`: four blocks of the lane ISA's
/// width (8 with AVX-512F, 4 with AVX2, 2 with SSE2) on a point-mass chain whose link count
/// has batch kernels, 0 where they go cell by cell (physical chains).
int batch_lanes(const chain& c);

/// The instruction sets the maps' batch lanes can run on here, lowest first: the compiler's
/// own ISA ("sse2" in a default build) and the variants the build compiled above it ("avx2":
/// AVX2 with FMA, "avx512f") that this CPU has.
std::vector<std::string_view> batch_lane_isas();

/// The ISA the lanes run on now: the last of batch_lane_isas(), unless the environment
/// variable NPEND_LANE_ISA names another one of them (read when the first map runs) or
/// use_batch_lane_isa chose one. Throws std::invalid_argument, naming NPEND_LANE_ISA, where
/// that names none of them.
std::string_view batch_lane_isa();

/// Makes the maps run their lanes on `isa`, one of batch_lane_isas() (std::invalid_argument
/// otherwise). The values of a map's cells agree across ISAs to round-off: each ISA has its
/// own SLEEF sines, and AVX2 and AVX-512F fuse multiply-adds.
void use_batch_lane_isa(std::string_view isa);

/// What a map shows in each cell.
enum class map_quantity {
  flip,      ///< flip_time
  lyapunov,  ///< the maximal Lyapunov exponent (rk4, one tangent vector)
  fli,       ///< the fast Lyapunov indicator at t_end (chaos_indicators)
  megno,     ///< MEGNO ⟨Y⟩ at t_end
  sali,      ///< SALI at t_end
  gali,      ///< GALI_k at t_end, k = map_cell_options::gali_order
  state,     ///< one coordinate of the state at t_end, map_cell_options::component
};
/// "flip", "lyapunov", "fli", "megno", "sali", "gali" or "state".
std::string_view map_quantity_name(map_quantity quantity);
/// The quantity called `name`; throws std::invalid_argument naming the valid names.
map_quantity parse_map_quantity(std::string_view name);

/// Whether a map integrates with `stepper` at all: rk4, dopri5, gauss4, gauss6 (the batch
/// lanes' steppers) or taylor (the chaos indicators only).
bool is_map_stepper(stepper_kind stepper);
/// The names of the steppers is_map_stepper takes, joined by ", " (for messages).
std::string map_stepper_names();
/// Whether a map of `quantity` integrates with `stepper`: flip, lyapunov and state with the
/// lanes' steppers (rk4, dopri5, gauss4, gauss6); the chaos indicators with chaos_indicators'
/// (rk4, taylor).
bool map_takes_stepper(map_quantity quantity, stepper_kind stepper);

struct map_cell_options {
  map_quantity quantity = map_quantity::flip;
  double t_end = 100;  ///< s
  double dt = 0.01;    ///< rk4's step (s); dopri5's first trial step
  /// As map_takes_stepper: the chaos indicators (fli, megno, sali, gali) take rk4 and taylor, as
  /// chaos_indicators does.
  map_stepping stepping = {};
  int flip_link = 0;  ///< flip: 0 any arm, k ≥ 1 arm k
  /// gali: k of GALI_k, 2..2n; 0 means n + 1, the least k beyond the dimension n of a
  /// torus, where regular cells fall as a power of t and chaotic ones exponentially.
  int gali_order = 0;
  /// state: which coordinate of the final state, 0..2n-1 ([φ, p]; angles not wrapped).
  int component = 0;
  /// Polled for a stop request inside each cell's steps, as flip_options::control: once it
  /// asks to stop, the cells not yet finished are NaN (may be null).
  run_control* control = nullptr;

  /// Throws std::invalid_argument naming the problem with these options for chain `c` (as
  /// map_cell would on its first cell): dt or t_end (also more than 2^53 steps of dt up to
  /// t_end, too many to count exactly), an arm that does not exist, a chain a
  /// flip map cannot take (see energy_forbids_flip). For callers that run cells where an
  /// exception cannot leave (threads).
  void validate(const chain& c) const;
};

/// One cell of a map: the flip time (flip_times of this one start, so on the batch lanes
/// where the chain has them, with flip_options from `options`), the maximal Lyapunov
/// exponent (1/s) of maximal_lyapunov_exponent with rk4 at dt (or dopri5, restarted at
/// every renormalisation as the library does) up to t_end (on the batch
/// lanes where the chain has them: the same rk4, renormalisations and sum, with the lanes'
/// tangent kernel and SLEEF's sines, so equal to the library's up to round-off), an indicator
/// of chaos_indicators (rk4 at dt, to t_end; on the batch lanes likewise), or a coordinate
/// of the state at t_end (rk4 at dt, a last shorter step landing on t_end; dopri5's dense
/// output at t_end; on the batch lanes likewise); NaN when the integration fails (an
/// integration_error) and, for a flip map, where the energy rules a flip out (energy_forbids_flip:
/// a map marks those cells apart from the +inf of cells that were integrated to t_end without
/// flipping). Throws std::invalid_argument as flip_time and maximal_lyapunov_exponent do.
double map_cell(const chain& c, std::span<const double> x0, const map_cell_options& options);

/// map_cell of each of count = starts.size() / 2n start states (dim count × 2n), the same
/// values bit for bit; the cells run batch_lanes at a time.
std::vector<double> map_cells(const chain& c, std::span<const double> starts,
                              const map_cell_options& options);

/// Value i (0 ≤ i < count) of `count` evenly spaced values from `from` to `to`, both
/// included (`from` alone when count is 1): the axes of a map.
double grid_value(double from, double to, int count, int i);

}  // namespace npend
