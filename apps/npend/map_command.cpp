// npend map: a quantity of chaos — the time to the first flip (Heyl's fractal) or the maximal
// Lyapunov exponent — over a 2-D grid of start states, computed in tiles on every core,
// written as .npy, PNG and JSON, and resumable after an interruption.
#include <fmt/format.h>
#include <omp.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <nlohmann/json.hpp>

#include "chain_options.hpp"
#include "command.hpp"
#include "input_parsing.hpp"
#include "npend/analysis/chaos_map.hpp"
#include "npend/integration_error.hpp"
#include "output_file.hpp"
#include "plotting.hpp"
#include "terminal_run.hpp"

namespace npend::app {

namespace {

namespace fs = std::filesystem;

struct map_command_options {
  cli::chain_options chain;
  std::string x, y, quantity = "flip", phi, p, out;
  double t_end = 100, dt = 0.01;
  int flip_link = 0, threads = 0, tile = 16;
  bool resume = false, json = false;
};

// One axis: count values from `from` to `to`, both ends included, of state coordinate
// `coordinate` (φ_1..φ_n, then p_1..p_n).
struct axis {
  std::string spec, name;
  int coordinate = 0;
  double from = 0, to = 0;
  int count = 0;
  double value(int i) const {
    return count == 1 ? from : from + (to - from) * static_cast<double>(i) / (count - 1);
  }
};

axis parse_axis(const std::string& text, const char* option, int links) {
  const auto parts = cli::split_list(text, ':');
  if (parts.size() != 4)
    throw cli::input_error(fmt::format(
        "{}: expected NAME:FROM:TO:COUNT (e.g. phi1:-3.14:3.14:256), got '{}'", option, text));
  axis a;
  a.spec = text;
  a.name = std::string(cli::trim(parts[0]));
  int index = 0;
  const auto numbered = [&](const char* prefix) {
    const std::string p = prefix;
    if (a.name.rfind(p, 0) != 0 || a.name.size() == p.size()) return false;
    const std::string digits = a.name.substr(p.size());
    if (digits.find_first_not_of("0123456789") != std::string::npos) return false;
    index = std::stoi(digits);
    return true;
  };
  if (numbered("phi") && index >= 1 && index <= links)
    a.coordinate = index - 1;
  else if (numbered("p") && index >= 1 && index <= links)
    a.coordinate = links + index - 1;
  else
    throw cli::input_error(fmt::format(
        "{}: '{}' is not a start coordinate of the {}-link chain (phi1..phi{}, p1..p{})", option,
        a.name, links, links, links));
  a.from = cli::parse_number(parts[1], option);
  a.to = cli::parse_number(parts[2], option);
  const double count = cli::parse_number(parts[3], option);
  if (count != std::floor(count) || count < 1 || count > 16384)
    throw cli::input_error(
        fmt::format("{}: the count must be a whole number 1..16384, got {}", option, parts[3]));
  a.count = static_cast<int>(count);
  return a;
}

// The .npy format (version 1.0): a little-endian float64 C-order array of shape (rows, cols).
std::string npy_header(int rows, int cols) {
  std::string dict =
      fmt::format("{{'descr': '<f8', 'fortran_order': False, 'shape': ({}, {}), }}", rows, cols);
  // Magic (6) + version (2) + length (2) + dict + padding + '\n', a multiple of 64 bytes.
  const std::size_t unpadded = 10 + dict.size() + 1;
  dict.append((64 - unpadded % 64) % 64, ' ');
  dict += '\n';
  std::string out("\x93NUMPY\x01\x00", 8);
  out += static_cast<char>(dict.size() & 0xff);
  out += static_cast<char>(dict.size() >> 8);
  return out + dict;
}

std::string bytes_of(const std::vector<double>& values) {
  return std::string(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(double));
}

constexpr long max_csv_cells = 65536;  // 256 × 256: beyond that only the .npy

// The grid as CSV rows x, y, value (y outer, as in the .npy); +inf and NaN as inf and nan.
void write_csv(const fs::path& path, const axis& ax, const axis& ay,
               const std::vector<double>& grid) {
  std::string text = fmt::format("{},{},value\n", ax.name, ay.name);
  std::size_t k = 0;
  for (int j = 0; j < ay.count; ++j)
    for (int i = 0; i < ax.count; ++i, ++k) {
      const double v = grid[k];
      text += fmt::format("{},{},{}\n", ax.value(i), ay.value(j),
                          std::isnan(v) ? std::string("nan") : fmt::format("{}", v));
    }
  cli::write_file_atomically(path, text);
}

// The start state of cell (i, j): the base state with the two axes' coordinates set.
std::vector<double> cell_state(const std::vector<double>& base, const axis& ax, const axis& ay,
                               int i, int j) {
  std::vector<double> state = base;
  state[static_cast<std::size_t>(ax.coordinate)] = ax.value(i);
  state[static_cast<std::size_t>(ay.coordinate)] = ay.value(j);
  return state;
}

struct tile_layout {
  int size, tiles_x, tiles_y;
  int count() const { return tiles_x * tiles_y; }
};

fs::path tile_path(const fs::path& dir, int index) {
  return dir / "tiles" / fmt::format("tile_{:06d}.bin", index);
}

// The values of tile `index` (row-major within the tile, clipped at the grid's edges).
std::vector<double> compute_tile(const chain& c, const map_command_options& o, const axis& ax,
                                 const axis& ay, const std::vector<double>& base,
                                 const tile_layout& layout, int index, std::atomic<long>& failed) {
  const int tx = index % layout.tiles_x, ty = index / layout.tiles_x;
  const int x0 = tx * layout.size, y0 = ty * layout.size;
  const int x1 = std::min(ax.count, x0 + layout.size), y1 = std::min(ay.count, y0 + layout.size);
  std::vector<double> values;
  for (int j = y0; j < y1; ++j)
    for (int i = x0; i < x1; ++i) {
      const std::vector<double> state = cell_state(base, ax, ay, i, j);
      try {
        if (o.quantity == "flip") {
          values.push_back(flip_time(c, state, {o.t_end, o.dt, o.flip_link}));
        } else {
          lyapunov_options lo;
          lo.integration.stepper = stepper_kind::rk4;
          lo.integration.t_end = o.t_end;
          lo.integration.dt = o.dt;
          values.push_back(maximal_lyapunov_exponent(c, state, lo).exponents.front());
        }
      } catch (const integration_error&) {
        values.push_back(std::numeric_limits<double>::quiet_NaN());
        ++failed;
      }
    }
  return values;
}

// The run's identity: a resumed run must be the same map.
nlohmann::json run_identity(const map_command_options& o, const chain& c, const axis& ax,
                            const axis& ay, const std::vector<double>& base) {
  return {{"links", c.links()},
          {"packed_parameters", c.packed_parameters()},
          {"x", ax.spec},
          {"y", ay.spec},
          {"quantity", o.quantity},
          {"t_end", o.t_end},
          {"dt", o.dt},
          {"flip_link", o.flip_link},
          {"tile", o.tile},
          {"base_state", base}};
}

// The heat map. `low`..`high` is the range of the finite values (for flip times dt..t_end, on
// a log scale). The palette is viridis between two thin bands: white at the top for the cells
// that never flipped (+inf), red at the bottom for failed cells (NaN). The colour bar runs
// from `bottom` to `top`, a hair beyond low and high, and those cells are given these ends.
// (Leaving them undefined needs gnuplot's `image pixels`, whose millions of sub-pixel
// rectangles wash the colours out.)
cli::plot_outcome write_png(const fs::path& dir, const map_command_options& o, const axis& ax,
                            const axis& ay, std::size_t header_bytes, double low, double high) {
  const bool flip = o.quantity == "flip";
  const double dx = ax.count > 1 ? (ax.to - ax.from) / (ax.count - 1) : 1;
  const double dy = ay.count > 1 ? (ay.to - ay.from) / (ay.count - 1) : 1;
  // low and high sit at these fractions of the colour bar (the palette's indices -0.02..4.02
  // put viridis's ends at 0.00495 and 0.99505).
  constexpr double low_at = 0.005, high_at = 0.995;
  const auto scale = [&](double v) { return flip ? std::log(v) : v; };
  const auto unscale = [&](double v) { return flip ? std::exp(v) : v; };
  const double range = (scale(high) - scale(low)) / (high_at - low_at);
  const double bottom = unscale(scale(low) - low_at * range),
               top = unscale(scale(low) + (1 - low_at) * range);
  cli::plot_panel panel{
      .title =
          flip ? fmt::format("Time to the first flip (s); white: no flip by {:g} s; red: "
                             "failed",
                             o.t_end)
               : fmt::format("Maximal Lyapunov exponent (1/s) over {:g} s; red: failed", o.t_end),
      .xlabel = ax.name,
      .ylabel = ay.name,
      .commands = {"set size ratio -1",
                   // viridis, a perceptual colour map, then white for the cells without a value
                   "set palette defined (-0.02 '#d62728', -0.0001 '#d62728', 0 '#440154', "
                   "1 '#3b528b', 2 '#21918c', 3 '#5ec962', 4 '#fde725', 4.0001 'white', "
                   "4.02 'white')",
                   fmt::format("set cbrange [{:.17g}:{:.17g}]", bottom, top),
                   fmt::format("set cblabel '{}'", flip ? "t_{flip} (s)" : "λ_1 (1/s)"),
                   fmt::format("set xrange [{}:{}]", std::min(ax.from, ax.to) - dx / 2,
                               std::max(ax.from, ax.to) + dx / 2),
                   fmt::format("set yrange [{}:{}]", std::min(ay.from, ay.to) - dy / 2,
                               std::max(ay.from, ay.to) + dy / 2)}};
  if (flip) panel.commands.push_back("set logscale cb");
  panel.curves.push_back(
      {"map.npy",
       fmt::format("($1 == $1 ? (abs($1) < 1e300 ? $1 : {:.17g}) : {:.17g})", top, bottom), "image",
       "",
       fmt::format("binary skip={} array=({},{}) format='%float64' dx={} dy={} origin=({},{})",
                   header_bytes, ax.count, ay.count, dx, dy, ax.from, ay.from)});
  return cli::write_plot(dir / "map", {.description = {"npend map: " + panel.title},
                                       .width = 900,
                                       .height = 800,
                                       .panels = {panel}});
}

int run_map(const map_command_options& o) {
  const auto started = std::chrono::steady_clock::now();
  const chain c = o.chain.make_chain(cli::model_support::conservative, "npend map");
  const int n = c.links();
  if (o.quantity != "flip" && o.quantity != "lyapunov")
    throw cli::input_error(fmt::format("--quantity: one of flip, lyapunov, got '{}'", o.quantity));
  const axis ax = parse_axis(o.x, "--x", n), ay = parse_axis(o.y, "--y", n);
  if (ax.coordinate == ay.coordinate)
    throw cli::input_error(fmt::format("--x and --y: both are {}", ax.name));
  if (!(o.t_end > 0) || !(o.dt > 0) || o.dt > o.t_end)
    throw cli::input_error(
        fmt::format("--t-end and --dt: need 0 < dt <= t-end, got {} and {}", o.dt, o.t_end));
  if (o.flip_link < 0 || o.flip_link > n)
    throw cli::input_error(
        fmt::format("--flip-link: 1..{} (or 0: any arm), got {}", n, o.flip_link));
  if (o.tile < 1 || o.tile > 1024)
    throw cli::input_error(fmt::format("--tile: 1..1024, got {}", o.tile));
  if (o.threads < 0) throw cli::input_error(fmt::format("--threads: >= 0, got {}", o.threads));
  std::vector<double> base(static_cast<std::size_t>(2 * n), 0.0);
  if (!o.phi.empty()) {
    const auto phi = cli::parse_angle_list(o.phi, "--phi", n);
    std::copy(phi.begin(), phi.end(), base.begin());
  }
  if (!o.p.empty()) {
    const auto p = cli::parse_number_list(o.p, "--p", static_cast<std::size_t>(n),
                                          fmt::format("p_1..p_{}", n));
    std::copy(p.begin(), p.end(), base.begin() + n);
  }
  if (o.quantity == "flip") energy_forbids_flip(c, base, o.flip_link);  // refuses springs early

  const fs::path dir(o.out);
  if (o.out.empty()) throw cli::input_error("--out: the folder for map.npy, map.png, map.json");
  const nlohmann::json identity = run_identity(o, c, ax, ay, base);
  const fs::path run_file = dir / "tiles" / "run.json";
  std::error_code ec;
  if (o.resume) {
    std::ifstream in(run_file);
    if (!in)
      throw cli::input_error(
          fmt::format("--resume: {} holds no interrupted map (no {})", o.out, run_file.string()));
    nlohmann::json before;
    try {
      in >> before;
    } catch (const nlohmann::json::exception&) {
      throw cli::input_error(fmt::format("--resume: {} is not readable", run_file.string()));
    }
    if (before != identity)
      throw cli::input_error(fmt::format(
          "--resume: {} holds a different map (other chain, axes, quantity or times)", o.out));
  } else {
    fs::create_directories(dir, ec);
    if (ec)
      throw cli::input_error(fmt::format("--out: cannot create '{}': {}", o.out, ec.message()));
    fs::remove_all(dir / "tiles", ec);
    fs::create_directories(dir / "tiles", ec);
    if (ec)
      throw cli::input_error(fmt::format("--out: cannot write in '{}': {}", o.out, ec.message()));
    cli::write_file_atomically(run_file, identity.dump(2) + "\n");
  }

  const tile_layout layout{o.tile, (ax.count + o.tile - 1) / o.tile,
                           (ay.count + o.tile - 1) / o.tile};
  std::vector<int> pending;
  for (int t = 0; t < layout.count(); ++t)
    if (!o.resume || !fs::exists(tile_path(dir, t))) pending.push_back(t);
  const int threads = o.threads > 0 ? o.threads : omp_get_max_threads();
  cli::terminal_run control;
  std::atomic<long> done{0}, failed{0};
  std::atomic<bool> stop{false};
  const long total = static_cast<long>(pending.size());
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
  for (long k = 0; k < total; ++k) {
    if (stop.load()) continue;
    const int index = pending[static_cast<std::size_t>(k)];
    const std::vector<double> values = compute_tile(c, o, ax, ay, base, layout, index, failed);
    cli::write_file_atomically(tile_path(dir, index), bytes_of(values));
    ++done;
    if (omp_get_thread_num() == 0) {
      control.progress(static_cast<double>(done.load()), static_cast<double>(total));
      if (control.stop_requested()) stop = true;
    }
  }
  control.finish();
  if (stop.load() || control.interrupted()) {
    fmt::print(stderr,
               "npend map: interrupted: {} of {} tiles are in {}; finish with the same command "
               "and --resume\n",
               layout.count() - total + done.load(), layout.count(), (dir / "tiles").string());
    return control.exit_code();
  }

  // Assemble the tiles into the row-major grid, row 0 = the first y value.
  std::vector<double> grid(static_cast<std::size_t>(ax.count) * static_cast<std::size_t>(ay.count));
  for (int t = 0; t < layout.count(); ++t) {
    std::ifstream in(tile_path(dir, t), std::ios::binary);
    const int tx = t % layout.tiles_x, ty = t / layout.tiles_x;
    const int x0 = tx * layout.size, y0 = ty * layout.size;
    const int x1 = std::min(ax.count, x0 + layout.size), y1 = std::min(ay.count, y0 + layout.size);
    std::vector<double> values(static_cast<std::size_t>((x1 - x0) * (y1 - y0)));
    in.read(reinterpret_cast<char*>(values.data()),
            static_cast<std::streamsize>(values.size() * sizeof(double)));
    if (!in)
      throw std::runtime_error(
          fmt::format("npend map: tile {} is damaged; run again without "
                      "--resume",
                      tile_path(dir, t).string()));
    std::size_t k = 0;
    for (int j = y0; j < y1; ++j)
      for (int i = x0; i < x1; ++i)
        grid[static_cast<std::size_t>(j) * static_cast<std::size_t>(ax.count) +
             static_cast<std::size_t>(i)] = values[k++];
  }
  const std::string header = npy_header(ay.count, ax.count);
  cli::write_file_atomically(dir / "map.npy", header + bytes_of(grid));
  const bool small = static_cast<long>(ax.count) * ay.count <= max_csv_cells;
  if (small) write_csv(dir / "map.csv", ax, ay, grid);
  long never = 0, nan = 0, forbidden = 0;
  for (int j = 0; j < ay.count; ++j)
    for (int i = 0; i < ax.count; ++i) {
      const double v = grid[static_cast<std::size_t>(j) * static_cast<std::size_t>(ax.count) +
                            static_cast<std::size_t>(i)];
      if (std::isnan(v)) ++nan;
      if (std::isinf(v)) {
        ++never;
        if (energy_forbids_flip(c, cell_state(base, ax, ay, i, j), o.flip_link)) ++forbidden;
      }
    }
  double low = std::numeric_limits<double>::infinity(), high = -low;
  for (const double v : grid)
    if (std::isfinite(v)) low = std::min(low, v), high = std::max(high, v);
  if (o.quantity == "flip") {
    low = o.dt;
    high = o.t_end;
  } else if (!(high > low)) {  // no finite value, or all equal: any range that shows them
    low = std::isfinite(low) ? low - 1 : 0;
    high = low + 2;
  }
  const cli::plot_outcome plot = write_png(dir, o, ax, ay, header.size(), low, high);
  if (!plot.rendered) fmt::print(stderr, "npend map: note: {}\n", plot.message);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  nlohmann::json summary = identity;
  summary["x"] = {{"name", ax.name}, {"from", ax.from}, {"to", ax.to}, {"count", ax.count}};
  summary["y"] = {{"name", ay.name}, {"from", ay.from}, {"to", ay.to}, {"count", ay.count}};
  summary["cells"] = ax.count * ay.count;
  summary["failed"] = nan;
  if (o.quantity == "flip") {
    summary["no_flip"] = never;
    summary["no_flip_by_energy"] = forbidden;
  }
  summary["threads"] = threads;
  summary["wall_seconds"] = seconds;
  summary["resumed"] = o.resume;
  summary["files"] = {"map.npy", "map.json", "map.gp", "map.png"};
  if (small) summary["files"].push_back("map.csv");
  cli::write_file_atomically(dir / "map.json", summary.dump(2) + "\n");
  fs::remove_all(dir / "tiles", ec);
  if (o.json) {
    std::cout << summary.dump(2) << "\n";
    return 0;
  }
  fmt::print("{} map of {} x {} cells ({} x {}) in {:.1f} s on {} threads: {}\n", o.quantity,
             ax.count, ay.count, ax.name, ay.name, seconds, threads, (dir / "map.npy").string());
  if (o.quantity == "flip")
    fmt::print("no flip by t = {:g} s: {} cells ({} of them ruled out by their energy)\n", o.t_end,
               never, forbidden);
  if (nan > 0) fmt::print("{} cells failed to integrate (NaN)\n", nan);
  return 0;
}

}  // namespace

void add_map_command(CLI::App& app, command_list& commands) {
  auto o = std::make_shared<map_command_options>();
  CLI::App* cmd = app.add_subcommand(
      "map",
      "A chaos map over a 2-D grid of starts: time to the first flip (Heyl's fractal) or the "
      "maximal Lyapunov exponent; tiles on every core, resumable; map.npy, map.png, map.json");
  o->chain.add_to(*cmd);
  cmd->add_option("--x", o->x, "NAME:FROM:TO:COUNT, NAME a start coordinate (phi1.., p1..)")
      ->required();
  cmd->add_option("--y", o->y, "NAME:FROM:TO:COUNT for the rows (row 0 = FROM)")->required();
  cmd->add_option("--quantity", o->quantity, "flip (default) or lyapunov");
  cmd->add_option("--phi", o->phi, "The start's other angles (rad; default 0)");
  cmd->add_option("--p", o->p, "The start's other momenta (kg m^2/s; default 0)");
  cmd->add_option("--t-end", o->t_end, "Integration time per cell in s (default 100)");
  cmd->add_option("--dt", o->dt, "rk4's step in s (default 0.01)");
  cmd->add_option("--flip-link", o->flip_link, "flip: only arm K counts (default 0: any arm)");
  cmd->add_option("--threads", o->threads, "Threads (default: every core)");
  cmd->add_option("--tile", o->tile, "Cells per tile side (default 16)");
  cmd->add_option("--out", o->out, "The folder for map.npy, map.png and map.json")->required();
  cmd->add_flag("--resume", o->resume,
                "Finish an interrupted map in --out (same command): its finished tiles are kept");
  cmd->add_flag("--json", o->json, "Print the summary (map.json) to stdout");
  commands.push_back({cmd, [o] { return run_map(*o); }});
}

}  // namespace npend::app
