#include "npend/analysis/orbits/periodic_orbit.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <optional>
#include <stdexcept>

#include "analysis/detail/conservative_chain.hpp"
#include "analysis/detail/dense_eigen.hpp"
#include "analysis/detail/monodromy.hpp"
#include "npend/analysis/stability/normal_modes.hpp"
#include "npend/chain_system.hpp"
#include "npend/integrators/gauss_legendre.hpp"
#include "npend/integrators/integrate.hpp"
#include "npend/integrators/integration_error.hpp"
#include "npend/integrators/taylor.hpp"

namespace npend {

void detail::check_conservative(const chain& c, const char* who) {
  const chain_parameters& p = c.parameters();
  if (p.is_damped())
    throw std::invalid_argument(fmt::format(
        "{}: the chain is damped; a free periodic orbit needs an undamped chain (joint and "
        "cart damping 0)",
        who));
  if (p.pivot.moves())
    throw std::invalid_argument(fmt::format(
        "{}: the pivot is driven ({}); free periodic orbits need a fixed pivot (a driven "
        "chain's orbits have the drive's period: see forced_orbit)",
        who, p.pivot.describe()));
  if (c.has_cart())
    throw std::invalid_argument(
        fmt::format("{}: the chain hangs from a cart; periodic orbits need a fixed pivot", who));
}

namespace {

// The unknowns of the shooting: the first segment's start (its q only at a turning point),
// the other segments' whole starts, then T.
struct shooting_layout {
  int d = 0, nq = 0, segments = 1;
  bool turning = false;
  int first() const { return turning ? nq : d; }
  int size() const { return first() + (segments - 1) * d + 1; }
  int start_column(int segment) const { return segment == 0 ? 0 : first() + (segment - 1) * d; }
  int period_column() const { return size() - 1; }
};

// The rows besides the segments' matching: H(x0) = E unless the energy is free (along an arc),
// the Poincaré phase condition, and the pseudo-arclength plane ⟨t, (x0 free, T) − u⟩ = 0.
struct shooting_constraints {
  std::optional<double> energy;
  std::optional<Eigen::VectorXd> phase_normal;  // with phase_point: ⟨n, x0 − point⟩ = 0
  std::vector<double> phase_point;
  std::optional<Eigen::VectorXd> arc_tangent;  // dim first() + 1
  Eigen::VectorXd arc_point;
};

Eigen::VectorXd orbit_flow(const chain& c, std::span<const double> x) {
  Eigen::VectorXd f(c.state_size());
  c.rhs(x, std::span<double>(f.data(), static_cast<std::size_t>(f.size())));
  return f;
}

// ∇H from the flow: on a fixed pivot f = (∂H/∂p, −∂H/∂q).
Eigen::VectorXd energy_gradient(const chain& c, std::span<const double> x) {
  const Eigen::VectorXd f = orbit_flow(c, x);
  const int nq = c.coordinates();
  Eigen::VectorXd g(f.size());
  g.head(nq) = -f.tail(f.size() - nq);
  g.tail(f.size() - nq) = f.head(nq);
  return g;
}

// How one segment is crossed: the stepper with its steps or tolerance, and the monodromy's
// method.
struct segment_integration {
  stepper_kind stepper = stepper_kind::gauss6;
  int steps = 0;         // gauss6
  double tolerance = 0;  // taylor
  monodromy_method method = monodromy_method::exact;
};

segment_integration segment_integration_of(const periodic_orbit_options& o) {
  return {o.stepper, (o.steps + o.segments - 1) / o.segments, o.integration_tolerance, o.monodromy};
}

// The segment's end and ∂end/∂start by Taylor's method, points within each step seen by
// `track` (detail::sampled_steps); `steps` grows by the steps taken.
Eigen::MatrixXd taylor_segment(const chain& c, std::vector<double>& x, double duration,
                               double tolerance, int& steps,
                               const std::function<void(std::span<const double>)>& track) {
  Eigen::MatrixXd tangent;
  int taken = 0;
  detail::taylor_monodromy(
      c, x, duration, tolerance, 0, 1, nullptr, tangent, taken, detail::taylor_shooting_max_steps,
      track ? detail::sampled_steps(track) : std::function<void(const taylor_tangents&)>());
  steps += taken;
  return tangent;
}

// One segment: x runs to its end over `duration` in `steps` Gauss–Legendre steps, every
// state after a step seen by `track`.
void flow_segment(const chain& c, std::vector<double>& x, double duration, int steps,
                  const std::function<void(std::span<const double>)>& track) {
  gauss_legendre<3> stepper;
  const auto system = make_implicit_system(c);
  const double dt = duration / steps;
  for (int k = 0; k < steps; ++k) {
    stepper.do_step(system, x, k * dt, dt);
    if (track) track(x);
  }
}

// One segment without its tangent: where the guess's flow takes a segment's start.
void advance_segment(const chain& c, std::vector<double>& x, double duration,
                     const segment_integration& how) {
  if (how.stepper == stepper_kind::taylor) {
    int steps = 0;
    taylor_segment(c, x, duration, how.tolerance, steps, {});
    return;
  }
  flow_segment(c, x, duration, how.steps, {});
}

// The segment's end and ∂end/∂start, exact (gauss6 or taylor) or by forward differences;
// `steps` grows by the steps of the pass.
Eigen::MatrixXd segment_with_tangent(const chain& c, std::vector<double>& x, double duration,
                                     const segment_integration& how, int& steps,
                                     const std::function<void(std::span<const double>)>& track) {
  if (how.stepper == stepper_kind::taylor)
    return taylor_segment(c, x, duration, how.tolerance, steps, track);
  Eigen::MatrixXd tangent;
  steps += how.steps;
  if (how.method == monodromy_method::exact) {
    detail::monodromy(c, x, duration, how.steps, 0, how.steps, nullptr, tangent, track);
    return tangent;
  }
  const std::vector<double> start = x;
  flow_segment(c, x, duration, how.steps, track);
  const int d = c.state_size();
  tangent.resize(d, d);
  for (int j = 0; j < d; ++j) {
    std::vector<double> nudged = start;
    const double h = std::sqrt(std::numeric_limits<double>::epsilon()) *
                     std::max(1.0, std::fabs(start[static_cast<std::size_t>(j)]));
    nudged[static_cast<std::size_t>(j)] += h;
    flow_segment(c, nudged, duration, how.steps, {});
    for (int i = 0; i < d; ++i)
      tangent(i, j) = (nudged[static_cast<std::size_t>(i)] - x[static_cast<std::size_t>(i)]) / h;
  }
  return tangent;
}

// The multipliers by descending |μ| without the trivial pair: the two closest to +1 (the
// flow direction and the energy give a Jordan block at 1 that the integration splits
// slightly).
void set_multipliers(const Eigen::MatrixXd& m, double stability_tolerance,
                     periodic_orbit_result& r) {
  const Eigen::VectorXcd ev = detail::general_eigenvalues(m);
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

void check_shooting_options(const chain& c, const periodic_orbit_options& o, const char* who) {
  if (o.steps < 2)
    throw std::invalid_argument(fmt::format("{}: steps must be >= 2, got {}", who, o.steps));
  if (o.segments < 1 || o.segments > o.steps)
    throw std::invalid_argument(fmt::format("{}: segments must be between 1 and steps ({}), got {}",
                                            who, o.steps, o.segments));
  if (!(o.tolerance > 0))
    throw std::invalid_argument(
        fmt::format("{}: tolerance must be positive, got {}", who, o.tolerance));
  if (!serves(o.stepper, stepper_use::monodromy))
    throw std::invalid_argument(fmt::format("{}: the shooting integrates with {}, not {}", who,
                                            stepper_names(stepper_use::monodromy),
                                            stepper_name(o.stepper)));
  if (o.stepper == stepper_kind::taylor) {
    if (!(o.integration_tolerance > 0 && o.integration_tolerance <= 1e-6))
      throw std::invalid_argument(fmt::format(
          "{}: the taylor tolerance must lie in (0, 1e-6], got {}", who, o.integration_tolerance));
    if (o.monodromy == monodromy_method::finite_difference)
      throw std::invalid_argument(fmt::format(
          "{}: finite-difference monodromies are gauss6's (taylor carries the exact tangent "
          "map)",
          who));
    check_stepper_fits(c, stepper_kind::taylor);
  }
  if (!o.winding.empty() && o.winding.size() != static_cast<std::size_t>(c.links()))
    throw std::invalid_argument(
        fmt::format("{}: winding has {} entries; the {}-link chain needs {}", who, o.winding.size(),
                    c.links(), c.links()));
  const bool rotates =
      std::any_of(o.winding.begin(), o.winding.end(), [](int w) { return w != 0; });
  if (rotates && o.phase == orbit_phase::turning_point)
    throw std::invalid_argument(fmt::format(
        "{}: a rotating orbit (winding not zero) has no turning point; use the poincare phase",
        who));
}

// Newton on the multiple-shooting system from the guess (x0, T): the segments' matching rows
// (φ(T/m; s_i) − s_{i+1}, the last one against s_0 shifted by the winding) and the
// constraints' rows. The correction is the least-squares, minimum-norm solution: energy
// conservation makes one matching row depend on the others, so the square system would be
// singular, and since the residual vanishes at the orbit the convergence stays quadratic.
periodic_orbit_result shoot(const chain& c, std::vector<double> x, double period,
                            const periodic_orbit_options& options,
                            const shooting_constraints& constraints) {
  shooting_layout L{c.state_size(), c.coordinates(), options.segments,
                    options.phase == orbit_phase::turning_point};
  const int d = L.d, m = L.segments;
  const segment_integration how = segment_integration_of(options);
  std::vector<double> shift(static_cast<std::size_t>(d));
  for (std::size_t i = 0; i < options.winding.size(); ++i)
    shift[static_cast<std::size_t>(c.angle_index(static_cast<int>(i)))] =
        2 * std::numbers::pi * options.winding[i];
  if (L.turning) std::fill(x.begin() + L.nq, x.end(), 0.0);

  periodic_orbit_result r;
  r.winding = options.winding;
  r.winding.resize(static_cast<std::size_t>(c.links()));
  // The starts of the segments: the first is x, the others where the guess's flow takes it.
  std::vector<std::vector<double>> starts(static_cast<std::size_t>(m), x);
  try {
    for (int i = 1; i < m; ++i) {
      starts[static_cast<std::size_t>(i)] = starts[static_cast<std::size_t>(i - 1)];
      advance_segment(c, starts[static_cast<std::size_t>(i)], period / m, how);
    }
  } catch (const integration_error&) {
    r.x0 = x;
    r.period = period;
    r.energy = c.hamiltonian(x);
    return r;
  }
  const int rows = m * d + (constraints.energy ? 1 : 0) + (constraints.phase_normal ? 1 : 0) +
                   (constraints.arc_tangent ? 1 : 0);
  Eigen::MatrixXd total;
  // With options.line_search, damped Newton: a correction that leaves a larger residual (or
  // a state the steps cannot follow) is taken again at half its length, up to max_halvings
  // times, from the last accepted iterate, and the shooting gives up when none of them
  // helps.
  constexpr int max_halvings = 3;
  const double energy_scale =
      std::max(1.0, std::fabs(constraints.energy ? *constraints.energy : 0.0));
  std::vector<std::vector<double>> accepted_starts = starts;
  double accepted_period = period, accepted_norm = std::numeric_limits<double>::infinity();
  Eigen::VectorXd last_step;
  int halvings = 0;
  const auto apply = [&](const Eigen::VectorXd& step) {
    starts = accepted_starts;
    period = accepted_period;
    for (int j = 0; j < L.first(); ++j) starts[0][static_cast<std::size_t>(j)] += step(j);
    for (int i = 1; i < m; ++i)
      for (int k = 0; k < d; ++k)
        starts[static_cast<std::size_t>(i)][static_cast<std::size_t>(k)] +=
            step(L.start_column(i) + k);
    period += step(L.period_column());
  };
  // A step back to half the last correction; false when that is used up.
  const auto retreat = [&]() {
    if (last_step.size() == 0 || halvings == max_halvings) return false;
    ++halvings;
    last_step /= 2;
    apply(last_step);
    return true;
  };
  for (int iteration = 0;;) {
    if (stop_requested(options.control)) {
      r.stopped = true;
      break;
    }
    std::vector<double> amplitudes(static_cast<std::size_t>(c.links()));
    const auto track = [&](std::span<const double> s) {
      for (int i = 0; i < c.links(); ++i) {
        double& a = amplitudes[static_cast<std::size_t>(i)];
        a = std::max(a, std::fabs(s[static_cast<std::size_t>(c.angle_index(i))]));
      }
    };
    track(starts[0]);
    Eigen::VectorXd residual(rows);
    Eigen::MatrixXd jac = Eigen::MatrixXd::Zero(rows, L.size());
    total = Eigen::MatrixXd::Identity(d, d);
    r.closure = 0;
    int steps = 0;
    bool failed = false;
    for (int i = 0; i < m && !failed; ++i) {
      std::vector<double> end = starts[static_cast<std::size_t>(i)];
      Eigen::MatrixXd tangent;
      try {
        tangent = segment_with_tangent(c, end, period / m, how, steps, track);
      } catch (const integration_error&) {
        failed = true;  // the step cannot follow this guess: not converged
        break;
      }
      total = tangent * total;
      const bool last = i == m - 1;
      const std::vector<double>& next = starts[static_cast<std::size_t>(last ? 0 : i + 1)];
      for (int k = 0; k < d; ++k) {
        const auto u = static_cast<std::size_t>(k);
        residual(i * d + k) = end[u] - next[u] - (last ? shift[u] : 0.0);
        r.closure = std::max(r.closure, std::fabs(residual(i * d + k)));
      }
      const int own = L.start_column(i), own_width = i == 0 ? L.first() : d;
      jac.block(i * d, own, d, own_width) = tangent.leftCols(own_width);
      const int other = L.start_column(last ? 0 : i + 1), other_width = last ? L.first() : d;
      for (int k = 0; k < other_width; ++k) jac(i * d + k, other + k) -= 1;
      jac.block(i * d, L.period_column(), d, 1) = orbit_flow(c, end) / m;
    }
    if (failed) {
      if (options.line_search && retreat()) continue;
      break;
    }
    int row = m * d;
    double energy_error = 0;
    if (constraints.energy) {
      residual(row) = c.hamiltonian(starts[0]) - *constraints.energy;
      energy_error = std::fabs(residual(row));
      jac.block(row, 0, 1, L.first()) = energy_gradient(c, starts[0]).head(L.first()).transpose();
      ++row;
    }
    if (constraints.phase_normal) {
      const Eigen::VectorXd& n = *constraints.phase_normal;
      residual(row) = n.dot(Eigen::Map<const Eigen::VectorXd>(starts[0].data(), d) -
                            Eigen::Map<const Eigen::VectorXd>(constraints.phase_point.data(), d));
      jac.block(row, 0, 1, L.first()) = n.head(L.first()).transpose();
      ++row;
    }
    if (constraints.arc_tangent) {
      const Eigen::VectorXd& t = *constraints.arc_tangent;
      Eigen::VectorXd u(L.first() + 1);
      u.head(L.first()) = Eigen::Map<const Eigen::VectorXd>(starts[0].data(), L.first());
      u(L.first()) = period;
      residual(row) = t.dot(u - constraints.arc_point);
      jac.block(row, 0, 1, L.first()) = t.head(L.first()).transpose();
      jac(row, L.period_column()) = t(L.first());
      ++row;
    }
    const double norm = residual.norm();
    // Close to the tolerance round-off makes the residual wander: judge steps only above it.
    if (options.line_search && !(norm < accepted_norm) && last_step.size() > 0 &&
        !(norm <= 1e3 * options.tolerance * energy_scale)) {
      if (retreat()) continue;
      break;  // no shorter step helps: this guess does not lead to an orbit
    }
    accepted_starts = starts;
    accepted_period = period;
    accepted_norm = norm;
    halvings = 0;
    r.iterations = iteration;
    r.amplitudes = amplitudes;
    r.steps = steps;
    if (!std::isfinite(r.closure)) break;
    if (r.closure <= options.tolerance && energy_error <= options.tolerance * energy_scale) {
      r.converged = true;
      set_multipliers(total, options.stability_tolerance, r);
      break;
    }
    if (iteration == options.max_iterations) break;
    ++iteration;
    last_step = jac.completeOrthogonalDecomposition().solve(-residual);
    apply(last_step);
    while (options.line_search && (!(period > 0) || !std::isfinite(period)))
      if (!retreat()) break;
    if (!(period > 0) || !std::isfinite(period)) break;
  }
  r.x0 = starts[0];
  r.period = period;
  r.energy = c.hamiltonian(starts[0]);
  return r;
}

// The phase condition's rows for a guess: a Poincaré plane through it across the flow.
void set_phase(const chain& c, const periodic_orbit_options& options,
               const std::vector<double>& guess, shooting_constraints& k) {
  if (options.phase != orbit_phase::poincare) return;
  k.phase_normal = orbit_flow(c, guess);
  k.phase_point = guess;
}

}  // namespace

periodic_orbit_result periodic_orbit(const chain& c, std::span<const double> x0_guess,
                                     double T_guess, const periodic_orbit_options& options) {
  detail::check_conservative(c, "periodic_orbit");
  if (x0_guess.size() != static_cast<std::size_t>(c.state_size()))
    throw std::invalid_argument(
        fmt::format("periodic_orbit: x0_guess has {} entries; the {}-link "
                    "chain needs {}",
                    x0_guess.size(), c.links(), c.state_size()));
  if (!(T_guess > 0) || !std::isfinite(T_guess))
    throw std::invalid_argument(
        fmt::format("periodic_orbit: T_guess must be positive and finite, got {}", T_guess));
  check_shooting_options(c, options, "periodic_orbit");
  std::vector<double> x(x0_guess.begin(), x0_guess.end());
  if (options.phase == orbit_phase::turning_point)
    std::fill(x.begin() + c.coordinates(), x.end(), 0.0);
  shooting_constraints k;
  k.energy = std::isnan(options.energy) ? c.hamiltonian(x) : options.energy;
  set_phase(c, options, x, k);
  return shoot(c, x, T_guess, options, k);
}

std::optional<continuation_method> continuation_method_from_name(std::string_view name) {
  if (name == "arclength") return continuation_method::pseudo_arclength;
  if (name == "natural") return continuation_method::natural;
  return std::nullopt;
}

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

namespace {

// A family followed from its first orbit towards energy_end, by options.method.
class family_walk {
 public:
  family_walk(const chain& c, const continuation_options& options, double energy_end,
              std::string end_word, nnm_branch& branch)
      : c_(c), o_(options), end_(energy_end), end_word_(std::move(end_word)), b_(branch) {}

