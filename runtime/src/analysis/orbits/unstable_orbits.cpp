#include "npend/analysis/orbits/unstable_orbits.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <stdexcept>
#include <utility>

#include "analysis/detail/conservative_chain.hpp"
#include "npend/analysis/chaos/lyapunov.hpp"
#include "npend/analysis/chaos/poincare_section.hpp"
#include "npend/integrators/integrate.hpp"

namespace npend {

namespace {

constexpr const char* search_name = "find_unstable_orbits";

void check_positive(double value, const char* name) {
  if (!(value > 0) || !std::isfinite(value))
    throw std::invalid_argument(
        fmt::format("{}: {} must be positive and finite, got {}", search_name, name, value));
}

void validate(const chain& c, std::span<const double> start,
              const unstable_orbit_search_options& o) {
  detail::check_conservative(c, search_name);
  if (start.size() != static_cast<std::size_t>(c.state_size()))
    throw std::invalid_argument(fmt::format("{}: start has {} entries; the {}-link chain needs {}",
                                            search_name, start.size(), c.links(), c.state_size()));
  for (const double v : start)
    if (!std::isfinite(v))
      throw std::invalid_argument(
          fmt::format("{}: start has a non-finite entry ({})", search_name, v));
  check_positive(o.period_max, "period_max");
  if (!(o.period_min >= 0 && o.period_min < o.period_max))
    throw std::invalid_argument(
        fmt::format("{}: period_min must be in [0, period_max = {}), got {}", search_name,
                    o.period_max, o.period_min));
  check_positive(o.search_time, "search_time");
  check_positive(o.dt, "dt");
  if (o.dt >= o.search_time)
    throw std::invalid_argument(fmt::format("{}: dt ({} s) must be shorter than search_time ({} s)",
                                            search_name, o.dt, o.search_time));
  check_positive(o.shooting_dt, "shooting_dt");
  if (!(o.segment_time > 0))
    throw std::invalid_argument(
        fmt::format("{}: segment_time must be positive (infinity: single shooting), got {}",
                    search_name, o.segment_time));
  check_positive(o.return_tolerance, "return_tolerance");
  check_positive(o.period_tolerance, "period_tolerance");
  check_positive(o.same_orbit_tolerance, "same_orbit_tolerance");
  if (o.lyapunov && !std::isnan(o.lyapunov_time)) {
    check_positive(o.lyapunov_time, "lyapunov_time");
    if (o.dt >= o.lyapunov_time)
      throw std::invalid_argument(
          fmt::format("{}: dt ({} s) must be shorter than lyapunov_time ({} s)", search_name, o.dt,
                      o.lyapunov_time));
  }
  if (o.max_candidates < 1)
    throw std::invalid_argument(
        fmt::format("{}: max_candidates must be >= 1, got {}", search_name, o.max_candidates));
  if (o.max_orbits < 0)
    throw std::invalid_argument(fmt::format("{}: max_orbits must be >= 0 (0: no limit), got {}",
                                            search_name, o.max_orbits));
}

// One phase of the search as the share [from, to] of the whole run's progress.
class phase_control final : public run_control {
 public:
  phase_control(run_control* parent, double from, double to)
      : m_parent(parent), m_from(from), m_to(to) {}
  void progress(double done, double total) override {
    if (m_parent != nullptr && total > 0)
      m_parent->progress(m_from + (m_to - m_from) * std::min(1.0, done / total), 1);
  }
  bool stop_requested() override { return npend::stop_requested(m_parent); }

