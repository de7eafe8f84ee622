// The paper's nonlinear corrections to the harmonic approximation (§6.4.1, §6.4.2): the
// truncated equations of motion around the hanging position, their second-order power-series
// solution, and how well they follow the true motion compared with the harmonic solution.
//
// The exact Euler–Lagrange equations are
//   Σ_j A_ij(φ) φ̈_j + Σ_j μ_max(i,j) l_i l_j sin(φ_i − φ_j) φ̇_j² + μ_i g l_i sin φ_i = 0
// with A_ij = μ_max(i,j) l_i l_j cos(φ_i − φ_j). Around φ = 0, with A⁰ = A(0) and
// K = ∇²V(0) = diag(μ_i g l_i):
// - harmonic:  Σ_j A⁰_ij φ̈_j + K_ii φ_i = 0;
// - paper:     the harmonic equations + Σ_j A⁰_ij (φ_i − φ_j) φ̇_j² (cos → 1,
//              sin(φ_i − φ_j) → φ_i − φ_j, sin φ_i → φ_i), the paper's double- and
//              triple-pendulum equations for any n;
// - cubic:     every term of third order in (φ, φ̇):
//              Σ_j A⁰_ij (1 − (φ_i − φ_j)²/2) φ̈_j + Σ_j A⁰_ij (φ_i − φ_j) φ̇_j²
//              + K_ii (φ_i − φ_i³/6) = 0.
// The paper's velocity terms are the right leading ones, but terms of the same order (φ³
// from sin φ, (φ_i − φ_j)² φ̈_j from cos) are left out: its equations are not a consistent
// cubic correction. Their acceleration error is O(ε³) in the amplitude ε, as the harmonic
// one; the cubic truncation's is O(ε⁵).
#pragma once

#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "npend/chain.hpp"

namespace npend {

enum class truncation { harmonic, paper, cubic };

/// "harmonic", "paper", "cubic".
std::string_view truncation_name(truncation kind);

/// φ̈ (dim n, rad/s²) solving the truncated equations `kind` at angles φ and angular
/// velocities φ̇ (dim n each). Throws std::invalid_argument for wrong sizes.
std::vector<double> truncated_acceleration(const chain& c, truncation kind,
                                           std::span<const double> phi,
                                           std::span<const double> dphi);

/// φ̈ (dim n) of the exact equations at φ, φ̇: d/dt(A⁻¹p) along Hamilton's flow, from the
/// generated Jacobian (φ̈ = ∂φ̇/∂x · f(x)).
std::vector<double> exact_acceleration(const chain& c, std::span<const double> phi,
                                       std::span<const double> dphi);

/// The paper's power-series ansatz φ_i(t) = a_i1 + a_i2 t + a_i3 t² solving the truncated
/// equations to second order in t: a_1 = φ(0), a_2 = φ̇(0), a_3 = φ̈(0)/2.
struct power_series {
  std::vector<double> a1, a2, a3;  ///< each dim n
  /// φ(t) and φ̇(t) (dim n).
  std::vector<double> angles(double t) const;
  std::vector<double> rates(double t) const;
};
power_series second_order_series(const chain& c, truncation kind, std::span<const double> phi0,
                                 std::span<const double> dphi0);

/// The paper's correction function Q = φ₁φ₂ / (φ̇₁φ̇₂) (s²; Abb. 6.3), NaN where φ̇₁φ̇₂ = 0.
double correction_function(std::span<const double> phi, std::span<const double> dphi);

struct correction_study_options {
  /// The horizon (s) over which the approximations are compared; 0: a quarter of the
  /// shortest linear period 2π/ω_n.
  double horizon = 0;
  /// Sample times on [0, horizon], both ends included (≥ 2).
  std::size_t samples = 201;
  /// The start scaled by these factors gives the orders in the amplitude (≥ 2 values,
  /// distinct, in (0, 1]).
  std::vector<double> scales{0.25, 0.125, 0.0625, 0.03125};

  /// Throws std::invalid_argument naming the field.
  void validate() const;
};

/// One approximation followed over the horizon, against the true motion.
struct correction_track {
  /// "harmonic solution" (the exact solution of the harmonic equations, by normal modes),
  /// "harmonic series", "paper series" (the second-order power series of those equations),
  /// "paper equations", "cubic equations" (integrated).
  std::string name;
  std::vector<std::vector<double>> angles;  ///< φ(t) at every sample (dim n each)
  std::vector<double> q;                    ///< Q(t) at every sample
  /// The first pole of Q: where φ̇₁φ̇₂ first changes sign (a turning point of φ₁ or φ₂),
  /// linearly interpolated between samples (s); NaN if none within the horizon.
  double q_pole = 0;
  /// max over the samples and links of |φ_i − φ_i^true| (rad).
  double max_error = 0;
  /// The same for the start scaled by each of options.scales, and its order: the slope of
  /// log max_error against log scale (least squares).
  std::vector<double> scaled_errors;
  double order = 0;
};

/// How the truncated equations' accelerations at t = 0 differ from the exact one.
struct acceleration_defect {
  truncation kind = truncation::harmonic;
  /// ‖φ̈_kind − φ̈_exact‖∞ at the start scaled by each of options.scales (rad/s²).
  std::vector<double> errors;
  /// The slope of log error against log scale: 3 for harmonic and paper, 5 for cubic.
  double order = 0;
};

struct correction_study {
  std::vector<double> phi0, dphi0;  ///< the start (dim n each)
  double horizon = 0;               ///< s
  std::vector<double> scales;
  std::vector<double> t;                         ///< sample times
  std::vector<std::vector<double>> true_angles;  ///< the chain's motion (Gauss–Legendre 6)
  std::vector<double> true_q;
  double true_q_pole = 0;                    ///< as correction_track::q_pole
  std::vector<correction_track> tracks;      ///< in the order listed in correction_track
  std::vector<acceleration_defect> defects;  ///< harmonic, paper, cubic
};

/// The truncations and the paper's series against the true motion from φ(0) = phi0,
/// φ̇(0) = dphi0 (dim n each, n ≥ 2), over a short horizon. Throws std::invalid_argument for
/// n < 2 (Q needs two links; for one link the paper's terms vanish), wrong sizes,
/// non-finite values, a start at rest (nothing to compare) or bad options.
correction_study harmonic_correction_study(const chain& c, std::span<const double> phi0,
                                           std::span<const double> dphi0,
                                           const correction_study_options& options = {});

}  // namespace npend
