// npend_bench_flip_map: the wall time of a flip map of the equal double pendulum from rest
// (Heyl's fractal) on one thread, computed two ways side by side in one process —
//   scalar: npend::flip_time cell after cell (odeint's rk4 on the scalar generated rhs,
//           std::sin), what a user calling the library per cell gets;
//   lanes:  npend::flip_times tile after tile (16 x 16 cells, as npend map hands them out),
//           rk4 on the batch kernels' W lanes with lanes refilled from the tile's queue —
// rounds interleaved; prints one JSON object (bench/run reports medians and the ratio).
//
// With --lyapunov 1, the same for a map of the maximal Lyapunov exponent (rk4 at dt 0.01):
// maximal_lyapunov_exponent cell by cell against map_cells on the lanes (tangent_batch);
// it prints the largest difference between the two maps instead of the cells differing.
// With --gauss6 1, the flip map by gauss6 at dt 0.01: the lanes' fixed-point stage iteration
// against the library's Newton (flip_time cell by cell).
// With --dopri5 TOL, the flip map by dopri5 at abs_tol = rel_tol = TOL instead of rk4: each
// lane under its own step control against flip_time's dopri5 cell by cell; it prints the
// largest relative difference of the flip times both runs find.
//
//   npend_bench_flip_map [--count N] [--t-end T] [--rounds R] [--lyapunov 0|1] [--dopri5 TOL]
//                        [--gauss6 0|1]  (defaults 256, 1000, 3, 0, 0: rk4, 0)
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <numbers>
#include <span>
#include <string>
#include <vector>

#include "npend/analysis/chaos/chaos_map.hpp"
#include "npend/batch_math.hpp"
#include "npend/chain.hpp"
#include "npend/integrators/integrate.hpp"

namespace {

struct settings {
  int count = 256;
  double t_end = 1000;
  int rounds = 3;
  bool lyapunov = false;
  double dopri5 = 0;  // the tolerance; 0: rk4
  bool gauss6 = false;
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
    if (a == "--count")
      s.count = static_cast<int>(v);
    else if (a == "--t-end")
      s.t_end = v;
    else if (a == "--rounds")
      s.rounds = static_cast<int>(v);
    else if (a == "--lyapunov")
      s.lyapunov = v != 0;
    else if (a == "--dopri5")
      s.dopri5 = v;
    else if (a == "--gauss6")
      s.gauss6 = v != 0;
    else {
      std::fprintf(stderr, "npend_bench_flip_map: unknown option %s\n", a.c_str());
      std::exit(2);
    }
  }
  if (s.count < 1 || s.count > 4096 || !(s.t_end > 0) || s.rounds < 1 || !(s.dopri5 >= 0)) {
    std::fprintf(stderr,
                 "npend_bench_flip_map: need 1 <= count <= 4096, t-end > 0, rounds >= 1, "
                 "dopri5 >= 0\n");
    std::exit(2);
  }
  return s;
}

std::vector<double> start_of(const settings& s, int i, int j) {
  return {npend::grid_value(-3.14, 3.14, s.count, i), npend::grid_value(-3.14, 3.14, s.count, j), 0,
          0};
}

// The baseline a user without the map's cell functions would write: npend::integrate per
// cell (rk4 at dt), an observer stopping the run at the first grid point where an arm is
// upright; the cells the energy rules out are skipped, as the other two runs skip them.
std::vector<double> integrate_map(const npend::chain& c, const settings& s,
                                  const npend::flip_options& o) {
  std::vector<double> map;
  npend::integration_options io;
  io.stepper = npend::stepper_kind::rk4;
  io.t_end = s.t_end;
  io.dt = o.dt;
  for (int j = 0; j < s.count; ++j)
    for (int i = 0; i < s.count; ++i) {
      const std::vector<double> x0 = start_of(s, i, j);
      double flipped = std::numeric_limits<double>::infinity();
      if (!npend::energy_forbids_flip(c, x0))
        npend::integrate(c, x0, io, [&](double t, std::span<const double> x) {
          if (std::fabs(x[0]) < std::numbers::pi && std::fabs(x[1]) < std::numbers::pi)
            return npend::observer_action::proceed;
          flipped = t;
          return npend::observer_action::stop;
        });
      map.push_back(flipped);
    }
  return map;
}

std::vector<double> scalar_map(const npend::chain& c, const settings& s,
                               const npend::flip_options& o) {
  std::vector<double> map;
  map.reserve(static_cast<std::size_t>(s.count) * static_cast<std::size_t>(s.count));
  for (int j = 0; j < s.count; ++j)
    for (int i = 0; i < s.count; ++i) map.push_back(npend::flip_time(c, start_of(s, i, j), o));
  return map;
}

// The map computed tile by tile (16 x 16 cells, as npend map hands them out): cells(starts)
// gives the values of a tile's starts.
template <class Cells>
std::vector<double> tiled(const settings& s, const Cells& cells) {
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
      const std::vector<double> times = cells(starts);
      std::size_t k = 0;
      for (int j = y0; j < std::min(s.count, y0 + tile); ++j)
        for (int i = x0; i < std::min(s.count, x0 + tile); ++i)
          map[static_cast<std::size_t>(j) * static_cast<std::size_t>(s.count) +
              static_cast<std::size_t>(i)] = times[k++];
    }
  return map;
}

