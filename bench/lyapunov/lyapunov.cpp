// The Lyapunov benchmark: the wall time of the Lyapunov spectrum (and of the maximal exponent
// alone) of the triple pendulum over T = 1000 s at dt = 1e-3 — gauss6 with the exact tangent
// map of its steps (the default), and rk4 integrating the variational equations — from the
// demo's strong excitation (the arms zigzag from rest, ε = E/(m g l) = 1.5). Median of a few
// runs. Then the wall time of the Floquet multipliers of the uniform-rod triple pendulum on
// a vertically shaken pivot (Acheson's setting) over one drive period. Prints a Markdown
// section (docs/benchmarks.md, through bench/run).
//
//   npend_bench_lyapunov [--quick]     (--quick: T = 100 s and one run, a smoke run)
#include "npend/analysis/chaos/lyapunov.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

#include "npend/analysis/stability/floquet.hpp"
#include "npend/excitation.hpp"

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

  // Floquet: the inverted uniform-rod triple pendulum (l = 0.2 m) on a pivot shaken
  // vertically with a = 2 mm at Ω = 1500 rad/s, one period of 400 gauss6 steps, the tangent
  // map of every step carried along (6 directions).
  npend::chain_parameters rods = npend::chain_parameters::uniform(3, 1.0, 0.2);
  rods.make_uniform_rods();
  rods.pivot = npend::pivot_motion::vertical(0.002, 1500);
  const npend::chain driven(rods);
  const std::vector<double> upright{std::numbers::pi, std::numbers::pi, std::numbers::pi, 0, 0, 0};
  const int floquet_runs = quick ? 3 : 21;
  std::vector<double> times;
  npend::floquet_result floquet;
  for (int k = 0; k < floquet_runs; ++k) {
    const auto started = std::chrono::steady_clock::now();
    floquet = npend::floquet_analysis(driven, upright);
    times.push_back(
        std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count());
  }
  std::sort(times.begin(), times.end());
  fmt::print(
      "\n**Floquet multipliers** of the inverted uniform-rod triple pendulum (m = 1 kg, "
      "l = 0.2 m) on a pivot shaken vertically (a = 2 mm, Ω = 1500 rad/s), over one drive "
      "period in 400 gauss6 steps with the tangent map: {:.2f} ms (median of {} runs), max |μ| "
      "= {:.6f} ({}).\n",
      1e3 * times[times.size() / 2], floquet_runs, floquet.max_modulus,
      floquet.stable ? "stable" : "unstable");
  return 0;
}
