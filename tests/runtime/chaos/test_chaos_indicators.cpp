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
#include "npend/analysis/chaos/chaos_map.hpp"
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

TEST_CASE("chaos indicators on taylor: rk4's at a fine step on a torus of the double pendulum") {
  // Two integrators and two ways to MEGNO's integrals (rk4 carries them as ODEs; Taylor
  // integrates ln‖w‖ by parts over its steps): on a regular orbit, where neither amplifies
  // its errors, all the indicators agree to well below rk4's error at dt (~1e-11 here).
  const npend::chain c(npend::chain_parameters::uniform(2));
  const std::vector<double> x0{0.3, 0.3, 0, 0};
  npend::chaos_indicator_options o;
  o.t_end = 50;
  o.dt = 5e-4;
  o.vectors = 4;
  o.sample_interval = 12.5;
  const auto reference = npend::chaos_indicators(c, x0, o);
  o.stepper = npend::stepper_kind::taylor;
  o.tolerance = 1e-12;
  const auto r = npend::chaos_indicators(c, x0, o);
  // The steps land on the sample times.
  REQUIRE(r.history.size() == 4);
  for (std::size_t i = 0; i < 4; ++i) CHECK(r.history[i].t == 12.5 * static_cast<double>(i + 1));
  CHECK(r.last.t == 50);
  for (std::size_t i = 0; i < r.state.size(); ++i)
    CHECK(std::fabs(r.state[i] - reference.state[i]) <= 1e-10);
  const auto agree = [](double a, double b, double tolerance) {
    return std::fabs(a - b) <= tolerance * std::fabs(b);
  };
  for (std::size_t k = 0; k < 4; ++k) {
    const auto& a = r.history[k];
    const auto& b = reference.history[k];
    // rk4's FLI is the largest ln‖w‖ at its step ends, off the true maximum by about
    // (dt/2)² L''; Taylor's locates the maximum within its steps.
    CHECK(agree(a.fli, b.fli, 1e-7));
    CHECK(agree(a.megno, b.megno, 1e-9));
    CHECK(agree(a.mean_megno, b.mean_megno, 1e-9));
    CHECK(agree(a.sali, b.sali, 1e-8));
    for (std::size_t j = 0; j < 3; ++j) CHECK(agree(a.gali[j], b.gali[j], 1e-8));
  }
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

TEST_CASE("chaos indicators on taylor: rk4's on the chaotic triple pendulum while they agree") {
  // Over 15 s both runs stay on the same chaotic trajectory (errors grow by e^(λ₁ t) ≈ 600);
  // over 1000 s they part, and their finite-time rates scatter by some 20 %.
  const auto c = triple();
  const auto x0 = zigzag(c, 1.5);
  npend::chaos_indicator_options o;
  o.t_end = 15;
  o.dt = 1e-4;
  o.vectors = 3;
  const auto reference = npend::chaos_indicators(c, x0, o);
  o.stepper = npend::stepper_kind::taylor;
  o.tolerance = 1e-13;
  const auto r = npend::chaos_indicators(c, x0, o);
  MESSAGE("chaotic, t = 15: FLI " << r.last.fli << " (rk4 " << reference.last.fli << "), <Y> "
                                  << r.last.mean_megno << " (rk4 " << reference.last.mean_megno
                                  << ")");
  REQUIRE(r.last.fli > 3);
  CHECK(std::fabs(r.last.fli - reference.last.fli) <= 1e-6 * reference.last.fli);
  CHECK(std::fabs(r.last.megno - reference.last.megno) <= 1e-6 * reference.last.megno);
  CHECK(std::fabs(r.last.mean_megno - reference.last.mean_megno) <=
        1e-6 * reference.last.mean_megno);
  CHECK(std::fabs(std::log(r.last.sali / reference.last.sali)) <= 1e-5);
  CHECK(std::fabs(std::log(r.last.gali[1] / reference.last.gali[1])) <= 1e-5);
}

TEST_CASE("chaos indicators: refuses other steppers and bad taylor tolerances") {
  const npend::chain c(npend::chain_parameters::uniform(2));
  const std::vector<double> x0{0.3, 0.3, 0, 0};
  npend::chaos_indicator_options o;
  o.t_end = 1;
  o.stepper = npend::stepper_kind::gauss6;
  CHECK_THROWS_WITH_AS(npend::chaos_indicators(c, x0, o),
                       "chaos indicators: they integrate with rk4, taylor, not gauss6",
                       std::invalid_argument);
  o.stepper = npend::stepper_kind::taylor;
  for (const double tolerance : {0.0, 1e-5, std::nan("")}) {
    o.tolerance = tolerance;
    CHECK_THROWS_WITH_AS(npend::chaos_indicators(c, x0, o),
                         doctest::Contains("the taylor tolerance must lie in (0, 1e-6]"),
                         std::invalid_argument);
  }
  // Seven links run on the loop kernels, which have no Taylor kernels.
  o.tolerance = 1e-10;
  const npend::chain seven(npend::chain_parameters::uniform(7));
  CHECK_THROWS_WITH_AS(npend::chaos_indicators(seven, std::vector<double>(14, 0.1), o),
                       doctest::Contains("taylor"), std::invalid_argument);
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

TEST_CASE("map cells on taylor: each the chaos indicator of its start, refusals named") {
  // The map runs taylor's indicators cell by cell (the lanes have no Taylor steps): each cell
  // is chaos_indicators' value at t_end, whatever the cells beside it.
  const npend::chain c(npend::chain_parameters::uniform(2));
  const std::vector<double> starts{0.3, 0.3, 0, 0, 1.5, 1.5, 0, 0, 2.0, -1.0, 0, 0};
  npend::map_cell_options o;
  o.quantity = npend::map_quantity::megno;
  o.t_end = 20;
  o.stepping.stepper = npend::stepper_kind::taylor;
  o.stepping.abs_tol = o.stepping.rel_tol = 1e-11;
  const std::vector<double> cells = npend::map_cells(c, starts, o);
  REQUIRE(cells.size() == 3);
  for (std::size_t k = 0; k < 3; ++k) {
    npend::chaos_indicator_options io;
    io.t_end = 20;
    io.stepper = npend::stepper_kind::taylor;
    io.tolerance = 1e-11;
    const std::vector<double> x0(starts.begin() + static_cast<std::ptrdiff_t>(4 * k),
                                 starts.begin() + static_cast<std::ptrdiff_t>(4 * k + 4));
    CHECK(cells[k] == npend::chaos_indicators(c, x0, io).last.mean_megno);
  }
  o.quantity = npend::map_quantity::flip;
  CHECK_THROWS_WITH_AS(npend::map_cells(c, starts, o),
                       "flip: taylor maps only the chaos indicators (fli, megno, sali, gali)",
                       std::invalid_argument);
  o.quantity = npend::map_quantity::fli;
  o.stepping.abs_tol = 1e-9;
  CHECK_THROWS_WITH_AS(npend::map_cells(c, starts, o),
                       doctest::Contains("taylor takes one tolerance"), std::invalid_argument);
  o.stepping.abs_tol = o.stepping.rel_tol = 1e-4;
  CHECK_THROWS_WITH_AS(npend::map_cells(c, starts, o),
                       doctest::Contains("the taylor tolerance must lie in (0, 1e-6]"),
                       std::invalid_argument);
  CHECK(npend::map_stepper_names() == "rk4, dopri5, gauss4, gauss6, taylor");
}
