#include "npend/analysis/chaos/poincare_section.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <boost/numeric/odeint/integrate/integrate_adaptive.hpp>
#include <boost/numeric/odeint/stepper/generation.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta_fehlberg78.hpp>
#include <cmath>
#include <functional>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <utility>

#include "npend/analysis/motion/energy_drift.hpp"

namespace npend {

namespace {

// Tolerances of the Hénon step: far below the integrators' own errors, above rounding.
constexpr double henon_tolerance = 1e-14;
// A Hénon result further than this fraction of the step from the dense-output estimate
// has passed a point where w·f vanished: it is not the crossing.
constexpr double henon_agreement = 1e-3;

double dot(std::span<const double> a, std::span<const double> b) {
  double sum = 0;
  for (std::size_t i = 0; i < a.size(); ++i) sum += a[i] * b[i];
  return sum;
}

// The chain's flow with g = w·x − c as the independent variable: y = (x, t) (dim 2n + 1),
// dy/dg = (f(x), 1) / (w·f(x)). odeint copies systems, so the work vector is shared.
class henon_system {
 public:
  henon_system(const chain& c, const section_plane& s)
      : m_chain(&c),
        m_normal(&s.normal),
        m_f(std::make_shared<std::vector<double>>(s.normal.size())) {}

  void operator()(const std::vector<double>& y, std::vector<double>& dyds, double /*g*/) const {
    const std::size_t d = m_f->size();
    m_chain->rhs(std::span<const double>(y.data(), d), *m_f, y[d]);
    const double rate = dot(*m_normal, *m_f);
    for (std::size_t i = 0; i < d; ++i) dyds[i] = (*m_f)[i] / rate;
    dyds[d] = 1 / rate;
  }

