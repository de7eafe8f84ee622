// Poincaré sections (paper §6.6.1): crossings of integrable cases on their known curves, a
// chaotic case against a brute-force fine-step reference, points on the section to rounding
// with the energy kept for every stepper, directions, stopping, and the tangential fallback.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "npend/analysis/chaos/poincare_section.hpp"
#include "npend/analysis/series/event_times.hpp"
#include "npend/analysis/stability/backbone.hpp"
#include "npend/analysis/stability/normal_modes.hpp"
#include "reference/reference_trajectory.hpp"
#include "support/test_signals.hpp"
#include "support/test_support.hpp"

using namespace npend;
using std::numbers::pi;

namespace {

const std::vector<double> strong_start{0.9, -0.6, 1.2, 0.0, 0.0, 0.0};

integration_options run_for(double t_end, stepper_kind k = stepper_kind::gauss6, double dt = 1e-3) {
  integration_options o;
  o.stepper = k;
  o.t_end = t_end;
  o.dt = dt;
  return o;
}

}  // namespace

TEST_CASE(
    "poincare_section: a single pendulum crosses phi = 0 on its energy curve, once a period") {
  const chain c(chain_parameters::uniform(1));  // m = 1 kg, l = 1 m: p = φ̇
  const double a = 1.0, g = c.parameters().g;
  const std::vector<double> x0{a, 0.0};
  const double energy = g * (1 - std::cos(a));
  const double period = npend::pendulum_period(a, 1.0, g);
  for (const auto direction : {crossing_direction::up, crossing_direction::down}) {
    const auto r = poincare_section(c, x0, section_plane::coordinate(1, 0, 0.0), run_for(30),
                                    {.direction = direction});
    REQUIRE(r.crossings.size() >= 10);
    const double p_expected =
        (direction == crossing_direction::up ? 1 : -1) * std::sqrt(2 * energy);
    for (std::size_t j = 0; j < r.crossings.size(); ++j) {
      const auto& k = r.crossings[j];
      CHECK(k.refined);
      CHECK(std::fabs(k.state[0]) < 1e-15);
      CHECK(k.state[1] == doctest::Approx(p_expected).epsilon(1e-12));
      // The first crossing a quarter (up: three quarters) of a period in, then one a period.
      const double phase = direction == crossing_direction::up ? 0.75 : 0.25;
      CHECK(k.t == doctest::Approx((phase + static_cast<double>(j)) * period).epsilon(1e-11));
    }
  }
}

TEST_CASE("poincare_section: integrating backwards finds the same crossings, refined") {
  const chain c(chain_parameters::uniform(1));
  const std::vector<double> x0{1.0, 0.0};
  const double period = npend::pendulum_period(1.0, 1.0, c.parameters().g);
  for (stepper_kind k : all_stepper_kinds()) {
    integration_options o = run_for(-10, k, -1e-3);
    o.abs_tol = o.rel_tol = 1e-12;
    // Backwards from rest at φ = a, φ falls through 0 at t = −T/4 (down along the integration)
    // and rises through it at t = −3T/4: "up" is along the integration, φ growing as t
    // decreases, so p = φ̇ < 0 there.
    const auto r = poincare_section(c, x0, section_plane::coordinate(1, 0, 0.0), o);
    INFO(stepper_name(k));
    REQUIRE(r.crossings.size() >= 4);
    for (std::size_t j = 0; j < r.crossings.size(); ++j) {
      const auto& x = r.crossings[j];
      CHECK(x.refined);
      CHECK(std::fabs(x.state[0]) < 1e-15);
      CHECK(x.state[1] ==
            doctest::Approx(-std::sqrt(2 * c.parameters().g * (1 - std::cos(1.0)))).epsilon(1e-7));
      CHECK(x.t == doctest::Approx(-(0.75 + static_cast<double>(j)) * period).epsilon(1e-7));
    }
  }
}

