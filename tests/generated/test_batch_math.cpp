// SLEEF's vectorised sincos behind the batch kernels (npend/batch_math.hpp): within 2 ulp of
// std::sin and std::cos over a dense sweep, at large arguments and at special points.
#include <doctest/doctest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <npend/batch_math.hpp>
#include <numbers>
#include <string>
#include <vector>

namespace {

constexpr int W = npend::batch_width;

// Distance in units in the last place between two doubles of the same sign (or both within
// an ulp of 0): the number of doubles between them.
double ulp_distance(double a, double b) {
  if (a == b) return 0;
  if (std::isnan(a) || std::isnan(b)) return std::isnan(a) && std::isnan(b) ? 0 : INFINITY;
  auto key = [](double x) {
    const auto bits = std::bit_cast<std::int64_t>(x);
    return bits < 0 ? std::numeric_limits<std::int64_t>::min() - bits : bits;
  };
  // The difference in integers (a double holds a key exactly only when it is small); keys of
  // opposite signs are far apart anyway.
  const std::int64_t ka = key(a), kb = key(b);
  if ((ka < 0) != (kb < 0))
    return std::fabs(static_cast<double>(ka)) + std::fabs(static_cast<double>(kb));
  return static_cast<double>(ka > kb ? ka - kb : kb - ka);
}

struct worst {
  double sin = 0, cos = 0;
  double sin_at = 0, cos_at = 0;
};

// Runs batch_sincos over `args` (W at a time, the tail padded with the first) and records
// the worst ulp distances from std::sin / std::cos.
worst sweep(const std::vector<double>& args) {
  worst w;
  double x[W], s[W], c[W];
  for (std::size_t i = 0; i < args.size(); i += W) {
    for (int l = 0; l < W; ++l) {
      const std::size_t k = i + static_cast<std::size_t>(l);
      x[l] = k < args.size() ? args[k] : args[0];
    }
    npend::batch_sincos(x, s, c);
    for (int l = 0; l < W; ++l) {
      const double ds = ulp_distance(s[l], std::sin(x[l]));
      const double dc = ulp_distance(c[l], std::cos(x[l]));
      if (ds > w.sin) w = {ds, w.cos, x[l], w.cos_at};
      if (dc > w.cos) w = {w.sin, dc, w.sin_at, x[l]};
    }
  }
  return w;
}

}  // namespace

TEST_CASE("batch_sincos: within 2 ulp of std::sin and std::cos over a dense sweep") {
  std::vector<double> args;
  // |x| ≤ 8: the range of a pendulum's angles, 2 million points.
  for (int i = -1000000; i <= 1000000; ++i) args.push_back(8.0 * i / 1000000.0);
  // Large |x| up to 1e4 (argument reduction), and a few far beyond.
  for (int i = -200000; i <= 200000; ++i) args.push_back(1e4 * i / 200000.0 + 0.123456789);
  for (const double big : {1e5, 1e6, 1e8, 1e10, 1e15, 1e22, 1e300}) {
    args.push_back(big);
    args.push_back(-big);
  }
  const worst w = sweep(args);
  INFO("isa " << std::string(npend::batch_isa()) << ", worst sin " << w.sin << " ulp at "
              << w.sin_at << ", worst cos " << w.cos << " ulp at " << w.cos_at);
  CHECK(w.sin <= 2);
  CHECK(w.cos <= 2);
}

TEST_CASE("batch_sincos: special points") {
  const double pi = std::numbers::pi;
  const std::vector<double> special{0.0,    -0.0,   pi,       -pi,       pi / 2, -pi / 2,
                                    2 * pi, 1e-300, -1e-300,  0x1p-1074, 1e-8,   -1e-8,
                                    3 * pi, pi / 4, 100 * pi, 1e4 * pi};
  const worst w = sweep(special);
  INFO("worst sin " << w.sin << " ulp at " << w.sin_at << ", worst cos " << w.cos << " ulp at "
                    << w.cos_at);
  CHECK(w.sin <= 2);
  CHECK(w.cos <= 2);
  // Exact values where they are exact: sin(±0) = ±0, cos(0) = 1, sin of a tiny x is x.
  double x[W], s[W], c[W];
  for (int l = 0; l < W; ++l) x[l] = l % 2 ? -0.0 : 1e-300;
  x[0] = 0.0;
  npend::batch_sincos(x, s, c);
  CHECK(s[0] == 0.0);
  CHECK_FALSE(std::signbit(s[0]));
  CHECK(c[0] == 1.0);
  CHECK(std::signbit(s[1]));
  for (int l = 2; l < W; ++l) CHECK(s[l] == x[l]);
}

TEST_CASE("batch_sincos: NaN for infinite and NaN arguments") {
  double x[W], s[W], c[W];
  for (int l = 0; l < W; ++l) x[l] = l % 3 == 0 ? INFINITY : l % 3 == 1 ? -INFINITY : NAN;
  npend::batch_sincos(x, s, c);
  for (int l = 0; l < W; ++l) {
    CHECK(std::isnan(s[l]));
    CHECK(std::isnan(c[l]));
  }
}

TEST_CASE("batch_isa: names the instruction set of batch_width") {
  const std::string isa = npend::batch_isa();
  if (isa == "avx512f")
    CHECK(W == 8);
  else if (isa == "avx2" || isa == "avx")
    CHECK(W == 4);
  else
    CHECK((isa == "sse2" && W == 2));
}
