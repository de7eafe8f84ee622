// npend_bench_flip_map: the wall time of a flip map of the equal double pendulum from rest
// (Heyl's fractal) on one thread, computed two ways side by side in one process —
//   scalar: npend::flip_time cell after cell (odeint's rk4 on the scalar generated rhs,
//           std::sin), what a user calling the library per cell gets;
//   lanes:  npend::flip_times tile after tile (16 x 16 cells, as npend map hands them out),
//           rk4 on the batch kernels' W lanes with lanes refilled from the tile's queue —
// rounds interleaved; prints one JSON object (bench/run reports medians and the ratio).
//
//   npend_bench_flip_map [--count N] [--t-end T] [--rounds R]   (defaults 256, 1000, 3)
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "npend/analysis/chaos_map.hpp"
#include "npend/batch_math.hpp"
#include "npend/chain.hpp"

namespace {

struct settings {
  int count = 256;
  double t_end = 1000;
  int rounds = 3;
};

settings parse(int argc, char** argv) {
  settings s;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (i + 1 >= argc) {
      std::fprintf(stderr, "npend_bench_flip_map: %s needs a value\n", a.c_str());
      std::exit(2);
    }
    const double v = std::atof(argv[++i]);
    if (a == "--count") s.count = static_cast<int>(v);
    else if (a == "--t-end") s.t_end = v;
    else if (a == "--rounds") s.rounds = static_cast<int>(v);
    else {
      std::fprintf(stderr, "npend_bench_flip_map: unknown option %s\n", a.c_str());
      std::exit(2);
    }
  }
  if (s.count < 1 || s.count > 4096 || !(s.t_end > 0) || s.rounds < 1) {
    std::fprintf(stderr, "npend_bench_flip_map: need 1 <= count <= 4096, t-end > 0, rounds >= 1\n");
    std::exit(2);
  }
  return s;
}

std::vector<double> start_of(const settings& s, int i, int j) {
  return {npend::grid_value(-3.14, 3.14, s.count, i), npend::grid_value(-3.14, 3.14, s.count, j),
          0, 0};
}

std::vector<double> scalar_map(const npend::chain& c, const settings& s,
                               const npend::flip_options& o) {
  std::vector<double> map;
  map.reserve(static_cast<std::size_t>(s.count) * static_cast<std::size_t>(s.count));
  for (int j = 0; j < s.count; ++j)
    for (int i = 0; i < s.count; ++i) map.push_back(npend::flip_time(c, start_of(s, i, j), o));
  return map;
}

std::vector<double> lane_map(const npend::chain& c, const settings& s,
                             const npend::flip_options& o) {
  constexpr int tile = 16;
  std::vector<double> map(static_cast<std::size_t>(s.count) * static_cast<std::size_t>(s.count));
  for (int y0 = 0; y0 < s.count; y0 += tile)
    for (int x0 = 0; x0 < s.count; x0 += tile) {
      std::vector<double> starts;
      for (int j = y0; j < std::min(s.count, y0 + tile); ++j)
        for (int i = x0; i < std::min(s.count, x0 + tile); ++i) {
          const auto x = start_of(s, i, j);
          starts.insert(starts.end(), x.begin(), x.end());
        }
      const std::vector<double> times = npend::flip_times(c, starts, o);
      std::size_t k = 0;
      for (int j = y0; j < std::min(s.count, y0 + tile); ++j)
        for (int i = x0; i < std::min(s.count, x0 + tile); ++i)
          map[static_cast<std::size_t>(j) * static_cast<std::size_t>(s.count) +
              static_cast<std::size_t>(i)] = times[k++];
    }
  return map;
}

template <class F>
double seconds_of(F&& f, std::vector<double>& out) {
  const auto start = std::chrono::steady_clock::now();
  out = f();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

std::string list(const std::vector<double>& v) {
  std::string text;
  for (std::size_t k = 0; k < v.size(); ++k) text += fmt::format("{}{:.3f}", k ? ", " : "", v[k]);
  return "[" + text + "]";
}

}  // namespace

int main(int argc, char** argv) {
  const settings s = parse(argc, argv);
  const npend::chain c(npend::chain_parameters::uniform(2));
  const npend::flip_options o{s.t_end, 0.01, 0};
  std::vector<double> scalar_seconds, lane_seconds, scalar, lanes;
  for (int r = 0; r < s.rounds; ++r) {
    scalar_seconds.push_back(seconds_of([&] { return scalar_map(c, s, o); }, scalar));
    lane_seconds.push_back(seconds_of([&] { return lane_map(c, s, o); }, lanes));
  }
  long differing = 0;
  for (std::size_t k = 0; k < scalar.size(); ++k)
    differing += (scalar[k] == lanes[k] || (std::isinf(scalar[k]) && std::isinf(lanes[k]))) ? 0 : 1;
  std::printf(
      "%s\n",
      fmt::format("{{\"count\": {}, \"t_end\": {}, \"rounds\": {}, \"isa\": \"{}\", \"lanes\": {}, "
                  "\"scalar_seconds\": {}, \"lane_seconds\": {}, \"cells_differing\": {}}}",
                  s.count, s.t_end, s.rounds, npend::batch_isa(), npend::batch_lanes(c),
                  list(scalar_seconds), list(lane_seconds), differing)
          .c_str());
  return 0;
}
