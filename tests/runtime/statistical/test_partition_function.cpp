// The canonical ensemble (analysis/partition_function.hpp) against the single pendulum's
// closed form in Bessel functions, the exponential convergence of the periodic trapezoid
// rule, ⟨E⟩ = −∂ ln Z/∂β by differences, equipartition at low and high temperature, and the
// quasi-Monte Carlo rule against the grid within its own error estimate.
#include <doctest/doctest.h>

#include <boost/math/special_functions/bessel.hpp>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "npend/analysis/statistical/langevin.hpp"
#include "npend/analysis/statistical/partition_function.hpp"
#include "npend/chain.hpp"

namespace {

npend::chain_parameters pendulum(double m, double l, double g) {
  npend::chain_parameters p;
  p.masses = {m};
  p.lengths = {l};
  p.g = g;
  return p;
}

// ln Z, ⟨E⟩, C and ⟨cos φ⟩ of one point mass (k = 1): with a = m g l, x = a / T,
// Q = √(m l²) 2π e^{−x} I₀(x), ⟨cos φ⟩ = I₁/I₀, ⟨cos² φ⟩ = (1 + I₂/I₀)/2.
struct closed_form {
  double log_z, energy, capacity, mean_cos;
};
closed_form single_pendulum(double m, double l, double g, double t) {
  const double a = m * g * l, x = a / t;
  using boost::math::cyl_bessel_i;
  const double i0 = cyl_bessel_i(0, x), i1 = cyl_bessel_i(1, x), i2 = cyl_bessel_i(2, x);
  const double cos1 = i1 / i0, cos2 = (1 + i2 / i0) / 2;
  const double q = std::sqrt(m * l * l) * 2 * std::numbers::pi * std::exp(-x) * i0;
  return {0.5 * std::log(2 * std::numbers::pi * t) + std::log(q), t / 2 + a * (1 - cos1),
          0.5 + a * a * (cos2 - cos1 * cos1) / (t * t), cos1};
}

}  // namespace

TEST_CASE("partition function: the single pendulum's closed form in Bessel functions") {
  const double m = 1.3, l = 0.8, g = 9.81;
  const npend::chain c(pendulum(m, l, g));
  const std::vector<double> temperatures{0.5, 3.0, 10.0, 60.0};
  const auto r = npend::canonical_ensemble(c, temperatures);
  REQUIRE(r.rule == "trapezoid");
  for (std::size_t i = 0; i < temperatures.size(); ++i) {
    const auto& s = r.states[i];
    const closed_form e = single_pendulum(m, l, g, temperatures[i]);
    INFO("T = " << temperatures[i]);
    CHECK(s.log_partition_function == doctest::Approx(e.log_z).epsilon(1e-13));
    CHECK(s.mean_energy == doctest::Approx(e.energy).epsilon(1e-12));
    CHECK(s.heat_capacity == doctest::Approx(e.capacity).epsilon(1e-11));
    CHECK(s.mean_cos[0] == doctest::Approx(e.mean_cos).epsilon(1e-12));
    CHECK(s.free_energy == doctest::Approx(-temperatures[i] * e.log_z).epsilon(1e-13));
  }
}

TEST_CASE("partition function: the periodic trapezoid rule converges exponentially") {
  const double m = 1.0, l = 1.0, g = 9.81, t = 2.0;
  const npend::chain c(pendulum(m, l, g));
  const closed_form e = single_pendulum(m, l, g, t);
  std::vector<double> error;
  for (const int grid : {8, 16, 24, 32}) {
    npend::partition_options o;
    o.grid = grid;
    const double temperature[] = {t};
    error.push_back(std::fabs(
        npend::canonical_ensemble(c, temperature, o).states[0].log_partition_function - e.log_z));
  }
  // Each 8 more points cut the error by a constant factor (x = a / T ≈ 4.9 here): a
  // straight line on a log scale, unlike the 1/M² of the rule on a non-periodic integrand.
  CHECK(error[0] > 1e-4);
  CHECK(error[1] < 1e-3 * error[0]);
  CHECK(error[2] < 1e-2 * error[1]);
  CHECK(error[3] < 1e-12);
}

TEST_CASE("partition function: <E> = -d ln Z / d beta, by differences of ln Z in T") {
  const npend::chain c(npend::chain_parameters::uniform(2));
  const double t = 4.0, h = 1e-3;
  const std::vector<double> temperatures{t - h, t, t + h};
  const auto r = npend::canonical_ensemble(c, temperatures);
  // ∂ ln Z/∂T = ⟨E⟩ / (k T²); C = ∂⟨E⟩/∂T.
  const double dlogz =
      (r.states[2].log_partition_function - r.states[0].log_partition_function) / (2 * h);
  CHECK(dlogz * t * t == doctest::Approx(r.states[1].mean_energy).epsilon(1e-7));
  const double de = (r.states[2].mean_energy - r.states[0].mean_energy) / (2 * h);
  CHECK(de == doctest::Approx(r.states[1].heat_capacity).epsilon(1e-6));
}

