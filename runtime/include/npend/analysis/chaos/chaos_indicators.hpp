// Fast chaos indicators of one trajectory, from deviation vectors evolved by the exact
// Jacobian: the fast Lyapunov indicator (FLI; Froeschlé, Lega & Gonczi 1997), MEGNO
// (Cincotta & Simó 2000), SALI (Skokos 2001) and GALI_k (Skokos, Bountis & Antonopoulos
// 2007). Each tells regular from chaotic motion in far less time than the Lyapunov exponent
// converges, which is what maps of many starts need (npend map --quantity fli|megno|sali|gali).
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "npend/chain.hpp"
#include "npend/integrators/stepper_kind.hpp"
#include "npend/run_control.hpp"

namespace npend {

struct chaos_indicator_options {
  double t_end = 100;  ///< s, from t = 0
  /// rk4 (fixed steps of dt) or taylor (adaptive steps on the Taylor series of the
  /// variational equations at `tolerance`); stepper_use::indicators.
  stepper_kind stepper = stepper_kind::rk4;
  double dt = 0.01;  ///< rk4's step (s); taylor's first trial step
  /// taylor: the absolute and relative tolerance of its steps (over the state and the
  /// vectors), in (0, 1e-6].
  double tolerance = 1e-12;
  /// k deviation vectors (2 ≤ k ≤ 2n): GALI_2..GALI_k are computed; SALI needs 2.
  std::size_t vectors = 2;
  /// Every this many seconds (rk4: a whole number of steps; taylor's steps land on the
  /// sample times) a sample of the indicators is kept in the result's history; 0 keeps none.
  double sample_interval = 0;
  run_control* control = nullptr;  ///< progress in s of t_end; may be null

  /// Throws std::invalid_argument naming the field: dt or t_end not finite and positive,
  /// t_end < dt, a sample interval < 0 or not finite, a stepper other than rk4 and taylor,
  /// a taylor tolerance outside (0, 1e-6]. (The vector count is checked against the chain by
  /// chaos_indicators.)
  void validate() const;
};

/// The indicators at one time t.
struct chaos_indicator_sample {
  double t = 0;
  /// FLI(t) = max_{s ≤ t} ln ‖w_1(s)‖ (w_1(0) a unit vector): grows like λ_1 t on a chaotic
  /// orbit, like ln t on a torus.
  double fli = 0;
  /// Y(t) = (2/t) ∫₀ᵗ s ẇ_1·w_1/‖w_1‖² ds, and the MEGNO ⟨Y⟩(t) = (1/t) ∫₀ᵗ Y(s) ds:
  /// ⟨Y⟩ → 2 on a torus (quasi-periodic), → 0 near a stable periodic orbit, ≈ λ_1 t / 2 on
  /// a chaotic orbit.
  double megno = 0;       ///< Y(t)
  double mean_megno = 0;  ///< ⟨Y⟩(t)
  /// SALI = min(‖ŵ_1 + ŵ_2‖, ‖ŵ_1 − ŵ_2‖) of the normalised vectors: stays away from 0 on a
  /// torus, falls like exp(−(λ_1 − λ_2) t) on a chaotic orbit.
  double sali = 0;
  /// GALI_j for j = 2..k (entry j − 2): the volume spanned by ŵ_1..ŵ_j, the product of the
  /// singular values of [ŵ_1 … ŵ_j]. On a chaotic orbit it falls like
  /// exp(−Σ_{i=2..j} (λ_1 − λ_i) t); on an n-torus it stays for j ≤ n and falls as a power
  /// of t for j > n.
  std::vector<double> gali;
};

struct chaos_indicator_result {
  chaos_indicator_sample last;                  ///< at t_end (or where the run stopped)
  std::vector<chaos_indicator_sample> history;  ///< every sample_interval, t = 0 excluded
  std::vector<double> state;                    ///< the state at last.t (dim 2n)
  bool stopped = false;                         ///< the run control asked to stop
};

/// The indicators of the trajectory from x0 (dim 2n) of chain `c`, integrated by rk4 at dt
/// (or by Taylor's method, options.stepper) together with k deviation vectors ẇ = J(x, t) w
/// (the exact Jacobian). The vectors start orthonormal — w_1 = (1, …, 1)/√(2n), as
/// maximal_lyapunov_exponent's, and the others the unit vectors e_1, e_2, … made orthogonal
/// to it — and are normalised after every step (the directions are not re-orthogonalised:
/// SALI and GALI measure how they align). rk4: MEGNO's two integrals ride along with the
/// state. taylor: they are integrated by parts into integrals of ln‖w_1‖ over each step,
/// taken by 8-point Gauss–Legendre quadrature on the step's polynomials, at whose nodes FLI's
/// maximum is also taken. Throws std::invalid_argument for bad options, a start of the wrong
/// size or non-finite, k outside 2..2n, or taylor on a chain without Taylor kernels;
/// npend::integration_error when the state or a vector becomes non-finite.
chaos_indicator_result chaos_indicators(const chain& c, std::span<const double> x0,
                                        const chaos_indicator_options& options);

/// The k deviation vectors chaos_indicators starts from for a state of dimension d (d × k,
/// column-major: vector j at [j*d, (j+1)*d)). For the batch lanes of the maps, which must
/// start where the library does.
std::vector<double> chaos_indicator_start(std::size_t d, std::size_t k);

/// The indicators at time t > 0 from FLI's running maximum `fli`, MEGNO's integrals
/// y = ∫ s ẇ₁·w₁/‖w₁‖² ds and z = ∫ Y ds, and the k ≥ 2 normalised deviation vectors `w`
/// (d × k, column-major), as chaos_indicators samples them.
chaos_indicator_sample chaos_indicator_sample_of(double t, double fli, double y, double z,
                                                 std::span<const double> w, std::size_t d);

}  // namespace npend
