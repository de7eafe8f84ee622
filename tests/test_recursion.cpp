// The hand-written O(n) recursion (tests/reference/chain_recursion.hpp), the benchmarks'
// lower limit, against the generated right-hand side for every link count in this build.
#include <doctest/doctest.h>

#include <stdexcept>

#include "npend/chain.hpp"
#include "reference/chain_recursion.hpp"
#include "support/test_support.hpp"

using npend::test::relative_error;

TEST_CASE("chain_recursion: rhs matches the generated rhs for every built link count") {
  for (const int n : npend::built_link_counts()) {
    std::mt19937_64 rng(300 + static_cast<unsigned>(n));
    double worst = 0;
    for (int s = 0; s < 200; ++s) {
      const auto params = npend::test::random_parameters(n, rng);
      const npend::chain generated(params);
      npend::reference::chain_recursion recursion(params.masses, params.lengths, params.g);
      const auto x = npend::test::random_state(n, rng);
      std::vector<double> f(x.size());
      recursion.rhs(x.data(), f.data());
      worst = std::max(worst, relative_error(f, generated.rhs(x)));
    }
    INFO("n = ", n, ": worst relative error ", worst);
    CHECK(worst < 1e-12);
  }
}

TEST_CASE("chain_recursion: the simple pendulum is p/(m l^2) and -m g l sin phi") {
  const double m = 1.5, l = 0.8, g = 9.81, phi = 0.7, p = -0.4;
  const std::vector<double> masses{m}, lengths{l};
  npend::reference::chain_recursion recursion(masses, lengths, g);
  const double x[2] = {phi, p};
  double f[2];
  recursion.rhs(x, f);
  CHECK(f[0] == doctest::Approx(p / (m * l * l)).epsilon(1e-15));
  CHECK(f[1] == doctest::Approx(-m * g * l * std::sin(phi)).epsilon(1e-15));
}

TEST_CASE("chain_recursion: rejects an empty chain and mismatched masses and lengths") {
  const std::vector<double> two{1.0, 1.0}, one{1.0}, none;
  CHECK_THROWS_AS(npend::reference::chain_recursion(two, one, 9.81), std::invalid_argument);
  CHECK_THROWS_AS(npend::reference::chain_recursion(none, none, 9.81), std::invalid_argument);
}
