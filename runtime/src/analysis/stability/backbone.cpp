#include "npend/analysis/stability/backbone.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "npend/analysis/series/event_times.hpp"
#include "npend/analysis/stability/normal_modes.hpp"
#include "npend/integrators/integrate.hpp"

namespace npend {

void backbone_options::validate() const {
  if (!(periods >= 3) || !std::isfinite(periods))
    throw std::invalid_argument(
        fmt::format("backbone: periods is {}: at least 3 linear periods are needed", periods));
  if (steps_per_period < 20)
    throw std::invalid_argument(
        fmt::format("backbone: steps_per_period is {}: at least 20 are needed", steps_per_period));
  for (double s : thresholds)
    if (!(s > 0 && s < 1))
      throw std::invalid_argument(
          fmt::format("backbone: threshold {} is not a relative shift in (0, 1)", s));
  if (!(amplitude_tolerance > 0) || !std::isfinite(amplitude_tolerance))
    throw std::invalid_argument(fmt::format(
        "backbone: amplitude_tolerance is {}: it must be positive", amplitude_tolerance));
}

namespace {

// The hanging chain's modes, checked for the requested one.
linearisation hanging_modes(const chain& c, int mode) {
  const int n = c.links();
  if (mode < 1 || mode > n)
    throw std::invalid_argument(fmt::format(
        "backbone: mode {} does not exist; the {}-link chain has modes 1..{}", mode, n, n));
  return normal_modes(c, std::vector<double>(static_cast<std::size_t>(n), 0.0));
}

void check_amplitude(double a) {
  if (!(a > 0 && a < std::numbers::pi))
    throw std::invalid_argument(fmt::format("backbone: amplitude {} rad is not in (0, pi)", a));
}

// The launch angles φ(0) = a·v / max_i |v_i| along the mode shape v (dim n).
std::vector<double> launch_angles(const std::vector<double>& v, double amplitude) {
  double largest = 0;
  for (double e : v) largest = std::max(largest, std::fabs(e));
  std::vector<double> phi(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) phi[i] = amplitude * v[i] / largest;
  return phi;
}

// `control` sees this integration's progress (or none: null).
backbone_point measure(const chain& c, const linearisation& lin, int mode, double amplitude,
                       const backbone_options& o, run_control* control) {
  const auto n = static_cast<std::size_t>(c.links());
  const auto k = static_cast<std::size_t>(mode - 1);
  std::vector<double> x0 = launch_angles(lin.modes[k].shape, amplitude);
  x0.resize(2 * n, 0.0);

  backbone_point point;
  point.amplitude = amplitude;
  point.energy = c.hamiltonian(x0);

  const double omega = lin.modes[k].frequency;
  const double period = 2 * std::numbers::pi / omega;
  integration_options io;
  io.stepper = stepper_kind::gauss6;
  io.dt = period / o.steps_per_period;
  io.t_end = o.periods * period;
  io.control = control;

  // Modal coordinates q = Vᵀ M φ and rates q̇ = Vᵀ M φ̇ of every mode at every step.
  std::vector<double> Mv(n * n);  // row j: (M v_j)ᵀ
  for (std::size_t j = 0; j < n; ++j)
    for (std::size_t a = 0; a < n; ++a) {
      double sum = 0;
      for (std::size_t b = 0; b < n; ++b) sum += lin.mass_matrix[a * n + b] * lin.modes[j].shape[b];
      Mv[j * n + a] = sum;
    }
  std::vector<double> samples, dphi(n);
  samples.reserve(static_cast<std::size_t>(o.periods * o.steps_per_period) + 2);
  double min_share = 1;
  integrate(c, x0, io, [&](double, std::span<const double> x) {
    c.velocities(x.first(n), x.subspan(n), dphi);
    double total = 0, own = 0;
    for (std::size_t j = 0; j < n; ++j) {
      double q = 0, dq = 0;
      for (std::size_t a = 0; a < n; ++a) {
        q += Mv[j * n + a] * x[a];
        dq += Mv[j * n + a] * dphi[a];
      }
      const double w = lin.modes[j].frequency;
      const double energy = 0.5 * (dq * dq + w * w * q * q);
      total += energy;
      if (j == k) {
        own = energy;
        samples.push_back(q);
      }
    }
    if (total > 0) min_share = std::min(min_share, own / total);
  });
  point.min_mode_share = min_share;
  if (stop_requested(control)) return point;  // cut short: unmeasured

  const std::vector<double> up = event_times(samples, io.dt, {.direction = crossing_direction::up});
  if (up.size() < 3) return point;
  point.measured = true;
  const double mean_period = (up.back() - up.front()) / static_cast<double>(up.size() - 1);
  point.frequency = 2 * std::numbers::pi / mean_period;
  point.relative_shift = point.frequency / omega - 1;
  double shortest = mean_period, longest = mean_period;
  for (std::size_t j = 1; j < up.size(); ++j) {
    shortest = std::min(shortest, up[j] - up[j - 1]);
    longest = std::max(longest, up[j] - up[j - 1]);
  }
  point.period_spread = (longest - shortest) / mean_period;
  return point;
}

// |shift| reached (or the motion not measurable as an oscillation of the mode).
bool departed(const backbone_point& p, double shift) {
  return !p.measured || std::fabs(p.relative_shift) >= shift;
}

}  // namespace

backbone_point measure_mode_frequency(const chain& c, int mode, double amplitude,
                                      const backbone_options& options) {
  options.validate();
  const linearisation lin = hanging_modes(c, mode);
  check_amplitude(amplitude);
  return measure(c, lin, mode, amplitude, options, options.control);
}

backbone_result backbone_curve(const chain& c, int mode, std::span<const double> amplitudes,
                               const backbone_options& options) {
  options.validate();
  const linearisation lin = hanging_modes(c, mode);
  if (amplitudes.empty()) throw std::invalid_argument("backbone: no amplitudes given");
  for (double a : amplitudes) check_amplitude(a);
  std::vector<double> sorted(amplitudes.begin(), amplitudes.end());
  std::sort(sorted.begin(), sorted.end());

  backbone_result r;
  r.mode = mode;
  r.linear_frequency = lin.modes[static_cast<std::size_t>(mode - 1)].frequency;
  r.shape = lin.modes[static_cast<std::size_t>(mode - 1)].shape;
  for (std::size_t i = 0; i < sorted.size(); ++i) {
    run_control_part part(options.control, i, sorted.size());
    r.points.push_back(measure(c, lin, mode, sorted[i], options, &part));
    if (part.stop_requested()) {
      r.stopped = true;
      return r;
    }
  }

  for (double shift : options.thresholds) {
    backbone_threshold threshold;
    threshold.shift = shift;
    const auto first = std::find_if(r.points.begin(), r.points.end(),
                                    [&](const backbone_point& p) { return departed(p, shift); });
    if (first != r.points.end()) {
      double low = first == r.points.begin() ? 0.0 : std::prev(first)->amplitude;
      double high = first->amplitude;
      while (high - low > options.amplitude_tolerance) {
        const double middle = 0.5 * (low + high);
        if (stop_requested(options.control)) {
          r.stopped = true;
          return r;
        }
        if (departed(measure(c, lin, mode, middle, options, nullptr), shift))
          high = middle;
        else
          low = middle;
      }
      threshold.amplitude = 0.5 * (low + high);
      threshold.energy = c.potential_energy(launch_angles(r.shape, *threshold.amplitude));
    }
    r.thresholds.push_back(threshold);
  }
  return r;
}

double pendulum_frequency_ratio(double amplitude) {
  if (!(amplitude >= 0 && amplitude < std::numbers::pi))
    throw std::invalid_argument(fmt::format(
        "pendulum_frequency_ratio: the amplitude must be in [0, pi) rad, got {}", amplitude));
  return std::numbers::pi / (2 * std::comp_ellint_1(std::sin(amplitude / 2)));
}

double pendulum_period(double amplitude, double length, double g) {
  if (!(amplitude >= 0 && amplitude < std::numbers::pi))
    throw std::invalid_argument(
        fmt::format("pendulum_period: the amplitude must be in [0, pi) rad, got {}", amplitude));
  if (!(length > 0) || !(g > 0))
    throw std::invalid_argument(fmt::format(
        "pendulum_period: the length and g must be positive, got {} m and {} m/s^2", length, g));
  return 4 * std::comp_ellint_1(std::sin(amplitude / 2)) / std::sqrt(g / length);
}

}  // namespace npend
