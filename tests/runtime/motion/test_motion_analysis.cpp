// The analysis pipeline of the library (paper §6.6 from one integration): the signals a
// simulation records, the bounded observables of its angles, the summaries the results carry
// (energy drift, section quality, Lyapunov pair sums), and analyze_motion end to end.
#include <doctest/doctest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "npend/analysis/chaos/lyapunov.hpp"
#include "npend/analysis/motion/energy_drift.hpp"
#include "npend/analysis/motion/motion_analysis.hpp"
#include "npend/analysis/series/sampled_signals.hpp"
#include "npend/integrators/integrate.hpp"

using npend::chain;

namespace {

const chain triple(npend::chain_parameters::uniform(3));

npend::simulated_start start(std::vector<double> x0, double t_end, std::size_t samples) {
  npend::integration_options o;
  o.t_end = t_end;
  o.dt = 1e-3;
  return {triple, std::move(x0), o, samples, "test"};
}

// Stops after the first progress report past `fraction` of the run.
struct stop_at final : npend::run_control {
  explicit stop_at(double f) : fraction(f) {}
  double fraction;
  bool past = false;
  void progress(double done, double total) override { past = past || done >= fraction * total; }
  bool stop_requested() override { return past; }
};

}  // namespace

TEST_CASE("relative_energy_error: relative to |H0|, absolute when H0 = 0") {
  CHECK(npend::relative_energy_error(10.5, 10.0) == doctest::Approx(0.05).epsilon(1e-15));
  CHECK(npend::relative_energy_error(-9.5, -10.0) == doctest::Approx(0.05).epsilon(1e-15));
  CHECK(npend::relative_energy_error(1e-12, 0.0) == 1e-12);
  CHECK(std::isfinite(npend::relative_energy_error(3.0, 0.0)));
}

TEST_CASE("energy_drift: the largest error over the states, H of the last one") {
  const std::vector<double> x0{0.3, -0.2, 0.5, 0, 0, 0};
  npend::energy_drift drift(triple, triple.hamiltonian(x0));
  CHECK(drift.max_relative_error() == 0);
  std::vector<double> a = x0, b = x0;
  a[3] = 0.1;  // more kinetic energy
  b[4] = 0.3;
  const double ha = triple.hamiltonian(a), hb = triple.hamiltonian(b), h0 = drift.initial();
  CHECK(drift.add(a) == ha);
  CHECK(drift.add(b) == hb);
  CHECK(drift.last() == hb);
  CHECK(drift.max_relative_error() ==
        std::max(std::fabs(ha - h0), std::fabs(hb - h0)) / std::fabs(h0));
}

TEST_CASE("simulate_signals: the grid's states as phi1..p3, stopped runs flagged") {
  const auto s = start({0.4, 0.1, -0.3, 0, 0, 0}, 2.0, 1001);
  const npend::simulated_signals r = npend::simulate_signals(s);
  REQUIRE(r.signals.names == std::vector<std::string>{"phi1", "phi2", "phi3", "p1", "p2", "p3"});
  CHECK(r.signals.default_signal == 2);
  REQUIRE(r.signals.samples() == 1001);
  CHECK(!r.run.stopped);
  // Sample 1000 is the state at t = 1 s of the same integration.
  auto half = s.integration;
  half.t_end = 1.0;
  const auto at_one = npend::integrate(triple, s.x0, half);
  for (std::size_t i = 0; i < 6; ++i) CHECK(r.signals.values[i][1000] == at_one.state[i]);

  stop_at control(0.25);
  auto stopped = s;
  stopped.integration.control = &control;
  const npend::simulated_signals cut = npend::simulate_signals(stopped);
  CHECK(cut.run.stopped);
  CHECK(cut.run.t < 1.0);
  CHECK(cut.signals.samples() < 1001);
}

TEST_CASE("chain_observable: sin, cos, wrapped angle and bob positions from the angles") {
  const auto r = npend::simulate_signals(start({2.5, -1.0, 3.0, 0, 0, 4.0}, 3.0, 3001)).signals;
  const auto x3 = npend::chain_observable(r, triple, "x3");
  const auto y2 = npend::chain_observable(r, triple, "y_2");
  const auto w3 = npend::chain_observable(r, triple, "wrapped_phi3");
  const auto s1 = npend::chain_observable(r, triple, "sin_phi1");
  REQUIRE(x3);
  REQUIRE(y2);
  REQUIRE(w3);
  REQUIRE(s1);
  CHECK(x3->unit == "m");
  std::vector<double> xy(6);
  for (std::size_t j = 0; j < r.samples(); j += 250) {
    const std::vector<double> phi{r.values[0][j], r.values[1][j], r.values[2][j]};
    triple.positions(phi, xy);  // the generated kernel: x_1, y_1, ..., x_3, y_3
    CHECK(x3->values[j] == doctest::Approx(xy[4]).epsilon(1e-14));
    CHECK(y2->values[j] == doctest::Approx(xy[3]).epsilon(1e-14));
    CHECK(std::fabs(w3->values[j]) <= std::numbers::pi);
    CHECK(std::sin(w3->values[j]) == doctest::Approx(std::sin(phi[2])).epsilon(1e-12));
    CHECK(s1->values[j] == std::sin(phi[0]));
  }
  CHECK(!npend::chain_observable(r, triple, "x4"));
  CHECK(!npend::chain_observable(r, triple, "sin_p1"));
  CHECK(!npend::chain_observable(r, triple, "x03"));
}

