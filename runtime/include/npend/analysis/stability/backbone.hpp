// Where the harmonic approximation stops being valid (paper §6.4): the full nonlinear chain
// launched along a normal mode of the hanging position with growing amplitude, its measured
// frequency against the amplitude (the backbone curve), and the amplitudes at which it
// departs from the linear frequency by a given fraction.
#pragma once

#include <optional>
#include <span>
#include <vector>

#include "npend/chain.hpp"
#include "npend/run_control.hpp"

namespace npend {

struct backbone_options {
  /// Linear periods 2π/ω_k integrated per amplitude; the frequency is averaged over them.
  double periods = 20;
  /// Gauss–Legendre (order 6) steps per linear period; the modal coordinate is sampled at
  /// every step and its zero crossings located by cubic interpolation (npend::event_times).
  int steps_per_period = 200;
  /// The relative frequency shifts |ω/ω_k − 1| whose amplitudes are located (default 1 %
  /// and 5 %).
  std::vector<double> thresholds{0.01, 0.05};
  /// The threshold amplitudes are bisected down to a bracket this narrow (rad).
  double amplitude_tolerance = 1e-4;
  /// Progress (amplitudes measured of those given) and stop requests; not owned, may be
  /// null. A stopped curve has the points measured so far and no thresholds.
  run_control* control = nullptr;

  /// Throws std::invalid_argument naming the field.
  void validate() const;
};

/// The nonlinear chain launched along mode k with amplitude a: φ(0) = a·v_k / max_i |v_k,i|
/// (so a is the largest start angle, rad) and p = 0, followed for `periods` linear periods.
/// What is measured is the modal coordinate q_k(t) = v_kᵀ M φ(t) (M = A(0), v_k
/// M-normalised): while the motion stays in the mode it is a periodic oscillation about 0.
/// For n ≥ 2 a launch along a linear mode is not a periodic orbit of the nonlinear chain at
/// finite amplitude — energy leaks into the other modes — so ω is then the mean frequency
/// of q_k, and period_spread and min_mode_share say how far from a clean mode the motion is.
struct backbone_point {
  double amplitude = 0;  ///< a (rad)
  double energy = 0;     ///< H at the start (J)
  /// False when q_k crossed zero upwards fewer than three times (no two full periods).
  bool measured = false;
  /// 2π (u − 1) / (t_u − t_1) over the u upward zero crossings t_1 < … < t_u of q_k (rad/s).
  double frequency = 0;
  double relative_shift = 0;  ///< ω / ω_k − 1 (negative: the mode softens)
  /// (max − min) / mean of the individual periods t_{j+1} − t_j: 0 for a periodic orbit.
  double period_spread = 0;
  /// The least share E_k / Σ_j E_j over the run of the linear modal energies
  /// E_j = ½ (q̇_j² + ω_j² q_j²): 1 while no other mode is excited.
  double min_mode_share = 0;
};

/// The amplitude at which |ω/ω_k − 1| first reaches `shift`.
struct backbone_threshold {
  double shift = 0;
  /// Bisected between the last scanned amplitude below the shift (or 0) and the first at or
  /// above it (a point that cannot be measured counts as above); empty when no scanned
  /// amplitude reaches the shift.
  std::optional<double> amplitude;
  double energy = 0;  ///< H at that amplitude (J), 0 when not reached
};

struct backbone_result {
  int mode = 0;                        ///< k, 1-based, modes in ascending frequency
  double linear_frequency = 0;         ///< ω_k (rad/s) of K v = ω² M v at the hanging position
  std::vector<double> shape;           ///< v_k (dim n), M-normalised
  std::vector<backbone_point> points;  ///< one per amplitude, ascending
  std::vector<backbone_threshold> thresholds;  ///< one per options.thresholds, same order
  bool stopped = false;  ///< options.control asked to stop before the curve was finished
};

/// One point of the backbone curve of mode k (1 ≤ k ≤ n) at amplitude a (0 < a < π).
/// Throws std::invalid_argument for a bad mode, amplitude or options.
backbone_point measure_mode_frequency(const chain& c, int mode, double amplitude,
                                      const backbone_options& options = {});

/// The backbone curve of mode k at the given amplitudes (rad, each in (0, π), any order;
/// reported ascending) and the threshold amplitudes. Throws std::invalid_argument for a bad
/// mode, an empty or bad amplitude list, or bad options.
backbone_result backbone_curve(const chain& c, int mode, std::span<const double> amplitudes,
                               const backbone_options& options = {});

/// The single pendulum's exact backbone, the measure of every backbone: its frequency ratio
/// ω/ω₀ = π / (2 K(sin(a/2))) at the amplitude a (rad, 0 ≤ a < π), K the complete elliptic
/// integral of the first kind and ω₀ = √(g/l) the linear frequency. 1 at a = 0, falling to 0
/// as a → π. Throws std::invalid_argument for an amplitude outside [0, π).
double pendulum_frequency_ratio(double amplitude);

/// The single pendulum's exact period T = 4 K(sin(a/2)) / ω₀ (s) at the amplitude a (rad,
/// 0 ≤ a < π), ω₀ = √(g/l) for a point mass on a rod of length l (m) under gravity g (m/s²):
/// 2π √(l/g) for small swings. Throws std::invalid_argument for an amplitude outside [0, π)
/// or a length or g that is not positive.
double pendulum_period(double amplitude, double length, double g);

}  // namespace npend
