// The hanging chain's modes for any n (analysis/hanging_chain.hpp) against the generated
// chain's normal modes, the simple pendulum, and the heavy rope's Bessel modes in the limit.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include "npend/analysis/stability/hanging_chain.hpp"
#include "npend/analysis/stability/normal_modes.hpp"
#include "npend/chain.hpp"
#include "support/test_support.hpp"

namespace {

// The relative errors of the first `count` frequencies of the uniform n-link chain of length
// L = 1.3 m against the rope's.
std::vector<double> rope_errors(int n, int count) {
  const double L = 1.3, g = 9.81;
  const std::vector<double> masses(static_cast<std::size_t>(n), 2.0 / n),
      lengths(static_cast<std::size_t>(n), L / n);
  const auto modes = npend::hanging_chain_modes(masses, lengths, g, count);
  std::vector<double> err;
  for (int k = 1; k <= count; ++k)
    err.push_back(std::fabs(
        modes[static_cast<std::size_t>(k - 1)].frequency / npend::rope_frequency(k, L, g) - 1));
  return err;
}

}  // namespace

TEST_CASE("hanging chain: the frequencies of the generated chain's normal modes at rest") {
  std::mt19937_64 rng(1501);
  for (int n = 1; n <= 6; ++n) {
    const npend::chain_parameters p = npend::test::random_parameters(n, rng);
    const npend::chain c(p);
    const auto expected = npend::normal_modes(c, std::vector<double>(static_cast<std::size_t>(n)));
    const auto modes = npend::hanging_chain_modes(p.masses, p.lengths, p.g, n);
    for (int k = 0; k < n; ++k) {
      INFO("n = " << n << ", mode " << k + 1);
      CHECK(modes[static_cast<std::size_t>(k)].frequency ==
            doctest::Approx(expected.modes[static_cast<std::size_t>(k)].frequency).epsilon(1e-11));
    }
  }
}

TEST_CASE("hanging chain: one link is the simple pendulum sqrt(g/l)") {
  const std::vector<double> m{0.7}, l{1.9};
  const auto modes = npend::hanging_chain_modes(m, l, 9.81, 1);
  CHECK(modes[0].frequency == doctest::Approx(std::sqrt(9.81 / 1.9)).epsilon(1e-15));
  CHECK(modes[0].displacement == std::vector<double>{1.0});
}

TEST_CASE("hanging chain: the uniform chain's modes converge to the heavy rope's") {
  // The bounds: the first five within 0.25 % at n = 100 and 0.05 % at n = 1000.
  const auto e100 = rope_errors(100, 5), e1000 = rope_errors(1000, 5);
  for (int k = 0; k < 5; ++k) {
    INFO("mode " << k + 1 << ": " << e100[static_cast<std::size_t>(k)] << " at n = 100, "
                 << e1000[static_cast<std::size_t>(k)] << " at n = 1000");
    CHECK(e100[static_cast<std::size_t>(k)] < 2.5e-3);
    CHECK(e1000[static_cast<std::size_t>(k)] < 5e-4);
    // First order in 1/n (docs/commands.md, npend rope): tenfold more links, tenfold less.
    const double order =
        std::log10(e100[static_cast<std::size_t>(k)] / e1000[static_cast<std::size_t>(k)]);
    CHECK(order == doctest::Approx(1.0).epsilon(0.1));
  }
  // The shape of mode 2 at n = 1000 against J0(j_{0,2} sqrt(s/L)), s from the free end.
  const int n = 1000;
  const double L = 1.3;
  const std::vector<double> masses(n, 1.0 / n), lengths(n, L / n);
  const auto modes = npend::hanging_chain_modes(masses, lengths, 9.81, 2);
  double worst = 0;
  for (int i = 1; i <= n; ++i) {
    const double s = L * (n - i) / n;
    worst = std::max(worst, std::fabs(modes[1].displacement[static_cast<std::size_t>(i - 1)] -
                                      npend::rope_shape(2, s, L)));
  }
  CHECK(worst < 2e-3);
}

TEST_CASE("hanging chain: bad input is refused with the reason") {
  const std::vector<double> one{1.0}, two{1.0, 1.0}, negative{-1.0};
  CHECK_THROWS_AS(npend::hanging_chain_modes(one, two, 9.81, 1), std::invalid_argument);
  CHECK_THROWS_AS(npend::hanging_chain_modes(two, two, 9.81, 3), std::invalid_argument);
  CHECK_THROWS_AS(npend::hanging_chain_modes(negative, one, 9.81, 1), std::invalid_argument);
  CHECK_THROWS_AS(npend::hanging_chain_modes(one, one, 0.0, 1), std::invalid_argument);
  CHECK_THROWS_AS(npend::rope_frequency(0, 1.0, 9.81), std::invalid_argument);
}

TEST_CASE("convergence_order: the exponent of errors that fall like a power of n") {
  // e = 0.7 n^-2 and e = 0.3 n^-1 exactly; the sign of an error does not matter.
  CHECK(npend::convergence_order(0.7 / (10.0 * 10.0), 10, 0.7 / (40.0 * 40.0), 40) ==
        doctest::Approx(2.0).epsilon(1e-14));
  CHECK(npend::convergence_order(-0.3 / 50.0, 50, 0.3 / 200.0, 200) ==
        doctest::Approx(1.0).epsilon(1e-14));
  CHECK_THROWS_AS(npend::convergence_order(0.1, 10, 0.05, 10), std::invalid_argument);
  CHECK_THROWS_AS(npend::convergence_order(0.1, 0, 0.05, 10), std::invalid_argument);
}
