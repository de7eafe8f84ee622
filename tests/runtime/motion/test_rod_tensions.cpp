// The rod tensions (analysis/rod_tensions.hpp, from the positions and velocities alone)
// against Newton's law for every bob, with its acceleration from the exact φ̈ of the
// generated rhs and Jacobian; and their closed forms.
#include <doctest/doctest.h>

#include <cmath>
#include <random>
#include <stdexcept>

#include "npend/analysis/motion/rod_tensions.hpp"
#include "npend/chain.hpp"
#include "support/test_support.hpp"

TEST_CASE("rod tensions: Newton's law for every bob, accelerations from the exact phi''") {
  std::mt19937_64 rng(1511);
  for (const int n : npend::built_link_counts()) {
    for (int trial = 0; trial < 4; ++trial) {
      const npend::chain_parameters p = npend::test::random_parameters(n, rng);
      const npend::chain c(p);
      const auto x = npend::test::random_state(n, rng);
      const auto N = static_cast<std::size_t>(n);
      const auto tau = npend::rod_tensions(c, x);
      // φ̇ = f_φ, φ̈ = (∂f_φ/∂x) f.
      std::vector<double> f(2 * N), jac(4 * N * N);
      c.rhs(x, f);
      c.jacobian(x, jac);
      std::vector<double> ddphi(N, 0.0);
      for (std::size_t i = 0; i < N; ++i)
        for (std::size_t j = 0; j < 2 * N; ++j) ddphi[i] += jac[i * 2 * N + j] * f[j];
      double ax = 0, ay = 0;  // bob k's acceleration, summed down the chain
      for (std::size_t k = 0; k < N; ++k) {
        const double s = std::sin(x[k]), co = std::cos(x[k]), l = p.lengths[k];
        // d²/dt² of l (sin φ, cos φ) = l φ̈ (cos φ, −sin φ) − l φ̇² (sin φ, cos φ).
        ax += l * (ddphi[k] * co - f[k] * f[k] * s);
        ay += l * (-ddphi[k] * s - f[k] * f[k] * co);
        double fx = -tau[k] * s, fy = -tau[k] * co + p.masses[k] * p.g;
        if (k + 1 < N) {
          fx += tau[k + 1] * std::sin(x[k + 1]);
          fy += tau[k + 1] * std::cos(x[k + 1]);
        }
        const double scale = p.masses[k] * (p.g + std::hypot(ax, ay)) + std::fabs(tau[k]);
        INFO("n = " << n << ", bob " << k + 1);
        CHECK(std::fabs(p.masses[k] * ax - fx) < 1e-11 * scale);
        CHECK(std::fabs(p.masses[k] * ay - fy) < 1e-11 * scale);
      }
    }
  }
}

TEST_CASE("rod tensions: the pendulum's m g cos phi + m l phi'^2 and the weight below at rest") {
  const double m = 1.3, l = 0.7, g = 9.81, phi = 0.9, p = 0.8;
  npend::chain_parameters one;
  one.masses = {m};
  one.lengths = {l};
  one.g = g;
  const npend::chain single(one);
  const double rate = p / (m * l * l);
  const std::vector<double> x{phi, p};
  CHECK(npend::rod_tensions(single, x)[0] ==
        doctest::Approx(m * g * std::cos(phi) + m * l * rate * rate).epsilon(1e-14));

  npend::chain_parameters q;
  q.masses = {1.0, 2.0, 0.5};
  q.lengths = {1.0, 0.4, 2.0};
  q.g = g;
  const npend::chain triple(q);
  const auto tau = npend::rod_tensions(triple, std::vector<double>(6, 0.0));
  CHECK(tau[0] == doctest::Approx(3.5 * g).epsilon(1e-14));
  CHECK(tau[1] == doctest::Approx(2.5 * g).epsilon(1e-14));
  CHECK(tau[2] == doctest::Approx(0.5 * g).epsilon(1e-14));
}

TEST_CASE("rod tensions: refused for a physical chain and for wrong sizes") {
  npend::chain_parameters p = npend::chain_parameters::uniform(2);
  p.damping = {0.1, 0.1};
  const npend::chain damped(p);
  CHECK_THROWS_AS(npend::rod_tensions(damped, std::vector<double>(4, 0.0)), std::invalid_argument);
  const npend::chain c(npend::chain_parameters::uniform(2));
  CHECK_THROWS_AS(npend::rod_tensions(c, std::vector<double>(3, 0.0)), std::invalid_argument);
}
