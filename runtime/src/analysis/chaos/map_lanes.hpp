// The map's cells on the batch lanes, for each instruction set the build has lanes for.
//
// map_lanes.cpp and the lanes and kernels it runs are compiled once for the compiler's own
// ISA and once more for each of AVX2 and AVX-512F above it (cmake/npend_lanes.cmake); each
// compilation fills one map_lanes. The map picks one when it runs (active_map_lanes): the
// best the CPU can run, or the one NPEND_LANE_ISA names. The lanes' arithmetic is the same
// program on each, so their values agree to round-off (each ISA's own sines, and fused
// multiply-adds from AVX2 on).
#pragma once

#include <cstddef>
#include <span>
#include <string_view>
#include <vector>

#include "npend/analysis/chaos/chaos_map.hpp"
#include "npend/analysis/chaos/lyapunov.hpp"
#include "npend/chain.hpp"

namespace npend::detail {

/// One ISA's lane runs. Each takes the starts (states of 2n, one after another) and writes
/// the values of the cells it runs into out (indexed like the starts), as chaos_map.cpp's
/// scalar path computes them up to round-off.
struct map_lanes {
  const char* isa;  ///< "sse2", "avx2", "avx512f" (or "avx" for an AVX-only -march)
  int lanes;        ///< lanes stepped at once: W × lane_blocks
  /// Whether this ISA's lanes have kernels for chain c.
  bool (*serves)(const chain& c);
  /// The flip times of the cells `queue` (stepper rk4, gauss4, gauss6 or dopri5).
  void (*flip_times)(const chain& c, std::span<const double> starts,
                     const std::vector<std::size_t>& queue, const flip_options& o,
                     std::vector<double>& out);
  /// The maximal Lyapunov exponents of every start (rk4 or dopri5).
  void (*lyapunov)(const chain& c, std::span<const double> starts, const lyapunov_options& lo,
                   std::vector<double>& out);
  /// The chaos indicator o.quantity of every start (rk4), with `vectors` deviation vectors.
  void (*indicators)(const chain& c, std::span<const double> starts, const map_cell_options& o,
                     std::size_t vectors, std::vector<double>& out);
  /// Coordinate o.component at o.t_end of every start; the cells a Gauss–Legendre lane could
  /// not solve go to `failed`, for the library.
  void (*final_coordinates)(const chain& c, std::span<const double> starts,
                            const map_cell_options& o, std::vector<double>& out,
                            std::vector<std::size_t>& failed);
};

/// The lanes the maps run on now (npend::use_batch_lane_isa): the best ISA the build and the
/// CPU share, unless NPEND_LANE_ISA named another when the first map ran. Throws
/// std::invalid_argument naming NPEND_LANE_ISA where it names none of them.
const map_lanes& active_map_lanes();

}  // namespace npend::detail