TEST_CASE("poincare_section: small oscillations of the double pendulum lie on closed curves") {
  // In the linear limit each normal mode keeps its energy E_k = ½(s_k² + ω_k² q_k²), with
  // q_k = v_kᵀ M φ and s_k = v_kᵀ p: on the section φ₁ = 0 the crossings lie on the closed
  // curve E_1, E_2 = const, and with incommensurate frequencies they go all the way round it.
  // (Mode 1 dominates φ₁ and φ̇₁ here, so the crossings come once per period of mode 1, and
  // mode 2's phase there advances by 2π ω₂/ω₁ = 2π (1 + √2) each time.)
  const chain c(chain_parameters::uniform(2));
  const auto lin = normal_modes(c, std::vector<double>{0, 0});
  const auto& M = lin.mass_matrix;
  const double amplitude = 1e-3;
  std::vector<double> x0(4, 0.0);
  for (int i = 0; i < 2; ++i)
    x0[static_cast<std::size_t>(i)] =
        amplitude * (lin.modes[0].shape[static_cast<std::size_t>(i)] +
                     0.05 * lin.modes[1].shape[static_cast<std::size_t>(i)]);
  struct modal {
    double energy, angle;
  };
  const auto mode = [&](std::span<const double> x, std::size_t k) {
    const auto& v = lin.modes[k].shape;
    const double w = lin.modes[k].frequency;
    double q = 0, s = 0;
    for (std::size_t i = 0; i < 2; ++i) {
      for (std::size_t j = 0; j < 2; ++j) q += v[i] * M[i * 2 + j] * x[j];
      s += v[i] * x[2 + i];
    }
    return modal{0.5 * (s * s + w * w * q * q), std::atan2(s, w * q)};
  };
  const auto r = poincare_section(c, x0, section_plane::coordinate(2, 0, 0.0),
                                  run_for(300, stepper_kind::gauss6, 0.01));
  REQUIRE(r.crossings.size() > 100);
  std::vector<double> angles;
  for (const auto& k : r.crossings) {
    for (std::size_t m = 0; m < 2; ++m)
      CHECK(mode(k.state, m).energy == doctest::Approx(mode(x0, m).energy).epsilon(1e-4));
    angles.push_back(mode(k.state, 1).angle);
  }
  // Mode 2's phase at the crossings covers the circle: no gap wider than 15°.
  std::sort(angles.begin(), angles.end());
  double gap = angles.front() + 2 * pi - angles.back();
  for (std::size_t j = 1; j < angles.size(); ++j) gap = std::max(gap, angles[j] - angles[j - 1]);
  CHECK(gap < 15 * pi / 180);
}

TEST_CASE("poincare_section: chaotic crossings match a brute-force fine-step reference") {
  const chain_parameters params = chain_parameters::uniform(3);
  const chain c(params);
  const double t_end = 5;
  const auto r = poincare_section(c, strong_start, section_plane::coordinate(3, 0, 0.0),
                                  run_for(t_end), {.direction = crossing_direction::both});
  // Brute force: classic RK4 at dt = 1e-5, φ₁'s sign changes between its samples located by
  // cubic interpolation (errors ~ dt⁴) — nothing of the dense output or of Hénon's trick.
  const double fine = 1e-5;
  const auto samples =
      test::rk4_trajectory(c, strong_start, static_cast<std::size_t>(t_end / fine) + 1, fine);
  std::vector<double> phi1;
  for (const auto& x : samples) phi1.push_back(x[0]);
  const auto brute = event_times(phi1, fine, {.direction = crossing_direction::both});
  REQUIRE(brute.size() >= 4);
  REQUIRE(r.crossings.size() == brute.size());
  const auto times = crossing_times(r.crossings);
  const auto reference =
      reference::reference_trajectory(reference::dense_chain_of(params), strong_start, times);
  for (std::size_t j = 0; j < brute.size(); ++j) {
    CAPTURE(j);
    CHECK(std::fabs(times[j] - brute[j]) < 1e-10);
    // The states against the tight-tolerance reference at the same times.
    CHECK(test::relative_error(r.crossings[j].state, reference[j]) < 1e-10);
  }
}

TEST_CASE("poincare_section: every stepper puts the points on the section and keeps the energy") {
  const chain c(chain_parameters::uniform(3));
  const double h0 = c.hamiltonian(strong_start);
  const std::vector<section_plane> sections{
      section_plane::coordinate(3, 0, 0.0),                   // φ₁ = 0
      section_plane::equal_coordinates(3, 1, 2),              // φ₂ = φ₃
      section_plane::coordinate(3, 3, 0.5),                   // p₁ = 0.5 kg m²/s
      section_plane{{0.5, 0.0, -1.0, 0.0, 0.0, 0.25}, 0.1}};  // any hyperplane
  for (stepper_kind k : all_stepper_kinds()) {
    integration_options o = run_for(20, k);
    o.abs_tol = o.rel_tol = 1e-12;
    // The energy error the stepper itself makes at dt = 1e-3 (tolerance 1e-12) over 20 s.
    const double energy_tolerance =
        k == stepper_kind::gauss6 || k == stepper_kind::rkf78 || k == stepper_kind::bulirsch_stoer
            ? 1e-11
            : 1e-7;
    for (const auto& s : sections) {
      const auto r =
          poincare_section(c, strong_start, s, o, {.direction = crossing_direction::both});
      INFO(stepper_name(k), ", section ", &s - sections.data());
      CHECK(r.crossings.size() >= 10);
      double residual = 0, energy = 0;
      for (const auto& x : r.crossings) {
        CHECK(x.refined);
        residual = std::max(residual, std::fabs(s.value(x.state)));
        energy = std::max(energy, std::fabs(c.hamiltonian(x.state) - h0) / h0);
      }
      CHECK(residual < 1e-12);
      CHECK(energy < energy_tolerance);
    }
  }
}

