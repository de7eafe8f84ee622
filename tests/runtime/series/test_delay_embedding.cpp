// delay_embedding, average_mutual_information, choose_delay, false_nearest_neighbours and
// cao_embedding on systems whose dimension is known.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>

#include "npend/analysis/series/delay_embedding.hpp"
#include "npend/analysis/series/embedding_dimension.hpp"
#include "npend/analysis/series/mutual_information.hpp"
#include "support/test_signals.hpp"

using namespace npend;
using std::numbers::pi;

namespace {

const double sine_omega = 2 * pi * 1.3;  // T = 0.769 s
const double sine_dt = 0.001;
std::vector<double> sine() { return test::sum_of_sines({{1, sine_omega, 0.2}}, 16384, sine_dt); }

}  // namespace

TEST_CASE("delay_embedding: rows are (x_j, x_{j−τ}, …, x_{j−(m−1)τ})") {
  std::vector<double> x(20);
  for (std::size_t j = 0; j < x.size(); ++j) x[j] = static_cast<double>(j * j);
  const auto v = delay_embedding(x, 3, 4);
  CHECK(v.count == 20 - 9);
  for (std::size_t i = 0; i < v.count; ++i)
    for (std::size_t c = 0; c < 4; ++c) CHECK(v.points[i * 4 + c] == x[i + 9 - 3 * c]);
  CHECK_THROWS_WITH_AS(delay_embedding(x, 7, 4),
                       "x has 20 samples; dimension 4 at delay 7 needs more than 21",
                       std::invalid_argument);
  CHECK_THROWS_AS(delay_embedding(x, 0, 2), std::invalid_argument);
}

TEST_CASE("average_mutual_information: I(0) is the entropy of the binned series") {
  std::mt19937_64 rng(9);
  std::normal_distribution<double> normal(0, 1);
  std::vector<double> x(5000);
  for (auto& v : x) v = normal(rng);
  const std::size_t bins = 12;
  const auto ami = average_mutual_information(
      x, 0.1, 5, {.bins = bins, .estimator = mutual_information_estimator::tisean});
  const auto [lo, hi] = std::minmax_element(x.begin(), x.end());
  std::vector<double> p(bins);
  for (const double v : x)
    p[std::min(bins - 1, static_cast<std::size_t>((v - *lo) / (*hi - *lo) * bins))] +=
        1.0 / x.size();
  double entropy = 0;
  for (const double q : p)
    if (q > 0) entropy -= q * std::log2(q);
  CHECK(ami.information[0] == doctest::Approx(entropy).epsilon(1e-12));
  CHECK(ami.lag[5] == doctest::Approx(0.5));
}

TEST_CASE("average_mutual_information: independent samples share almost no information") {
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<double> x(20000);
  for (auto& v : x) v = u(rng);
  const auto ami = average_mutual_information(
      x, 1.0, 5, {.bins = 16, .estimator = mutual_information_estimator::tisean});
  CHECK(ami.information[0] == doctest::Approx(4).epsilon(0.005));  // log₂ 16, uniform
  // The histogram bias is about (B−1)²/(2 N ln 2) ≈ 0.008 bit.
  for (std::size_t k = 1; k <= 5; ++k) CHECK(ami.information[k] < 0.02);
}

TEST_CASE(
    "average_mutual_information: the averaged estimate's first minimum of a sine is near a quarter "
    "period") {
  // A sine's pairs lie on a curve, and a single histogram's I(tau) zigzags from lag to lag by
  // more than it falls (TISEAN's estimate, the default, finds its first dip at 0.107 s here):
  // the averaged shifted histograms smooth that out.
  const auto ami = average_mutual_information(
      sine(), sine_dt, 400, {.estimator = mutual_information_estimator::averaged});
  REQUIRE(ami.first_minimum);
  // Pairs in quadrature lie on a circle: the least dependence a sine's pairs show.
  CHECK(*ami.first_minimum == doctest::Approx(pi / 2 / sine_omega).epsilon(0.1));
}

