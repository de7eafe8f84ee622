// The periodic-orbit benchmark: continuing the first nonlinear normal mode of the triple
// pendulum (equal unit masses and lengths) from a 0.01 rad swing up to 100 J, where its largest
// angle is 2.55 rad and its largest Floquet multiplier 3e4, by pseudo-arclength with single
// shooting — once with the exact monodromy matrix (the Gauss–Legendre step's tangent map,
// npend's way) and once with finite differences of 2n + 1 plain passes (how continuation codes
// without variational equations get it). Both shoot every orbit to the same closure
// ‖φ(T) − x0‖∞ ≤ 1e-11. Runs interleaved, medians. Prints a Markdown section
// (docs/benchmarks.md, through bench/run) whose last line is the ratio.
//
//   npend_bench_orbits [--quick]     (--quick: up to 40 J, one run each)
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <string>
#include <vector>

#include "npend/analysis/orbits/periodic_orbit.hpp"

namespace {

struct run_result {
  double seconds = 0;
  npend::nnm_branch branch;
};

run_result continue_first_mode(const npend::chain& c, double energy_max,
                               npend::monodromy_method method) {
  npend::continuation_options o;
  o.energy_max = energy_max;
  o.orbit.monodromy = method;
  const auto started = std::chrono::steady_clock::now();
  run_result r;
  r.branch = npend::continue_mode(c, 0, o);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return r;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

std::string row(const char* name, const std::vector<run_result>& runs, double seconds) {
  const npend::nnm_branch& b = runs.front().branch;
  double closure = 0, angle = 0;
  for (const npend::nnm_point& p : b.points) closure = std::max(closure, p.closure);
  if (!b.points.empty())
    for (double a : b.points.back().amplitudes) angle = std::max(angle, a);
  return fmt::format("| {} | {} | {:.4g} J | {:.3f} rad | {:.3g} | {:.2e} | {:.3f} s |\n", name,
                     b.points.size(), b.points.empty() ? 0.0 : b.points.back().energy, angle,
                     b.points.empty() ? 0.0 : b.points.back().max_multiplier, closure, seconds);
}

}  // namespace

int main(int argc, char** argv) {
  const bool quick = argc > 1 && std::string(argv[1]) == "--quick";
  const double energy_max = quick ? 40 : 100;
  const int runs = quick ? 1 : 3;
  const npend::chain c(npend::chain_parameters::uniform(3));
  std::vector<run_result> exact, differences;
  std::vector<double> exact_times, difference_times;
  for (int k = 0; k < runs; ++k) {
    exact.push_back(continue_first_mode(c, energy_max, npend::monodromy_method::exact));
    differences.push_back(
        continue_first_mode(c, energy_max, npend::monodromy_method::finite_difference));
    exact_times.push_back(exact.back().seconds);
    difference_times.push_back(differences.back().seconds);
  }
  const double t_exact = median(exact_times), t_differences = median(difference_times);
  fmt::print(
      "## Periodic orbits: continuing a nonlinear normal mode\n\n"
      "The triple pendulum's first nonlinear normal mode (unit masses and lengths) continued by "
      "pseudo-arclength from a 0.01 rad swing up to {:g} J, every orbit shot to "
      "‖φ(T) − x₀‖∞ ≤ 1e-11 with 400 Gauss–Legendre steps per period: the monodromy matrix "
      "from the exact tangent map of the steps against forward differences of 2n + 1 plain "
      "passes. Medians of {} interleaved runs (bench/orbits/).\n\n"
      "| monodromy | orbits | last energy | its largest angle | its max \\|μ\\| | largest "
      "closure | time |\n|---|---|---|---|---|---|---|\n",
      energy_max, runs);
  fmt::print("{}", row("exact tangent map", exact, t_exact));
  fmt::print("{}", row("finite differences", differences, t_differences));
  fmt::print("\nexact monodromy faster: {:.1f}x\n", t_differences / t_exact);
  return 0;
}