std::vector<double> lane_map(const npend::chain& c, const settings& s,
                             const npend::flip_options& o) {
  return tiled(s,
               [&](const std::vector<double>& starts) { return npend::flip_times(c, starts, o); });
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

// The Lyapunov map cell by cell (the library's maximal_lyapunov_exponent) and on the lanes
// (map_cells, tile by tile); prints its JSON line.
int lyapunov_maps(const npend::chain& c, const settings& s) {
  npend::map_cell_options mo;
  mo.quantity = npend::map_quantity::lyapunov;
  mo.t_end = s.t_end;
  mo.dt = 0.01;
  npend::lyapunov_options lo;
  lo.integration.stepper = npend::stepper_kind::rk4;
  lo.integration.t_end = s.t_end;
  lo.integration.dt = mo.dt;
  const auto cell_by_cell = [&] {
    std::vector<double> map;
    for (int j = 0; j < s.count; ++j)
      for (int i = 0; i < s.count; ++i)
        map.push_back(npend::maximal_lyapunov_exponent(c, start_of(s, i, j), lo).exponents[0]);
    return map;
  };
  const auto on_lanes = [&] {
    return tiled(
        s, [&](const std::vector<double>& starts) { return npend::map_cells(c, starts, mo); });
  };
  std::vector<double> scalar_seconds, lane_seconds, scalar, lanes;
  for (int r = 0; r < s.rounds; ++r) {
    scalar_seconds.push_back(seconds_of(cell_by_cell, scalar));
    lane_seconds.push_back(seconds_of(on_lanes, lanes));
  }
  double largest = 0;
  for (std::size_t k = 0; k < scalar.size(); ++k)
    largest = std::max(largest, std::fabs(scalar[k] - lanes[k]));
  std::printf(
      "%s\n",
      fmt::format("{{\"quantity\": \"lyapunov\", \"count\": {}, \"t_end\": {}, \"rounds\": {}, "
                  "\"isa\": \"{}\", \"lanes\": {}, \"scalar_seconds\": {}, "
                  "\"lane_seconds\": {}, \"largest_difference\": {}}}",
                  s.count, s.t_end, s.rounds, npend::batch_isa(), npend::batch_lanes(c),
                  list(scalar_seconds), list(lane_seconds), largest)
          .c_str());
  return 0;
}

int main(int argc, char** argv) {
  const settings s = parse(argc, argv);
  const npend::chain c(npend::chain_parameters::uniform(2));
  if (s.lyapunov) return lyapunov_maps(c, s);
  npend::flip_options o{s.t_end, 0.01, 0};
  if (s.dopri5 > 0) o.stepping = {npend::stepper_kind::dopri5, s.dopri5, s.dopri5};
  if (s.gauss6) o.stepping.stepper = npend::stepper_kind::gauss6;
  std::vector<double> scalar_seconds, lane_seconds, integrate_seconds, scalar, lanes, integrated;
  for (int r = 0; r < s.rounds; ++r) {
    scalar_seconds.push_back(seconds_of([&] { return scalar_map(c, s, o); }, scalar));
    lane_seconds.push_back(seconds_of([&] { return lane_map(c, s, o); }, lanes));
    if (o.stepping.stepper == npend::stepper_kind::rk4)
      integrate_seconds.push_back(seconds_of([&] { return integrate_map(c, s, o); }, integrated));
  }
  // integrate's observer sees the same rk4 steps as flip_time: the same times.
  long integrate_differing = 0;
  for (std::size_t k = 0; k < integrated.size(); ++k)
    integrate_differing += integrated[k] == scalar[k] ? 0 : 1;
  long differing = 0;
  double largest = 0;  // relative, over the cells both runs see flip
  for (std::size_t k = 0; k < scalar.size(); ++k) {
    differing += (scalar[k] == lanes[k] || (std::isinf(scalar[k]) && std::isinf(lanes[k]))) ? 0 : 1;
    if (std::isfinite(scalar[k]) && std::isfinite(lanes[k]) && scalar[k] > 0)
      largest = std::max(largest, std::fabs(scalar[k] - lanes[k]) / scalar[k]);
  }
  std::printf("%s\n",
              fmt::format("{{\"count\": {}, \"t_end\": {}, \"rounds\": {}, \"stepper\": \"{}\", "
                          "\"tolerance\": {}, \"isa\": \"{}\", \"lanes\": {}, "
                          "\"scalar_seconds\": {}, \"lane_seconds\": {}, \"cells_differing\": {}, "
                          "\"largest_relative_difference\": {}, \"integrate_seconds\": {}, "
                          "\"integrate_cells_differing\": {}}}",
                          s.count, s.t_end, s.rounds, npend::stepper_name(o.stepping.stepper),
                          s.dopri5, npend::batch_isa(), npend::batch_lanes(c), list(scalar_seconds),
                          list(lane_seconds), differing, largest, list(integrate_seconds),
                          integrate_differing)
                  .c_str());
  return 0;
}