  // From the family's first orbits (one, or two known to lie on it, in its direction).
  void run(std::span<const periodic_orbit_result> firsts) {
    const periodic_orbit_result& first = firsts.front();
    first_period_ = first.period;
    direction_ = end_ > first.energy ? 1.0 : -1.0;
    for (const periodic_orbit_result& r : firsts) b_.points.push_back(to_nnm_point(r));
    // A mode's family starts at a tiny energy and doubles it; an orbit's family steps a
    // twentieth of the way to the end.
    double step = (b_.mode >= 0 ? std::fabs(first.energy) : std::fabs(end_ - first.energy) / 20) *
                  o_.initial_step_ratio;
    // Two points at fixed energies give the arc its first secant.
    while (b_.points.size() < 2 || o_.method == continuation_method::natural) {
      if (finished()) return;
      const double last = b_.points.back().energy;
      const double e = direction_ > 0 ? std::min(last + step, end_) : std::max(last - step, end_);
      const periodic_orbit_result r = at_energy(e);
      if (r.stopped) return stop();
      if (r.converged) {
        b_.points.push_back(to_nnm_point(r));
        if (e == end_) return end(fmt::format("reached {}", end_word_));
        if (r.iterations <= 4) step *= 1.5;
        continue;
      }
      step /= 2;
      if (step < o_.min_step_ratio * std::max(std::fabs(last), 1e-300))
        return end(fmt::format(
            "the shooting stopped converging beyond E = {} J (the energy step fell below "
            "min_step_ratio)",
            last));
    }
    along_arc();
  }