 private:
  const chain* m_chain;
  const std::vector<double>* m_normal;
  std::shared_ptr<std::vector<double>> m_f;
};

}  // namespace

double section_plane::value(std::span<const double> x) const {
  const double g = dot(normal, x) - level;
  return circular ? wrapped_angle(g) : g;
}

section_plane section_plane::coordinate(int links, std::size_t index, double level) {
  if (links < 1)
    throw std::invalid_argument(fmt::format("section_plane: links must be >= 1, got {}", links));
  const auto size = static_cast<std::size_t>(2 * links);
  if (index >= size)
    throw std::invalid_argument(fmt::format(
        "section_plane: coordinate index {} is out of range 0..{} (the state has 2n = {} entries)",
        index, size - 1, size));
  if (!std::isfinite(level))
    throw std::invalid_argument(fmt::format("section_plane: level {} is not finite", level));
  section_plane s;
  s.normal.assign(size, 0.0);
  s.normal[index] = 1;
  s.level = level;
  s.circular = index < static_cast<std::size_t>(links);
  return s;
}

section_plane section_plane::equal_coordinates(int links, std::size_t first, std::size_t second) {
  section_plane s = coordinate(links, first, 0.0);
  if (second >= s.normal.size())
    throw std::invalid_argument(fmt::format(
        "section_plane: coordinate index {} is out of range 0..{}", second, s.normal.size() - 1));
  if (first == second)
    throw std::invalid_argument(
        fmt::format("section_plane: coordinate {} compared with itself", first));
  s.normal[second] = -1;
  s.circular = s.circular && second < static_cast<std::size_t>(links);
  return s;
}

double section_plane::branch_level(std::span<const double> a, std::span<const double> b) const {
  if (!circular) return level;
  constexpr double turn = 2 * std::numbers::pi;
  const double ua = dot(normal, a) - level, ub = dot(normal, b) - level;
  // The multiples of 2π in (ua, ub] going up, or [ub, ua) going down: the nearest to ua.
  const double j = ub >= ua ? std::floor(ua / turn) + 1 : std::ceil(ua / turn) - 1;
  const bool crossed = ub >= ua ? j * turn <= ub : j * turn >= ub;
  // A start exactly on a branch is no crossing of it (as for a plane), so ua = 2πj is
  // excluded above; the branch a step ends on is included.
  return crossed ? level + j * turn : level;
}

void section_plane::validate(std::size_t state_size) const {
  if (normal.size() != state_size)
    throw std::invalid_argument(
        fmt::format("section normal has {} entries; the state has {}", normal.size(), state_size));
  bool nonzero = false;
  for (std::size_t i = 0; i < normal.size(); ++i) {
    if (!std::isfinite(normal[i]))
      throw std::invalid_argument(
          fmt::format("section normal entry {} is {}: it must be finite", i + 1, normal[i]));
    nonzero = nonzero || normal[i] != 0;
  }
  if (!nonzero) throw std::invalid_argument("section normal is all 0: it defines no hyperplane");
  if (circular)
    for (std::size_t i = 0; i < normal.size(); ++i)
      if (i >= normal.size() / 2 ? normal[i] != 0 : normal[i] != std::round(normal[i]))
        throw std::invalid_argument(fmt::format(
            "circular section: normal entry {} is {}; a section of angles on the circle needs "
            "integer entries on the angles and 0 on the momenta",
            i + 1, normal[i]));
  if (!std::isfinite(level))
    throw std::invalid_argument(fmt::format("section level {} is not finite", level));
}

crossing_locator::crossing_locator(const chain& c, section_plane section,
                                   crossing_direction direction, std::size_t max_crossings)
    : m_chain(&c),
      m_section(std::move(section)),
      m_direction(direction),
      m_max_crossings(max_crossings) {
  m_section.validate(static_cast<std::size_t>(c.state_size()));
  m_buffer.resize(m_section.normal.size());
  m_f.resize(m_section.normal.size());
}

observer_action crossing_locator::operator()(const integration_step& step) {
  // On the circle, the plane of this step is the branch w·x = c + 2πj it may cross.
  const double level = m_section.branch_level(step.x_begin(), step.x_end());
  const auto value = [&](std::span<const double> x) { return dot(m_section.normal, x) - level; };
  const double g0 = value(step.x_begin()), g1 = value(step.x_end());
  const bool up = g0 < 0 && g1 >= 0, down = g0 > 0 && g1 <= 0;
  if (!((up && m_direction != crossing_direction::down) ||
        (down && m_direction != crossing_direction::up)))
    return observer_action::proceed;

  section_crossing crossing;
  if (g1 == 0) {
    // The step ends on the section: its end state is the crossing.
    crossing.t = step.t_end();
    crossing.state.assign(step.x_end().begin(), step.x_end().end());
  } else {
    // 1. The root of g on the dense output, by regula falsi in its Illinois form (the
    //    retained end's value is halved when the same end is kept twice in a row).
    double a = step.t_begin(), ga = g0, b = step.t_end(), gb = g1;
    double t = b;
    int kept = 0;
    const double width = std::fabs(b - a);
    for (int iteration = 0; iteration < 100; ++iteration) {
      t = (a * gb - b * ga) / (gb - ga);
      if (!(t > std::min(a, b) && t < std::max(a, b))) t = 0.5 * (a + b);
      step.state_at(t, m_buffer);
      const double g = value(m_buffer);
      if (g == 0 || std::fabs(b - a) <= 1e-14 * width) break;
      if ((g < 0) == (gb < 0)) {
        b = t;
        gb = g;
        if (kept == -1) ga /= 2;
        kept = -1;
      } else {
        a = t;
        ga = g;
        if (kept == 1) gb /= 2;
        kept = 1;
      }
    }
    crossing.t = t;
    crossing.state = m_buffer;
    // 2. Hénon's trick from the nearer end of the step.
    crossing.refined = polish(step, g0, g1, crossing);
  }
  m_crossings.push_back(std::move(crossing));
  return m_max_crossings != 0 && m_crossings.size() >= m_max_crossings ? observer_action::stop
                                                                       : observer_action::proceed;
}

bool crossing_locator::polish(const integration_step& step, double g_begin, double g_end,
                              section_crossing& crossing) {
  namespace odeint = boost::numeric::odeint;
  // The sign of dg/dt at the crossing: g grows along the step at an up crossing, and the step
  // runs backwards in time when the integration does.
  const double sign = (g_begin < 0 ? 1.0 : -1.0) * (step.t_end() > step.t_begin() ? 1.0 : -1.0);
  const auto rate = [&](std::span<const double> x, double t) {
    m_chain->rhs(x, m_f, t);
    return dot(m_section.normal, m_f);
  };
  // Hénon's system needs w·f of the crossing's sign from the start end to the crossing.
  if (!(sign * rate(crossing.state, crossing.t) > 0)) return false;
  struct end {
    std::span<const double> x;
    double t, g;
  };
  std::array<end, 2> ends{end{step.x_begin(), step.t_begin(), g_begin},
                          end{step.x_end(), step.t_end(), g_end}};
  if (std::fabs(g_end) < std::fabs(g_begin)) std::swap(ends[0], ends[1]);
  const double h = std::fabs(step.t_end() - step.t_begin());
  const std::size_t d = m_buffer.size();
  for (const end& e : ends) {
    if (!(sign * rate(e.x, e.t) > 0)) continue;
    std::vector<double> y(e.x.begin(), e.x.end());
    y.push_back(e.t);
    try {
      odeint::integrate_adaptive(
          odeint::make_controlled(henon_tolerance, henon_tolerance,
                                  odeint::runge_kutta_fehlberg78<std::vector<double>>()),
          henon_system(*m_chain, m_section), y, e.g, 0.0, -e.g);
    } catch (const std::exception&) {
      continue;  // odeint gave up on the step size: w·f vanished on the way
    }
    if (!std::all_of(y.begin(), y.end(), [](double v) { return std::isfinite(v); })) continue;
    const double t = y[d];
    double deviation = 0, scale = 1;
    for (std::size_t i = 0; i < d; ++i) {
      deviation = std::max(deviation, std::fabs(y[i] - crossing.state[i]));
      scale = std::max(scale, std::fabs(y[i]));
    }
    if (std::fabs(t - crossing.t) > henon_agreement * h || deviation > henon_agreement * scale)
      continue;
    crossing.t = t;
    crossing.state.assign(y.begin(), y.begin() + static_cast<std::ptrdiff_t>(d));
    return true;
  }
  return false;
}

poincare_result poincare_section(const chain& c, std::span<const double> x0,
                                 const section_plane& section,
                                 const integration_options& integration,
                                 const poincare_options& options) {
  crossing_locator locator(c, section, options.direction, options.max_crossings);
  poincare_result result;
  result.integration = integrate(c, x0, integration, {}, std::ref(locator));
  result.crossings = locator.crossings();
  return result;
}

std::vector<double> crossing_times(std::span<const section_crossing> crossings) {
  std::vector<double> times;
  times.reserve(crossings.size());
  for (const auto& c : crossings) times.push_back(c.t);
  return times;
}

section_quality crossing_quality(const chain& c, const section_plane& section,
                                 std::span<const section_crossing> crossings, double h0) {
  section_quality q;
  energy_drift energy(c, h0);
  for (const auto& x : crossings) {
    q.max_residual = std::max(q.max_residual, std::fabs(section.value(x.state)));
    energy.add(x.state);
    q.unrefined += x.refined ? 0 : 1;
  }
  q.max_rel_energy_error = energy.max_relative_error();
  return q;
}

}  // namespace npend
