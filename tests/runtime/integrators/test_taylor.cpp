// The taylor stepper on the generated Taylor kernels: the coefficients against the single
// pendulum's by hand, the double run against the long double run of the same recurrences
// and against the Gauss–Legendre integrator, energy conservation, the physical chain with a
// driven pivot, the cart, and the refusals.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "npend/chain.hpp"
#include "npend/integrators/integrate.hpp"
#include "npend/integrators/integrate_system.hpp"
#include "npend/integrators/taylor.hpp"

using npend::chain;
using npend::integration_options;
using npend::stepper_kind;

namespace taylor_test {

// The end state of a long double Taylor run from x0 over [0, t_end], its last step cut to
// end on t_end.
std::vector<long double> long_double_run(const chain& c, const std::vector<double>& x0,
                                         double t_end, double tol, int order = 0) {
  npend::taylor_integrator<long double> integrator(c.kernels_in_use(), tol, tol, order);
  std::vector<long double> x(x0.begin(), x0.end());
  integrator.reset(0, x.data());
  const long double end = t_end;
  while (integrator.time() < end) integrator.step(1, end - integrator.time(), 0.1L);
  return integrator.state();
}

integration_options taylor_options(double t_end, double tol, double dt = 0) {
  integration_options o;
  o.stepper = stepper_kind::taylor;
  o.t_end = t_end;
  o.dt = dt > 0 ? dt : t_end;
  o.abs_tol = o.rel_tol = tol;
  return o;
}

double largest_difference(const std::vector<double>& a, const std::vector<long double>& b) {
  double worst = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
    worst = std::max(worst, static_cast<double>(std::fabs(a[i] - b[i])));
  return worst;
}

}  // namespace taylor_test

using namespace taylor_test;

TEST_CASE("taylor kernels: the single pendulum's coefficients as derived by hand, order 4") {
  // φ' = p/(m l²), p' = −m g l sin φ; with s = sin φ0, c = cos φ0 the coefficients of
  // φ(t0 + τ) and p(t0 + τ) follow from (sin φ)'' = c φ'' − s φ'² term by term.
  npend::chain_parameters p = npend::chain_parameters::uniform(1, 1.3, 0.8, 9.81);
  const chain ch(p);
  const double m = 1.3, l = 0.8, g = 9.81, phi = 0.9, mom = -0.7;
  const double s = std::sin(phi), co = std::cos(phi), inertia = m * l * l, mgl = m * g * l;
  const double phi1 = mom / inertia, p1 = -mgl * s;
  const double phi2 = p1 / (2 * inertia), p2 = -mgl * co * phi1 / 2;
  const double phi3 = p2 / (3 * inertia), p3 = -mgl * (co * 2 * phi2 - s * phi1 * phi1) / 6;
  const double phi4 = p3 / (4 * inertia);
  const npend::taylor_kernels* k = ch.kernels_in_use().taylor();
  REQUIRE(k != nullptr);
  const int order = 4, stride = order + 1;
  std::vector<double> series(2 * stride, 0.0),
      work(static_cast<std::size_t>(k->work_slots * stride));
  series[0] = phi;
  series[stride] = mom;
  k->coefficients(ch.kernels_in_use().packed().data(), nullptr, order, series.data(), work.data());
  const double want_phi[] = {phi, phi1, phi2, phi3, phi4};
  const double want_p[] = {mom, p1, p2, p3};
  for (int j = 0; j <= order; ++j) {
    INFO("order ", j);
    CHECK(series[j] == doctest::Approx(want_phi[j]).epsilon(1e-14));
    if (j < 4) CHECK(series[stride + j] == doctest::Approx(want_p[j]).epsilon(1e-14));
  }
}

TEST_CASE("taylor: the double run agrees with the long double run of the same recurrences") {
  // A regular orbit of the triple pendulum over 20 s, and the chaotic start from 1.5 rad
  // over 10 s, where round-off is amplified by e^{λt}: the long double reference at 1e-19
  // is the double run's independent check of its round-off and truncation.
  const chain c(npend::chain_parameters::uniform(3));
  struct case_t {
    std::vector<double> x0;
    double t_end, tol, within;
  };
  const case_t cases[] = {
      {{0.3, 0.3, 0.3, 0.0, 0.0, 0.0}, 20, 1e-15, 1e-13},
      {{1.5, 1.5, 1.5, 0.0, 0.0, 0.0}, 10, 1e-15, 1e-10},
  };
  for (const auto& cs : cases) {
    const auto reference = long_double_run(c, cs.x0, cs.t_end, 1e-19);
    const auto check = long_double_run(c, cs.x0, cs.t_end, 1e-18, 30);
    const auto r = npend::integrate(c, cs.x0, taylor_options(cs.t_end, cs.tol));
    const double error = largest_difference(r.state, reference);
    INFO("from ", cs.x0[0], ": error ", error, " in ", r.steps, " steps; the references differ by ",
         largest_difference(std::vector<double>(check.begin(), check.end()), reference));
    CHECK(largest_difference(std::vector<double>(check.begin(), check.end()), reference) <
          cs.within / 100);
    CHECK(error < cs.within);
  }
}

