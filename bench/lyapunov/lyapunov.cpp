// The Lyapunov benchmark: the wall time of the Lyapunov spectrum (and of the maximal exponent
// alone) of the triple pendulum over T = 1000 s at dt = 1e-3 — gauss6 with the exact tangent
// map of its steps (the default), and rk4 integrating the variational equations — from the
// demo's strong excitation (the arms zigzag from rest, ε = E/(m g l) = 1.5). Median of a few
// runs. Then taylor (the Taylor series of the variational equations) against gauss6 at equal
// accuracy: each setting's error in the state at t = 10 s against a long double Taylor
// reference, beside its time for the spectrum and for the maximal exponent. Then the wall time of
// the Floquet multipliers of the uniform-rod triple pendulum on a vertically shaken pivot
// (Acheson's setting) over one drive period, gauss6 against taylor; and the chaos indicators of
// a torus of the double pendulum, rk4 against taylor. Prints a Markdown section
// (docs/benchmarks.md, through bench/run).
//
//   npend_bench_lyapunov [--quick]     (--quick: T = 100 s and one run, a smoke run)
#include "npend/analysis/chaos/lyapunov.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

#include "npend/analysis/chaos/chaos_indicators.hpp"
#include "npend/analysis/stability/floquet.hpp"
#include "npend/excitation.hpp"
#include "npend/integrators/taylor.hpp"

namespace {

std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  return "unknown";
}

struct measurement {
  double seconds;
  npend::lyapunov_result result;
};

measurement measure(const npend::chain& c, const std::vector<double>& x0,
                    const npend::lyapunov_options& o, bool maximal, int runs) {
  std::vector<double> times;
  npend::lyapunov_result result;
  for (int k = 0; k < runs; ++k) {
    const auto started = std::chrono::steady_clock::now();
    result =
        maximal ? npend::maximal_lyapunov_exponent(c, x0, o) : npend::lyapunov_spectrum(c, x0, o);
    times.push_back(
        std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count());
  }
  std::sort(times.begin(), times.end());
  return {times[times.size() / 2], result};
}

// The state at t_end from x0 by long double Taylor steps at 1e-19, the last cut to t_end.
std::vector<long double> reference_state(const npend::chain& c, const std::vector<double>& x0,
                                         double t_end) {
  npend::taylor_integrator<long double> integrator(c.kernels_in_use(), 1e-19, 1e-19);
  std::vector<long double> x(x0.begin(), x0.end());
  integrator.reset(0, x.data());
  const long double end = t_end;
  while (integrator.time() < end) integrator.step(1, end - integrator.time(), 0.1L);
  return integrator.state();
}

// taylor's variational series against gauss6's tangent map: for each setting the error of the
// state the spectrum's run reaches at t = 10 s, and the time of the spectrum and of the
// maximal exponent over t_end.
void equal_accuracy_section(const npend::chain& c, const std::vector<double>& x0, double t_end,
                            int runs) {
  const auto reference = reference_state(c, x0, 10);
  struct setting {
    npend::stepper_kind stepper;
    double dt, tol;
  };
  const std::vector<setting> settings{
      {npend::stepper_kind::gauss6, 5e-3, 0},     {npend::stepper_kind::gauss6, 2e-3, 0},
      {npend::stepper_kind::gauss6, 1e-3, 0},     {npend::stepper_kind::taylor, 1e-3, 1e-10},
      {npend::stepper_kind::taylor, 1e-3, 1e-12}, {npend::stepper_kind::taylor, 1e-3, 1e-14}};
  fmt::print(
      "\n**At equal accuracy: taylor against gauss6.** The accuracy of a setting is the largest "
      "error of the state its spectrum run reaches at t = 10 s, against a long double Taylor run "
      "at 1e-19 (the chaotic start magnifies every error by e^(λ t)); the times are the spectrum's "
      "and the maximal exponent's over T = {:g} s, medians of {} run{}. taylor steps under the "
      "tolerance over the state and the vectors, dt = 1e-3 s only sets the grid of the "
      "re-orthonormalisations (every 0.1 s).\n\n",
      t_end, runs, runs == 1 ? "" : "s");
  fmt::print(
      "| stepper | setting | state error at t = 10 s | spectrum (s) | maximal exponent (s) | λ_1 "
      "(1/s) |\n");
  fmt::print("|---|---|---:|---:|---:|---:|\n");
  for (const setting& s : settings) {
    npend::lyapunov_options o;
    o.integration.stepper = s.stepper;
    o.integration.dt = s.dt;
    if (s.tol > 0) o.integration.abs_tol = o.integration.rel_tol = s.tol;
    o.integration.t_end = 10;
    const auto ten = npend::lyapunov_spectrum(c, x0, o);
    double error = 0;
    for (std::size_t i = 0; i < x0.size(); ++i)
      error = std::max(error, static_cast<double>(std::fabs(ten.state[i] - reference[i])));
    o.integration.t_end = t_end;
    const measurement spectrum = measure(c, x0, o, false, runs);
    const measurement maximal = measure(c, x0, o, true, runs);
    fmt::print("| {} | {} | {:.1e} | {:.2f} | {:.2f} | {:.4f} |\n", npend::stepper_name(s.stepper),
               s.tol > 0 ? fmt::format("tol {:g}", s.tol) : fmt::format("dt {:g}", s.dt), error,
               spectrum.seconds, maximal.seconds, spectrum.result.exponents[0]);
  }
}

