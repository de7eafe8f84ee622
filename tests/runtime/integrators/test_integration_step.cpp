// The step observer of npend::integrate: the steps it sees cover the run without gaps, come
// before the grid points they reach, can stop the run, and interpolate the solution
// (integration_step::state_at) — the dense output the Poincaré sections are located on.
#include <doctest/doctest.h>

#include <cmath>
#include <stdexcept>

#include "npend/integrators/integrate.hpp"
#include "reference/reference_trajectory.hpp"
#include "support/test_support.hpp"

using npend::chain;
using npend::integration_options;
using npend::integration_step;
using npend::observer_action;
using npend::stepper_kind;

namespace {

const std::vector<double> strong_start{0.9, -0.6, 1.2, 0.0, 0.0, 0.0};

integration_options options_for(stepper_kind k, double t_end, double dt) {
  integration_options o;
  o.stepper = k;
  o.t_end = t_end;
  o.dt = dt;
  o.abs_tol = o.rel_tol = 1e-12;
  return o;
}

// The exact flow over `duration` from x (the tight-tolerance reference).
std::vector<double> flow(const npend::chain_parameters& p, std::span<const double> x,
                         double duration) {
  return npend::reference::reference_trajectory(npend::reference::dense_chain_of(p),
                                                {x.begin(), x.end()}, {duration})
      .front();
}

}  // namespace

TEST_CASE("integrate: the step observer sees consecutive steps, each before its grid points") {
  const chain c(npend::chain_parameters::uniform(3));
  for (stepper_kind k : npend::all_stepper_kinds())
    for (const double dt : {0.01, -0.01}) {
      integration_options o = options_for(k, dt > 0 ? 1.0 : -1.0, dt);
      std::size_t steps = 0, grid_points = 0;
      double last_end = 0;
      std::vector<double> last_state = strong_start;
      bool contiguous = true, ordered = true;
      const auto r = npend::integrate(
          c, strong_start, o,
          [&](double t, std::span<const double>) {
            // Every grid point after the start lies within a step already seen.
            if (grid_points++ > 0) ordered = ordered && dt * (last_end - t) >= -1e-12;
            return observer_action::proceed;
          },
          [&](const integration_step& s) {
            ++steps;
            contiguous = contiguous && s.t_begin() == last_end &&
                         std::equal(last_state.begin(), last_state.end(), s.x_begin().begin()) &&
                         dt * (s.t_end() - s.t_begin()) > 0;
            last_end = s.t_end();
            last_state.assign(s.x_end().begin(), s.x_end().end());
            return observer_action::proceed;
          });
      INFO(npend::stepper_name(k), ", dt = ", dt);
      CHECK(contiguous);
      CHECK(ordered);
      CHECK(steps == r.steps);
      // The dense-output steppers step past the last grid point and interpolate back to it.
      const bool dense = k == stepper_kind::dopri5 || k == stepper_kind::bulirsch_stoer ||
                         k == stepper_kind::rosenbrock4 || k == stepper_kind::taylor;
      if (dense) {
        CHECK(dt * (last_end - o.t_end) >= 0);
      } else {
        CHECK(last_end == doctest::Approx(o.t_end).epsilon(1e-12));
        CHECK(last_state == r.state);
      }
      if (!npend::is_adaptive(k)) CHECK(steps == 100);
    }
}

TEST_CASE("integrate: a step observer can stop the run at the end of a step") {
  const chain c(npend::chain_parameters::uniform(2));
  const std::vector<double> x0{0.3, -0.2, 0.1, 0.0};
  for (stepper_kind k : npend::all_stepper_kinds()) {
    const integration_options o = options_for(k, 10, 0.01);
    std::vector<double> seen;
    double end = 0;
    const auto r = npend::integrate(c, x0, o, {}, [&](const integration_step& s) {
      end = s.t_end();
      seen.assign(s.x_end().begin(), s.x_end().end());
      return s.t_end() >= 0.5 ? observer_action::stop : observer_action::proceed;
    });
    INFO(npend::stepper_name(k));
    CHECK(r.stopped);
    CHECK(r.t == end);
    CHECK(r.t >= 0.5);
    CHECK(r.t < 1.0);
    CHECK(r.state == seen);
  }
}