TEST_CASE("poincare_section: both directions are the up and the down crossings, alternating") {
  const chain c(chain_parameters::uniform(3));
  const auto section = section_plane::coordinate(3, 2, 0.0);
  const auto up = poincare_section(c, strong_start, section, run_for(10));
  const auto down = poincare_section(c, strong_start, section, run_for(10),
                                     {.direction = crossing_direction::down});
  const auto both = poincare_section(c, strong_start, section, run_for(10),
                                     {.direction = crossing_direction::both});
  REQUIRE(both.crossings.size() == up.crossings.size() + down.crossings.size());
  REQUIRE(!up.crossings.empty());
  const auto rate = [&](const section_crossing& x) { return c.rhs(x.state)[2]; };  // φ̇₃
  for (const auto& x : up.crossings) CHECK(rate(x) > 0);
  for (const auto& x : down.crossings) CHECK(rate(x) < 0);
  for (std::size_t j = 1; j < both.crossings.size(); ++j) {
    const auto& previous = both.crossings[j - 1];
    const auto& current = both.crossings[j];
    CHECK(previous.t < current.t);
    // rising, falling, rising, …
    CHECK(rate(previous) * rate(current) < 0);
  }
}

TEST_CASE("poincare_section: max_crossings stops the integration at the last one") {
  const chain c(chain_parameters::uniform(3));
  const auto r =
      poincare_section(c, strong_start, section_plane::coordinate(3, 2, 0.0), run_for(100),
                       {.direction = crossing_direction::both, .max_crossings = 5});
  REQUIRE(r.crossings.size() == 5);
  CHECK(r.integration.stopped);
  CHECK(r.integration.t >= r.crossings.back().t);
  CHECK(r.integration.t < r.crossings.back().t + 1e-3 + 1e-12);
}

TEST_CASE("crossing_locator: a crossing Henon's trick cannot reach keeps the dense output") {
  // A made-up step of the single pendulum whose interpolant rises through φ = 0 while the
  // states say it moves down (p < 0): w·f has the wrong sign everywhere, so the crossing
  // stays where the dense output puts it, marked unrefined.
  struct straight_line final : detail::step_interpolant {
    std::vector<double> a, b;
    void state_at(double t, std::span<double> x) const override {
      for (std::size_t i = 0; i < x.size(); ++i) x[i] = a[i] + t * (b[i] - a[i]);
    }
    int degree() const override { return 1; }
  };
  const chain c(chain_parameters::uniform(1));
  straight_line line;
  line.a = {-0.1, -1.0};
  line.b = {0.1, -1.0};
  crossing_locator locator(c, section_plane::coordinate(1, 0, 0.0));
  CHECK(locator(integration_step(0.0, line.a, 1.0, line.b, line)) == observer_action::proceed);
  REQUIRE(locator.crossings().size() == 1);
  const auto& x = locator.crossings().front();
  CHECK_FALSE(x.refined);
  CHECK(x.t == doctest::Approx(0.5).epsilon(1e-14));
  CHECK(std::fabs(x.state[0]) < 1e-15);
  CHECK(x.state[1] == -1.0);
  // Moving away from the section, or not reaching it, is no crossing.
  line.b = {-0.05, 1.0};
  CHECK(locator(integration_step(1.0, line.a, 2.0, line.b, line)) == observer_action::proceed);
  CHECK(locator.crossings().size() == 1);
}

TEST_CASE("section_plane: coordinates, equal coordinates and bad planes") {
  const auto phi2 = section_plane::coordinate(3, 1, 0.25);
  CHECK(phi2.normal == std::vector<double>{0, 1, 0, 0, 0, 0});
  CHECK(phi2.value(std::vector<double>{9, 1.25, 9, 9, 9, 9}) == 1.0);
  const auto stretched = section_plane::equal_coordinates(3, 1, 2);
  CHECK(stretched.normal == std::vector<double>{0, 1, -1, 0, 0, 0});
  CHECK_THROWS_AS(section_plane::coordinate(3, 6, 0.0), std::invalid_argument);
  CHECK_THROWS_AS(section_plane::coordinate(0, 0, 0.0), std::invalid_argument);
  CHECK_THROWS_AS(section_plane::coordinate(3, 0, std::nan("")), std::invalid_argument);
  CHECK_THROWS_AS(section_plane::equal_coordinates(3, 2, 2), std::invalid_argument);
  CHECK_THROWS_AS(section_plane::equal_coordinates(3, 2, 7), std::invalid_argument);
  const chain c(chain_parameters::uniform(3));
  CHECK_THROWS_WITH_AS(poincare_section(c, strong_start, section_plane{{1, 0}, 0}, run_for(1)),
                       "section normal has 2 entries; the state has 6", std::invalid_argument);
  CHECK_THROWS_WITH_AS(
      poincare_section(c, strong_start, section_plane{std::vector<double>(6, 0.0), 0}, run_for(1)),
      "section normal is all 0: it defines no hyperplane", std::invalid_argument);
  CHECK_THROWS_AS(
      poincare_section(c, strong_start, section_plane{{1, 0, 0, 0, 0, INFINITY}, 0}, run_for(1)),
      std::invalid_argument);
}