TEST_CASE("partition function: equipartition, C -> n at low and n/2 at high temperature") {
  const npend::chain c(npend::chain_parameters::uniform(2));  // m g l = 9.81
  npend::partition_options o;
  o.grid = 512;
  const std::vector<double> temperatures{0.02, 1e4};
  const auto r = npend::canonical_ensemble(c, temperatures, o);
  // Harmonic: 2n quadratic terms, each k/2; the anharmonic part is O(T/(m g l)) ≈ 0.2 %.
  CHECK(r.states[0].heat_capacity == doctest::Approx(2.0).epsilon(5e-3));
  CHECK(r.states[0].mean_energy == doctest::Approx(2 * 0.02).epsilon(5e-3));
  // Free rotation: V no longer matters, only the n momenta count; ⟨E⟩ → n k T/2 + ⟨V⟩ with
  // ⟨cos φ_k⟩ → 0 in V = Σ g μ_k l_k (1 − cos φ_k): ⟨V⟩ → g (μ_1 l_1 + μ_2 l_2) = 3 g.
  CHECK(r.states[1].heat_capacity == doctest::Approx(1.0).epsilon(1e-5));
  CHECK(r.states[1].mean_energy - 1e4 == doctest::Approx(3 * 9.81).epsilon(1e-2));
  // det A depends on φ1 − φ2 only, so at infinite T each angle is uniform: <cos phi> -> 0.
  CHECK(std::fabs(r.states[1].mean_cos[0]) < 1e-2);
  CHECK(std::fabs(r.states[1].mean_cos[1]) < 1e-2);
}

TEST_CASE("partition function: quasi-Monte Carlo agrees with the grid within its error") {
  npend::chain_parameters two, three;
  two.masses = {1.0, 2.0};
  two.lengths = {0.7, 1.2};
  three.masses = {1.0, 0.5, 1.5};
  three.lengths = {1.0, 0.8, 0.6};
  const std::vector<double> temperatures{8.0, 40.0};
  for (const auto& p : {two, three}) {
    const npend::chain c(p);
    const auto grid = npend::canonical_ensemble(c, temperatures);
    npend::partition_options o;
    o.rule = npend::partition_rule::quasi_monte_carlo;
    o.points = 16384;
    const auto qmc = npend::canonical_ensemble(c, temperatures, o);
    REQUIRE(qmc.rule == "quasi-monte-carlo");
    for (std::size_t i = 0; i < temperatures.size(); ++i) {
      const auto &a = grid.states[i], &b = qmc.states[i];
      INFO("n = " << c.links() << ", T = " << temperatures[i]);
      CHECK(a.log_partition_error < 1e-10);
      CHECK(b.log_partition_error > 0);
      CHECK(std::fabs(a.log_partition_function - b.log_partition_function) <
            5 * b.log_partition_error);
      CHECK(std::fabs(a.mean_energy - b.mean_energy) < 5 * b.mean_energy_error);
      CHECK(std::fabs(a.heat_capacity - b.heat_capacity) < 5 * b.heat_capacity_error);
      CHECK(b.log_partition_error < 1e-3);
    }
  }
}

TEST_CASE("partition function: the time average of H under Langevin dynamics is <E>") {
  // The dynamic check: a thermostatted trajectory samples e^{-H/kT}, so its mean energy is
  // the ensemble's. Two temperatures, so a noise of the wrong strength cannot pass both.
  npend::chain_parameters p = npend::chain_parameters::uniform(2);
  p.damping = {1.0, 0.5};
  const npend::chain c(p);
  npend::chain_parameters conservative = p;
  conservative.damping.clear();
  for (const double t : {1.5, 6.0}) {
    const double temperature[] = {t};
    const double expected =
        npend::canonical_ensemble(npend::chain(conservative), temperature).states[0].mean_energy;
    npend::langevin_options o;
    o.t_end = 2000;
    o.dt = 0.01;
    const auto r = npend::langevin_mean_energy(c, std::vector<double>(4, 0.0), t, o);
    INFO("T = " << t << ": <H> = " << r.mean_energy << " +- " << r.standard_error
                << ", <E> = " << expected);
    CHECK(r.standard_error < 0.04 * expected);
    CHECK(std::fabs(r.mean_energy - expected) < 4 * r.standard_error);
  }
}

TEST_CASE("partition function: refuses damping, springs and non-positive temperatures") {
  npend::chain_parameters p = npend::chain_parameters::uniform(2);
  const std::vector<double> one{1.0}, zero{0.0};
  CHECK_THROWS_AS(npend::canonical_ensemble(npend::chain(p), zero), std::invalid_argument);
  p.damping = {0.1, 0.0};
  CHECK_THROWS_AS(npend::canonical_ensemble(npend::chain(p), one), std::invalid_argument);
  p.damping = {};
  p.stiffness = {1.0, 1.0};
  CHECK_THROWS_AS(npend::canonical_ensemble(npend::chain(p), one), std::invalid_argument);
}

