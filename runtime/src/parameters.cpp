#include "npend/parameters.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "npend/chain_kernels.hpp"

namespace npend {

namespace {

std::size_t u(int i) { return static_cast<std::size_t>(i); }

bool any_nonzero(const std::vector<double>& v) {
  return std::any_of(v.begin(), v.end(), [](double x) { return x != 0.0; });
}

// An optional per-link list: empty or one finite entry per link, ≥ 0 where `non_negative`.
void check_optional(const std::vector<double>& values, int links, const char* what,
                    bool non_negative) {
  if (values.empty()) return;
  if (values.size() != u(links))
    throw std::invalid_argument(fmt::format("{} values for {}: give one per link ({}) or none",
                                            values.size(), what, links));
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (!std::isfinite(values[i]))
      throw std::invalid_argument(
          fmt::format("{} {} is {}: it must be a finite number", what, i + 1, values[i]));
    if (non_negative && values[i] < 0)
      throw std::invalid_argument(
          fmt::format("{} {} is {}: it must not be negative", what, i + 1, values[i]));
  }
}

double entry_or(const std::vector<double>& values, int i, double fallback) {
  return values.empty() ? fallback : values[u(i)];
}

// Whether the mass matrix A(φ) is positive definite at every configuration, and if not, which
// links make it singular. Throws std::invalid_argument naming them.
//
// The rule. T = ½ φ̇ᵀAφ̇ = ½ Σ_k (m_k |v_k|² + J_k φ̇_k²) ≥ 0, so A is positive semidefinite
// everywhere, and singular at φ exactly when some φ̇ ≠ 0 has T = 0: every centre of mass at
// rest (all m_k > 0) and every link with J_k > 0 not turning. Let w_k be the velocity of the
// lower end of link k (joint k + 1), w_0 = 0 at the fixed pivot, and e'_k = (cos φ_k, −sin φ_k)
// the direction link k's points move in when it turns; then w_k = w_{k−1} + l_k φ̇_k e'_k and
// v_k = w_{k−1} + c_k φ̇_k e'_k. Let link a be the first with φ̇_a ≠ 0. Its upper joint is at
// rest (w_{a−1} = 0), so v_a = c_a φ̇_a e'_a = 0 needs c_a = 0, and J_a = 0; then its lower
// end moves, w_a = l_a φ̇_a e'_a ≠ 0. Every later link i that such a motion reaches, joint i
// moving with w_{i−1} ≠ 0, must keep its centre of mass still: c_i φ̇_i e'_i = −w_{i−1}, which
// needs c_i ≠ 0, J_i = 0 and link i lined up with w_{i−1}, i.e. with link a (φ_i ≡ φ_a mod π:
// a configuration, always reachable). Its lower end then moves with
// w_i = w_{i−1} (1 − l_i / c_i): the motion ends at rest at link b where c_b = l_b (the links
// below b need not move), or runs out of the chain at link n. So:
//
//   A is singular somewhere  ⇔  there are links a < b ≤ n, or a = b = n, with
//     c_a = 0 and J_a = 0, and J_i = 0 and c_i ≠ 0 for a < i ≤ b,
//     and b = n or c_b = l_b;
//   it is singular exactly where links a..b are lined up (φ_i − φ_a ∈ {0, π}).
//
// In the articulated-body factorisation det A = Π_k D_k, D_k being the inertia link k shows
// about its joint with the links below free (D_k = m_k c_k² + J_k plus l_k² times the
// apparent mass of the links below at joint k + 1, along e'_k), this is D_a = 0: link a has no
// inertia about its joint of its own (m_a c_a² + J_a = 0), and links a+1..b, lined up, give
// joint a + 1 no apparent mass across the line. Point masses (c = l, J = 0) never qualify: a
// needs c_a = 0 < l_a. Tested against the dense mass matrix's determinant over a grid of
// configurations (tests/runtime/test_physical_chain.cpp).
// "link 3" or "links 3..5" (1-based, from ≤ to).
std::string link_range(int from, int to) {
  return from == to ? fmt::format("link {}", from) : fmt::format("links {}..{}", from, to);
}

void check_mass_matrix_regular(const chain_parameters& p) {
  const int n = p.links();
  // The singular motion's links a..b (0-based) and whether it ends at rest at b (c_b = l_b).
  const auto refuse = [](int a, int b, bool ends_at_rest) {
    if (a == b)
      return std::invalid_argument(fmt::format(
          "link {} has its centre of mass at its joint (c = 0) and no inertia: its angle has no "
          "inertia and the equations are singular; give it J > 0 or c != 0",
          a + 1));
    const std::string below =
        link_range(a + 2, b + 1) + (a + 1 == b ? " has no inertia" : " have no inertia");
    const std::string end =
        !ends_at_rest ? std::string(" down to the chain's end")
        : a + 1 == b
            ? std::string(" and its centre of mass at its lower end (c = l)")
            : fmt::format(" and link {} its centre of mass at its lower end (c = l)", b + 1);
    return std::invalid_argument(fmt::format(
        "{} make the mass matrix singular where they line up (phi_{}..phi_{} equal mod pi): "
        "link {} has its centre of mass at its joint (c = 0) and no inertia, {}{}, so they can "
        "move without kinetic energy; give one of them an inertia J > 0",
        link_range(a + 1, b + 1), a + 1, b + 1, a + 1, below, end));
  };
  int start = -1;  // link a of a motion that has reached the current link, or -1
  for (int i = 0; i < n; ++i) {
    const double c = entry_or(p.com, i, p.lengths[u(i)]), J = entry_or(p.inertia, i, 0.0);
    if (J != 0.0)
      start = -1;
    else if (c == 0.0)
      start = i;  // a new motion: link i turns about its own centre of mass
    else if (start >= 0 && c == p.lengths[u(i)])
      throw refuse(start, i, true);
  }
  if (start >= 0) throw refuse(start, n - 1, false);
}

}  // namespace

