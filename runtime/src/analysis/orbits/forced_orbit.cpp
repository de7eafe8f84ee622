#include "npend/analysis/orbits/forced_orbit.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "analysis/detail/dense_eigen.hpp"
#include "analysis/detail/monodromy.hpp"
#include "npend/integrators/integration_error.hpp"
#include "npend/integrators/taylor.hpp"

namespace npend {

namespace {

// Forced orbits need a built-in periodic drive (its period is the orbit's) and no damping:
// a damped chain's forced response is an attractor whose multipliers are not reciprocal, a
// different problem (and its stability verdict needs floquet_analysis's error weighing).
void check_forced(const chain& c, const char* who) {
  const chain_parameters& p = c.parameters();
  if (c.has_cart())
    throw std::invalid_argument(
        fmt::format("{}: the chain hangs from a cart; forced orbits need a pivot driven with "
                    "vertical:A:OMEGA or horizontal:A:OMEGA",
                    who));
  if (p.is_damped())
    throw std::invalid_argument(
        fmt::format("{}: the chain is damped; damping is excluded: forced orbits are found for "
                    "undamped chains (joint damping 0)",
                    who));
  if (!p.pivot.moves())
    throw std::invalid_argument(fmt::format(
        "{}: the pivot is fixed; a forced orbit needs a driven pivot (vertical:A:OMEGA or "
        "horizontal:A:OMEGA); free periodic orbits of a fixed pivot: see periodic_orbit",
        who));
  if (p.pivot.type != pivot_motion::kind::vertical &&
      p.pivot.type != pivot_motion::kind::horizontal)
    throw std::invalid_argument(
        fmt::format("{}: the pivot follows a custom path, which has no period; a forced orbit "
                    "needs a built-in periodic drive (vertical:A:OMEGA or horizontal:A:OMEGA)",
                    who));
}

// One pass over T from t = 0 (the drive's phase at the orbit's start): the end state, the
// monodromy, each angle's largest |φ_i| over the start and the step points (taylor: 16
// points of each step's polynomial, its end included), and the steps taken.
struct forced_pass {
  std::vector<double> end;
  Eigen::MatrixXd monodromy;
  std::vector<double> amplitudes;
  int steps = 0;
};

forced_pass integrate_forced(const chain& c, const std::vector<double>& x0, double period,
                             const forced_orbit_options& options) {
  forced_pass r;
  r.end = x0;
  r.amplitudes.resize(static_cast<std::size_t>(c.links()));
  const auto track = [&](std::span<const double> x) {
    for (int i = 0; i < c.links(); ++i) {
      double& a = r.amplitudes[static_cast<std::size_t>(i)];
      a = std::max(a, std::fabs(x[static_cast<std::size_t>(c.angle_index(i))]));
    }
  };
  track(x0);
  if (options.stepper == stepper_kind::taylor) {
    detail::taylor_monodromy(
        c, r.end, period, options.integration_tolerance, 0, 1, nullptr, r.monodromy, r.steps,
        detail::taylor_shooting_max_steps * options.periods, detail::sampled_steps(track));
    return r;
  }
  r.steps = options.steps * options.periods;
  detail::monodromy(c, r.end, period, r.steps, 0, r.steps, nullptr, r.monodromy, track);
  return r;
}

void set_forced_multipliers(const Eigen::MatrixXd& m, double stability_tolerance,
                            forced_orbit_result& r) {
  const Eigen::VectorXcd ev = detail::general_eigenvalues(m);
  std::vector<std::complex<double>> mu(ev.data(), ev.data() + ev.size());
  std::sort(mu.begin(), mu.end(), [](auto a, auto b) {
    return std::abs(a) != std::abs(b) ? std::abs(a) > std::abs(b) : a.imag() > b.imag();
  });
  r.multipliers = mu;
  r.max_multiplier = mu.empty() ? 0.0 : std::abs(mu.front());
  r.stable = r.max_multiplier <= 1 + stability_tolerance;
}

// The kind of instability an unstable orbit shows: its largest multiplier real and positive
// (it left through +1), real and negative (through −1), or complex.
nnm_bifurcation_kind forced_instability_kind(const forced_point& unstable) {
  if (unstable.multipliers.empty()) return nnm_bifurcation_kind::branch_point;
  const std::complex<double> largest = unstable.multipliers.front();
  if (std::fabs(largest.imag()) > 1e-9 * std::abs(largest))
    return nnm_bifurcation_kind::complex_pair;
  return largest.real() > 0 ? nnm_bifurcation_kind::branch_point
                            : nnm_bifurcation_kind::period_doubling;
}

}  // namespace

chain with_drive_frequency(const chain& c, double frequency) {
  check_forced(c, "with_drive_frequency");
  if (!(frequency > 0) || !std::isfinite(frequency))
    throw std::invalid_argument(fmt::format(
        "with_drive_frequency: the drive frequency must be positive and finite, got {} rad/s",
        frequency));
  chain_parameters p = c.parameters();
  p.pivot.frequency = frequency;
  return chain(p);
}

forced_orbit_result forced_orbit(const chain& c, std::span<const double> x0_guess,
                                 const forced_orbit_options& options) {
  check_forced(c, "forced_orbit");
  const int d = c.state_size();
  if (x0_guess.size() != static_cast<std::size_t>(d))
    throw std::invalid_argument(
        fmt::format("forced_orbit: x0_guess has {} entries; the {}-link chain needs {}",
                    x0_guess.size(), c.links(), d));
  if (options.periods < 1)
    throw std::invalid_argument(
        fmt::format("forced_orbit: periods must be >= 1, got {}", options.periods));
  if (options.steps < 2)
    throw std::invalid_argument(
        fmt::format("forced_orbit: steps must be >= 2, got {}", options.steps));
  if (!serves(options.stepper, stepper_use::monodromy))
    throw std::invalid_argument(fmt::format("forced_orbit: the shooting integrates with {}, not {}",
                                            stepper_names(stepper_use::monodromy),
                                            stepper_name(options.stepper)));
  if (options.stepper == stepper_kind::taylor &&
      !(options.integration_tolerance > 0 && options.integration_tolerance <= 1e-6))
    throw std::invalid_argument(
        fmt::format("forced_orbit: the taylor tolerance must lie in (0, 1e-6], got {}",
                    options.integration_tolerance));
  if (!(options.tolerance > 0))
    throw std::invalid_argument(
        fmt::format("forced_orbit: tolerance must be positive, got {}", options.tolerance));
  const pivot_motion& drive = c.parameters().pivot;
  if (!(drive.frequency > 0) || !std::isfinite(drive.frequency))
    throw std::invalid_argument(
        fmt::format("forced_orbit: the drive frequency must be positive and finite, got {} rad/s",
                    drive.frequency));

  forced_orbit_result r;
  r.frequency = drive.frequency;
  r.period = options.periods * drive.period();
  std::vector<double> x(x0_guess.begin(), x0_guess.end());
  for (int iteration = 0;; ++iteration) {
    if (stop_requested(options.control)) {
      r.stopped = true;
      break;
    }
    forced_pass pass;
    try {
      pass = integrate_forced(c, x, r.period, options);
    } catch (const integration_error&) {
      break;  // the step cannot follow this guess: not converged
    }
    Eigen::VectorXd residual(d);
    r.closure = 0;
    for (int i = 0; i < d; ++i) {
      const auto u = static_cast<std::size_t>(i);
      residual(i) = pass.end[u] - x[u];
      r.closure = std::max(r.closure, std::fabs(residual(i)));
    }
    r.iterations = iteration;
    r.steps = pass.steps;
    if (!std::isfinite(r.closure)) break;
    if (r.closure <= options.tolerance) {
      r.converged = true;
      r.amplitudes = pass.amplitudes;
      set_forced_multipliers(pass.monodromy, options.stability_tolerance, r);
      break;
    }
    if (iteration == options.max_iterations) break;
    // ∂/∂x0 of φ(T; x0) − x0 is M − I. The period is fixed by the drive: no column for T,
    // no phase condition.
    Eigen::MatrixXd jac = pass.monodromy - Eigen::MatrixXd::Identity(d, d);
    const Eigen::VectorXd step = jac.completeOrthogonalDecomposition().solve(-residual);
    if (!step.allFinite()) break;
    for (int j = 0; j < d; ++j) x[static_cast<std::size_t>(j)] += step(j);
  }
  r.x0 = x;
  return r;
}

forced_point to_forced_point(const forced_orbit_result& r) {
  return {.frequency = r.frequency,
          .period = r.period,
          .x0 = r.x0,
          .amplitudes = r.amplitudes,
          .multipliers = r.multipliers,
          .max_multiplier = r.max_multiplier,
          .stable = r.stable,
          .closure = r.closure,
          .iterations = r.iterations};
}

namespace {

// The guess at Ω = w: the secant through the last two points (x0 against Ω), or the last
// point's start.
std::vector<double> predict_forced(const std::vector<forced_point>& points, double w) {
  const forced_point& b = points.back();
  std::vector<double> x = b.x0;
  if (points.size() == 1) return x;
  const forced_point& a = points[points.size() - 2];
  const double t = (w - b.frequency) / (b.frequency - a.frequency);
  for (std::size_t i = 0; i < x.size(); ++i) x[i] += t * (b.x0[i] - a.x0[i]);
  return x;
}

forced_orbit_result shoot_at(const chain& c, double w, const std::vector<double>& guess,
                             const forced_orbit_options& options) {
  return forced_orbit(with_drive_frequency(c, w), guess, options);
}

}  // namespace

drive_branch continue_drive(const chain& c, std::span<const double> x0_start,
                            const drive_continuation_options& options) {
  check_forced(c, "continue_drive");
  const double w0 = c.parameters().pivot.frequency, w_end = options.frequency_end;
  if (!(w_end > 0) || !std::isfinite(w_end))
    throw std::invalid_argument(fmt::format(
        "continue_drive: frequency_end must be a positive, finite drive frequency, got {} rad/s",
        w_end));
  if (w_end == w0)
    throw std::invalid_argument(fmt::format(
        "continue_drive: frequency_end ({} rad/s) equals the chain's drive frequency", w_end));
  if (!(options.initial_step >= 0) || !(options.max_step >= 0))
    throw std::invalid_argument(
        fmt::format("continue_drive: initial_step and max_step must be >= 0, got {} and {}",
                    options.initial_step, options.max_step));
  if (!(options.frequency_tolerance > 0))
    throw std::invalid_argument(
        fmt::format("continue_drive: frequency_tolerance must be positive, got {}",
                    options.frequency_tolerance));
  const double range = std::fabs(w_end - w0), direction = w_end > w0 ? 1.0 : -1.0;
  const double max_step = options.max_step > 0 ? options.max_step : range / 20;
  double step = std::min(options.initial_step > 0 ? options.initial_step : max_step, max_step);
  run_control* control = options.orbit.control;

  drive_branch branch;
  const forced_orbit_result first = forced_orbit(c, x0_start, options.orbit);
  if (first.stopped || !first.converged) {
    branch.stopped = first.stopped;
    branch.end_reason = first.stopped ? "stopped" : "the first orbit did not converge";
    return branch;
  }
  branch.points.push_back(to_forced_point(first));
  while (true) {
    if (report_progress(control, std::fabs(branch.points.back().frequency - w0), range)) {
      branch.stopped = true;
      branch.end_reason = "stopped";
      return branch;
    }
    if (static_cast<int>(branch.points.size()) >= options.max_points) {
      branch.end_reason = "max_points reached";
      break;
    }
    const double last = branch.points.back().frequency;
    double w = last + direction * step;
    // The last step stretches to Ω_end rather than leave a sliver (or a rounding's worth).
    if (direction * (w_end - w) < step / 4) w = w_end;
    const forced_orbit_result r = shoot_at(c, w, predict_forced(branch.points, w), options.orbit);
    if (r.stopped) {
      branch.stopped = true;
      branch.end_reason = "stopped";
      return branch;
    }
    if (r.converged) {
      branch.points.push_back(to_forced_point(r));
      if (w == w_end) {
        branch.end_reason = "reached frequency_end";
        break;
      }
      if (r.iterations <= 3) step = std::min(1.5 * step, max_step);
      continue;
    }
    // Near a bifurcation (a multiplier at +1) or a resonance the prediction misses: shorter
    // steps, and once they are negligible the branch ends here.
    step /= 2;
    if (step < options.min_step_ratio * last) {
      branch.end_reason = fmt::format(
          "the shooting stopped converging beyond Omega = {} rad/s (a fold of the response "
          "curve or a bifurcation: the step fell below min_step_ratio)",
          last);
      break;
    }
  }

  // Each change of stability, by bisection on the stability flag (a and b keep their order
  // along the branch, whichever way Ω runs).
  for (std::size_t i = 0; i + 1 < branch.points.size(); ++i) {
    forced_point a = branch.points[i], b = branch.points[i + 1];
    if (a.stable == b.stable) continue;
    while (std::fabs(b.frequency - a.frequency) >
           options.frequency_tolerance * std::max(a.frequency, b.frequency)) {
      const double w = (a.frequency + b.frequency) / 2;
      std::vector<double> guess = a.x0;
      for (std::size_t k = 0; k < guess.size(); ++k) guess[k] += (b.x0[k] - a.x0[k]) / 2;
      const forced_orbit_result r = shoot_at(c, w, guess, options.orbit);
      if (r.stopped) {
        branch.stopped = true;
        branch.end_reason = "stopped";
        return branch;
      }
      if (!r.converged) break;
      forced_point m = to_forced_point(r);
      (m.stable == a.stable ? a : b) = std::move(m);
    }
    drive_stability_change change;
    change.stable_side = a.stable ? a : b;
    change.unstable_side = a.stable ? b : a;
    change.stable_above = change.stable_side.frequency > change.unstable_side.frequency;
    change.kind = forced_instability_kind(change.unstable_side);
    change.frequency = (a.frequency + b.frequency) / 2;
    change.bracket = std::fabs(b.frequency - a.frequency);
    branch.changes.push_back(std::move(change));
  }
  return branch;
}

}  // namespace npend