TEST_CASE("choose_delay: each method on a sine") {
  const auto x = sine();
  const double quarter = pi / 2 / sine_omega;
  const auto t4 = choose_delay(x, sine_dt, delay_method::quarter_period);
  REQUIRE(t4.found);
  CHECK(t4.estimate == doctest::Approx(quarter).epsilon(0.01));
  CHECK(t4.samples == static_cast<std::size_t>(std::lround(t4.estimate / sine_dt)));
  CHECK(t4.seconds == doctest::Approx(static_cast<double>(t4.samples) * sine_dt));
  const auto zero = choose_delay(x, sine_dt, delay_method::acf_zero);
  CHECK(zero.estimate == doctest::Approx(quarter).epsilon(0.01));
  const auto minimum = choose_delay(x, sine_dt, delay_method::acf_minimum);
  CHECK(minimum.estimate == doctest::Approx(2 * quarter).epsilon(0.01));
  // The averaged estimate (on a sine the default single histogram zigzags: see above).
  const auto automatic = choose_delay(x, sine_dt, delay_method::automatic,
                                      {.estimator = mutual_information_estimator::averaged});
  REQUIRE(automatic.found);
  CHECK(automatic.method == delay_method::mutual_information);
  CHECK(automatic.estimate == doctest::Approx(quarter).epsilon(0.1));
  CHECK(delay_method_from_name("acf-min") == delay_method::acf_minimum);
  CHECK(delay_method_name(delay_method::quarter_period) == "T/4");
  CHECK_FALSE(delay_method_from_name("T/3"));
}

TEST_CASE("false_nearest_neighbours: a sine embeds in 2 dimensions") {
  const auto x = sine();
  // A quarter period, the delay that puts a sine's delay vectors on a circle (the single
  // histogram's mutual information, the default, zigzags on a sine: see above).
  const std::size_t tau = choose_delay(x, sine_dt, delay_method::quarter_period).samples;
  const auto fnn = false_nearest_neighbours(x, tau, 5, {.theiler_window = tau});
  REQUIRE(fnn.found);
  CHECK(fnn.dimension == 2);
  CHECK(fnn.fraction[0] > 0.2);  // on a line, points going up and down are neighbours
  CHECK(fnn.fraction[1] < 0.01);
  const auto cao = cao_embedding(x, tau, 5, {.theiler_window = tau});
  REQUIRE(cao.found);
  CHECK(cao.dimension == 2);
  CHECK(cao.e1[0] < 0.1);
}

TEST_CASE("false_nearest_neighbours: the Hénon map's x-series embeds in 2 dimensions") {
  const auto x = test::henon_x(4000);
  const auto fnn = false_nearest_neighbours(x, 1, 5);
  REQUIRE(fnn.found);
  CHECK(fnn.dimension == 2);
  CHECK(fnn.fraction[0] > 0.5);
  const auto cao = cao_embedding(x, 1, 5);
  REQUIRE(cao.found);
  CHECK(cao.dimension == 2);
}

TEST_CASE("false_nearest_neighbours: the Lorenz attractor embeds in 3 dimensions") {
  const double dt = 0.01;
  const auto x = test::lorenz_x(10000, dt);
  const auto tau = choose_delay(x, dt);  // the mutual information's minimum, ≈ 0.17 s
  REQUIRE(tau.found);
  CHECK(tau.seconds == doctest::Approx(0.17).epsilon(0.15));
  const auto fnn = false_nearest_neighbours(x, tau.samples, 6, {.theiler_window = tau.samples});
  REQUIRE(fnn.found);
  CHECK(fnn.dimension == 3);
  CHECK(fnn.fraction[1] > 0.02);  // the 2-D projection still folds the attractor
  const auto cao = cao_embedding(x, tau.samples, 6, {.theiler_window = tau.samples});
  REQUIRE(cao.found);
  CHECK(cao.dimension == 3);
  CHECK(cao.e1[1] < 0.5);
}

TEST_CASE("false_nearest_neighbours: white noise has no small embedding dimension") {
  std::mt19937_64 rng(17);
  std::normal_distribution<double> normal(0, 1);
  std::vector<double> x(5000);
  for (auto& v : x) v = normal(rng);
  const auto fnn = false_nearest_neighbours(x, 1, 5);
  CHECK_FALSE(fnn.found);
  CHECK(fnn.dimension == 0);
  // Cao's E2 stays near 1 for random data.
  const auto cao = cao_embedding(x, 1, 5);
  for (const double e2 : cao.e2) CHECK(e2 == doctest::Approx(1).epsilon(0.1));
}

TEST_CASE("false_nearest_neighbours: bad arguments throw naming them") {
  const auto x = sine();
  CHECK_THROWS_WITH_AS(false_nearest_neighbours(std::vector<double>(100, 1.0), 1, 3),
                       "x is constant: it has no embedding dimension", std::invalid_argument);
  CHECK_THROWS_WITH_AS(
      false_nearest_neighbours(std::vector<double>(x.begin(), x.begin() + 50), 10, 5),
      "x has 50 samples; max_dimension 5 at delay 10 with a Theiler window of 0 needs at least 53",
      std::invalid_argument);
  CHECK_THROWS_AS(false_nearest_neighbours(x, 0, 3), std::invalid_argument);
  CHECK_THROWS_AS(cao_embedding(x, 1, 3, {.saturation = 0}), std::invalid_argument);
}
