// The integrator benchmark: for the triple pendulum with equal masses and lengths started
// at all angles 1.5 rad, p = 0, the relative energy error of every stepper over 10^6 steps of
// dt = 1e-3; and the throughput of every stepper at n = 2, 3, 6, measured side by side
// (interleaved rounds, medians); and the Newton work per Gauss–Legendre step. Prints
// Markdown tables (docs/integrators.md).
//
//   npend_bench_integrators [--quick] [--throughput]
//     --quick       10^4 steps and 3 rounds, a smoke run
//     --throughput  the throughput table alone (bench/run puts it beside the kernel timings)
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include "npend/chain_system.hpp"
#include "npend/integrators/gauss_legendre.hpp"
#include "npend/integrators/integrate.hpp"

namespace {

using clock_type = std::chrono::steady_clock;

std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  return "unknown";
}

std::vector<double> start_state(int n) {
  std::vector<double> x(static_cast<std::size_t>(2 * n), 0.0);
  std::fill(x.begin(), x.begin() + n, 1.5);
  return x;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t m = v.size() / 2;
  return v.size() % 2 == 1 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

// Part 1: max_{s <= t} |H(s) − H(0)| / H(0) at the checkpoints, and the value at the end.
void energy_table(double t_end) {
  const npend::chain c(npend::chain_parameters::uniform(3));
  const auto x0 = start_state(3);
  const double h0 = c.hamiltonian(x0);
  std::vector<double> checkpoints;
  for (double t = 1; t <= t_end * (1 + 1e-12); t *= 10) checkpoints.push_back(t);

  fmt::print(
      "## Energy error: triple pendulum, m = 1 kg, l = 1 m, g = 9.81, all angles 1.5 rad, "
      "p = 0\n\n");
  fmt::print(
      "dt = 1e-3 (the output grid; the fixed-step steppers' step), t = 0 ... {:g} s, "
      "{:.0e} output steps; adaptive steppers at abs_tol = rel_tol = 1e-10. Entries: the "
      "largest |H(s) - H(0)| / H(0) for s <= t.\n\n",
      t_end, t_end / 1e-3);
  fmt::print("| stepper |");
  for (double t : checkpoints) fmt::print(" t = {:g} s |", t);
  fmt::print(" at t = {:g} s | internal steps | wall time (s) |\n|---|", t_end);
  for (std::size_t i = 0; i < checkpoints.size() + 3; ++i) fmt::print("---:|");
  fmt::print("\n");
  for (const auto kind : npend::all_stepper_kinds()) {
    npend::integration_options o;
    o.stepper = kind;
    o.t_end = t_end;
    o.dt = 1e-3;
    double worst = 0, last = 0;
    std::vector<double> at_checkpoints;
    std::size_t next = 0;
    const auto started = clock_type::now();
    const auto result = npend::integrate(c, x0, o, [&](double t, std::span<const double> x) {
      last = std::fabs(c.hamiltonian(x) - h0) / h0;
      worst = std::max(worst, last);
      if (next < checkpoints.size() && t >= checkpoints[next] - 1e-9) {
        at_checkpoints.push_back(worst);
        ++next;
      }
    });
    const double seconds = std::chrono::duration<double>(clock_type::now() - started).count();
    fmt::print("| {} |", npend::stepper_name(kind));
    for (double e : at_checkpoints) fmt::print(" {:.1e} |", e);
    fmt::print(" {:.1e} | {} | {:.2f} |\n", last, result.steps, seconds);
    std::fflush(stdout);
  }
  fmt::print("\n");
}

// Part 2: throughput at n = 2, 3, 6; each round runs every stepper once (side by side).
void throughput_table(double t_sim, int rounds) {
  fmt::print(
      "## Integration throughput: all angles 1.5 rad, p = 0, dt = 1e-3, t = 0 ... {:g} s per "
      "run\n\n",
      t_sim);
  fmt::print(
      "Median wall time of {} interleaved rounds (each round runs every stepper once). "
      "Steps/s counts the stepper's own steps (for rkf78 at least one per output step); "
      "'vs rk4' is the run time relative to rk4 at the same n.\n\n",
      rounds);
  fmt::print(
      "| n | stepper | steps per run | median time (ms) | steps/s | simulated s per s | vs rk4 "
      "|\n");
  fmt::print("|---:|---|---:|---:|---:|---:|---:|\n");
  const auto kinds = npend::all_stepper_kinds();
  for (int n : {2, 3, 6}) {
    const npend::chain c(npend::chain_parameters::uniform(n));
    const auto x0 = start_state(n);
    std::vector<std::vector<double>> times(kinds.size());
    std::vector<std::size_t> steps(kinds.size());
    for (int r = 0; r < rounds; ++r)
      for (std::size_t k = 0; k < kinds.size(); ++k) {
        npend::integration_options o;
        o.stepper = kinds[k];
        o.t_end = t_sim;
        o.dt = 1e-3;
        const auto started = clock_type::now();
        steps[k] = npend::integrate(c, x0, o).steps;
        times[k].push_back(std::chrono::duration<double>(clock_type::now() - started).count());
      }
    const double rk4 = median(times[0]);
    for (std::size_t k = 0; k < kinds.size(); ++k) {
      const double t = median(times[k]);
      fmt::print("| {} | {} | {} | {:.1f} | {:.3g} | {:.0f} | {:.2f} |\n", n,
                 npend::stepper_name(kinds[k]), steps[k], 1e3 * t,
                 static_cast<double>(steps[k]) / t, t_sim / t, t / rk4);
    }
    std::fflush(stdout);
  }
  fmt::print("\n");
}

// Part 3: the Newton work behind a Gauss–Legendre step (the stepper's own counters).
template <class Stepper>
void newton_row(int n, double t_sim) {
  const npend::chain c(npend::chain_parameters::uniform(n));
  auto x = start_state(n);
  const auto system = npend::make_implicit_system(c);
  Stepper stepper;
  const double dt = 1e-3;
  const auto steps = static_cast<int>(std::lround(t_sim / dt));
  for (int k = 0; k < steps; ++k) stepper.do_step(system, x, k * dt, dt);
  const auto& s = stepper.statistics();
  const auto per_step = [&](std::size_t count) {
    return static_cast<double>(count) / static_cast<double>(s.steps);
  };
  fmt::print("| {} | gauss{} | {:.2f} | {:.2f} | {:.4f} | {:.4f} | {} |\n", n, Stepper::order_value,
             per_step(s.newton_iterations), per_step(s.rhs_evaluations),
             per_step(s.jacobian_evaluations), per_step(s.factorizations), s.full_newton_steps);
}

void newton_table(double t_sim) {
  fmt::print(
      "## Gauss-Legendre Newton work: all angles 1.5 rad, p = 0, dt = 1e-3, t = 0 ... {:g} s\n\n",
      t_sim);
  fmt::print(
      "| n | stepper | iterations/step | rhs/step | Jacobians/step | LU factorisations/step | "
      "steps with full Newton |\n|---:|---|---:|---:|---:|---:|---:|\n");
  for (int n : {2, 3, 6}) {
    newton_row<npend::gauss_legendre4>(n, t_sim);
    newton_row<npend::gauss_legendre6>(n, t_sim);
  }
  fmt::print("\n");
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false, throughput_only = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--quick") {
      quick = true;
    } else if (arg == "--throughput") {
      throughput_only = true;
    } else {
      fmt::print(stderr, "npend_bench_integrators: unknown option '{}' (--quick, --throughput)\n",
                 arg);
      return 2;
    }
  }
  const double long_run = quick ? 10.0 : 1000.0, short_run = quick ? 1.0 : 10.0;
  const int rounds = quick ? 3 : 7;
  if (throughput_only) {
    throughput_table(short_run, rounds);
    return 0;
  }
  fmt::print(
      "# npend integrator benchmark\n\nMachine: {}; compiler: g++ {}; flags -O3 -march=native "
      "(kernels, runtime and benchmark).\n\n",
      cpu_model(), __VERSION__);
  energy_table(long_run);
  throughput_table(short_run, rounds);
  newton_table(long_run);
  return 0;
}
