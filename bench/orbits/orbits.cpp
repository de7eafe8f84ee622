// The periodic-orbit benchmark: continuing the first nonlinear normal mode of the triple
// pendulum (equal unit masses and lengths) from a 0.01 rad swing up to 100 J, where its largest
// angle is 2.55 rad and its largest Floquet multiplier 3e4, by pseudo-arclength with single
// shooting — once with the exact monodromy matrix (the Gauss–Legendre step's tangent map,
// npend's way) and once with finite differences of 2n + 1 plain passes (how continuation codes
// without variational equations get it), and once on Taylor's method at 1e-14 (its exact
// tangent map: the orbits are the flow's rather than the Gauss–Legendre map's). All shoot
// every orbit to the same closure ‖φ(T) − x0‖∞ ≤ 1e-11; the last orbit is then re-integrated
// by rkf78 at 1e-14 over its period, an independent look at how well it closes. Runs
// interleaved, medians. Prints a Markdown section (docs/benchmarks.md, through bench/run)
// whose last line is the exact/finite-difference ratio.
//
//   npend_bench_orbits [--quick]     (--quick: up to 40 J, one run each)
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <vector>

#include "npend/analysis/orbits/periodic_orbit.hpp"
#include "npend/integrators/integrate.hpp"

namespace {

struct run_result {
  double seconds = 0;
  npend::nnm_branch branch;
};

// One way of shooting the family's orbits.
struct setting {
  const char* name;
  npend::monodromy_method method = npend::monodromy_method::exact;
  npend::stepper_kind stepper = npend::stepper_kind::gauss6;
  int steps = 400;  // gauss6's per period
};

run_result continue_first_mode(const npend::chain& c, double energy_max, const setting& how) {
  npend::continuation_options o;
  o.energy_max = energy_max;
  o.orbit.monodromy = how.method;
  o.orbit.stepper = how.stepper;
  o.orbit.steps = how.steps;
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

// max |x(T) − x0| of the orbit re-integrated by rkf78 at 1e-14.
double rkf78_closure(const npend::chain& c, const npend::nnm_point& p) {
  npend::integration_options run;
  run.stepper = npend::stepper_kind::rkf78;
  run.t_end = run.dt = p.period;
  run.abs_tol = run.rel_tol = 1e-14;
  const npend::integration_result back = npend::integrate(c, p.x0, run);
  double gap = 0;
  for (std::size_t i = 0; i < p.x0.size(); ++i)
    gap = std::max(gap, std::fabs(back.state[i] - p.x0[i]));
  return gap;
}

std::string row(const npend::chain& c, const char* name, const std::vector<run_result>& runs,
                double seconds) {
  const npend::nnm_branch& b = runs.front().branch;
  if (b.points.empty())
    return fmt::format("| {} | 0 | — | — | — | — | — | {:.3f} s |\n", name, seconds);
  double closure = 0, angle = 0;
  for (const npend::nnm_point& p : b.points) closure = std::max(closure, p.closure);
  const npend::nnm_point& last = b.points.back();
  for (double a : last.amplitudes) angle = std::max(angle, a);
  return fmt::format("| {} | {} | {:.4g} J | {:.3f} rad | {:.3g} | {:.2e} | {:.2e} | {:.3f} s |\n",
                     name, b.points.size(), last.energy, angle, last.max_multiplier, closure,
                     rkf78_closure(c, last), seconds);
}

}  // namespace

int main(int argc, char** argv) {
  const bool quick = argc > 1 && std::string(argv[1]) == "--quick";
  const double energy_max = quick ? 40 : 100;
  const int runs = quick ? 1 : 3;
  const npend::chain c(npend::chain_parameters::uniform(3));
  // The first two are the exact/finite-difference comparison; the others gauss6 at finer
  // steps, to meet Taylor's accuracy.
  const std::vector<setting> settings{
      {"gauss6 (400 steps), exact tangent map"},
      {"gauss6 (400 steps), finite differences", npend::monodromy_method::finite_difference},
      {"gauss6 (1600 steps), exact tangent map", npend::monodromy_method::exact,
       npend::stepper_kind::gauss6, 1600},
      {"taylor 1e-14, exact tangent map", npend::monodromy_method::exact,
       npend::stepper_kind::taylor}};
  std::vector<std::vector<run_result>> results(settings.size());
  std::vector<std::vector<double>> times(settings.size());
  for (int k = 0; k < runs; ++k)
    for (std::size_t i = 0; i < settings.size(); ++i) {
      results[i].push_back(continue_first_mode(c, energy_max, settings[i]));
      times[i].push_back(results[i].back().seconds);
    }
  std::vector<double> medians;
  for (const auto& t : times) medians.push_back(median(t));
  fmt::print(
      "## Periodic orbits: continuing a nonlinear normal mode\n\n"
      "The triple pendulum's first nonlinear normal mode (unit masses and lengths) continued by "
      "pseudo-arclength from a 0.01 rad swing up to {:g} J, every orbit shot to "
      "‖φ(T) − x₀‖∞ ≤ 1e-11 with 400 Gauss–Legendre steps per period (1600 in one row): the "
      "monodromy matrix "
      "from the exact tangent map of the steps against forward differences of 2n + 1 plain "
      "passes; and on Taylor's method at 1e-14 with the Taylor series of the variational "
      "equations. rkf78 closure: max |x(T) − x₀| of the last orbit re-integrated by rkf78 at "
      "1e-14. Medians of {} interleaved runs (bench/orbits/).\n\n"
      "| shooting | orbits | last energy | its largest angle | its max \\|μ\\| | largest "
      "closure | rkf78 closure | time |\n|---|---|---|---|---|---|---|---|\n",
      energy_max, runs);
  for (std::size_t i = 0; i < settings.size(); ++i)
    fmt::print("{}", row(c, settings[i].name, results[i], medians[i]));
  fmt::print("\ntaylor against gauss6 at 400 and 1600 steps: {:.2f}x and {:.2f}x the time\n",
             medians[3] / medians[0], medians[3] / medians[2]);
  fmt::print("\nexact monodromy faster: {:.1f}x\n", medians[1] / medians[0]);
  return 0;
}
