// The work-precision benchmark: wall time against the error of the final state, for Taylor's
// method and the other steppers, on one thread. Each run goes through npend::integrate from
// t = 0 to T with one output point at T (the adaptive steppers: dt = T; the fixed-step ones:
// dt is their step); its error is the largest |x_i(T) − x_i^ref(T)| over the state, against a
// long double Taylor run at tolerance 1e-19 whose last step ends exactly on T. A second long
// double run at another order and tolerance checks the reference; their difference is
// printed. On a driven pivot both references take fixed steps of a power of two (order 30 in
// steps of 2^-7 s, order 36 in steps of 2^-8 s): the drive's series is evaluated at each
// step's start time as a double, exact only on such a grid (adaptive steps there leave the
// two references 1e-13 apart where they agree to 1e-17 on the grid).
//
//   npend_bench_work_precision [--quick] [--csv PATH]
//     --quick     two cases, fewer settings and repetitions: a smoke run
//     --csv PATH  the points (case, stepper, setting, steps, ms, error) as CSV, for
//                 plot_work_precision.py
//
// Times are medians over interleaved repetitions (each repetition runs every setting of the
// case once); a run shorter than the timed block repeats inside it, and the block's time is
// divided by the count. Prints Markdown (bench/run puts it into docs/benchmarks.md).
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "npend/chain.hpp"
#include "npend/integrators/integrate.hpp"
#include "npend/integrators/taylor.hpp"

