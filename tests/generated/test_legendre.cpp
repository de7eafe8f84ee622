// The Legendre transform both ways, and the energies it connects.
#include <doctest/doctest.h>

#include "npend/chain.hpp"
#include "support/test_support.hpp"

using npend::chain;

TEST_CASE("velocities: momenta -> velocities -> momenta round trip") {
  for (int n = 1; n <= 6; ++n) {
    std::mt19937_64 rng(500 + static_cast<unsigned>(n));
    for (int s = 0; s < 100; ++s) {
      const chain c(npend::test::random_parameters(n, rng));
      const auto x = npend::test::random_state(n, rng);
      const auto nn = static_cast<std::size_t>(n);
      const std::span<const double> phi(x.data(), nn), p(x.data() + nn, nn);
      std::vector<double> dphi(nn), p_back(nn);
      c.velocities(phi, p, dphi);
      c.momenta(phi, dphi, p_back);
      CHECK(npend::test::relative_error(p_back, p) < 1e-13);
      // and state_from_velocities gives back the same state.
      CHECK(npend::test::relative_error(c.state_from_velocities(phi, dphi), x) < 1e-13);
    }
  }
}

TEST_CASE("hamiltonian: H = T + V at dphi = A^-1 p, and L = T - V") {
  for (int n = 1; n <= 6; ++n) {
    std::mt19937_64 rng(600 + static_cast<unsigned>(n));
    for (int s = 0; s < 100; ++s) {
      const chain c(npend::test::random_parameters(n, rng));
      const auto x = npend::test::random_state(n, rng);
      const auto nn = static_cast<std::size_t>(n);
      const std::span<const double> phi(x.data(), nn), p(x.data() + nn, nn);
      std::vector<double> dphi(nn);
      c.velocities(phi, p, dphi);
      const double T = c.kinetic_energy(phi, dphi), V = c.potential_energy(phi);
      CHECK(c.hamiltonian(x) == doctest::Approx(T + V).epsilon(1e-13));
      CHECK(c.lagrangian(phi, dphi) == doctest::Approx(T - V).epsilon(1e-12));
      // T = ½ pᵀ φ̇ (Euler's theorem for the quadratic form).
      double pdphi = 0;
      for (std::size_t i = 0; i < nn; ++i) pdphi += p[i] * dphi[i];
      CHECK(T == doctest::Approx(0.5 * pdphi).epsilon(1e-13));
    }
  }
}

TEST_CASE("momenta: dL/d(dphi) = A dphi, checked by central differences of L") {
  // L is quadratic in φ̇, so a central difference is exact up to rounding.
  for (int n = 1; n <= 6; ++n) {
    std::mt19937_64 rng(700 + static_cast<unsigned>(n));
    for (int s = 0; s < 20; ++s) {
      const chain c(npend::test::random_parameters(n, rng));
      const auto x = npend::test::random_state(n, rng);
      const auto nn = static_cast<std::size_t>(n);
      const std::span<const double> phi(x.data(), nn);
      std::vector<double> dphi(x.begin() + n, x.end()), p(nn), A(nn * nn);
      c.momenta(phi, dphi, p);
      c.mass_matrix(phi, A);
      for (std::size_t i = 0; i < nn; ++i) {
        double a_dphi = 0;
        for (std::size_t j = 0; j < nn; ++j) a_dphi += A[i * nn + j] * dphi[j];
        CHECK(p[i] == doctest::Approx(a_dphi).epsilon(1e-13).scale(1));
        const double h = 0.5;
        std::vector<double> up = dphi, down = dphi;
        up[i] += h;
        down[i] -= h;
        const double dl = (c.lagrangian(phi, up) - c.lagrangian(phi, down)) / (2 * h);
        CHECK(dl == doctest::Approx(p[i]).epsilon(1e-11).scale(1));
      }
    }
  }
}

TEST_CASE("chain: bad parameters and unbuilt link counts are refused with a clear message") {
  using npend::chain_parameters;
  auto params = chain_parameters::uniform(3);
  params.masses[1] = -1;
  CHECK_THROWS_WITH_AS(chain{params}, "mass 2 is -1: it must be a positive finite number",
                       std::invalid_argument);
  params = chain_parameters::uniform(3);
  params.lengths.pop_back();
  CHECK_THROWS_AS(chain{params}, std::invalid_argument);
  params = chain_parameters::uniform(3);
  params.g = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_AS(chain{params}, std::invalid_argument);
  // A physical chain of a link count outside NPEND_LINKS names the option that adds it (a
  // point-mass chain runs on the loop kernels).
  const auto built = npend::built_link_counts();
  const int missing = built.back() + 1;
  try {
    auto damped = chain_parameters::uniform(missing);
    damped.damping.assign(static_cast<std::size_t>(missing), 0.1);
    chain c{damped};
    FAIL("expected an exception");
  } catch (const std::invalid_argument& e) {
    CHECK(std::string(e.what()).find("-DNPEND_LINKS=") != std::string::npos);
  }
  const chain c(chain_parameters::uniform(2));
  std::vector<double> short_state{0.0, 0.0, 0.0};
  CHECK_THROWS_AS(c.hamiltonian(short_state), std::invalid_argument);
}