 private:
  bool finished() {
    if (static_cast<int>(b_.points.size()) < o_.max_points) return false;
    end("max_points reached");
    return true;
  }
  void end(std::string reason) { b_.end_reason = std::move(reason); }
  void stop() {
    b_.stopped = true;
    end("stopped");
  }

  periodic_orbit_options shooting(double period) const {
    periodic_orbit_options s = o_.orbit;
    if (o_.steps_follow_period && period > first_period_)
      s.steps = static_cast<int>(std::ceil(s.steps * period / first_period_));
    return s;
  }

  // The orbit at energy e from the prediction through the last two points (one point: the
  // harmonic scaling of the angles' offsets, the period unchanged).
  periodic_orbit_result at_energy(double e) const {
    const nnm_point& b = b_.points.back();
    std::vector<double> x = b.x0;
    double period = b.period;
    if (b_.points.size() == 1) {
      const double s = std::sqrt(e / b.energy);
      if (b_.mode >= 0 && std::isfinite(s) && s > 0)
        for (double& v : x) v *= s;
    } else {
      const nnm_point& a = b_.points[b_.points.size() - 2];
      const double t = (e - b.energy) / (b.energy - a.energy);
      for (std::size_t i = 0; i < x.size(); ++i) x[i] += t * (b.x0[i] - a.x0[i]);
      period += t * (b.period - a.period);
    }
    if (!(period > 0) || !std::isfinite(period)) return {};  // extrapolated past sense
    const periodic_orbit_options s = shooting(period);
    shooting_constraints k;
    k.energy = e;
    set_phase(c_, s, x, k);
    return shoot(c_, x, period, s, k);
  }

