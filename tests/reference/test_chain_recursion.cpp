// The hand-written O(n) recursion (tests/reference/include/reference/chain_recursion.hpp), the
// benchmarks' lower limit: its closed form for one link and its argument checks. Its
// agreement with the generated rhs for every built link count is checked where the
// benchmarks use it (tests/bench/test_bench_peers.cpp).
#include <doctest/doctest.h>

#include <stdexcept>

#include "npend/chain.hpp"
#include "reference/chain_recursion.hpp"
#include "support/test_support.hpp"

using npend::test::relative_error;

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
