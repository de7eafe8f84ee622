// Run-time parameters of an n-link chain: masses, lengths and g — and, for the physical
// chain, the links' centres of mass and inertias, joint springs and damping, and the pivot's
// motion.
#pragma once

#include <array>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace npend {

/// Standard gravity, the default g (m/s²).
inline constexpr double standard_gravity = 9.81;

/// The pivot's prescribed motion r₀(t) (m; x right, y down). Built in: harmonic motion
/// a cos(Ωt) of the pivot's height (`vertical`: r₀ = (0, −a cos Ωt), up is −y) or along x
/// (`horizontal`: r₀ = (a cos Ωt, 0)). A `custom` path gives r₀ and its first two
/// derivatives; the equations need the acceleration, ∂f/∂t its rate, taken from the
/// acceleration by a central difference for a custom path.
struct pivot_motion {
  enum class kind { fixed, vertical, horizontal, custom };
  using vec2 = std::array<double, 2>;

  kind type = kind::fixed;
  double amplitude = 0;                                          ///< a (m), built-in drives
  double frequency = 0;                                          ///< Ω (rad/s), built-in drives
  std::function<vec2(double)> position, velocity, acceleration;  ///< custom paths

  static pivot_motion vertical(double amplitude, double frequency);
  static pivot_motion horizontal(double amplitude, double frequency);

  bool moves() const { return type != kind::fixed; }
  /// 2π/Ω of a built-in drive; 0 for a fixed pivot or a custom path.
  double period() const;
  vec2 position_at(double t) const;
  vec2 acceleration_at(double t) const;
  /// d/dt of the acceleration.
  vec2 jerk_at(double t) const;
  /// The Taylor coefficients of the acceleration about t: a(t + τ) = Σ_k (ax[k], ay[k]) τ^k
  /// for k = 0..order − 1 (zero for a fixed pivot), for the Taylor integrator's inputs.
  /// Throws std::invalid_argument for a custom path, whose derivatives are not known.
  void acceleration_series(double t, int order, double* ax, double* ay) const;
  void acceleration_series(double t, int order, long double* ax, long double* ay) const;
  /// "fixed", "vertical:A:OMEGA", "horizontal:A:OMEGA" or "custom".
  std::string describe() const;
};

/// Masses m_1..m_n (kg), rod lengths l_1..l_n (m) and gravity g (m/s²) of an n-link chain —
/// the paper's model — and optionally what makes it a physical chain. The optional lists
/// are either empty (their default) or have one entry per link.
///
/// The point-mass kernels take [m_1..m_n, l_1..l_n, g] (dim 2n + 1); a chain with any of the
/// physical features runs on the physical kernels, params as chain_layout::physical_param_size.
struct chain_parameters {
  std::vector<double> masses;
  std::vector<double> lengths;
  double g = standard_gravity;

  /// Link k's centre of mass, a distance c_k (m) down the link from its upper joint
  /// (default c = l: the mass at the link's end), and its moment of inertia J_k (kg m²)
  /// about that centre (default 0).
  std::vector<double> com, inertia;
  /// Joint j (joining link j−1 to link j; joint 1 is the pivot): a torsion spring k_j
  /// (N m/rad) with rest angle θ_j⁰ (rad) on θ_j = φ_j − φ_{j−1}, and viscous damping b_j
  /// (N m s/rad). Defaults 0.
  std::vector<double> stiffness, rest_angles, damping;
  pivot_motion pivot;
  /// A cart of mass M (kg) in place of the pivot, rolling along x with viscous damping b_x
  /// (N s/m; default 0): the pendulum on a cart. The state gains the cart's position x_c
  /// and its momentum p_x (x = [x_c, φ_1..φ_n, p_x, p_1..p_n]); the cart takes the place of
  /// a moving pivot (the two do not combine).
  std::optional<double> cart_mass;
  double cart_damping = 0;

  /// n equal links: the paper's setting.
  static chain_parameters uniform(int links, double mass = 1.0, double length = 1.0,
                                  double g = standard_gravity);

  /// Uniform rods: c = l/2 and J = m l²/12 for every link (needs masses and lengths).
  void make_uniform_rods();

  /// The link count n (= masses.size()).
  int links() const { return static_cast<int>(masses.size()); }

  /// Whether the chain needs the physical kernels: any centre of mass or inertia given,
  /// any spring, rest angle or damping that is not zero, a moving pivot or a cart.
  bool is_physical() const;
  /// Whether the chain hangs from a cart.
  bool has_cart() const { return cart_mass.has_value(); }
  /// Whether H is conserved along the flow: no damping and a fixed pivot.
  bool is_conservative() const;
  bool is_damped() const;

  /// Throws std::invalid_argument naming the problem: no links, masses and lengths of
  /// different counts, a non-finite or non-positive mass or length, g not finite or < 0 (or
  /// 0 for a point-mass chain), an optional list of
  /// the wrong length, a negative inertia, stiffness or damping, links whose mass matrix is
  /// singular at some configuration (naming them), a drive whose amplitude or frequency is
  /// not a finite number ≥ 0 resp. > 0, a cart mass that is not a finite number > 0, a cart
  /// damping that is not a finite number ≥ 0 or is given without a cart, a cart with a
  /// moving pivot.
  ///
  /// The mass matrix A(φ) is positive definite at every φ unless some link a has c_a = 0 and
  /// J_a = 0 and the links a+1..b below it have J = 0 and c ≠ 0, with b = n or c_b = l_b;
  /// such a chain is singular where links a..b line up (the derivation is in parameters.cpp).
  void validate() const;

  /// [m_1..m_n, l_1..l_n, g] (dim 2n + 1).
  std::vector<double> packed() const;
  /// [m, l, g, c, J, k, θ⁰, b] (dim 7n + 1) with the defaults filled in.
  std::vector<double> physical_packed() const;
  /// physical_packed() followed by [M, b_x] (dim 7n + 3): the cart's kernels' parameters.
  std::vector<double> cart_packed() const;
};

}  // namespace npend