  // (the start's free entries, T): the coordinates the arc is measured in.
  Eigen::VectorXd arc_coordinates(const nnm_point& p) const {
    const int free =
        o_.orbit.phase == orbit_phase::turning_point ? c_.coordinates() : c_.state_size();
    Eigen::VectorXd u(free + 1);
    for (int j = 0; j < free; ++j) u(j) = p.x0[static_cast<std::size_t>(j)];
    u(free) = p.period;
    return u;
  }

  void along_arc() {
    double ds =
        (arc_coordinates(b_.points.back()) - arc_coordinates(b_.points[b_.points.size() - 2]))
            .norm();
    while (!finished()) {
      const nnm_point& a = b_.points[b_.points.size() - 2];
      const nnm_point& b = b_.points.back();
      const Eigen::VectorXd ub = arc_coordinates(b), secant = ub - arc_coordinates(a);
      const Eigen::VectorXd t = secant / secant.norm();
      const Eigen::VectorXd predicted = ub + ds * t;
      const int free = static_cast<int>(predicted.size()) - 1;
      std::vector<double> x(b.x0.size());
      for (std::size_t i = 0; i < x.size(); ++i)
        x[i] = b.x0[i] + ds / secant.norm() * (b.x0[i] - a.x0[i]);
      const double period = predicted(free);
      shooting_constraints k;
      k.arc_tangent = t;
      k.arc_point = predicted;
      const periodic_orbit_options s = shooting(period);
      set_phase(c_, s, x, k);
      const periodic_orbit_result r =
          period > 0 ? shoot(c_, x, period, s, k) : periodic_orbit_result{};
      if (r.stopped) return stop();
      if (!r.converged) {
        ds /= 2;
        if (ds < o_.min_step_ratio * ub.norm())
          return end(fmt::format(
              "the shooting stopped converging beyond E = {} J (the arclength step fell below "
              "min_step_ratio)",
              b.energy));
        continue;
      }
      // A corrector that lands far off the predicted arc (its secant turned by more than
      // about 37°) has likely jumped to another family: a shorter step instead.
      const Eigen::VectorXd turn = arc_coordinates(to_nnm_point(r)) - ub;
      if (turn.dot(t) < 0.8 * turn.norm()) {
        ds /= 2;
        if (ds < o_.min_step_ratio * ub.norm())
          return end(fmt::format(
              "the family turned too sharply to follow beyond E = {} J (the arclength step fell "
              "below min_step_ratio)",
              b.energy));
        continue;
      }
      if (direction_ * (r.energy - end_) >= 0) {
        // Past the end: the orbit at the end energy itself, between b and r.
        b_.points.push_back(to_nnm_point(r));
        const periodic_orbit_result last = at_energy(end_);
        b_.points.pop_back();
        if (last.stopped) return stop();
        if (last.converged) {
          note_fold(last);
          b_.points.push_back(to_nnm_point(last));
          return end(fmt::format("reached {}", end_word_));
        }
        ds /= 2;  // not reached from here: a shorter arc step lands closer
        continue;
      }
      if (direction_ * (r.energy - b_.points.front().energy) < 0)
        return end(fmt::format("the branch turned back {} its first energy",
                               direction_ > 0 ? "below" : "above"));
      note_fold(r);
      b_.points.push_back(to_nnm_point(r));
      if (r.iterations <= 4) ds *= 1.5;
    }
  }