// The Floquet multipliers of the inverted uniform-rod triple pendulum (l = 0.2 m) on a pivot
// shaken vertically with a = 2 mm at Ω = 1500 rad/s (Acheson's setting), over one drive
// period with the monodromy carried along (6 directions): gauss6's tangent map at several
// step counts against taylor's variational series at several tolerances. Each setting's
// time is floquet_analysis's whole run (its second run for the error estimate included);
// its distance is the largest entry of M − M_ref over the largest of M_ref, M_ref from gauss6
// at 6400 steps.
void floquet_section(bool quick) {
  npend::chain_parameters rods = npend::chain_parameters::uniform(3, 1.0, 0.2);
  rods.make_uniform_rods();
  rods.pivot = npend::pivot_motion::vertical(0.002, 1500);
  const npend::chain driven(rods);
  const std::vector<double> upright{std::numbers::pi, std::numbers::pi, std::numbers::pi, 0, 0, 0};
  npend::floquet_options reference_options;
  reference_options.steps = 6400;
  const npend::floquet_result reference =
      npend::floquet_analysis(driven, upright, reference_options);
  double reference_size = 0;
  for (const double m : reference.monodromy)
    reference_size = std::max(reference_size, std::fabs(m));

  struct floquet_setting {
    npend::stepper_kind stepper;
    int steps;
    double tolerance;
  };
  const std::vector<floquet_setting> settings{
      {npend::stepper_kind::gauss6, 100, 0},   {npend::stepper_kind::gauss6, 400, 0},
      {npend::stepper_kind::gauss6, 1600, 0},  {npend::stepper_kind::taylor, 0, 1e-10},
      {npend::stepper_kind::taylor, 0, 1e-13}, {npend::stepper_kind::taylor, 0, 1e-15}};
  const int runs = quick ? 3 : 21;
  fmt::print(
      "\n**Floquet multipliers** of the inverted uniform-rod triple pendulum (m = 1 kg, "
      "l = 0.2 m) on a pivot shaken vertically (a = 2 mm, Ω = 1500 rad/s), over one drive "
      "period with the monodromy matrix M carried along: gauss6's tangent map against "
      "taylor's Taylor series of the variational equations. Time: the whole analysis, its "
      "second run for the error estimate included (gauss6: at half the steps; taylor: at 100 "
      "times the tolerance), median of {} runs. Distance: max |M − M_ref| / max |M_ref|, "
      "M_ref from gauss6 at 6400 steps.\n\n",
      runs);
  fmt::print(
      "| stepper | setting | steps | time (ms) | max \\|μ\\| − 1 | error estimate | distance "
      "from M_ref |\n|---|---|---:|---:|---:|---:|---:|\n");
  for (const floquet_setting& s : settings) {
    npend::floquet_options o;
    o.stepper = s.stepper;
    if (s.stepper == npend::stepper_kind::taylor)
      o.tolerance = s.tolerance;
    else
      o.steps = s.steps;
    std::vector<double> times;
    npend::floquet_result r;
    for (int k = 0; k < runs; ++k) {
      const auto started = std::chrono::steady_clock::now();
      r = npend::floquet_analysis(driven, upright, o);
      times.push_back(
          std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count());
    }
    std::sort(times.begin(), times.end());
    double distance = 0;
    for (std::size_t i = 0; i < r.monodromy.size(); ++i)
      distance = std::max(distance, std::fabs(r.monodromy[i] - reference.monodromy[i]));
    fmt::print("| {} | {} | {} | {:.2f} | {:.1e} | {:.1e} | {:.1e} |\n",
               npend::stepper_name(s.stepper),
               s.stepper == npend::stepper_kind::taylor ? fmt::format("tol {:g}", s.tolerance)
                                                        : fmt::format("{} steps", s.steps),
               r.steps, 1e3 * times[times.size() / 2], r.max_modulus - 1, r.modulus_error,
               distance / reference_size);
  }
}