pivot_motion pivot_motion::vertical(double amplitude, double frequency) {
  pivot_motion p;
  p.type = kind::vertical;
  p.amplitude = amplitude;
  p.frequency = frequency;
  return p;
}

pivot_motion pivot_motion::horizontal(double amplitude, double frequency) {
  pivot_motion p = vertical(amplitude, frequency);
  p.type = kind::horizontal;
  return p;
}

double pivot_motion::period() const {
  return (type == kind::vertical || type == kind::horizontal) ? 2 * std::numbers::pi / frequency
                                                              : 0.0;
}

namespace {

// cos(φ + dπ/2), the d-th derivative of cos at φ, from cos φ (d even) or sin φ (d odd):
// the cycle cos, −sin, −cos, sin.
template <class T>
T shifted_cosine(int d, T cos_or_sin) {
  return d % 4 == 0 || d % 4 == 3 ? cos_or_sin : -cos_or_sin;
}

// A built-in drive's displacement s along its axis, placed on x (horizontal) or on y with the
// sign that makes s the height (vertical; y points down).
template <class T>
std::array<T, 2> on_axis(const pivot_motion& p, T s) {
  if (p.type == pivot_motion::kind::horizontal) return {s, T(0)};
  return {T(0), -s};
}

// The built-in drives: s(t) = a cos(Ωt) along the axis, its d-th derivative
// a Ω^d cos(Ωt + dπ/2).
pivot_motion::vec2 harmonic(const pivot_motion& p, double t, int derivative) {
  const double w = p.frequency, phase = w * t;
  double s = p.amplitude;
  for (int i = 0; i < derivative; ++i) s *= w;
  s *= shifted_cosine(derivative, derivative % 2 == 0 ? std::cos(phase) : std::sin(phase));
  return on_axis(p, s);
}

// a(t + τ)'s coefficients of a built-in drive: s^(k+2)(t)/k!, from one cosine and sine.
template <class T>
void harmonic_acceleration_series(const pivot_motion& p, double t, int order, T* ax, T* ay) {
  if (p.type == pivot_motion::kind::fixed) {
    std::fill(ax, ax + order, T(0));
    std::fill(ay, ay + order, T(0));
    return;
  }
  if (p.type == pivot_motion::kind::custom)
    throw std::invalid_argument(
        "the taylor stepper needs the pivot's acceleration as a Taylor series, which a custom "
        "pivot path does not give: use a built-in drive or another stepper");
  using std::cos;
  using std::sin;
  const T w = p.frequency, phase = w * static_cast<T>(t);
  const T c = cos(phase), s = sin(phase);
  T scale = static_cast<T>(p.amplitude) * w * w;  // a Ω^(k+2) / k!
  for (int k = 0; k < order; ++k) {
    const int d = k + 2;
    const std::array<T, 2> a = on_axis(p, scale * shifted_cosine(d, d % 2 == 0 ? c : s));
    ax[k] = a[0];
    ay[k] = a[1];
    scale *= w / static_cast<T>(k + 1);
  }
}

}  // namespace

