// Start states of a requested energy: deflections and kicks.
#include <doctest/doctest.h>

#include <cmath>
#include <numbers>

#include "npend/excitation.hpp"
#include "reference/dense_chain.hpp"
#include "support/test_support.hpp"

using npend::chain;

TEST_CASE("deflected_state: all arms by arccos(1 - E / (g sum mu_j l_j)), at rest") {
  std::mt19937_64 rng(41);
  for (int n = 1; n <= 6; ++n) {
    const npend::chain_parameters params = npend::test::random_parameters(n, rng);
    const chain c(params);
    const npend::reference::dense_chain ref(params.masses, params.lengths, params.g);
    double weight = 0;  // V(α, …, α) = g Σ μ_j l_j (1 − cos α)
    for (int j = 0; j < n; ++j) weight += params.g * ref.mu(j) * ref.l(j);
    for (double fraction : {0.01, 0.3, 1.0, 1.9}) {
      const double energy = fraction * weight;
      const auto x = npend::deflected_state(c, energy);
      const double alpha = std::acos(1 - energy / weight);
      INFO("n = ", n, ", E = ", energy);
      for (int i = 0; i < n; ++i) {
        CHECK(x[static_cast<std::size_t>(i)] == doctest::Approx(alpha).epsilon(1e-12));
        CHECK(x[static_cast<std::size_t>(n + i)] == 0);
      }
      CHECK(c.hamiltonian(x) == doctest::Approx(energy).epsilon(1e-14));
    }
    CHECK(npend::max_deflection_energy(c) == doctest::Approx(2 * weight).epsilon(1e-15));
    const auto top = npend::deflected_state(c, 2 * weight);
    CHECK(top[0] == doctest::Approx(std::numbers::pi).epsilon(1e-7));
  }
}

TEST_CASE("deflected_state: H equals the energy along any direction, up to the reachable limit") {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> entry(-1.0, 1.0);
  for (int n = 1; n <= 6; ++n) {
    const chain c(npend::test::random_parameters(n, rng));
    std::vector<double> u;
    for (int i = 0; i < n; ++i) u.push_back(entry(rng));
    const double top = npend::max_deflection_energy(c, u);
    double largest = 0;
    for (double v : u) largest = std::max(largest, std::fabs(v));
    std::vector<double> upright(u);
    for (double& v : upright) v *= std::numbers::pi / largest;
    CHECK(top == doctest::Approx(c.potential_energy(upright)).epsilon(1e-15));
    for (double fraction : {1e-6, 0.1, 0.5, 0.99}) {
      const auto x = npend::deflected_state(c, fraction * top, u);
      INFO("n = ", n, ", fraction ", fraction);
      CHECK(c.hamiltonian(x) == doctest::Approx(fraction * top).epsilon(1e-12));
      const double s = x[0] / u[0];  // x = s u with s > 0
      CHECK(s > 0);
      for (int i = 0; i < n; ++i)
        CHECK(x[static_cast<std::size_t>(i)] ==
              doctest::Approx(s * u[static_cast<std::size_t>(i)]).epsilon(1e-14));
    }
  }
}

TEST_CASE("kicked_state: the default is a horizontal impulse on the lowest bob, H = E") {
  std::mt19937_64 rng(43);
  for (int n = 1; n <= 6; ++n) {
    const npend::chain_parameters params = npend::test::random_parameters(n, rng);
    const chain c(params);
    const double energy = 7.5;
    const auto x = npend::kicked_state(c, energy);
    const auto nn = static_cast<std::size_t>(n);
    CHECK(c.hamiltonian(x) == doctest::Approx(energy).epsilon(1e-14));
    // An impulse J on bob n at φ = 0 gives p_i = J ∂x_n/∂φ_i = J l_i; from rest the
    // kinetic energy is then ½ J v_n, v_n = Σ l_i φ̇_i the bob's horizontal speed.
    const double J = x[nn] / params.lengths[0];
    std::vector<double> dphi(nn);
    c.velocities(std::span(x).first(nn), std::span(x).subspan(nn), dphi);
    double v = 0;
    for (std::size_t i = 0; i < nn; ++i) {
      CHECK(x[i] == 0);
      CHECK(x[nn + i] == doctest::Approx(J * params.lengths[i]).epsilon(1e-15));
      v += params.lengths[i] * dphi[i];
    }
    CHECK(0.5 * J * v == doctest::Approx(energy).epsilon(1e-13));

    std::vector<double> d(nn, 0.0);
    d[0] = 1;  // a momentum on the first joint only
    const auto y = npend::kicked_state(c, energy, d);
    CHECK(c.hamiltonian(y) == doctest::Approx(energy).epsilon(1e-14));
    CHECK(npend::kicked_state(c, 0.0) == std::vector<double>(2 * nn, 0.0));
  }
}

TEST_CASE(
    "excited_state: refuses energies below the minimum and out of reach, and bad directions") {
  const chain c(npend::chain_parameters::uniform(3));
  CHECK_THROWS_WITH_AS(
      npend::deflected_state(c, -1),
      "energy -1 J is below the minimum 0 J of the potential (the chain hanging at rest)",
      std::invalid_argument);
  CHECK_THROWS_WITH_AS(npend::kicked_state(c, -0.5), doctest::Contains("is below the minimum 0 J"),
                       std::invalid_argument);
  CHECK_THROWS_WITH_AS(npend::deflected_state(c, 200),
                       "energy 200 J is out of reach of a deflection from rest: at most 117.72 J, "
                       "with an arm pointing straight up; use a kick for higher energies",
                       std::invalid_argument);
  CHECK(c.hamiltonian(npend::kicked_state(c, 200)) == doctest::Approx(200).epsilon(1e-14));
  CHECK_THROWS_WITH_AS(npend::deflected_state(c, std::nan("")), "energy nan J is not finite",
                       std::invalid_argument);
  const std::vector<double> zero{0, 0, 0}, two{1, 1};
  CHECK_THROWS_WITH_AS(npend::deflected_state(c, 1, zero),
                       "direction is zero: it must have a non-zero entry", std::invalid_argument);
  CHECK_THROWS_WITH_AS(npend::kicked_state(c, 1, two),
                       "direction has 2 entries; the 3-link chain needs 3", std::invalid_argument);
  CHECK(npend::excited_state(c, 5, npend::excitation::deflection) == npend::deflected_state(c, 5));
  CHECK(npend::excited_state(c, 5, npend::excitation::kick) == npend::kicked_state(c, 5));
  CHECK(npend::parse_excitation("kick") == npend::excitation::kick);
  CHECK(npend::excitation_name(npend::excitation::deflection) == "deflection");
  CHECK_THROWS_WITH_AS(npend::parse_excitation("push"),
                       "unknown excitation 'push': choose one of deflection, kick",
                       std::invalid_argument);
}

TEST_CASE("energy_from_epsilon: E = eps m g l for equal links, refused otherwise") {
  const chain c(npend::chain_parameters::uniform(3, 2.0, 0.5, 9.81));
  CHECK(npend::energy_from_epsilon(c, 3.0) == doctest::Approx(3.0 * 2.0 * 9.81 * 0.5));
  CHECK(npend::epsilon_from_energy(c, npend::energy_from_epsilon(c, 0.7)) == doctest::Approx(0.7));
  npend::chain_parameters p = npend::chain_parameters::uniform(3);
  p.masses[2] = 2;
  CHECK_THROWS_WITH_AS(npend::energy_from_epsilon(chain(p), 1.0),
                       "epsilon = E/(m g l) is defined for equal masses and equal lengths only",
                       std::invalid_argument);
}