TEST_CASE("poincare_section: a rotating pendulum crosses phi = 0 on the circle once a turn") {
  // Above the separatrix the single pendulum turns over for ever: φ grows without bound,
  // and on the circle it passes φ ≡ 0 once a turn, T_rev = ∫₀^{2π} dφ / φ̇(φ) apart with
  // φ̇ = √(2 (E − g (1 − cos φ))) (m = l = 1). The trapezoid rule on the periodic integrand
  // converges exponentially: an independent T_rev to rounding.
  const chain c(chain_parameters::uniform(1));
  const double g = c.parameters().g;
  for (const double p0 : {7.0, -7.0}) {  // E = 24.5 J > 2 g: turning either way
    const std::vector<double> x0{0.1, p0};
    const double energy = c.hamiltonian(x0);
    constexpr int nodes = 4096;
    double revolution = 0;
    for (int k = 0; k < nodes; ++k) {
      const double phi = 2 * pi * k / nodes;
      revolution += (2 * pi / nodes) / std::sqrt(2 * (energy - g * (1 - std::cos(phi))));
    }
    const auto direction = p0 > 0 ? crossing_direction::up : crossing_direction::down;
    const auto circle = poincare_section(c, x0, section_plane::coordinate(1, 0, 0.0), run_for(20),
                                         {.direction = direction});
    REQUIRE(circle.crossings.size() >= 10);
    for (std::size_t j = 0; j < circle.crossings.size(); ++j) {
      const auto& k = circle.crossings[j];
      CHECK(k.refined);
      // On the branch 2πj of the unwrapped angle, to rounding.
      CHECK(std::fabs(k.state[0] - std::round(k.state[0] / (2 * pi)) * 2 * pi) < 1e-12);
      if (j > 0)
        CHECK(k.t - circle.crossings[j - 1].t == doctest::Approx(revolution).epsilon(1e-10));
    }
    // None the other way round, and on the unwrapped angle none at all after the start.
    const auto other =
        poincare_section(c, x0, section_plane::coordinate(1, 0, 0.0), run_for(20),
                         {.direction = p0 > 0 ? crossing_direction::down : crossing_direction::up});
    CHECK(other.crossings.empty());
    section_plane unwrapped = section_plane::coordinate(1, 0, 0.0);
    unwrapped.circular = false;
    const auto plane = poincare_section(c, x0, unwrapped, run_for(20), {.direction = direction});
    CHECK(plane.crossings.size() == (p0 > 0 ? 0u : 1u));  // -7: back through 0 once, early
  }
}

TEST_CASE("section_plane: circular sections of angles, their branches and bad circular planes") {
  const auto phi1 = section_plane::coordinate(2, 0, 0.5);
  CHECK(phi1.circular);
  CHECK(!section_plane::coordinate(2, 2, 0.5).circular);  // p1: a momentum is no angle
  CHECK(section_plane::equal_coordinates(2, 0, 1).circular);
  CHECK(!section_plane::equal_coordinates(2, 0, 3).circular);
  // The branch crossed between two states, either way; a start on a branch is no crossing.
  const double turn = 2 * pi;
  const auto at = [](double phi) { return std::vector<double>{phi, 0, 0, 0}; };
  CHECK(phi1.branch_level(at(0.5 + turn - 0.01), at(0.5 + turn + 0.01)) == 0.5 + turn);
  CHECK(phi1.branch_level(at(0.5 - 2 * turn + 0.01), at(0.5 - 2 * turn - 0.01)) ==
        doctest::Approx(0.5 - 2 * turn).epsilon(1e-15));
  CHECK(phi1.branch_level(at(0.5 + turn), at(0.5 + turn + 0.01)) == 0.5);  // not crossed
  CHECK(phi1.value(at(0.5 + 3 * turn + 0.2)) == doctest::Approx(0.2).epsilon(1e-12));
  const chain c(chain_parameters::uniform(2));
  section_plane bad = phi1;
  bad.normal = {0.5, 0, 0, 0};
  CHECK_THROWS_AS(bad.validate(4), std::invalid_argument);
  bad.normal = {1, 0, 1, 0};
  CHECK_THROWS_AS(bad.validate(4), std::invalid_argument);
}
