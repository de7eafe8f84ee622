// The batch lanes of the chaos maps (private to the runtime): many cells integrated at once
// on the generated batch kernels (npend/batch_kernels.hpp), W = batch_width lanes to a block
// and lane_blocks blocks to a step, with finished lanes refilled from a queue of cells.
// chaos_map.cpp runs flip times, Lyapunov exponents and chaos indicators on them.
//
// The arithmetic of a lane never depends on its slot or its neighbours, so a cell's value
// depends on its start alone, however the cells are queued, refilled or moved.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <optional>
#include <utility>
#include <vector>

#include "npend/chain.hpp"

// clang-format off
// Last: in a lane variant's unit, it switches what follows to the variant's ISA.
#include "npend/batch_kernels.hpp"
// clang-format on

// The lanes are compiled once for each ISA the build has them for (cmake/npend_lanes.cmake),
// so everything here sits in the ISA's inline namespace (npend/batch_math.hpp).
namespace npend::detail {
inline namespace NPEND_BATCH_ISA_NAMESPACE {

// The batch kernels the lanes run chain `c` on, or nullptr.
const batch_kernels* lane_kernels(const chain& c);

// Blocks of batch_width lanes stepped at once, in one call of the kernels. One block's rhs
// is a short chain of dependent operations (a sincos, then a division), whose latency a
// single block leaves the processor waiting out; independent blocks let it overlap them
// (bench/batch/flip_map_benchmark.cpp measures what they gain on a machine).
constexpr int lane_blocks = batch_blocks;

// What the lanes integrate, one block of W lanes at a time (W = batch_width): the chain's
// state alone (rhs_batch), or with tangent vectors (tangent_batch, tangents_batch). A block holds
// the `coordinates` of its W lanes in the kernels' structure-of-arrays layout, coordinate i of the
// block's lane l at [i*W + l]: the state's 2n coordinates first, then
//   tangent = 1: one tangent vector (2n), the Lyapunov map's;
//   tangent = k ≥ 2 with `indicators`: k deviation vectors (2n each), then the time t
//   (dt/dt = 1, so that each lane knows its own t) and MEGNO's integrals y and z, as
//   chaos_indicators' augmented system.
class lane_system {
 public:
  static constexpr int W = batch_width;

  lane_system(const batch_kernels& k, const double* params, int n, int tangent, bool indicators)
      : m_kernels(k),
        m_params(params),
        m_d(static_cast<std::size_t>(2 * n)),
        m_tangent(static_cast<std::size_t>(tangent)),
        m_indicators(indicators) {}

  std::size_t coordinates() const { return m_d * (1 + m_tangent) + (m_indicators ? 3 : 0); }
  std::size_t vector(std::size_t j) const { return m_d * (1 + j); }  // its first coordinate
  std::size_t time() const { return m_d * (1 + m_tangent); }
  std::size_t y() const { return time() + 1; }
  std::size_t z() const { return time() + 2; }

  /// dxdt of `blocks` blocks of W lanes (each lane `coordinates` long, structure-of-arrays),
  /// block b at x + b*stride and dxdt + b*stride, in one call of the kernels.
  void operator()(int blocks, std::size_t stride, const double* x, double* dxdt);

 private:
  // MEGNO's integrands y' = t (w·J w)/|w|² and z' = 2y/t, and t' = 1, on one block's lanes.
  void megno_integrands(const double* x, double* dxdt) const;

  const batch_kernels& m_kernels;
  const double* m_params;
  std::size_t m_d, m_tangent;
  bool m_indicators;
};

// The lanes' layout, which every lane stepper shares: lane_blocks blocks of a lane_system's
// lanes. Block b holds lanes b*W .. b*W + W-1: coordinate i of lane l at
// [b*B + i*W + l % W], B = coordinates × W. A stepper's step(blocks) advances the first
// `blocks` blocks only.
class lane_layout {
 public:
  static constexpr int W = batch_width;
  static constexpr int lanes = W * lane_blocks;

  explicit lane_layout(lane_system system)
      : m_system(std::move(system)),
        m_block(m_system.coordinates() * W),
        m_x(m_block * lane_blocks) {}

  const lane_system& system() const { return m_system; }
  double* state() { return m_x.data(); }
  std::size_t coordinates() const { return m_system.coordinates(); }

  /// Where coordinate i of lane l lives in state().
  std::size_t at(std::size_t i, std::size_t l) const { return (l / W) * m_block + i * W + l % W; }

  /// The system's dxdt at lane l's coordinates in x (laid out as state()): coordinates
  /// first .. first + count - 1 into out. One block's rhs on copies of the lane, so the same
  /// bits as the lane's own steps compute at that state; for a value wanted once per cell
  /// (the flip lanes' interpolant), not per step.
  void derivative_at(const double* x, std::size_t l, std::size_t first, std::size_t count,
                     double* out);

 protected:
  /// The system's dxdt on each of the first `blocks` blocks of x.
  void rhs(int blocks, const double* x, double* dxdt);

  lane_system m_system;
  std::size_t m_block;  // B
  std::vector<double> m_x;
  std::vector<double> m_probe, m_probe_f;  // derivative_at's block
};

// rk4 on the lanes: odeint's runge_kutta4 step, sum for sum, so that each lane computes what
// the scalar library's stepper computes from the same state, but with the kernels' sines.
class lane_rk4 : public lane_layout {
 public:
  lane_rk4(lane_system system, double dt)
      : lane_layout(std::move(system)),
        m_k1(m_x.size()),
        m_k2(m_x.size()),
        m_k3(m_x.size()),
        m_k4(m_x.size()),
        m_tmp(m_x.size()),
        m_before(m_x.size()),
        // odeint's coefficients a_ij dt and b_i dt, as it rounds them.
        m_half(0.5 * dt),
        m_zero(0.0 * dt),
        m_full(1.0 * dt),
        m_sixth((1.0 / 6.0) * dt),
        m_third((1.0 / 3.0) * dt) {}

  /// One rk4 step of dt for the first `blocks` blocks. The state before it stays in
  /// state_before() (the two buffers trade places: state() moves with every step).
  void step(int blocks);
  const double* state_before() const { return m_before.data(); }

  /// As lane_gauss's: an rk4 lane has nothing to forget and never fails.
  void restart(std::size_t) {}
  bool failed(std::size_t) const { return false; }

  /// Lane `to` takes lane `from`'s coordinates.
  void copy_lane(std::size_t to, std::size_t from);

 private:
  std::vector<double> m_k1, m_k2, m_k3, m_k4, m_tmp, m_before;
  double m_half, m_zero, m_full, m_sixth, m_third;
};

// Dormand–Prince 5(4) on the lanes, each lane with its own time and step size: what
// npend::integrate runs for stepper_kind::dopri5 (odeint's make_dense_output of
// runge_kutta_dopri5), step for step. A step() is one attempt per lane — odeint's try_step with its
// error norm max_i |err_i| / (abs_tol + rel_tol (|x_i| + |h| |f_i|)) and its step adjustment — so a
// lane either advances (accepted) or keeps its state with a shorter step; state_at is the stepper's
// own dense output over the lane's last accepted step.
class lane_dopri5 : public lane_layout {
 public:
  /// odeint gives up a step after this many tries (its failed_step_checker).
  static constexpr int max_tries = 500;

  lane_dopri5(lane_system system, double abs_tol, double rel_tol);

  /// Lane l starts from the state now in its coordinates, at time t with a first trial
  /// step h (odeint's initialize: the derivative is evaluated on the next step).
  void restart(std::size_t l, double t, double h);

  /// One attempt of every lane of the first `blocks` blocks.
  void step(int blocks);

  /// Whether lane l's last attempt was accepted; the attempts of its current step so far.
  bool accepted(std::size_t l) const { return m_accept[l] != 0; }
  int tries(std::size_t l) const { return m_lane[l].tries; }
  /// Lane l's time, and the step it tries next.
  double time(std::size_t l) const { return m_lane[l].t; }
  /// Where lane l's last accepted step began.
  double step_begin(std::size_t l) const { return m_lane[l].t_old; }
  double step_size(std::size_t l) const { return m_h[l]; }

  /// The dense output of lane l's last accepted step at time t within it: coordinates
  /// first .. first + count - 1 into out.
  void state_at(std::size_t l, double t, std::size_t first, std::size_t count, double* out) const;

  /// Lane `to` takes lane `from`'s state, derivative, time and step.
  void copy_lane(std::size_t to, std::size_t from);

 private:
  struct lane {
    double t = 0, t_old = 0;
    int tries = 0;
    bool fresh = true;
  };
  // out = x + Σ h_l c_j k_j, term after term as odeint's scale_sum (coefficient j of lane l
  // at m_coefficient[j * lanes + l]).
  template <std::size_t K>
  void combine(int blocks, double* out, const double* x,
               const std::array<std::pair<const double*, int>, K>& terms);

  double m_abs_tol, m_rel_tol;
  std::array<lane, lanes> m_lane{};
  // Per lane, for the vector loops: the step it tries, its error norm, 1 where its last
  // attempt was accepted.
  std::array<double, lanes> m_h{}, m_error{}, m_accept{};
  std::vector<double> m_f, m_x_old, m_f_old, m_k2, m_k3, m_k4, m_k5, m_k6, m_tmp, m_out, m_f_out,
      m_coefficient;
};

// Gauss–Legendre with `Stages` stages (2: gauss4, 3: gauss6) at the fixed step dt on the
// lanes: what
// npend::gauss_legendre computes, up to round-off. Every lane solves its stage equations
// Z_i = h Σ_j a_ij f(x + Z_j) by fixed-point iteration — only rhs evaluations, which the lanes
// do fast, where the library's simplified Newton needs a Jacobian and an LU factorisation
// per lane — from the library's starting guess (its previous step's collocation polynomial,
// after the first step) and to the library's stopping rule (the estimated remaining error
// below 1e-3 of the rounding unit, or round-off noise). The solution of the stage equations
// does not depend on the iteration that finds it, so the steps agree with the library's to
// round-off. A lane stops iterating when it has converged, on its own, so its value does not
// depend on its neighbours. A lane whose iteration does not converge in max_iterations
// (h‖J‖ too large for a fixed point) is marked failed: its cell belongs to the library,
// whose Newton iteration may still solve it.
template <int Stages>
class lane_gauss : public lane_layout {
 public:
  static constexpr int s = Stages;
  static constexpr int max_iterations = 60;

  lane_gauss(lane_system system, double dt);

  /// Lane l starts from the state now in its coordinates: no previous step to extrapolate.
  void restart(std::size_t l) {
    m_previous[l] = 0;
    m_failed[l] = 0;
  }

  /// One step of dt for every lane of the first `blocks` blocks. The state before it stays
  /// in state_before() (the two buffers trade places: state() moves with every step).
  void step(int blocks);
  const double* state_before() const { return m_before.data(); }

  /// Whether lane l's stage iteration failed (in any step since its restart).
  bool failed(std::size_t l) const { return m_failed[l] != 0; }

  void copy_lane(std::size_t to, std::size_t from);

 private:
  double m_dt;
  // Coefficients as gauss_legendre forms them: the starting guess's extrapolation of the
  // previous step's collocation polynomial, and d = bᵀA⁻¹ (x1 = x0 + Σ d_i Z_i).
  std::array<std::array<double, Stages>, Stages> m_extrapolation{};
  std::array<double, Stages> m_d{};
  std::vector<double> m_tmp, m_before;
  std::array<std::vector<double>, Stages> m_z, m_f, m_f_kept;
  // Per lane: a previous step to extrapolate from, failure, still iterating (1/0), and the
  // iteration's last correction norm.
  std::array<unsigned char, lanes> m_previous{}, m_failed{};
  std::array<double, lanes> m_active{}, m_last_norm{}, m_x_norm{};
};

// What a lane carries besides its coordinates.
struct lane_slot {
  std::size_t cell = 0;   // index of its start in the queue's `starts`
  long long steps = 0;    // steps (dopri5: attempts) taken from the start
  long long reached = 0;  // dopri5 Lyapunov lanes: the steps of dt whose end the lane passed
  double sum = 0;         // Σ ln of the (first) tangent vector's growth
  double peak = 0;        // the indicators' FLI: the running maximum of `sum`
};

// Runs the cells `queue` on the lanes of rk (a lane_rk4, lane_dopri5 or lane_gauss): start(x, l,
// cell) writes cell's start into lane l of x = rk.state() (read again after every step: a stepper
// may keep the state before the step in a second buffer); after every step, done(x, l, slot) —
// slot.steps (the steps, or the attempts, taken) already counted —
// returns the cell's value once it is finished, std::nullopt otherwise; the value goes to
// out[slot.cell] and the lane takes the next cell. Once the
// queue is empty the live lanes move down into the lowest blocks, so that only
// ceil(live / W) blocks are stepped; the idle lanes of the last of them run a copy of a live
// lane (results unused), so that every lane stepped holds a finite state. A lane's
// arithmetic does not depend on its slot, so moving a lane changes nothing.
// `watch(x, b, most)`, given the coordinates and the most steps any lane of block b has
// taken, may say that no lane of the block can be done after this step (false): then done
// is not asked for them. A check over a block's coordinates vectorises where a call of done
// per lane and step does not (the flip map's test took 11 % of its time).
struct always_look {
  bool operator()(const double*, std::size_t, long long) const { return true; }
};

template <class Stepper, class Start, class Done, class Watch = always_look>
void run_on_lanes(Stepper& rk, const std::vector<std::size_t>& queue, const Start& start,
                  const Done& done, std::vector<double>& out, const Watch& watch = {}) {
  constexpr std::size_t lanes = Stepper::lanes, W = Stepper::W;
  double* x = rk.state();
  std::array<std::optional<lane_slot>, lanes> slot{};
  std::size_t next = 0;
  const auto load = [&](std::size_t l) {
    slot[l].reset();
    if (next == queue.size()) return;
    slot[l] = lane_slot{queue[next++]};
    start(x, l, slot[l]->cell);
  };
  for (std::size_t l = 0; l < lanes; ++l) load(l);
  // Live lanes to the lowest slots, idle ones of the last block padded; the blocks to step.
  const auto compact = [&]() {
    std::size_t live = 0;
    for (std::size_t l = 0; l < lanes; ++l)
      if (slot[l]) {
        if (l != live) {
          rk.copy_lane(live, l);
          slot[live] = slot[l];
          slot[l].reset();
        }
        ++live;
      }
    const std::size_t blocks = (live + W - 1) / W;
    for (std::size_t l = live; l < blocks * W; ++l) rk.copy_lane(l, 0);
    return static_cast<int>(blocks);
  };
  int blocks = compact();
  while (blocks > 0) {
    rk.step(blocks);
    x = rk.state();
    bool emptied = false;
    for (std::size_t b = 0; b < static_cast<std::size_t>(blocks); ++b) {
      long long most = 0;
      for (std::size_t l = b * W; l < (b + 1) * W; ++l)
        if (slot[l]) most = std::max(most, ++slot[l]->steps);
      if (!watch(x, b, most)) continue;
      for (std::size_t l = b * W; l < (b + 1) * W; ++l) {
        if (!slot[l]) continue;
        const std::optional<double> value = done(x, l, *slot[l]);
        if (!value) continue;
        out[slot[l]->cell] = *value;
        load(l);
        emptied |= !slot[l];
      }
    }
    if (emptied) blocks = compact();
  }
}

}  // namespace NPEND_BATCH_ISA_NAMESPACE
}  // namespace npend::detail