 private:
  run_control* m_parent;
  double m_from, m_to;
};

// x with its angles (the first n entries on a fixed pivot) on the circle.
std::vector<double> wrapped_state(std::span<const double> x, int links) {
  std::vector<double> w(x.begin(), x.end());
  for (int i = 0; i < links; ++i)
    w[static_cast<std::size_t>(i)] = wrapped_angle(w[static_cast<std::size_t>(i)]);
  return w;
}

// Entry k of a − b, an angle's on the circle.
double difference(std::span<const double> a, std::span<const double> b, std::size_t k, int links) {
  const double d = a[k] - b[k];
  return k < static_cast<std::size_t>(links) ? wrapped_angle(d) : d;
}

// max_k |a_k − b_k| (angles on the circle).
double state_distance(std::span<const double> a, std::span<const double> b, int links) {
  double largest = 0;
  for (std::size_t k = 0; k < a.size(); ++k)
    largest = std::max(largest, std::fabs(difference(a, b, k, links)));
  return largest;
}

struct close_return {
  std::size_t i = 0, j = 0;  // crossings
  double distance = 0;
  std::vector<int> winding;  // whole turns of each angle from i to j
};

// The whole turns of each angle from unwrapped state a to b (dim n).
std::vector<int> turns(std::span<const double> a, std::span<const double> b, int links) {
  std::vector<int> w(static_cast<std::size_t>(links));
  for (std::size_t k = 0; k < w.size(); ++k)
    w[k] = static_cast<int>(std::lround((b[k] - a[k]) / (2 * std::numbers::pi)));
  return w;
}

bool rotates(const std::vector<int>& winding) {
  return std::any_of(winding.begin(), winding.end(), [](int w) { return w != 0; });
}

// An orbit's crossings of φ_1 = 0 in one period, both ways (angles on the circle).
struct orbit_trace {
  std::vector<std::vector<double>> up_unwrapped;  // the upward ones' states unwrapped
  std::vector<std::vector<double>> down;          // the downward ones
};

// The crossings of φ_1 = 0 in one period of the orbit, with the shooting's own
// Gauss–Legendre steps: a little over half a period forwards and as much backwards from x0,
// so that the errors grow over about T/2 only; a crossing that both runs see (T apart) counts
// once, and so does x0 itself when it lies exactly on the section (which neither run counts).
// The upward ones go to o.section_points, in time order.
orbit_trace trace_orbit(const chain& c, unstable_orbit& o, int steps) {
  const int n = c.links();
  const section_plane section = section_plane::coordinate(n, 0, 0.0);
  integration_options run;
  run.stepper = stepper_kind::gauss6;
  run.dt = o.period / steps;
  run.t_end = std::ceil(0.55 * steps) * run.dt;
  const poincare_options both{.direction = crossing_direction::both};
  const poincare_result ahead = poincare_section(c, o.x0, section, run, both);
  run.dt = -run.dt;
  run.t_end = -run.t_end;
  const poincare_result behind = poincare_section(c, o.x0, section, run, both);
  std::vector<double> f(static_cast<std::size_t>(c.state_size()));
  const auto upwards = [&](std::span<const double> x) {
    c.rhs(x, f);
    return f[0] > 0;
  };
  struct point {
    double t;
    const std::vector<double>* state;
    bool up;
  };
  std::vector<point> points;
  if (section.value(o.x0) == 0) points.push_back({0.0, &o.x0, upwards(o.x0)});
  const double edge = 1e-6 * o.period;
  for (const section_crossing& x : ahead.crossings)
    points.push_back({x.t, &x.state, upwards(x.state)});
  const std::size_t forward = points.size();
  for (const section_crossing& x : behind.crossings) {
    const bool up = upwards(x.state);
    if (std::none_of(
            points.begin(), points.begin() + static_cast<std::ptrdiff_t>(forward),
            [&](const point& y) { return y.up == up && std::fabs(y.t - x.t - o.period) <= edge; }))
      points.push_back({x.t, &x.state, up});
  }
  std::sort(points.begin(), points.end(), [](const point& a, const point& b) { return a.t < b.t; });
  o.section_points.clear();
  o.section_times.clear();
  orbit_trace trace;
  for (const point& x : points) {
    if (!x.up) {
      trace.down.push_back(wrapped_state(*x.state, n));
      continue;
    }
    o.section_times.push_back(x.t);
    o.section_points.push_back(wrapped_state(*x.state, n));
    trace.up_unwrapped.push_back(*x.state);
  }
  return trace;
}

// Whether the chain is symmetric under the mirror (φ, p) → (−φ, −p): V(−φ) = V(φ), which
// a spring with a rest angle breaks.
bool mirror_symmetric(const chain& c) {
  const chain_parameters& p = c.parameters();
  for (std::size_t j = 0; j < p.rest_angles.size(); ++j)
    if (p.rest_angles[j] != 0 && !p.stiffness.empty() && p.stiffness[j] != 0) return false;
  return true;
}

// The upward section points of an orbit's images under the chain's symmetries, the orbit's
// own first: time reversal R (φ, p, t) → (φ, −p, −t) turns the downward crossings into
// upward ones, R(x) = (φ, −p); with the mirror S (φ, p) → (−φ, −p) also S(down) and
// SR(up) = (−φ, p).
std::vector<std::vector<std::vector<double>>> symmetry_images(const unstable_orbit& o,
                                                              const orbit_trace& trace, int links,
                                                              bool mirror) {
  const auto map = [&](const std::vector<std::vector<double>>& points, double angle_sign,
                       double momentum_sign) {
    std::vector<std::vector<double>> mapped = points;
    for (auto& x : mapped)
      for (std::size_t k = 0; k < x.size(); ++k)
        x[k] = (k < static_cast<std::size_t>(links) ? angle_sign : momentum_sign) * x[k] + 0.0;
    return mapped;
  };
  std::vector<std::vector<std::vector<double>>> images{o.section_points, map(trace.down, 1, -1)};
  if (mirror) {
    images.push_back(map(trace.down, -1, -1));
    images.push_back(map(o.section_points, -1, 1));
  }
  return images;
}

int segments(const unstable_orbit_search_options& o, double period) {
  return std::max(o.shooting.segments, static_cast<int>(std::ceil(period / o.segment_time)));
}

// At least ⌈T / shooting_dt⌉ steps, a whole number per segment.
int shooting_steps(const unstable_orbit_search_options& o, double period) {
  const int m = segments(o, period);
  const int steps = std::max(o.shooting.steps, static_cast<int>(std::ceil(period / o.shooting_dt)));
  return (steps + m - 1) / m * m;
}

unstable_orbit to_orbit(const periodic_orbit_result& r) {
  unstable_orbit o;
  o.x0 = r.x0;
  o.period = r.period;
  o.energy = r.energy;
  o.closure = r.closure;
  o.iterations = r.iterations;
  o.multipliers = r.multipliers;
  o.max_multiplier = r.max_multiplier;
  o.lyapunov_rate = std::log(r.max_multiplier) / r.period;
  o.stable = r.stable;
  o.winding = r.winding;
  return o;
}

// Whether two sets of section points share a point (one orbit: its points are the same).
bool share_a_point(const std::vector<std::vector<double>>& a,
                   const std::vector<std::vector<double>>& b, double tolerance, int links) {
  for (const auto& p : a)
    for (const auto& q : b)
      if (state_distance(p, q, links) <= tolerance) return true;
  return false;
}

// A found orbit and the section points of its symmetry images (its own first).
struct known_orbit {
  std::vector<std::vector<std::vector<double>>> images;
};

// Whether orbit b is the known orbit a or one of its symmetry images.
bool same_orbit(const unstable_orbit& a, const known_orbit& images, const unstable_orbit& b,
                const unstable_orbit_search_options& options, int links) {
  if (std::fabs(a.period - b.period) > options.period_tolerance * std::max(a.period, b.period))
    return false;
  if (a.section_points.empty() || b.section_points.empty())
    return state_distance(a.x0, b.x0, links) <= options.same_orbit_tolerance;
  return std::any_of(images.images.begin(), images.images.end(), [&](const auto& image) {
    return share_a_point(image, b.section_points, options.same_orbit_tolerance, links);
  });
}

// How many of the images are distinct orbits.
int distinct_images(const known_orbit& k, double tolerance, int links) {
  int distinct = 0;
  for (std::size_t i = 0; i < k.images.size(); ++i) {
    bool seen = false;
    for (std::size_t j = 0; j < i && !seen; ++j)
      seen = share_a_point(k.images[i], k.images[j], tolerance, links);
    distinct += seen ? 0 : 1;
  }
  return std::max(1, distinct);
}

// The close returns of the crossings, without those that shadow a shorter return from the
// same crossing repeatedly, by the number of crossings between their ends, then by distance;
// those along which an arm turned over are counted in `rotating`.
std::vector<close_return> close_returns(const std::vector<section_crossing>& crossings,
                                        const unstable_orbit_search_options& options, int links,
                                        std::size_t& rotating) {
  const std::size_t count = crossings.size(), d = 2 * static_cast<std::size_t>(links);
  std::vector<std::vector<double>> wrapped;
  wrapped.reserve(count);
  for (const section_crossing& x : crossings) wrapped.push_back(wrapped_state(x.state, links));
  // Each coordinate's range over the crossings (φ_1 is 0 on the section: left out; a
  // coordinate that does not vary counts as equal).
  std::vector<double> range(d, 0.0);
  for (std::size_t k = 1; k < d; ++k) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const auto& w : wrapped) {
      lo = std::min(lo, w[k]);
      hi = std::max(hi, w[k]);
    }
    // A coordinate the same at every crossing (to rounding) tells no returns apart.
    range[k] =
        count > 0 && hi - lo > 1e-9 * std::max({1.0, std::fabs(lo), std::fabs(hi)}) ? hi - lo : 0.0;
  }
  std::vector<close_return> found;
  for (std::size_t i = 0; i < count; ++i) {
    std::vector<std::size_t> lags;  // of the returns from i kept so far
    for (std::size_t j = i + 1; j < count; ++j) {
      const double span = crossings[j].t - crossings[i].t;
      if (span > options.period_max) break;
      if (span < options.period_min) continue;
      double distance = 0;
      for (std::size_t k = 1; k < d; ++k) {
        const double delta = std::fabs(difference(wrapped[j], wrapped[i], k, links));
        distance = std::max(distance, range[k] > 0 ? delta / range[k] : 0.0);
      }
      if (distance > options.return_tolerance) continue;
      const std::size_t lag = j - i;
      if (std::any_of(lags.begin(), lags.end(), [&](std::size_t l) { return lag % l == 0; }))
        continue;
      lags.push_back(lag);
      found.push_back({i, j, distance, turns(crossings[i].state, crossings[j].state, links)});
      if (rotates(found.back().winding)) ++rotating;
    }
  }
  std::sort(found.begin(), found.end(), [](const close_return& a, const close_return& b) {
    return a.j - a.i != b.j - b.i ? a.j - a.i < b.j - b.i : a.distance < b.distance;
  });
  return found;
}

}  // namespace

