#include "npend/parameters.hpp"

#include <fmt/format.h>

#include <algorithm>
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

// The built-in drives: s(t) = a cos(Ωt) along the axis (its k-th derivative), placed on x
// (horizontal) or on y with the sign that makes s the height (vertical; y points down).
pivot_motion::vec2 harmonic(const pivot_motion& p, double t, int derivative) {
  const double w = p.frequency, phase = w * t;
  double s = 0;
  switch (derivative) {
    case 0:
      s = p.amplitude * std::cos(phase);
      break;
    case 1:
      s = -p.amplitude * w * std::sin(phase);
      break;
    case 2:
      s = -p.amplitude * w * w * std::cos(phase);
      break;
    default:
      s = p.amplitude * w * w * w * std::sin(phase);
      break;
  }
  return p.type == pivot_motion::kind::horizontal ? pivot_motion::vec2{s, 0.0}
                                                  : pivot_motion::vec2{0.0, -s};
}

}  // namespace

pivot_motion::vec2 pivot_motion::position_at(double t) const {
  if (type == kind::fixed) return {0.0, 0.0};
  if (type == kind::custom) return position(t);
  return harmonic(*this, t, 0);
}

pivot_motion::vec2 pivot_motion::velocity_at(double t) const {
  if (type == kind::fixed) return {0.0, 0.0};
  if (type == kind::custom) return velocity(t);
  return harmonic(*this, t, 1);
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
         any_nonzero(damping) || pivot.moves();
}

bool chain_parameters::is_damped() const { return any_nonzero(damping); }

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
  // The last link's angle moves only its own mass point and rotation: with neither, the
  // mass matrix is singular.
  if (entry_or(com, n - 1, 1.0) == 0.0 && entry_or(inertia, n - 1, 0.0) == 0.0)
    throw std::invalid_argument(fmt::format(
        "link {} has its centre of mass at its joint (c = 0) and no inertia: its angle has no "
        "inertia and the equations are singular; give it J > 0 or c != 0",
        n));
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

}  // namespace npend