void pivot_motion::acceleration_series(double t, int order, double* ax, double* ay) const {
  harmonic_acceleration_series(*this, t, order, ax, ay);
}

void pivot_motion::acceleration_series(double t, int order, long double* ax,
                                       long double* ay) const {
  harmonic_acceleration_series(*this, t, order, ax, ay);
}

pivot_motion::vec2 pivot_motion::position_at(double t) const {
  if (type == kind::fixed) return {0.0, 0.0};
  if (type == kind::custom) return position(t);
  return harmonic(*this, t, 0);
}

pivot_motion::vec2 pivot_motion::acceleration_at(double t) const {
  if (type == kind::fixed) return {0.0, 0.0};
  if (type == kind::custom) return acceleration(t);
  return harmonic(*this, t, 2);
}

pivot_motion::vec2 pivot_motion::jerk_at(double t) const {
  if (type == kind::fixed) return {0.0, 0.0};
  if (type != kind::custom) return harmonic(*this, t, 3);
  // A central difference with the step that balances truncation and rounding (h ~ ε^{1/3}).
  const double h = 6e-6 * std::max(1.0, std::fabs(t));
  const vec2 a = acceleration(t + h), b = acceleration(t - h);
  return {(a[0] - b[0]) / (2 * h), (a[1] - b[1]) / (2 * h)};
}

std::string pivot_motion::describe() const {
  switch (type) {
    case kind::fixed:
      return "fixed";
    case kind::vertical:
      return fmt::format("vertical:{}:{}", amplitude, frequency);
    case kind::horizontal:
      return fmt::format("horizontal:{}:{}", amplitude, frequency);
    case kind::custom:
      return "custom";
  }
  return "?";
}

chain_parameters chain_parameters::uniform(int links, double mass, double length, double g) {
  if (links < 1)
    throw std::invalid_argument(fmt::format("links must be at least 1, got {}", links));
  chain_parameters p;
  p.masses.assign(u(links), mass);
  p.lengths.assign(u(links), length);
  p.g = g;
  return p;
}

void chain_parameters::make_uniform_rods() {
  com.resize(lengths.size());
  inertia.resize(lengths.size());
  for (std::size_t i = 0; i < lengths.size() && i < masses.size(); ++i) {
    com[i] = lengths[i] / 2;
    inertia[i] = masses[i] * lengths[i] * lengths[i] / 12;
  }
}

bool chain_parameters::is_physical() const {
  return !com.empty() || !inertia.empty() || any_nonzero(stiffness) || any_nonzero(rest_angles) ||
         any_nonzero(damping) || pivot.moves() || has_cart();
}

bool chain_parameters::is_damped() const { return any_nonzero(damping) || cart_damping != 0; }

bool chain_parameters::is_conservative() const { return !is_damped() && !pivot.moves(); }

