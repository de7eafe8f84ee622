// FLI, MEGNO, SALI and GALI against what they are known to do: on a torus of the
// moderately excited triple pendulum ⟨Y⟩ → 2, SALI and GALI_2..GALI_3 stay away from 0,
// GALI_4 falls like t^-2 and FLI grows like ln t; on a chaotic orbit of the strongly excited
// one ⟨Y⟩ grows like λ₁ t / 2, FLI like λ₁ t, SALI falls like exp(−(λ₁ − λ₂) t) — with λ₁, λ₂
// from lyapunov_spectrum (Benettin's method with gauss6's exact tangent map, a different
// integrator and algorithm).
#include <doctest/doctest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "npend/analysis/chaos/chaos_indicators.hpp"
#include "npend/analysis/chaos/lyapunov.hpp"
#include "npend/excitation.hpp"
#include "npend/integrators/integrate.hpp"

namespace {

npend::chain triple() { return npend::chain(npend::chain_parameters::uniform(3)); }

std::vector<double> zigzag(const npend::chain& c, double epsilon) {
  const std::vector<double> direction{1.0, -1.0, 1.0};
  return npend::deflected_state(c, npend::energy_from_epsilon(c, epsilon), direction);
}

// Least-squares slope of y against t over the samples with t in [from, to] and y finite.
template <class Value>
double slope(const std::vector<npend::chaos_indicator_sample>& h, double from, double to,
             Value value) {
  double n = 0, st = 0, sy = 0, stt = 0, sty = 0;
  for (const auto& s : h) {
    const double y = value(s);
    if (s.t < from || s.t > to || !std::isfinite(y)) continue;
    n += 1;
    st += s.t;
    sy += y;
    stt += s.t * s.t;
    sty += s.t * y;
  }
  REQUIRE(n >= 3);
  return (n * sty - st * sy) / (n * stt - st * st);
}

// |measured / expected − 1| ≤ tolerance (doctest's Approx scales by 1 + |value|, too loose
// for rates below 1).
bool within(double measured, double expected, double tolerance) {
  return std::fabs(measured / expected - 1) <= tolerance;
}

}  // namespace

TEST_CASE("chaos indicators: a torus of the moderately excited triple pendulum") {
  // ε = 0.3 is still regular (ε = 0.5 is chaotic). At the paper's weak ε = 0.01 the motion
  // is so nearly linear — isochronous, deviations barely grow — that ⟨Y⟩ takes far longer to
  // reach 2 (1.01 at t = 2000 s).
  const auto c = triple();
  npend::chaos_indicator_options o;
  o.t_end = 4000;
  o.dt = 0.01;
  o.vectors = 4;
  o.sample_interval = 1;
  const auto r = npend::chaos_indicators(c, zigzag(c, 0.3), o);
  MESSAGE("torus: <Y> = " << r.last.mean_megno << ", SALI = " << r.last.sali
                          << ", FLI = " << r.last.fli);
  CHECK(std::fabs(r.last.mean_megno - 2) < 0.1);
  CHECK(std::fabs(2 - r.last.mean_megno) < std::fabs(2 - r.history[999].mean_megno));
  double least_sali = 1;
  for (const auto& s : r.history)
    if (s.t >= 200) least_sali = std::min(least_sali, s.sali);
  CHECK(least_sali > 1e-3);
  // Against ln t from t = 200 s on: GALI_2 and GALI_3 stay (the torus has dimension 3),
  // GALI_4 falls like t^-2 (Skokos, Bountis & Antonopoulos 2007); FLI grows like ln t, the
  // linear growth of deviations on a torus.
  const auto log_slope = [&](auto value) {
    std::vector<npend::chaos_indicator_sample> logged;
    for (const auto& s : r.history) {
      npend::chaos_indicator_sample l;
      l.t = std::log(s.t);
      l.fli = value(s);
      logged.push_back(l);
    }
    return slope(logged, std::log(200.0), std::log(4000.0), [](const auto& s) { return s.fli; });
  };
  CHECK(std::fabs(log_slope([](const auto& s) { return std::log(s.gali[0]); })) < 0.3);
  CHECK(std::fabs(log_slope([](const auto& s) { return std::log(s.gali[1]); })) < 0.3);
  CHECK(within(log_slope([](const auto& s) { return std::log(s.gali[2]); }), -2, 0.1));
  CHECK(within(log_slope([](const auto& s) { return s.fli; }), 1, 0.1));
}