namespace {

using clock_type = std::chrono::steady_clock;

struct problem {
  std::string name;   // the Markdown heading
  std::string label;  // the CSV's and the plot's name of the case (no commas)
  npend::chain chain;
  std::vector<double> x0;
  double t_end;
  std::string note = {};  // printed under the heading
};

// One run: a stepper at one tolerance (adaptive) or step (fixed-step).
struct setting {
  npend::stepper_kind kind;
  double value;  // abs_tol = rel_tol, or dt
};

struct measurement {
  setting s{};
  std::size_t steps = 0;
  double error = std::numeric_limits<double>::quiet_NaN();
  std::string failure;        // what integrate threw; empty if it ran
  int repeats = 1;            // integrations per timed block
  std::vector<double> times;  // seconds per integration, one per repetition
};

// A reference run: Taylor's method in long double at a tolerance and order, adaptive or
// (halvings > 0) in steps of 2^-halvings s, each shorter where the tolerance asks for it.
struct reference_setting {
  double tolerance;
  int order;  // 0: from the tolerance
  int halvings;
};

struct reference_run {
  reference_setting s{};
  std::vector<long double> state;
  std::size_t steps = 0;
  std::size_t shorter = 0;  // steps the tolerance made shorter than the fixed step
  int order = 0;
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t m = v.size() / 2;
  return v.size() % 2 == 1 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  return "unknown";
}

// The reference from x0 to T: the last step is cut to end on T (T must be a multiple of a
// fixed step).
reference_run reference(const problem& p, const reference_setting& s) {
  const long double end = p.t_end;
  const long double step = s.halvings > 0 ? std::ldexp(1.0L, -s.halvings) : end;
  if (std::fmod(end, step) != 0)
    throw std::invalid_argument(
        fmt::format("reference: T = {} is no multiple of 2^-{} s", p.t_end, s.halvings));
  npend::taylor_integrator<long double> taylor(p.chain.kernels_in_use(), s.tolerance, s.tolerance,
                                               s.order);
  const std::vector<long double> x0(p.x0.begin(), p.x0.end());
  taylor.reset(0, x0.data());
  reference_run r;
  r.s = s;
  r.order = taylor.order();
  // A remainder of a few ulps of T is left when the sum of the steps rounds below T.
  for (long double left = end; left > end * 1e-17L; left = end - taylor.time()) {
    const long double limit = std::min(step, left);
    if (taylor.step(1, limit, limit) < limit && s.halvings > 0) ++r.shorter;
    ++r.steps;
  }
  r.state = taylor.state();
  return r;
}

double largest_difference(const std::vector<double>& x, const std::vector<long double>& ref) {
  double largest = 0;
  for (std::size_t i = 0; i < x.size(); ++i)
    largest = std::max(largest, static_cast<double>(std::fabs(x[i] - ref[i])));
  return largest;
}

npend::integration_options options_for(const problem& p, const setting& s) {
  npend::integration_options o;
  o.stepper = s.kind;
  o.t_end = p.t_end;
  if (npend::is_adaptive(s.kind)) {
    o.dt = p.t_end;  // one output point, at T; also the first trial step
    o.abs_tol = o.rel_tol = s.value;
  } else {
    o.dt = s.value;
  }
  return o;
}

const char* setting_name(npend::stepper_kind kind) {
  return npend::is_adaptive(kind) ? "tol" : "dt";
}

std::vector<setting> settings_for(bool quick, double t_end) {
  using npend::stepper_kind;
  std::vector<setting> settings;
  const std::vector<double> taylor_tols =
      quick ? std::vector<double>{1e-8, 1e-12, 1e-15}
            : std::vector<double>{1e-6, 1e-8, 1e-10, 1e-12, 1e-14, 1e-15, 1e-16};
  const std::vector<double> tols = quick ? std::vector<double>{1e-8, 1e-12}
                                         : std::vector<double>{1e-6, 1e-8, 1e-10, 1e-12, 1e-14};
  for (double tol : taylor_tols) settings.push_back({stepper_kind::taylor, tol});
  for (const auto kind : {stepper_kind::rkf78, stepper_kind::dopri5, stepper_kind::bulirsch_stoer})
    for (double tol : tols) settings.push_back({kind, tol});
  const std::vector<double> gauss_dts =
      quick ? std::vector<double>{1e-2, 2e-3} : std::vector<double>{1e-2, 5e-3, 2e-3, 1e-3};
  for (double dt : gauss_dts) settings.push_back({stepper_kind::gauss6, dt});
  // rk4's finest step costs 10^6 steps at T = 100 s; the coarse one shows its slope.
  const std::vector<double> rk4_dts =
      quick || t_end > 10 ? std::vector<double>{1e-3, 1e-4} : std::vector<double>{1e-3, 1e-4, 1e-5};
  for (double dt : rk4_dts) settings.push_back({stepper_kind::rk4, dt});
  return settings;
}

// One integration; its result and wall time.
npend::integration_result run_once(const problem& p, const npend::integration_options& o) {
  return npend::integrate(p.chain, p.x0, o);
}

std::vector<measurement> measure(const problem& p, const std::vector<long double>& ref,
                                 const std::vector<setting>& settings, int repetitions,
                                 double block_seconds) {
  std::vector<measurement> m;
  // A first run of each setting: its error and steps (the runs are deterministic), and how
  // many integrations fill a timed block.
  for (const auto& s : settings) {
    measurement r;
    r.s = s;
    const auto o = options_for(p, s);
    try {
      const auto started = clock_type::now();
      const auto result = run_once(p, o);
      const double seconds = std::chrono::duration<double>(clock_type::now() - started).count();
      if (std::fabs(result.t - p.t_end) > 1e-9 * p.t_end)
        throw std::runtime_error(fmt::format("ended at t = {} instead of {}", result.t, p.t_end));
      r.steps = result.steps;
      r.error = largest_difference(result.state, ref);
      r.repeats = std::max(1, static_cast<int>(std::ceil(block_seconds / std::max(seconds, 1e-7))));
    } catch (const std::exception& e) {
      r.failure = e.what();
    }
    m.push_back(std::move(r));
  }
  for (int k = 0; k < repetitions; ++k)
    for (auto& r : m) {
      if (!r.failure.empty()) continue;
      const auto o = options_for(p, r.s);
      std::size_t steps = 0;
      const auto started = clock_type::now();
      for (int i = 0; i < r.repeats; ++i) steps += run_once(p, o).steps;
      const double seconds = std::chrono::duration<double>(clock_type::now() - started).count();
      r.times.push_back(seconds / r.repeats);
      if (steps != r.steps * static_cast<std::size_t>(r.repeats))
        throw std::runtime_error("a repeated run took different steps");
    }
  return m;
}

void print_case(const problem& p, const reference_run& ref, const reference_run& check,
                const std::vector<measurement>& m, int repetitions, std::FILE* csv) {
  fmt::print("### {}\n\n", p.name);
  if (!p.note.empty()) fmt::print("{}\n\n", p.note);
  const auto steps = [](const reference_run& r) {
    if (r.s.halvings == 0)
      return fmt::format("tolerance {:g}, order {}, {} steps", r.s.tolerance, r.order, r.steps);
    return fmt::format("tolerance {:g}, order {}, {} steps of 2^-{} s{}", r.s.tolerance, r.order,
                       r.steps, r.s.halvings,
                       r.shorter == 0 ? "" : fmt::format(" ({} shorter)", r.shorter));
  };
  fmt::print(
      "Reference: long double Taylor (64-bit mantissa), {}; checked against a second long "
      "double run, {}: largest difference {:.1e}. Time: median of {} interleaved repetitions, "
      "ms per integration.\n\n",
      steps(ref), steps(check),
      largest_difference(std::vector<double>(check.state.begin(), check.state.end()), ref.state),
      repetitions);
  fmt::print("| stepper | setting | steps | ms (median) | error |\n|---|---|---:|---:|---:|\n");
  for (const auto& r : m) {
    const auto name = npend::stepper_name(r.s.kind);
    if (!r.failure.empty()) {
      fmt::print("| {} | {} = {:g} | — | — | failed: {} |\n", name, setting_name(r.s.kind),
                 r.s.value, r.failure);
      continue;
    }
    const double ms = 1e3 * median(r.times);
    fmt::print("| {} | {} = {:g} | {} | {:.3g} | {:.1e} |\n", name, setting_name(r.s.kind),
               r.s.value, r.steps, ms, r.error);
    if (csv != nullptr)
      fmt::print(csv, "{},{},{},{:g},{},{:.6g},{:.6e}\n", p.label, name, setting_name(r.s.kind),
                 r.s.value, r.steps, ms, r.error);
  }
  // The cheapest run of each stepper that reaches each error level: the ratios to taylor
  // at equal error are read off here.
  std::vector<npend::stepper_kind> kinds;
  for (const auto& r : m)
    if (std::find(kinds.begin(), kinds.end(), r.s.kind) == kinds.end()) kinds.push_back(r.s.kind);
  fmt::print("\nThe cheapest run reaching each error level (ms; — = none of its settings):\n\n");
  fmt::print("| error ≤ |");
  for (const auto kind : kinds) fmt::print(" {} |", npend::stepper_name(kind));
  fmt::print("\n|---:|");
  for (std::size_t i = 0; i < kinds.size(); ++i) fmt::print("---:|");
  fmt::print("\n");
  for (double level : {1e-6, 1e-8, 1e-10, 1e-12, 1e-13}) {
    fmt::print("| {:g} |", level);
    for (const auto kind : kinds) {
      std::optional<double> best;
      for (const auto& r : m)
        if (r.s.kind == kind && r.failure.empty() && r.error <= level)
          best = std::min(best.value_or(INFINITY), 1e3 * median(r.times));
      if (best)
        fmt::print(" {:.3g} |", *best);
      else
        fmt::print(" — |");
    }
    fmt::print("\n");
  }
  fmt::print("\n");
  std::fflush(stdout);
}

std::vector<problem> problems(bool quick) {
  std::vector<problem> all;
  const npend::chain triple(npend::chain_parameters::uniform(3));
  all.push_back({"Triple pendulum, chaotic start: φ = (1.5, 1.5, 1.5), p = 0, T = 10 s",
                 "triple pendulum chaotic (T = 10 s)",
                 triple,
                 {1.5, 1.5, 1.5, 0, 0, 0},
                 10.0});
  if (!quick)
    all.push_back({"Triple pendulum, regular start: φ = (0.3, 0.3, 0.3), p = 0, T = 100 s",
                   "triple pendulum regular (T = 100 s)",
                   triple,
                   {0.3, 0.3, 0.3, 0, 0, 0},
                   100.0});
  if (!quick) {
    std::vector<double> x0(12, 0.0);
    std::fill(x0.begin(), x0.begin() + 6, 0.5);
    all.push_back({"Six-link chain: all angles 0.5, p = 0, T = 10 s", "six links (T = 10 s)",
                   npend::chain(npend::chain_parameters::uniform(6)), x0, 10.0});
  }
  auto rods = npend::chain_parameters::uniform(2);
  rods.make_uniform_rods();
  rods.pivot = npend::pivot_motion::vertical(0.01, 60);
  all.push_back(
      {"Physical double pendulum: uniform rods (m = 1 kg, l = 1 m, c = l/2, J = m l²/12), "
       "pivot driven vertically (a = 0.01 m, Ω = 60 rad/s), φ = (0.5, −0.3), p = 0, T = 10 s",
       "physical double pendulum driven (T = 10 s)",
       npend::chain(rods),
       {0.5, -0.3, 0, 0},
       10.0,
       "The amplitude is 0.01 m on purpose: at a = 0.05 m this start is chaotic (a change of 1e-12 "
       "in "
       "φ₁ grows to order 1 by T = 10 s), beyond any stepper's reach in double."});
  return all;
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false;
  std::string csv_path;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--quick") {
      quick = true;
    } else if (arg == "--csv" && i + 1 < argc) {
      csv_path = argv[++i];
    } else {
      fmt::print(stderr, "npend_bench_work_precision: unknown option '{}' (--quick, --csv PATH)\n",
                 arg);
      return 2;
    }
  }
  std::FILE* csv = nullptr;
  if (!csv_path.empty()) {
    csv = std::fopen(csv_path.c_str(), "w");
    if (csv == nullptr) {
      fmt::print(stderr, "npend_bench_work_precision: cannot write '{}'\n", csv_path);
      return 1;
    }
    fmt::print(csv, "case,stepper,setting,value,steps,ms,error\n");
  }
  const int repetitions = quick ? 3 : 7;
  const double block_seconds = quick ? 2e-3 : 20e-3;
  fmt::print(
      "Machine: {}; compiler: g++ {}; flags -O3 -march=native (kernels, runtime and benchmark); "
      "one thread. Every run is `npend::integrate` from t = 0 to T: the adaptive steppers at "
      "abs_tol = rel_tol = tol with one output point at T, rk4 and gauss6 at step dt. Error: "
      "max_i |x_i(T) − x_i^ref(T)| over the state [φ, p]. Runs shorter than {:g} ms repeat "
      "inside the timed block.\n\n",
      cpu_model(), __VERSION__, 1e3 * block_seconds);
  for (const auto& p : problems(quick)) {
    const bool driven = p.chain.parameters().pivot.moves();
    const auto ref =
        reference(p, driven ? reference_setting{1e-19, 30, 7} : reference_setting{1e-19, 0, 0});
    const auto check =
        reference(p, driven ? reference_setting{1e-19, 36, 8} : reference_setting{3e-20, 30, 0});
    const auto m = measure(p, ref.state, settings_for(quick, p.t_end), repetitions, block_seconds);
    print_case(p, ref, check, m, repetitions, csv);
  }
  if (csv != nullptr && std::fclose(csv) != 0) {
    fmt::print(stderr, "npend_bench_work_precision: cannot write '{}'\n", csv_path);
    return 1;
  }
  return 0;
}