unstable_orbit_search_result find_unstable_orbits(const chain& c, std::span<const double> start,
                                                  const unstable_orbit_search_options& options) {
  validate(c, start, options);
  const int n = c.links();
  unstable_orbit_search_result result;
  result.energy = c.hamiltonian(start);
  const double shooting_share = options.lyapunov ? 0.5 : 0.3;

  // The chaotic trajectory and its crossings.
  phase_control search_control(options.control, 0, 0.3);
  integration_options run;
  run.stepper = stepper_kind::gauss6;
  run.t_end = options.search_time;
  run.dt = options.dt;
  run.control = &search_control;
  const poincare_result trajectory =
      poincare_section(c, start, section_plane::coordinate(n, 0, 0.0), run, {});
  result.crossings = trajectory.crossings.size();
  if (trajectory.integration.stopped) {
    result.stopped = true;
    return result;
  }

  if (options.lyapunov) {
    phase_control lyapunov_control(options.control, 0.3, 0.5);
    lyapunov_options lyapunov;
    lyapunov.integration = run;
    lyapunov.integration.t_end =
        std::isnan(options.lyapunov_time) ? options.search_time : options.lyapunov_time;
    lyapunov.integration.control = &lyapunov_control;
    const lyapunov_result l = maximal_lyapunov_exponent(c, start, lyapunov);
    if (l.stopped) {
      result.stopped = true;
      return result;
    }
    result.lyapunov_exponent = l.exponents.front();
    result.lyapunov_time = l.t;
  }

  const std::vector<close_return> returns =
      close_returns(trajectory.crossings, options, n, result.rotating);
  result.candidates = returns.size();
  const double planned = static_cast<double>(
      std::min(returns.size(), static_cast<std::size_t>(options.max_candidates)));
  phase_control shooting_control(options.control, shooting_share, 1);
  std::vector<close_return> shadowed;  // the stretches of the converged candidates
  const auto shoot = [&](std::span<const double> guess, double period,
                         const std::vector<int>& winding) {
    periodic_orbit_options o = options.shooting;
    o.phase = orbit_phase::poincare;
    o.energy = result.energy;
    o.winding = winding;
    o.segments = segments(options, period);
    o.steps = shooting_steps(options, period);
    o.control = &shooting_control;
    return periodic_orbit(c, guess, period, o);
  };
  const bool mirror = mirror_symmetric(c);
  std::vector<known_orbit> known;  // parallel to result.orbits
  for (const close_return& r : returns) {
    if (result.tried == static_cast<std::size_t>(options.max_candidates)) break;
    if (options.max_orbits > 0 &&
        result.orbits.size() >= static_cast<std::size_t>(options.max_orbits))
      break;
    if (stop_requested(options.control)) {
      result.stopped = true;
      break;
    }
    // The trajectory shadows an orbit found on a stretch that overlaps this one.
    if (std::any_of(shadowed.begin(), shadowed.end(), [&](const close_return& s) {
          return s.j - s.i == r.j - r.i && r.i < s.j && s.i < r.j;
        }))
      continue;
    shooting_control.progress(static_cast<double>(result.tried), planned);
    ++result.tried;
    const std::vector<double> guess = wrapped_state(trajectory.crossings[r.i].state, n);
    periodic_orbit_result shot =
        shoot(guess, trajectory.crossings[r.j].t - trajectory.crossings[r.i].t, r.winding);
    if (shot.stopped) {
      result.stopped = true;
      break;
    }
    if (!shot.converged) continue;
    ++result.converged;
    shadowed.push_back(r);
    unstable_orbit orbit = to_orbit(shot);
    orbit_trace trace = trace_orbit(c, orbit, shooting_steps(options, orbit.period));
    // A section point that recurs within the period: the orbit is a shorter one repeated.
    for (std::size_t m = 1; m < orbit.section_points.size(); ++m) {
      if (state_distance(orbit.section_points[m], orbit.section_points[0], n) >
          options.same_orbit_tolerance)
        continue;
      ++result.repeats;
      shot = shoot(orbit.section_points[0], orbit.section_times[m] - orbit.section_times[0],
                   turns(trace.up_unwrapped[0], trace.up_unwrapped[m], n));
      if (shot.stopped) result.stopped = true;
      if (shot.converged) {
        orbit = to_orbit(shot);
        trace = trace_orbit(c, orbit, shooting_steps(options, orbit.period));
      } else {
        orbit.period = 0;  // not kept
      }
      break;
    }
    if (result.stopped) break;
    if (!(orbit.period > 0)) continue;
    if (orbit.period < options.period_min * (1 - options.period_tolerance) ||
        orbit.period > options.period_max * (1 + options.period_tolerance)) {
      ++result.out_of_range;
      continue;
    }
    bool found_before = false;
    for (std::size_t k = 0; k < known.size() && !found_before; ++k)
      found_before = same_orbit(result.orbits[k], known[k], orbit, options, n);
    if (found_before) {
      ++result.duplicates;
      continue;
    }
    known.push_back({symmetry_images(orbit, trace, n, mirror)});
    orbit.copies = distinct_images(known.back(), options.same_orbit_tolerance, n);
    result.orbits.push_back(std::move(orbit));
  }
  std::sort(result.orbits.begin(), result.orbits.end(),
            [](const unstable_orbit& a, const unstable_orbit& b) { return a.period < b.period; });
  return result;
}

}  // namespace npend