void chain_parameters::validate() const {
  if (masses.empty()) throw std::invalid_argument("a chain needs at least one link");
  if (lengths.size() != masses.size())
    throw std::invalid_argument(fmt::format("{} masses but {} lengths: give one of each per link",
                                            masses.size(), lengths.size()));
  const auto check = [](const std::vector<double>& values, const char* what) {
    for (std::size_t i = 0; i < values.size(); ++i)
      if (!std::isfinite(values[i]) || values[i] <= 0)
        throw std::invalid_argument(fmt::format("{} {} is {}: it must be a positive finite number",
                                                what, i + 1, values[i]));
  };
  check(masses, "mass");
  check(lengths, "length");
  // g = 0 is a chain on a horizontal table: only its springs can hold it, so only physical
  // chains may have it.
  if (!std::isfinite(g) || g < 0 || (g == 0 && !is_physical()))
    throw std::invalid_argument(fmt::format(
        "g is {}: it must be a positive finite number (0 only for a physical chain)", g));
  const int n = links();
  check_optional(com, n, "centre of mass", false);
  check_optional(inertia, n, "inertia", true);
  check_optional(stiffness, n, "stiffness", true);
  check_optional(rest_angles, n, "rest angle", false);
  check_optional(damping, n, "damping", true);
  check_mass_matrix_regular(*this);
  if (pivot.type == pivot_motion::kind::vertical || pivot.type == pivot_motion::kind::horizontal) {
    if (!std::isfinite(pivot.amplitude) || pivot.amplitude < 0)
      throw std::invalid_argument(
          fmt::format("pivot amplitude is {}: it must be a finite number >= 0", pivot.amplitude));
    if (!std::isfinite(pivot.frequency) || pivot.frequency <= 0)
      throw std::invalid_argument(fmt::format(
          "pivot frequency is {}: it must be a positive finite number (rad/s)", pivot.frequency));
  }
  if (pivot.type == pivot_motion::kind::custom &&
      (!pivot.position || !pivot.velocity || !pivot.acceleration))
    throw std::invalid_argument(
        "a custom pivot path needs its position, velocity and acceleration functions");
  if (cart_mass && (!std::isfinite(*cart_mass) || *cart_mass <= 0))
    throw std::invalid_argument(
        fmt::format("cart mass is {}: it must be a positive finite number (kg)", *cart_mass));
  if (!std::isfinite(cart_damping) || cart_damping < 0)
    throw std::invalid_argument(
        fmt::format("cart damping is {}: it must be a finite number >= 0 (N s/m)", cart_damping));
  if (cart_damping != 0 && !cart_mass)
    throw std::invalid_argument("cart damping needs a cart: give the cart mass too");
  if (cart_mass && pivot.moves())
    throw std::invalid_argument(
        "a cart and a moving pivot do not combine: the chain hangs from the cart");
}

std::vector<double> chain_parameters::packed() const {
  const int n = links();
  std::vector<double> out(u(chain_layout::param_size(n)));
  for (int i = 0; i < n; ++i) {
    out[u(chain_layout::mass_index(n, i))] = masses[u(i)];
    out[u(chain_layout::length_index(n, i))] = lengths[u(i)];
  }
  out[u(chain_layout::gravity_index(n))] = g;
  return out;
}

std::vector<double> chain_parameters::physical_packed() const {
  const int n = links();
  std::vector<double> out = packed();
  out.resize(u(chain_layout::physical_param_size(n)));
  for (int i = 0; i < n; ++i) {
    out[u(chain_layout::com_index(n, i))] = entry_or(com, i, lengths[u(i)]);
    out[u(chain_layout::inertia_index(n, i))] = entry_or(inertia, i, 0.0);
    out[u(chain_layout::stiffness_index(n, i))] = entry_or(stiffness, i, 0.0);
    out[u(chain_layout::rest_angle_index(n, i))] = entry_or(rest_angles, i, 0.0);
    out[u(chain_layout::damping_index(n, i))] = entry_or(damping, i, 0.0);
  }
  return out;
}

std::vector<double> chain_parameters::cart_packed() const {
  const int n = links();
  std::vector<double> out = physical_packed();
  out.resize(u(cart_layout::param_size(n)));
  out[u(cart_layout::cart_mass_index(n))] = cart_mass.value_or(0.0);
  out[u(cart_layout::cart_damping_index(n))] = cart_damping;
  return out;
}

}  // namespace npend
