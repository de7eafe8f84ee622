// The options of a map as `npend map` takes them — the chain, the two axes, the quantity,
// the start and the stepping — parsed into the library's map_grid and map_cell_options with
// the command line's messages. `npend map` and `npend explore` (whose requests carry the same
// options) share them, so that a request is refused as the command line would refuse it.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <string_view>

#include "chain_options.hpp"
#include "npend/analysis/chaos/chaos_map.hpp"
#include "npend/analysis/chaos/map_grid.hpp"

namespace npend::app {

/// Every option of `npend map`, as typed.
struct map_command_options {
  cli::chain_options chain;
  std::string x, y, quantity = "flip", component, phi, p, dphi, out, part;
  std::string stepper, abs_tol, rel_tol, tol;  // as typed; empty: rk4, tolerances 1e-10
  std::string device;                          // as typed; empty: cpu
  double t_end = 100, dt = 0.01;
  int flip_link = 0, gali_order = 0, threads = 0, tile = 16;
  bool resume = false, json = false, force = false;
  std::string merge_dir;  // npend map merge DIR [--json]
  bool merge_json = false;
};

/// Adds the options that say which map to compute (everything but where and how it runs:
/// --threads, --tile, --device, --out, --resume, --force, --part, --json) to `cmd`.
void add_map_view_options(CLI::App& cmd, map_command_options& o);

/// What the options describe: the chain's grid and what each cell computes. Throws
/// cli::input_error naming the option, with `npend map`'s messages.
struct map_view {
  map_grid grid;
  map_cell_options cell;
};
map_view describe_map(const map_command_options& o);

/// How a quantity is shown: the plot's title, the colour bar's label and whether its scale is
/// logarithmic (times and the indicators that fall exponentially).
struct quantity_style {
  std::string title, label;
  bool logarithmic = false;
};
quantity_style style_of(const map_command_options& o, map_quantity quantity);

/// The header of a .npy file (format 1.0) of a C-order (rows, cols) array of `descr`
/// ('<f8': little-endian float64, '|u1': bytes): map.npy's and npend explore's.
std::string npy_header(int rows, int cols, std::string_view descr = "<f8");

}  // namespace npend::app