namespace {

// The harmonic (Laplace) limit of ln Z for a chain without springs: V = Σ a_i (1 − cos φ_i)
// ≈ ½ Σ a_i φ_i², det A ≈ det A(0), so Q = √det A(0) Π √(2π k T / a_i) and
// Z = (2π k T)^{n/2} Q: ln Z = n ln(2π T) + ½ ln det A(0) − ½ Σ ln a_i (k = 1), with
// ⟨E⟩ = n T and C = n. For uniform(2): A(0) = [[2, 1], [1, 1]], a = (2 g, g).
double harmonic_log_z_uniform2(double t) {
  const double g = 9.81;
  return 2 * std::log(2 * std::numbers::pi * t) - 0.5 * std::log(2 * g * g);
}

}  // namespace

TEST_CASE("partition function: the harmonic limit below the temperatures the circle resolves") {
  // At T = 1e-4 J the well is 2e-3 rad wide, and a grid of 128 points over the circle put
  // all of the weight on φ = 0: C came out 1 (n/2) with an error estimate of 0, and at
  // 1e-300 J it was NaN.
  const npend::chain c(npend::chain_parameters::uniform(2));
  const std::vector<double> temperatures{1e-4, 1e-12, 1e-300};
  const auto r = npend::canonical_ensemble(c, temperatures);
  for (std::size_t i = 0; i < temperatures.size(); ++i) {
    const double t = temperatures[i];
    const auto& s = r.states[i];
    INFO("T = " << t);
    // The anharmonic corrections are O(T / (m g l)) relative: 1e-5 at T = 1e-4.
    const double anharmonic = 10 * t / 9.81 + 1e-12;
    CHECK(s.heat_capacity == doctest::Approx(2.0).epsilon(anharmonic));
    CHECK(s.mean_energy == doctest::Approx(2 * t).epsilon(anharmonic));
    CHECK(std::fabs(s.log_partition_function - harmonic_log_z_uniform2(t)) < anharmonic);
    CHECK(s.heat_capacity_error < 1e-9);
  }
  // ⟨φ_i²⟩ = T / a_i: ⟨cos φ_1⟩ = 1 − T / (4 g), ⟨cos φ_2⟩ = 1 − T / (2 g).
  CHECK((1 - r.states[0].mean_cos[0]) == doctest::Approx(1e-4 / (4 * 9.81)).epsilon(1e-3));
  CHECK((1 - r.states[0].mean_cos[1]) == doctest::Approx(1e-4 / (2 * 9.81)).epsilon(1e-3));
}

TEST_CASE("partition function: continuous where the rule's box leaves the circle") {
  // One pendulum, a = m g l: the box is the circle for T >= a/25 and shrinks below. On both
  // sides of the switch, and well below it, the Bessel closed form holds.
  const double m = 1.3, l = 0.8, g = 9.81, a = m * g * l, switch_t = a / 25;
  const npend::chain c(pendulum(m, l, g));
  const std::vector<double> temperatures{switch_t * (1 + 1e-9), switch_t * (1 - 1e-9), 0.05, 0.02};
  const auto r = npend::canonical_ensemble(c, temperatures);
  for (std::size_t i = 0; i < temperatures.size(); ++i) {
    const closed_form e = single_pendulum(m, l, g, temperatures[i]);
    INFO("T = " << temperatures[i]);
    CHECK(r.states[i].log_partition_function == doctest::Approx(e.log_z).epsilon(1e-12));
    CHECK(r.states[i].mean_energy == doctest::Approx(e.energy).epsilon(1e-12));
    CHECK(r.states[i].heat_capacity == doctest::Approx(e.capacity).epsilon(1e-10));
  }
  CHECK(r.states[0].heat_capacity == doctest::Approx(r.states[1].heat_capacity).epsilon(1e-10));
  // Two links (128 points per angle): the second angle's box leaves the circle at a_2/25.
  const npend::chain two(npend::chain_parameters::uniform(2));
  const double t2 = 9.81 / 25;
  const std::vector<double> around{t2 * (1 + 1e-9), t2 * (1 - 1e-9)};
  const auto s = npend::canonical_ensemble(two, around);
  CHECK(s.states[0].heat_capacity == doctest::Approx(s.states[1].heat_capacity).epsilon(1e-9));
  CHECK(s.states[0].mean_energy == doctest::Approx(s.states[1].mean_energy).epsilon(1e-9));
  // ln Z moves by ∂ ln Z/∂T ΔT = ⟨E⟩/T² ΔT (4e-9 here); beyond that it must not jump.
  const double slope = s.states[1].mean_energy / (t2 * t2);
  CHECK(std::fabs(s.states[0].log_partition_function - s.states[1].log_partition_function -
                  slope * (around[0] - around[1])) < 1e-12);
  CHECK(s.states[1].heat_capacity_error < 1e-9);
}

TEST_CASE("partition function: refuses k T outside the normal doubles") {
  const npend::chain c(npend::chain_parameters::uniform(2));
  const std::vector<double> tiny{1e-310};
  CHECK_THROWS_AS(npend::canonical_ensemble(c, tiny), std::invalid_argument);
}