  // The energy turns back between the last point and r: a fold, its extreme energy from the
  // parabola through the last three energies against the arc's point count.
  void note_fold(const periodic_orbit_result& r) {
    const std::size_t n = b_.points.size();
    if (n < 2) return;
    const double e0 = b_.points[n - 2].energy, e1 = b_.points[n - 1].energy, e2 = r.energy;
    if ((e1 - e0) * (e2 - e1) >= 0) return;
    const double curvature = e0 - 2 * e1 + e2;
    const double vertex = curvature != 0 ? e1 - (e2 - e0) * (e2 - e0) / (8 * curvature) : e1;
    b_.folds.push_back({.after = n - 1, .energy = vertex});
  }

  const chain& c_;
  const continuation_options& o_;
  double end_;
  std::string end_word_;
  nnm_branch& b_;
  double first_period_ = 0, direction_ = 1;
};

void check_continuation(const continuation_options& o, const char* who) {
  if (o.max_points < 1)
    throw std::invalid_argument(
        fmt::format("{}: max_points must be >= 1, got {}", who, o.max_points));
  if (!(o.initial_step_ratio > 0) || !(o.min_step_ratio > 0))
    throw std::invalid_argument(
        fmt::format("{}: initial_step_ratio and min_step_ratio must be positive", who));
}

}  // namespace

nnm_branch continue_mode(const chain& c, int mode, const continuation_options& options) {
  detail::check_conservative(c, "continue_mode");
  check_shooting_options(c, options.orbit, "continue_mode");
  check_continuation(options, "continue_mode");
  const int n = c.links();
  if (mode < 0 || mode >= n)
    throw std::invalid_argument(
        fmt::format("continue_mode: mode {} is out of range; the {}-link chain has modes 0..{}",
                    mode, n, n - 1));
  if (std::any_of(options.orbit.winding.begin(), options.orbit.winding.end(),
                  [](int w) { return w != 0; }))
    throw std::invalid_argument(
        "continue_mode: a normal mode's family oscillates; its winding must be zero");
  if (!(options.start_amplitude > 0) || !std::isfinite(options.start_amplitude))
    throw std::invalid_argument(fmt::format(
        "continue_mode: start_amplitude must be positive, got {}", options.start_amplitude));
  // The linear modes are those of the hanging chain: a spring with a rest angle holds the
  // chain at rest elsewhere.
  const chain_parameters& params = c.parameters();
  for (std::size_t j = 0; j < params.rest_angles.size(); ++j)
    if (params.rest_angles[j] != 0 && j < params.stiffness.size() && params.stiffness[j] != 0)
      throw std::invalid_argument(
          "continue_mode: the springs' rest angles hold the chain at rest away from hanging "
          "straight down, where the linear modes are taken; shoot an orbit near its resting "
          "state with periodic_orbit (npend orbit) and follow its family with continue_orbit "
          "(--continue-to)");
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

  periodic_orbit_options shoot_first = options.orbit;
  shoot_first.energy = e0;
  const periodic_orbit_result first =
      periodic_orbit(c, x, 2 * std::numbers::pi / m.frequency, shoot_first);
  if (first.stopped || !first.converged) {
    branch.stopped = first.stopped;
    branch.end_reason = first.stopped ? "stopped" : "the first point did not converge";
    return branch;
  }
  family_walk(c, options, options.energy_max, "energy_max", branch)
      .run(std::span<const periodic_orbit_result>(&first, 1));
  return branch;
}

nnm_branch continue_orbit(const chain& c, const periodic_orbit_result& start, double energy_end,
                          const continuation_options& options) {
  detail::check_conservative(c, "continue_orbit");
  check_shooting_options(c, options.orbit, "continue_orbit");
  check_continuation(options, "continue_orbit");
  if (!start.converged || start.x0.size() != static_cast<std::size_t>(c.state_size()))
    throw std::invalid_argument(
        "continue_orbit: the start must be a converged orbit of this chain");
  if (!std::isfinite(energy_end) || energy_end == start.energy)
    throw std::invalid_argument(fmt::format(
        "continue_orbit: the end energy must be finite and differ from the orbit's ({} J), got {}",
        start.energy, energy_end));
  nnm_branch branch;
  branch.mode = -1;
  family_walk(c, options, energy_end, "the end energy", branch)
      .run(std::span<const periodic_orbit_result>(&start, 1));
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

namespace {

// The direction in x0 along which a new family leaves the orbit p: at a branch point the
// smallest right singular vector of the fixed-energy shooting Jacobian (rows φ(T) − x0,
// H(x0) − E and the plane across the flow; columns x0 and T), at a period doubling the
// monodromy's eigenvector whose eigenvalue is nearest −1. Normalised to ‖v‖∞ = 1.
Eigen::VectorXd new_direction(const chain& c, const nnm_point& p, const periodic_orbit_options& o,
                              bool doubling) {
  const int d = c.state_size();
  std::vector<double> end = p.x0;
  const segment_integration whole_period{o.stepper, o.steps, o.integration_tolerance, o.monodromy};
  int steps = 0;
  const Eigen::MatrixXd m = segment_with_tangent(c, end, p.period, whole_period, steps, {});
  Eigen::VectorXd v(d);
  if (doubling) {
    const detail::general_eigensystem eigen = detail::general_eigen_decomposition(m);
    Eigen::Index k = 0;
    for (Eigen::Index i = 1; i < eigen.values.size(); ++i)
      if (std::abs(eigen.values(i) + 1.0) < std::abs(eigen.values(k) + 1.0)) k = i;
    v = eigen.vectors.col(k).real();
  } else {
    const Eigen::VectorXd f0 = orbit_flow(c, p.x0);
    Eigen::MatrixXd jac = Eigen::MatrixXd::Zero(d + 2, d + 1);
    jac.topLeftCorner(d, d) = m - Eigen::MatrixXd::Identity(d, d);
    jac.block(0, d, d, 1) = orbit_flow(c, end);
    jac.block(d, 0, 1, d) = energy_gradient(c, p.x0).transpose();
    jac.block(d + 1, 0, 1, d) = f0.transpose();
    v = detail::right_singular_vectors(jac).col(d).head(d);
  }
  return v / v.cwiseAbs().maxCoeff();
}

double start_distance(const std::vector<double>& a, const std::vector<double>& b) {
  double gap = 0;
  for (std::size_t i = 0; i < a.size(); ++i) gap = std::max(gap, std::fabs(a[i] - b[i]));
  return gap;
}

}  // namespace

nnm_branch switch_branch(const chain& c, const nnm_bifurcation& at, double energy_end,
                         const continuation_options& options) {
  detail::check_conservative(c, "switch_branch");
  check_shooting_options(c, options.orbit, "switch_branch");
  check_continuation(options, "switch_branch");
  nnm_branch branch;
  branch.mode = -1;
  if (at.kind == nnm_bifurcation_kind::complex_pair) {
    branch.end_reason =
        "a complex pair leaves the circle: no family of the same period branches off";
    return branch;
  }
  const bool doubling = at.kind == nnm_bifurcation_kind::period_doubling;
  // The unstable side's orbit: there the new direction is already separated from the others.
  const nnm_point& base = at.unstable_side;
  periodic_orbit_options shoot = options.orbit;
  shoot.phase = orbit_phase::poincare;
  const Eigen::VectorXd v = new_direction(c, base, shoot, doubling);
  double scale = 1;
  for (const double x : base.x0) scale = std::max(scale, std::fabs(x));
  const double side = energy_end > at.energy ? 1.0 : -1.0;
  // An orbit of the new family at energy e, from the bifurcation's orbit moved by `along` ·
  // v: converged, and neither the old family's orbit there nor (period doubling) that orbit
  // run twice.
  const auto new_orbit = [&](double e, double along) -> std::optional<periodic_orbit_result> {
    periodic_orbit_options o = shoot;
    o.energy = e;
    const periodic_orbit_result old = periodic_orbit(c, base.x0, base.period, o);
    std::vector<double> guess = base.x0;
    for (std::size_t i = 0; i < guess.size(); ++i)
      guess[i] += along * v(static_cast<Eigen::Index>(i));
    const periodic_orbit_result r =
        periodic_orbit(c, guess, doubling ? 2 * base.period : base.period, o);
    if (!r.converged) return std::nullopt;
    // The old family's orbit, perhaps crossing another plane: the same start, or the same
    // period (at one energy, distinct families' periods differ by far more than the 1e-10 the
    // closure leaves).
    if (old.converged && !doubling &&
        (start_distance(r.x0, old.x0) <= 1e-6 ||
         std::fabs(r.period - old.period) <= 1e-8 * old.period))
      return std::nullopt;
    if (doubling) {
      const periodic_orbit_result single = periodic_orbit(c, r.x0, r.period / 2, o);
      if (single.converged && start_distance(single.x0, r.x0) <= 1e-6) return std::nullopt;
    }
    return r;
  };
  for (const double offset : {1e-4, 1e-3, 1e-2}) {
    const double e1 = at.energy * (1 + side * offset), e2 = at.energy * (1 + 2 * side * offset);
    for (const double distance : {0.01, 0.03, 0.1, 0.3})
      for (const double sign : {1.0, -1.0}) {
        if (stop_requested(options.orbit.control)) {
          branch.stopped = true;
          branch.end_reason = "stopped";
          return branch;
        }
        // A pitchfork's new orbits move away as √|E − E_b|: the second point √2 farther.
        const double along = sign * distance * scale * std::sqrt(offset);
        const auto first = new_orbit(e1, along);
        if (!first) continue;
        const auto second = new_orbit(e2, std::sqrt(2.0) * along);
        if (!second) continue;
        continuation_options follow = options;
        follow.orbit = shoot;
        follow.orbit.energy = std::numeric_limits<double>::quiet_NaN();
        const std::array<periodic_orbit_result, 2> firsts{*first, *second};
        if (side * (energy_end - second->energy) <= 0) {
          for (const periodic_orbit_result& r : firsts) branch.points.push_back(to_nnm_point(r));
          branch.end_reason = "reached the end energy";
          return branch;
        }
        family_walk(c, follow, energy_end, "the end energy", branch).run(firsts);
        return branch;
      }
  }
  branch.end_reason = fmt::format(
      "no orbit of a new family was found {} the bifurcation (a family on the other side "
      "needs an end energy there)",
      side > 0 ? "above" : "below");
  return branch;
}

}  // namespace npend