TEST_CASE("integration_step: state_at meets the step's ends and the exact flow in between") {
  const npend::chain_parameters p = npend::chain_parameters::uniform(3);
  const chain c(p);
  for (stepper_kind k : npend::all_stepper_kinds()) {
    const integration_options o = options_for(k, 1.0, 1e-3);
    double end_error = 0, inner_error = 0;
    std::size_t step = 0;
    std::vector<double> x(6);
    npend::integrate(c, strong_start, o, {}, [&](const integration_step& s) {
      s.state_at(s.t_begin(), x);
      end_error = std::max(end_error, npend::test::relative_error(x, s.x_begin()));
      s.state_at(s.t_end(), x);
      end_error = std::max(end_error, npend::test::relative_error(x, s.x_end()));
      // Every 7th step: a third and two thirds into it, against the exact flow from its start.
      if (step++ % 7 == 0)
        for (const double theta : {1.0 / 3, 2.0 / 3}) {
          const double h = s.t_end() - s.t_begin();
          s.state_at(s.t_begin() + theta * h, x);
          inner_error = std::max(inner_error,
                                 npend::test::relative_error(x, flow(p, s.x_begin(), theta * h)));
        }
      return observer_action::proceed;
    });
    INFO(npend::stepper_name(k), ": ends ", end_error, ", inside ", inner_error);
    CHECK(end_error < 1e-14);
    // The interpolation error (plus the step's own local error): for the cubic Hermite
    // interpolant h⁴/384·|x⁗| ≈ 5e-10 at the most violent moments of this chaotic run
    // (|x⁗| ~ 1e5 there); the dense-output steppers' own formulas at tolerance 1e-12 do better.
    CHECK(inner_error < 1e-9);
  }
}

TEST_CASE(
    "integration_step: the Hermite interpolant of the fixed-step steppers is O(h^4) or better") {
  const npend::chain_parameters p = npend::chain_parameters::uniform(3);
  const chain c(p);
  // A start in motion (from rest, φ(t) is even in t and p(t) odd, which hides terms).
  const std::vector<double> x0{0.9, -0.6, 1.2, 0.5, -0.3, 0.8};
  for (stepper_kind k : {stepper_kind::rk4, stepper_kind::gauss4, stepper_kind::gauss6}) {
    // The error in the middle of the first step, against the exact flow, for h and h/2.
    std::vector<double> errors;
    for (const double h : {0.01, 0.005}) {
      std::vector<double> x(6);
      npend::integrate(c, x0, options_for(k, 4 * h, h), {}, [&](const integration_step& s) {
        s.state_at(0.5 * h, x);
        return observer_action::stop;
      });
      errors.push_back(npend::test::relative_error(x, flow(p, x0, 0.5 * h)));
    }
    INFO(npend::stepper_name(k), ": errors ", errors[0], ", ", errors[1]);
    // Halving h divides the error by 2⁴ = 16 or more (a linear interpolant: by 4; the h⁵
    // terms — rk4's and gauss4's local errors, the next Hermite term — still show here).
    CHECK(errors[0] / errors[1] > 12);
  }
}

TEST_CASE("integration_step: state_at refuses times outside the step and wrong sizes") {
  const chain c(npend::chain_parameters::uniform(3));
  int checked = 0;
  npend::integrate(c, strong_start, options_for(stepper_kind::gauss6, 0.1, 0.01), {},
                   [&](const integration_step& s) {
                     std::vector<double> x(6), short_x(5);
                     CHECK_THROWS_AS(s.state_at(s.t_end() + 1e-3, x), std::invalid_argument);
                     CHECK_THROWS_AS(s.state_at(s.t_begin() - 1e-3, x), std::invalid_argument);
                     CHECK_THROWS_AS(s.state_at(s.t_begin(), short_x), std::invalid_argument);
                     CHECK_NOTHROW(s.state_at(s.t_begin(), x));
                     ++checked;
                     return observer_action::stop;
                   });
  CHECK(checked == 1);
}
