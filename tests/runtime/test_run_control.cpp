// integrate_with (any odeint stepper by its category) against the stepper_kind factory, and
// the run control every long computation accepts: progress that reaches its total, and a
// stop request that ends the computation early with what it has, flagged.
#include <doctest/doctest.h>

#include <boost/numeric/odeint/stepper/generation.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta4.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta_cash_karp54.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta_dopri5.hpp>
#include <cmath>
#include <vector>

#include "npend/analysis/chaos/lyapunov.hpp"
#include "npend/analysis/chaos/poincare_section.hpp"
#include "npend/analysis/stability/backbone.hpp"
#include "npend/chain_system.hpp"
#include "npend/integrators/integrate.hpp"
#include "npend/integrators/integrate_system.hpp"
#include "support/test_support.hpp"

using npend::chain;
using npend::integration_options;
using npend::stepper_kind;

using npend::test::max_difference;

namespace {

namespace odeint = boost::numeric::odeint;
using state = std::vector<double>;

// Records every progress report, and asks to stop once `stop_after` reports were seen.
struct recording_control final : npend::run_control {
  std::vector<double> done, total;
  std::size_t stop_after = static_cast<std::size_t>(-1);
  void progress(double d, double t) override {
    done.push_back(d);
    total.push_back(t);
  }
  bool stop_requested() override { return done.size() >= stop_after; }
};

const chain triple(npend::chain_parameters::uniform(3));
const std::vector<double> start{0.9, -0.4, 0.3, 0.2, 0.0, -0.1};

integration_options grid(double t_end, double dt) {
  integration_options o;
  o.t_end = t_end;
  o.dt = dt;
  return o;
}

}  // namespace

TEST_CASE("integrate_with: the factory's steppers give the factory's results, bit for bit") {
  const auto system = npend::make_implicit_system(triple);
  integration_options o = grid(2, 0.01);

  o.stepper = stepper_kind::rk4;
  odeint::runge_kutta4<state> rk4;
  CHECK(npend::integrate_with(rk4, system.first, start, o).state ==
        npend::integrate(triple, start, o).state);

  o.stepper = stepper_kind::gauss6;
  npend::gauss_legendre6 gauss;
  CHECK(npend::integrate_with(gauss, system, start, o).state ==
        npend::integrate(triple, start, o).state);

  o.stepper = stepper_kind::dopri5;
  auto dopri = odeint::make_dense_output(o.abs_tol, o.rel_tol, odeint::runge_kutta_dopri5<state>());
  CHECK(npend::integrate_with(dopri, system.first, start, o).state ==
        npend::integrate(triple, start, o).state);
}

TEST_CASE("integrate_with: an odeint stepper npend does not name (Cash-Karp, controlled)") {
  const auto system = npend::make_implicit_system(triple);
  integration_options o = grid(2, 0.01);
  auto cash_karp = odeint::make_controlled(1e-12, 1e-12, odeint::runge_kutta_cash_karp54<state>());
  const npend::integration_result r = npend::integrate_with(cash_karp, system.first, start, o);
  CHECK(r.outputs == 201);
  CHECK(r.steps > 0);
  // Against the order-6 symplectic reference at a step where its error is ~1e-13.
  o.dt = 0.001;
  CHECK(max_difference(r.state, npend::integrate(triple, start, o).state) < 1e-9);
  // Energy, the conservation law the stepper knows nothing of.
  CHECK(std::fabs(triple.hamiltonian(r.state) - triple.hamiltonian(start)) < 1e-10);
}

TEST_CASE("integrate_with: a non-finite state names the supplied stepper") {
  const auto system = npend::make_implicit_system(triple);
  odeint::runge_kutta4<state> rk4;
  const std::vector<double> violent{1, 1, 1, 1e300, 1, 1};
  CHECK_THROWS_WITH_AS(npend::integrate_with(rk4, system.first, violent, grid(1, 0.01)),
                       doctest::Contains("supplied stepper's step"), npend::integration_error);
}

TEST_CASE("run control: integrate reports every grid point and stops when asked") {
  recording_control control;
  integration_options o = grid(1, 0.01);
  o.control = &control;
  const auto whole = npend::integrate(triple, start, o);
  CHECK_FALSE(whole.stopped);
  REQUIRE(control.done.size() == 101);
  CHECK(control.done.front() == 0);
  CHECK(control.done.back() == control.total.back());

  recording_control stopping;
  stopping.stop_after = 31;
  o.control = &stopping;
  const auto cut = npend::integrate(triple, start, o);
  CHECK(cut.stopped);
  CHECK(cut.t == doctest::Approx(0.3));
  CHECK(cut.outputs == 31);
}

TEST_CASE("run control: a Lyapunov spectrum and an ensemble report progress and stop") {
  npend::lyapunov_options o;
  o.integration = grid(20, 0.01);
  o.renormalisation_interval = 0.1;
  recording_control control;
  o.integration.control = &control;
  const auto whole = npend::lyapunov_spectrum(triple, start, o);
  CHECK_FALSE(whole.stopped);
  REQUIRE_FALSE(control.done.empty());
  CHECK(control.done.back() == control.total.back());
  // One report per re-orthonormalisation, not one per step of the inner integrations.
  CHECK(control.done.size() == 200);

  for (stepper_kind kind : {stepper_kind::gauss6, stepper_kind::dopri5}) {
    CAPTURE(npend::stepper_name(kind));
    recording_control stopping;
    stopping.stop_after = 50;
    o.integration.stepper = kind;
    o.integration.control = &stopping;
    const auto cut = npend::lyapunov_spectrum(triple, start, o);
    CHECK(cut.stopped);
    CHECK(cut.t == doctest::Approx(5.0));
  }

  recording_control ensemble_control;
  o.integration.stepper = stepper_kind::gauss6;
  o.integration.control = &ensemble_control;
  npend::lyapunov_ensemble_options e;
  e.members = 3;
  e.maximal = true;
  const auto ensemble = npend::lyapunov_ensemble(triple, start, o, e);
  CHECK_FALSE(ensemble.stopped);
  // The members are consecutive thirds of one progress from 0 to 3.
  CHECK(ensemble_control.total.front() == 3);
  CHECK(ensemble_control.done.back() == doctest::Approx(3));
  for (std::size_t i = 1; i < ensemble_control.done.size(); ++i)
    CHECK(ensemble_control.done[i] >= ensemble_control.done[i - 1]);
}

TEST_CASE("run control: a backbone curve stops between amplitudes") {
  recording_control control;
  control.stop_after = 1;  // the first grid point of the first amplitude
  npend::backbone_options o;
  o.control = &control;
  const std::vector<double> amplitudes{0.1, 0.2, 0.3};
  const auto r =
      npend::backbone_curve(chain(npend::chain_parameters::uniform(2)), 1, amplitudes, o);
  CHECK(r.stopped);
  CHECK(r.points.size() == 1);
  CHECK(r.thresholds.empty());
}

TEST_CASE("run control: a Poincare section is cut short with the crossings found so far") {
  integration_options o = grid(50, 0.01);
  recording_control control;
  control.stop_after = 1001;
  o.control = &control;
  const auto cut =
      npend::poincare_section(triple, start, npend::section_plane::coordinate(3, 0, 0.0), o);
  CHECK(cut.integration.stopped);
  CHECK(cut.integration.t == doctest::Approx(10.0));
}
