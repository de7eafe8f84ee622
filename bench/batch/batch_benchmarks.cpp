// npend_bench_batch: throughput (states/s) of the batch rhs (generated batch_<n>.cpp, W lanes,
// SLEEF's sincos) against the scalar generated rhs (chain_<n>.cpp, std::sin) on one core
// (Google Benchmark; bench/run reports the medians and their ratios in docs/benchmarks.md).
//
// Both evaluate the same pool of 1024 random states (bench/workload.hpp) of the chain with
// unequal masses and lengths: the scalar kernel one state after another, the batch kernel W
// at a time from the pool transposed to structure-of-arrays. Before timing, every batch
// output is checked against the scalar one (relative 1e-13 of the largest term).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <batch_index.hpp>
#include <chain_index.hpp>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "npend/chain.hpp"
#include "workload.hpp"

namespace {

constexpr int W = npend::batch_width;
constexpr std::size_t pool_size = 1024;  // a multiple of every W
constexpr int benchmark_links[] = {2, 3, 6};

struct batch_case {
  int links;
  std::vector<double> params;  // [m, l, g]
  npend::bench::state_pool pool;
  std::vector<double> soa;  // the pool in groups of W states, each group structure-of-arrays
};

batch_case make_case(int n) {
  const npend::chain c(npend::bench::random_parameters(n, 1000u + static_cast<unsigned>(n)));
  batch_case b{n,
               c.packed_parameters(),
               npend::bench::state_pool(n, pool_size, 2000u + static_cast<unsigned>(n)),
               {}};
  const std::size_t m = b.pool.state_size;
  b.soa.resize(pool_size * m);
  for (std::size_t g = 0; g < pool_size / W; ++g)
    for (std::size_t l = 0; l < W; ++l)
      for (std::size_t i = 0; i < m; ++i) b.soa[g * W * m + i * W + l] = b.pool.state(g * W + l)[i];
  return b;
}

// The largest difference between the batch and the scalar outputs, relative to the largest
// scalar output of the state.
double worst_difference(const batch_case& b) {
  const auto& scalar = *npend::generated::find_chain(b.links);
  const auto& batch = *npend::generated::find_batch(b.links);
  const std::size_t m = b.pool.state_size;
  std::vector<double> want(m), got(m * W);
  double worst = 0;
  for (std::size_t g = 0; g < pool_size / W; ++g) {
    batch.rhs_batch(b.soa.data() + g * W * m, b.params.data(), got.data(), 1, 0);
    for (std::size_t l = 0; l < W; ++l) {
      scalar.rhs(b.pool.state(g * W + l), b.params.data(), want.data());
      double scale = 0, diff = 0;
      for (std::size_t i = 0; i < m; ++i) {
        scale = std::max(scale, std::fabs(want[i]));
        diff = std::max(diff, std::fabs(got[i * W + l] - want[i]));
      }
      worst = std::max(worst, diff / scale);
    }
  }
  return worst;
}

void scalar_rhs(benchmark::State& state, const batch_case* b) {
  const auto rhs = npend::generated::find_chain(b->links)->rhs;
  std::vector<double> out(b->pool.state_size);
  std::size_t i = 0;
  for (auto _ : state) {
    rhs(b->pool.state(i), b->params.data(), out.data());
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
    i = (i + 1) & (pool_size - 1);
  }
  state.SetItemsProcessed(state.iterations());
}

void batch_rhs(benchmark::State& state, const batch_case* b) {
  const auto rhs = npend::generated::find_batch(b->links)->rhs_batch;
  const std::size_t m = b->pool.state_size;
  std::vector<double> out(m * W);
  std::size_t g = 0;
  for (auto _ : state) {
    rhs(b->soa.data() + g * W * m, b->params.data(), out.data(), 1, 0);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
    g = (g + 1) % (pool_size / W);
  }
  state.SetItemsProcessed(state.iterations() * W);
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 2;
  benchmark::AddCustomContext("batch_isa", npend::batch_isa());
  benchmark::AddCustomContext("batch_width", std::to_string(W));
  std::vector<batch_case> cases;
  cases.reserve(std::size(benchmark_links));
  for (const int n : benchmark_links) {
    if (npend::generated::find_batch(n) == nullptr) {
      std::fprintf(stderr, "npend_bench_batch: %d links not built\n", n);
      continue;
    }
    if (npend::generated::find_batch(n)->width != W) {
      std::fprintf(stderr, "npend_bench_batch: the kernels have %d lanes, this program %d\n",
                   npend::generated::find_batch(n)->width, W);
      return 1;
    }
    cases.push_back(make_case(n));
    const double worst = worst_difference(cases.back());
    if (!(worst <= 1e-13)) {
      std::fprintf(stderr, "npend_bench_batch: the batch rhs at n = %d differs by %.3g\n", n,
                   worst);
      return 1;
    }
  }
  for (const auto& b : cases) {
    const std::string n = std::to_string(b.links);
    benchmark::RegisterBenchmark(("rhs_states/scalar/" + n).c_str(), scalar_rhs, &b);
    benchmark::RegisterBenchmark(("rhs_states/batch/" + n).c_str(), batch_rhs, &b);
  }
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
