#include "npend/analysis/orbits/periodic_orbit.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "analysis/detail/monodromy.hpp"
#include "npend/analysis/stability/normal_modes.hpp"
#include "npend/integrators/integration_error.hpp"

namespace npend {

namespace {

// Shooting needs a conserved H and an autonomous flow: damping spirals every orbit in, a
// drive makes the period the drive's (Floquet's business), and a cart adds the conserved
// momentum p_x, a second trivial pair of multipliers this step does not separate.
void check_conservative(const chain& c, const char* who) {
  const chain_parameters& p = c.parameters();
  if (p.is_damped())
    throw std::invalid_argument(fmt::format(
        "{}: the chain is damped; a free periodic orbit needs an undamped chain (joint and "
        "cart damping 0)",
        who));
  if (p.pivot.moves())
    throw std::invalid_argument(fmt::format(
        "{}: the pivot is driven ({}); free periodic orbits need a fixed pivot (a driven "
        "chain's orbits have the drive's period: see floquet_analysis)",
        who, p.pivot.describe()));
  if (c.has_cart())
    throw std::invalid_argument(
        fmt::format("{}: the chain hangs from a cart; periodic orbits need a fixed pivot", who));
}

// One Gauss–Legendre pass over the period from x0: the end state, the monodromy and each
// angle's largest |φ_i| over the start and the step points.
struct period_pass {
  std::vector<double> end;
  Eigen::MatrixXd monodromy;
  std::vector<double> amplitudes;
};

period_pass integrate_period(const chain& c, const std::vector<double>& x0, double period,
                             int steps) {
  period_pass r;
  r.end = x0;
  r.amplitudes.resize(static_cast<std::size_t>(c.links()));
  const auto track = [&](std::span<const double> x) {
    for (int i = 0; i < c.links(); ++i) {
      double& a = r.amplitudes[static_cast<std::size_t>(i)];
      a = std::max(a, std::fabs(x[static_cast<std::size_t>(c.angle_index(i))]));
    }
  };
  track(x0);
  detail::monodromy(c, r.end, period, steps, 0, steps, nullptr, r.monodromy, track);
  return r;
}

Eigen::VectorXd orbit_flow(const chain& c, const std::vector<double>& x) {
  Eigen::VectorXd f(c.state_size());
  c.rhs(x, std::span<double>(f.data(), static_cast<std::size_t>(f.size())));
  return f;
}

// The multipliers by descending |μ| without the trivial pair: the two closest to +1 (the
// flow direction and the energy give a Jordan block at 1 that the integration splits
// slightly).
void set_multipliers(const Eigen::MatrixXd& m, double stability_tolerance,
                     periodic_orbit_result& r) {
  const Eigen::VectorXcd ev = Eigen::EigenSolver<Eigen::MatrixXd>(m, false).eigenvalues();
  std::vector<std::complex<double>> mu(ev.data(), ev.data() + ev.size());
  for (int k = 0; k < 2 && !mu.empty(); ++k)
    mu.erase(std::min_element(mu.begin(), mu.end(), [](auto a, auto b) {
      return std::abs(a - 1.0) < std::abs(b - 1.0);
    }));
  std::sort(mu.begin(), mu.end(), [](auto a, auto b) {
    return std::abs(a) != std::abs(b) ? std::abs(a) > std::abs(b) : a.imag() > b.imag();
  });
  r.multipliers = mu;
  r.max_multiplier = mu.empty() ? 1.0 : std::abs(mu.front());
  r.stable = r.max_multiplier <= 1 + stability_tolerance;
}

}  // namespace

periodic_orbit_result periodic_orbit(const chain& c, std::span<const double> x0_guess,
                                     double T_guess, const periodic_orbit_options& options) {
  check_conservative(c, "periodic_orbit");
  const int d = c.state_size(), nq = c.coordinates();
  if (x0_guess.size() != static_cast<std::size_t>(d))
    throw std::invalid_argument(
        fmt::format("periodic_orbit: x0_guess has {} entries; the {}-link "
                    "chain needs {}",
                    x0_guess.size(), c.links(), d));
  if (!(T_guess > 0) || !std::isfinite(T_guess))
    throw std::invalid_argument(
        fmt::format("periodic_orbit: T_guess must be positive and finite, got {}", T_guess));
  if (options.steps < 2)
    throw std::invalid_argument(
        fmt::format("periodic_orbit: steps must be >= 2, got {}", options.steps));
  if (!(options.tolerance > 0))
    throw std::invalid_argument(
        fmt::format("periodic_orbit: tolerance must be positive, got {}", options.tolerance));

  const bool turning = options.phase == orbit_phase::turning_point;
  std::vector<double> x(x0_guess.begin(), x0_guess.end());
  if (turning) std::fill(x.begin() + nq, x.end(), 0.0);
  const std::vector<double> guess = x;
  const Eigen::VectorXd f_guess = orbit_flow(c, guess);
  const double energy = std::isnan(options.energy) ? c.hamiltonian(x) : options.energy;
  // Unknowns: the free entries of x0 (q only at a turning point), then T.
  const int free = turning ? nq : d, rows = d + 1 + (turning ? 0 : 1);
  double period = T_guess;

  periodic_orbit_result r;
  for (int iteration = 0;; ++iteration) {
    if (stop_requested(options.control)) {
      r.stopped = true;
      break;
    }
    period_pass pass;
    try {
      pass = integrate_period(c, x, period, options.steps);
    } catch (const integration_error&) {
      break;  // the step cannot follow this guess: not converged
    }
    Eigen::VectorXd residual(rows);
    r.closure = 0;
    for (int i = 0; i < d; ++i) {
      const auto u = static_cast<std::size_t>(i);
      residual(i) = pass.end[u] - x[u];
      r.closure = std::max(r.closure, std::fabs(residual(i)));
    }
    residual(d) = c.hamiltonian(x) - energy;
    const Eigen::VectorXd f0 = orbit_flow(c, x);
    if (!turning)
      residual(d + 1) = f_guess.dot(Eigen::Map<const Eigen::VectorXd>(x.data(), d) -
                                    Eigen::Map<const Eigen::VectorXd>(guess.data(), d));
    r.iterations = iteration;
    if (!std::isfinite(r.closure)) break;
    if (r.closure <= options.tolerance &&
        std::fabs(residual(d)) <= options.tolerance * std::max(1.0, std::fabs(energy))) {
      r.converged = true;
      r.amplitudes = pass.amplitudes;
      set_multipliers(pass.monodromy, options.stability_tolerance, r);
      break;
    }
    if (iteration == options.max_iterations) break;

    // ∂/∂x0 of φ(T) − x0 is M − I; ∂/∂T is f(φ(T)). On a fixed pivot f = (∂H/∂p, −∂H/∂q),
    // so ∇H comes from f without another kernel.
    const Eigen::VectorXd f_end = orbit_flow(c, pass.end);
    Eigen::MatrixXd jac = Eigen::MatrixXd::Zero(rows, free + 1);
    for (int j = 0; j < free; ++j) {
      jac.col(j).head(d) = pass.monodromy.col(j);
      jac(j, j) -= 1;
      jac(d, j) = j < nq ? -f0(nq + j) : f0(j - nq);
      if (!turning) jac(d + 1, j) = f_guess(j);
    }
    jac.col(free).head(d) = f_end;
    const Eigen::VectorXd step = jac.completeOrthogonalDecomposition().solve(-residual);
    for (int j = 0; j < free; ++j) x[static_cast<std::size_t>(j)] += step(j);
    period += step(free);
    if (!(period > 0) || !std::isfinite(period)) break;
  }
  r.x0 = x;
  r.period = period;
  r.energy = c.hamiltonian(x);
  return r;
}

namespace {

// The guess at energy e: the secant through the last two points (in x0 and T against E),
// or from a single point the harmonic scaling (angles ∝ √E, the period unchanged).
std::pair<std::vector<double>, double> predict_orbit(const std::vector<nnm_point>& points,
                                                     double e) {
  const nnm_point& b = points.back();
  std::vector<double> x = b.x0;
  if (points.size() == 1) {
    const double s = std::sqrt(e / b.energy);
    for (double& v : x) v *= s;
    return {x, b.period};
  }
  const nnm_point& a = points[points.size() - 2];
  const double t = (e - b.energy) / (b.energy - a.energy);
  for (std::size_t i = 0; i < x.size(); ++i) x[i] += t * (b.x0[i] - a.x0[i]);
  return {x, b.period + t * (b.period - a.period)};
}

}  // namespace

nnm_point to_nnm_point(const periodic_orbit_result& r) {
  return {.energy = r.energy,
          .period = r.period,
          .frequency = 2 * std::numbers::pi / r.period,
          .x0 = r.x0,
          .amplitudes = r.amplitudes,
          .multipliers = r.multipliers,
          .max_multiplier = r.max_multiplier,
          .stable = r.stable,
          .closure = r.closure,
          .iterations = r.iterations};
}

nnm_branch continue_mode(const chain& c, int mode, const continuation_options& options) {
  check_conservative(c, "continue_mode");
  const int n = c.links();
  if (mode < 0 || mode >= n)
    throw std::invalid_argument(
        fmt::format("continue_mode: mode {} is out of range; the {}-link chain has modes 0..{}",
                    mode, n, n - 1));
  if (!(options.start_amplitude > 0) || !std::isfinite(options.start_amplitude))
    throw std::invalid_argument(fmt::format(
        "continue_mode: start_amplitude must be positive, got {}", options.start_amplitude));
  const linearisation lin = normal_modes(c, std::vector<double>(static_cast<std::size_t>(n)));
  const normal_mode& m = lin.modes[static_cast<std::size_t>(mode)];
  if (!(m.frequency > 0))
    throw std::invalid_argument(
        fmt::format("continue_mode: mode {} of the hanging chain does not oscillate (ω² = {})",
                    mode, m.omega_squared));
  nnm_branch branch;
  branch.mode = mode;
  branch.linear_frequency = m.frequency;
  branch.shape = m.shape;
  double largest = 0;
  for (const double v : m.shape) largest = std::max(largest, std::fabs(v));
  std::vector<double> x(static_cast<std::size_t>(c.state_size()));
  for (int i = 0; i < n; ++i)
    x[static_cast<std::size_t>(c.angle_index(i))] =
        options.start_amplitude * m.shape[static_cast<std::size_t>(i)] / largest;
  const double e0 = c.hamiltonian(x);
  if (!(options.energy_max > e0))
    throw std::invalid_argument(
        fmt::format("continue_mode: energy_max ({} J) must exceed the first point's energy ({} J)",
                    options.energy_max, e0));

  periodic_orbit_options shoot = options.orbit;
  shoot.energy = e0;
  const periodic_orbit_result first =
      periodic_orbit(c, x, 2 * std::numbers::pi / m.frequency, shoot);
  if (first.stopped || !first.converged) {
    branch.stopped = first.stopped;
    branch.end_reason = first.stopped ? "stopped" : "the first point did not converge";
    return branch;
  }
  branch.points.push_back(to_nnm_point(first));
  double step = e0 * options.initial_step_ratio;
  while (true) {
    if (static_cast<int>(branch.points.size()) >= options.max_points) {
      branch.end_reason = "max_points reached";
      break;
    }
    const double last = branch.points.back().energy;
    const double e = std::min(last + step, options.energy_max);
    const auto [guess, period] = predict_orbit(branch.points, e);
    shoot.energy = e;
    const periodic_orbit_result r = periodic_orbit(c, guess, period, shoot);
    if (r.stopped) {
      branch.stopped = true;
      branch.end_reason = "stopped";
      break;
    }
    if (r.converged) {
      branch.points.push_back(to_nnm_point(r));
      if (e >= options.energy_max) {
        branch.end_reason = "reached energy_max";
        break;
      }
      if (r.iterations <= 4) step *= 1.5;
      continue;
    }
    // Near a fold in energy or the separatrix the prediction misses: shorter steps, and
    // once they are negligible the branch ends here.
    step /= 2;
    if (step < options.min_step_ratio * last) {
      branch.end_reason = fmt::format(
          "the shooting stopped converging beyond E = {} J (the energy step fell below "
          "min_step_ratio)",
          last);
      break;
    }
  }
  return branch;
}

std::optional<nnm_point> locate_departure(const chain& c, const nnm_branch& branch, double shift,
                                          const periodic_orbit_options& options, double tolerance) {
  if (!(shift > 0 && shift < 1))
    throw std::invalid_argument(
        fmt::format("locate_departure: shift must be in (0, 1), got {}", shift));
  if (!(tolerance > 0))
    throw std::invalid_argument(
        fmt::format("locate_departure: tolerance must be positive, got {}", tolerance));
  // g < 0 before the departure, ≥ 0 from it on.
  const auto g = [&](const nnm_point& p) {
    return std::fabs(p.frequency / branch.linear_frequency - 1) - shift;
  };
  const auto beyond = std::find_if(branch.points.begin(), branch.points.end(),
                                   [&](const nnm_point& p) { return g(p) >= 0; });
  if (beyond == branch.points.end() || beyond == branch.points.begin()) return std::nullopt;
  nnm_point a = *(beyond - 1), b = *beyond;
  double ga = g(a), gb = g(b);
  int side = 0;  // which end stayed twice in a row (Illinois: halve its g)
  periodic_orbit_options shoot = options;
  for (int iteration = 0; iteration < 100; ++iteration) {
    if (std::fabs(gb) <= tolerance * shift) return b;
    if (b.energy - a.energy <= 4 * std::numeric_limits<double>::epsilon() * b.energy) break;
    double e = b.energy - gb * (b.energy - a.energy) / (gb - ga);
    if (!(e > a.energy && e < b.energy)) e = (a.energy + b.energy) / 2;
    const double t = (e - a.energy) / (b.energy - a.energy);
    std::vector<double> guess = a.x0;
    for (std::size_t i = 0; i < guess.size(); ++i) guess[i] += t * (b.x0[i] - a.x0[i]);
    shoot.energy = e;
    const periodic_orbit_result r =
        periodic_orbit(c, guess, a.period + t * (b.period - a.period), shoot);
    if (r.stopped || !r.converged) break;
    const nnm_point m = to_nnm_point(r);
    const double gm = g(m);
    if (gm >= 0) {
      b = m;
      gb = gm;
      if (side == -1) ga /= 2;
      side = -1;
    } else {
      a = m;
      ga = gm;
      if (side == 1) gb /= 2;
      side = 1;
    }
  }
  // The bracket cannot shrink further (or a shot failed): its nearer end.
  return std::fabs(ga) < std::fabs(gb) ? a : b;
}

std::string_view nnm_bifurcation_name(nnm_bifurcation_kind kind) {
  switch (kind) {
    case nnm_bifurcation_kind::branch_point:
      return "branch point";
    case nnm_bifurcation_kind::period_doubling:
      return "period doubling";
    case nnm_bifurcation_kind::complex_pair:
      return "complex pair";
  }
  return "";
}

namespace {

// The kind of instability an unstable orbit shows: its largest multiplier real and positive
// (through +1), real and negative (through −1), or complex.
nnm_bifurcation_kind instability_kind(const nnm_point& unstable) {
  const auto largest =
      std::max_element(unstable.multipliers.begin(), unstable.multipliers.end(),
                       [](const auto& a, const auto& b) { return std::abs(a) < std::abs(b); });
  if (largest == unstable.multipliers.end()) return nnm_bifurcation_kind::branch_point;
  if (std::fabs(largest->imag()) > 1e-9 * std::abs(*largest))
    return nnm_bifurcation_kind::complex_pair;
  return largest->real() > 0 ? nnm_bifurcation_kind::branch_point
                             : nnm_bifurcation_kind::period_doubling;
}

}  // namespace

std::vector<nnm_bifurcation> locate_bifurcations(const chain& c, const nnm_branch& branch,
                                                 const periodic_orbit_options& options,
                                                 double energy_tolerance) {
  if (!(energy_tolerance > 0))
    throw std::invalid_argument(fmt::format(
        "locate_bifurcations: energy_tolerance must be positive, got {}", energy_tolerance));
  std::vector<nnm_bifurcation> found;
  periodic_orbit_options shoot = options;
  for (std::size_t i = 0; i + 1 < branch.points.size(); ++i) {
    nnm_point a = branch.points[i], b = branch.points[i + 1];
    if (a.stable == b.stable) continue;
    // Bisect on the stability flag, a below b in energy throughout.
    while (b.energy - a.energy > energy_tolerance * std::max(1.0, b.energy)) {
      const double e = (a.energy + b.energy) / 2;
      std::vector<double> guess = a.x0;
      for (std::size_t k = 0; k < guess.size(); ++k) guess[k] += (b.x0[k] - a.x0[k]) / 2;
      shoot.energy = e;
      const periodic_orbit_result r = periodic_orbit(c, guess, (a.period + b.period) / 2, shoot);
      if (r.stopped || !r.converged) break;
      (to_nnm_point(r).stable == a.stable ? a : b) = to_nnm_point(r);
    }
    nnm_bifurcation f;
    f.loses_stability = a.stable;
    f.stable_side = a.stable ? a : b;
    f.unstable_side = a.stable ? b : a;
    f.kind = instability_kind(f.unstable_side);
    f.energy = (a.energy + b.energy) / 2;
    found.push_back(std::move(f));
  }
  return found;
}

}  // namespace npend