TEST_CASE("winds_over: an angle whose series covers more than a turn") {
  npend::time_series x{"test", "phi3", 0, 0.1, {0.0, 3.0, 6.3}, "rad"};
  CHECK(npend::winds_over(x));
  x.values.back() = 6.2;
  CHECK(!npend::winds_over(x));
  x = {"test", "p3", 0, 0.1, {0.0, 30.0}, ""};
  CHECK(!npend::winds_over(x));
}

TEST_CASE("crossing_quality: residual, energy error and unrefined crossings of a section") {
  std::vector<npend::section_crossing> crossings(2);
  crossings[0].state = {0.0, 0.3, 0.2, 1.0, 0.0, 0.0};
  crossings[1].state = {1e-13, 0.3, 0.2, 1.0, 0.0, 0.1};
  crossings[1].refined = false;
  const auto section = npend::section_plane::coordinate(3, 0, 0.0);
  const double h0 = triple.hamiltonian(crossings[0].state);
  const npend::section_quality q = npend::crossing_quality(triple, section, crossings, h0);
  CHECK(q.max_residual == 1e-13);
  CHECK(q.max_rel_energy_error ==
        npend::relative_energy_error(triple.hamiltonian(crossings[1].state), h0));
  CHECK(q.unrefined == 1);
  const npend::section_quality none = npend::crossing_quality(triple, section, {}, h0);
  CHECK(none.max_residual == 0);
  CHECK(none.unrefined == 0);
}

TEST_CASE("pair_sums: lambda_i + lambda_(d+1-i) of a spectrum, filled in the full spectrum") {
  const std::vector<double> spectrum{1.5, 0.25, 0.0, -0.0, -0.25, -1.5};
  CHECK(npend::pair_sums(spectrum) == std::vector<double>{0.0, 0.0, 0.0});
  CHECK(npend::pair_sums(std::vector<double>{2.0, 1.0, -3.0}) == std::vector<double>{-1.0});
  npend::lyapunov_options o;
  o.integration.t_end = 5;
  o.integration.dt = 0.005;
  const std::vector<double> x0{1.0, -1.0, 1.0, 0, 0, 0};
  const auto full = npend::lyapunov_spectrum(triple, x0, o);
  REQUIRE(full.pair_sums.size() == 3);
  for (std::size_t i = 0; i < 3; ++i)
    CHECK(full.pair_sums[i] == full.exponents[i] + full.exponents[5 - i]);
  CHECK(npend::maximal_lyapunov_exponent(triple, x0, o).pair_sums.empty());
}

TEST_CASE("analyze_motion: one integration gives the series, the section and the events") {
  npend::motion_analysis_options options;
  options.coordinate = 2;
  options.section = npend::section_plane::coordinate(3, 0, 0.0);
  options.event = npend::section_plane::coordinate(3, 2, 0.0);
  const auto s = start({0.1, -0.1, 0.1, 0, 0, 0}, 60.0, 8192);
  const npend::motion_analysis a = npend::analyze_motion(s, options);
  CHECK(!a.run.stopped);
  CHECK(a.series.name == "phi3");
  CHECK(a.series.values == a.signals.values[2]);
  // The section is φ1 = 0 upwards: once per period of the motion, over 60 s many times.
  REQUIRE(a.section.size() > 20);
  CHECK(a.section_quality.max_residual < 1e-12);
  CHECK(a.section_quality.max_rel_energy_error < 1e-9);
  CHECK(a.event_times.size() > 40);
  REQUIRE(!a.peaks.empty());
  CHECK(a.recurrence.has_value());

  stop_at control(0.1);
  auto stopped = s;
  stopped.integration.control = &control;
  const npend::motion_analysis cut = npend::analyze_motion(stopped, options);
  CHECK(cut.run.stopped);
  CHECK(cut.peaks.empty());

  options.coordinate = 6;
  CHECK_THROWS_AS(npend::analyze_motion(s, options), std::invalid_argument);
  options.coordinate = 2;
  CHECK_THROWS_WITH_AS(npend::analyze_motion(start({0, 0, 0, 0, 0, 0}, 1.0, 512), options),
                       doctest::Contains("nothing moves"), std::invalid_argument);
}