// FLI, MEGNO, SALI and GALI of a torus of the double pendulum (φ = 0.3, 0.3 from rest, 4
// vectors, t = 100 s): rk4 at several steps against taylor at several tolerances. The error
// of a setting is the larger of FLI's and ⟨Y⟩'s relative distance from rk4 at dt = 1e-4 (on
// a torus neither run amplifies its errors). Medians over the runs.
void indicators_section(bool quick) {
  const npend::chain c(npend::chain_parameters::uniform(2));
  const std::vector<double> x0{0.3, 0.3, 0, 0};
  npend::chaos_indicator_options base;
  base.t_end = 100;
  base.vectors = 4;
  npend::chaos_indicator_options fine = base;
  fine.dt = 1e-4;
  const npend::chaos_indicator_result reference = npend::chaos_indicators(c, x0, fine);
  struct indicator_setting {
    npend::stepper_kind stepper;
    double value;  // rk4: dt; taylor: tolerance
  };
  const std::vector<indicator_setting> settings{
      {npend::stepper_kind::rk4, 1e-2},     {npend::stepper_kind::rk4, 2e-3},
      {npend::stepper_kind::rk4, 1e-3},     {npend::stepper_kind::taylor, 1e-8},
      {npend::stepper_kind::taylor, 1e-10}, {npend::stepper_kind::taylor, 1e-12}};
  const int runs = quick ? 3 : 11;
  fmt::print(
      "\n**Chaos indicators** (FLI, MEGNO, SALI, GALI) of a torus of the double pendulum "
      "(m = 1 kg, l = 1 m, φ = 0.3, 0.3 from rest), 4 deviation vectors, t = 100 s: rk4 "
      "against taylor (MEGNO's integrals by quadrature over its steps). Error: the larger of "
      "FLI's and ⟨Y⟩'s relative distance from rk4 at dt = 1e-4. Median of {} runs.\n\n"
      "| stepper | setting | time (ms) | error | FLI | ⟨Y⟩ |\n|---|---|---:|---:|---:|---:|\n",
      runs);
  for (const indicator_setting& s : settings) {
    npend::chaos_indicator_options o = base;
    o.stepper = s.stepper;
    if (s.stepper == npend::stepper_kind::taylor)
      o.tolerance = s.value;
    else
      o.dt = s.value;
    std::vector<double> times;
    npend::chaos_indicator_result r;
    for (int k = 0; k < runs; ++k) {
      const auto started = std::chrono::steady_clock::now();
      r = npend::chaos_indicators(c, x0, o);
      times.push_back(
          std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count());
    }
    std::sort(times.begin(), times.end());
    const double error = std::max(std::fabs(r.last.fli / reference.last.fli - 1),
                                  std::fabs(r.last.mean_megno / reference.last.mean_megno - 1));
    fmt::print("| {} | {} {:g} | {:.1f} | {:.1e} | {:.10f} | {:.10f} |\n",
               npend::stepper_name(s.stepper),
               s.stepper == npend::stepper_kind::taylor ? "tol" : "dt", s.value,
               1e3 * times[times.size() / 2], error, r.last.fli, r.last.mean_megno);
  }
}

}  // namespace

int main(int argc, char** argv) {
  const bool quick = argc > 1 && std::string(argv[1]) == "--quick";
  const double t_end = quick ? 100 : 1000, dt = 1e-3;
  const int runs = quick ? 1 : 3;
  const npend::chain c(npend::chain_parameters::uniform(3));
  const auto x0 =
      npend::deflected_state(c, npend::energy_from_epsilon(c, 1.5), std::vector<double>{1, -1, 1});

  fmt::print("## Lyapunov spectrum: triple pendulum, T = {:g} s, dt = {:g} s\n\n", t_end, dt);
  fmt::print(
      "Measured by `npend_bench_lyapunov` (`bench/lyapunov/`){}: m = 1 kg, l = 1 m, g = 9.81, the "
      "demo's strong excitation (arms zigzag from rest, ε = 1.5), re-orthonormalised every 0.1 s; "
      "median of {} run{}. Machine: {}; compiler: g++ {}; flags -O3 -march=native.\n\n",
      quick ? " — **a quick run**" : "", runs, runs == 1 ? "" : "s", cpu_model(), __VERSION__);
  fmt::print(
      "| what | stepper, tangent method | steps | wall time (s) | µs per step | λ_1 (1/s) | Σλ_i "
      "(1/s) |\n");
  fmt::print("|---|---|---:|---:|---:|---:|---:|\n");
  for (const auto stepper : {npend::stepper_kind::gauss6, npend::stepper_kind::rk4})
    for (const bool maximal : {false, true}) {
      npend::lyapunov_options o;
      o.integration.stepper = stepper;
      o.integration.t_end = t_end;
      o.integration.dt = dt;
      const measurement m = measure(c, x0, o, maximal, runs);
      const double steps = t_end / dt;
      fmt::print("| {} | {}, {} | {:.0f} | {:.2f} | {:.2f} | {:.4f} | {} |\n",
                 maximal ? "maximal exponent (1 vector)" : "spectrum (6 vectors)",
                 npend::stepper_name(stepper), m.result.method, steps, m.seconds,
                 1e6 * m.seconds / steps, m.result.exponents[0],
                 maximal ? std::string("—") : fmt::format("{:.1e}", m.result.sum));
    }
  fmt::print(
      "\nThe exponents of the two steppers differ: at dt = 1e-3 their trajectories of this "
      "chaotic motion part after some tens of seconds, and finite-time exponents of the two "
      "runs need not agree (see the spread that `npend lyapunov` reports).\n");
  equal_accuracy_section(c, x0, t_end, runs);

  floquet_section(quick);
  indicators_section(quick);
  return 0;
}