TEST_CASE("chaos indicators: a chaotic orbit of the strong triple pendulum") {
  const auto c = triple();
  const auto x0 = zigzag(c, 1.5);
  npend::lyapunov_options lo;
  lo.integration.t_end = 1000;
  lo.integration.dt = 0.005;
  const auto spectrum = npend::lyapunov_spectrum(c, x0, lo);
  const double l1 = spectrum.exponents[0];
  REQUIRE(l1 > 0.2);

  npend::chaos_indicator_options o;
  o.t_end = 1000;
  o.dt = 0.005;
  o.sample_interval = 1;
  const auto r = npend::chaos_indicators(c, x0, o);
  const double megno_slope =
      slope(r.history, 200, 1000, [](const auto& s) { return s.mean_megno; });
  const double fli_slope = slope(r.history, 200, 1000, [](const auto& s) { return s.fli; });
  MESSAGE("lambda_1 = " << l1 << ": MEGNO slope " << megno_slope << ", FLI slope " << fli_slope);
  CHECK(within(megno_slope, l1 / 2, 0.1));
  CHECK(within(fli_slope, l1, 0.1));
  CHECK(r.last.sali < 1e-12);
}

TEST_CASE("chaos indicators: SALI falls like exp(-(lambda_1 - lambda_2) t)") {
  // SALI reaches round-off within a minute here, too short for one run's rate to settle:
  // over ten 40 s stretches of one chaotic orbit, Σ ln SALI(40 s) against
  // −Σ (λ₁ − λ₂) · 40 s of the finite-time exponents of the same stretches.
  const auto c = triple();
  std::vector<std::vector<double>> starts;
  npend::integration_options along;
  along.t_end = 900;
  along.dt = 0.01;
  npend::integrate(c, zigzag(c, 1.5), along, [&](double t, std::span<const double> x) {
    if (std::fmod(t + 1e-9, 100.0) < 1e-6) starts.emplace_back(x.begin(), x.end());
  });
  REQUIRE(starts.size() == 10);
  double log_sali = 0, expected = 0;
  for (const auto& start : starts) {
    npend::chaos_indicator_options o;
    o.t_end = 40;
    o.dt = 0.005;
    const auto r = npend::chaos_indicators(c, start, o);
    REQUIRE(r.last.sali > 1e-14);  // still above round-off
    log_sali += std::log(r.last.sali);
    npend::lyapunov_options lo;
    lo.integration.t_end = 40;
    lo.integration.dt = 0.005;
    const auto l = npend::lyapunov_spectrum(c, start, lo).exponents;
    expected -= (l[0] - l[1]) * 40;
  }
  MESSAGE("sum of ln SALI " << log_sali << ", of -(lambda_1 - lambda_2) t " << expected);
  CHECK(within(log_sali, expected, 0.1));
}

TEST_CASE("chaos indicators: bad input") {
  const auto c = triple();
  const std::vector<double> x0(6, 0.1);
  npend::chaos_indicator_options o;
  o.t_end = 1;
  o.vectors = 1;
  CHECK_THROWS_WITH_AS(npend::chaos_indicators(c, x0, o),
                       doctest::Contains("vectors is 1: it must be 2..6"), std::invalid_argument);
  o.vectors = 7;
  CHECK_THROWS_AS(npend::chaos_indicators(c, x0, o), std::invalid_argument);
  o.vectors = 2;
  o.dt = 0;
  CHECK_THROWS_WITH_AS(npend::chaos_indicators(c, x0, o), doctest::Contains("0 < dt <= t_end"),
                       std::invalid_argument);
  o.dt = 0.01;
  CHECK_THROWS_AS(npend::chaos_indicators(c, std::vector<double>(5, 0.0), o),
                  std::invalid_argument);
  std::vector<double> bad = x0;
  bad[2] = NAN;
  CHECK_THROWS_WITH_AS(npend::chaos_indicators(c, bad, o), doctest::Contains("not finite"),
                       std::invalid_argument);
}