TEST_CASE("taylor: agrees with gauss6 on the triple pendulum and keeps H to its tolerance") {
  const chain c(npend::chain_parameters::uniform(3));
  const std::vector<double> x0{0.3, -0.2, 0.4, 0.1, 0.0, -0.1};
  const double h0 = c.hamiltonian(x0);
  integration_options g;
  g.stepper = stepper_kind::gauss6;
  g.t_end = 50;
  g.dt = 2.5e-3;
  const auto gauss = npend::integrate(c, x0, g);
  double worst_energy = 0;
  const auto taylor = npend::integrate(
      c, x0, taylor_options(50, 1e-14, 0.5), [&](double, std::span<const double> x) {
        worst_energy = std::max(worst_energy, std::fabs(c.hamiltonian(x) - h0) / h0);
      });
  double worst = 0;
  for (std::size_t i = 0; i < x0.size(); ++i)
    worst = std::max(worst, std::fabs(taylor.state[i] - gauss.state[i]));
  INFO("difference from gauss6 ", worst, ", energy error ", worst_energy);
  CHECK(worst < 1e-10);
  CHECK(worst_energy < 1e-13);
}

TEST_CASE("taylor: the physical chain with a driven pivot, springs and damping") {
  // Rods, a spring and damping at the second joint, the pivot shaken vertically (a Ω² = 3.7 g;
  // a shake five times as strong makes this start chaotic): the drive enters the Taylor
  // kernels as the series of the pivot's acceleration.
  npend::chain_parameters p = npend::chain_parameters::uniform(2, 1.0, 0.5);
  p.make_uniform_rods();
  p.stiffness = {0.0, 2.0};
  p.rest_angles = {0.0, 0.1};
  p.damping = {0.01, 0.02};
  p.pivot = npend::pivot_motion::vertical(0.01, 60);
  const chain c(p);
  const std::vector<double> x0{0.5, -0.3, 0.0, 0.1};
  const auto reference = long_double_run(c, x0, 5, 1e-19);
  const auto r = npend::integrate(c, x0, taylor_options(5, 1e-14));
  integration_options g;
  g.stepper = stepper_kind::gauss6;
  g.t_end = 5;
  g.dt = 2.5e-4;
  const auto gauss = npend::integrate(c, x0, g);
  INFO("taylor against long double ", largest_difference(r.state, reference),
       ", gauss6 against long double ", largest_difference(gauss.state, reference));
  CHECK(largest_difference(r.state, reference) < 1e-12);
  CHECK(largest_difference(gauss.state, reference) < 1e-12);
}

TEST_CASE("taylor: the chain on a cart agrees with gauss6") {
  npend::chain_parameters p = npend::chain_parameters::uniform(2);
  p.cart_mass = 2.0;
  p.cart_damping = 0.1;
  const chain c(p);
  const std::vector<double> x0{0.0, 0.6, -0.4, 0.2, 0.0, 0.1};
  const auto r = npend::integrate(c, x0, taylor_options(5, 1e-14));
  integration_options g;
  g.stepper = stepper_kind::gauss6;
  g.t_end = 5;
  g.dt = 1e-3;
  const auto gauss = npend::integrate(c, x0, g);
  double worst = 0;
  for (std::size_t i = 0; i < x0.size(); ++i)
    worst = std::max(worst, std::fabs(r.state[i] - gauss.state[i]));
  INFO("difference from gauss6 ", worst);
  CHECK(worst < 1e-9);
}

TEST_CASE("taylor: refusals name the problem") {
  // Eight links run on the loop kernels, which have no Taylor kernels.
  const chain long_chain(npend::chain_parameters::uniform(8));
  CHECK_THROWS_WITH_AS(
      npend::integrate(long_chain, std::vector<double>(16, 0.1), taylor_options(1, 1e-10)),
      doctest::Contains("NPEND_LINKS"), std::invalid_argument);
  npend::chain_parameters custom = npend::chain_parameters::uniform(2);
  custom.pivot.type = npend::pivot_motion::kind::custom;
  custom.pivot.position = [](double) { return npend::pivot_motion::vec2{0, 0}; };
  custom.pivot.velocity = custom.pivot.position;
  custom.pivot.acceleration = custom.pivot.position;
  CHECK_THROWS_WITH_AS(
      npend::integrate(chain(custom), std::vector<double>(4, 0.1), taylor_options(1, 1e-10)),
      doctest::Contains("custom pivot path"), std::invalid_argument);
  const chain c(npend::chain_parameters::uniform(2));
  integration_options o = taylor_options(1, 1e-10);
  o.taylor_order = 1;
  CHECK_THROWS_WITH_AS(npend::integrate(c, std::vector<double>(4, 0.1), o),
                       doctest::Contains("taylor_order"), std::invalid_argument);
  CHECK(npend::taylor_order_for(1e-15) == 19);
  CHECK(npend::taylor_order_for(1e-10) == 13);
}

TEST_CASE("taylor: a fixed order reaches the same state, and the equilibrium steps on") {
  const chain c(npend::chain_parameters::uniform(2));
  const std::vector<double> x0{1.0, 0.5, 0.0, 0.0};
  integration_options o = taylor_options(5, 1e-13);
  const auto chosen = npend::integrate(c, x0, o);
  o.taylor_order = 25;
  const auto fixed = npend::integrate(c, x0, o);
  double worst = 0;
  for (std::size_t i = 0; i < x0.size(); ++i)
    worst = std::max(worst, std::fabs(chosen.state[i] - fixed.state[i]));
  INFO("order 25 against the chosen order: ", worst, ", steps ", fixed.steps, " vs ", chosen.steps);
  CHECK(worst < 1e-10);
  CHECK(fixed.steps < chosen.steps);
  // At rest at the bottom every coefficient vanishes: the run takes steps of dt and stays.
  const auto rest = npend::integrate(c, std::vector<double>(4, 0.0), taylor_options(1, 1e-12, 0.1));
  CHECK(rest.state == std::vector<double>(4, 0.0));
}
