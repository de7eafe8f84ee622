// npend map: a quantity of chaos — the time to the first flip (Heyl's fractal) or the maximal
// Lyapunov exponent — over a 2-D grid of start states, computed in tiles on every core (and
// across the ranks of an MPI job, or the jobs of an array with --part and `npend map merge`),
// written as .npy, PNG and JSON, and resumable after an interruption. The run itself — its
// identity, tiles, resume, parallel computation and assembly — is the library's map_run
// (npend/analysis/chaos/map_run.hpp), which also keeps the output folder's rules; this file
// parses, prints and writes the result files.
#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <future>
#include <iostream>
#include <limits>
#include <nlohmann/json.hpp>

#include "chain_options.hpp"
#include "command.hpp"
#include "input_parsing.hpp"
#include "integrator_options.hpp"
#include "map_options.hpp"
#include "npend/analysis/chaos/chaos_map.hpp"
#include "npend/analysis/chaos/map_grid.hpp"
#include "npend/analysis/chaos/map_run.hpp"
#include "output_file.hpp"
#include "plotting.hpp"
#include "section_spec.hpp"
#include "terminal_run.hpp"
#include "thread_count.hpp"
#ifdef NPEND_WITH_MPI
#include "map_mpi.hpp"
#endif

namespace npend::app {

namespace {

namespace fs = std::filesystem;

using axis = map_axis;

std::string bytes_of(const std::vector<double>& values) {
  return std::string(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(double));
}

constexpr long max_csv_cells = 65536;  // 256 × 256: beyond that only the .npy
constexpr int max_drawn_cells = 1024;  // cells a side that map.png draws

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

// --part I/N: the tiles whose index is I - 1 modulo N (map_part).
map_part parse_part(const std::string& text) {
  const auto whole = [](std::string_view piece, int& out) {
    const std::string digits(cli::trim(piece));
    if (digits.empty() || digits.size() > 6 ||
        digits.find_first_not_of("0123456789") != std::string::npos)
      return false;
    out = std::stoi(digits);
    return true;
  };
  const auto pieces = cli::split_list(text, '/');
  map_part share;
  if (pieces.size() != 2 || !whole(pieces[0], share.index) || !whole(pieces[1], share.count) ||
      share.index < 1 || share.index > share.count)
    throw cli::input_error(
        fmt::format("--part: expected I/N with 1 <= I <= N (e.g. 3/8), got '{}'", text));
  return share;
}

// The options and the library's run they describe.
struct map_job {
  map_command_options o;
  map_run run;

  bool parted() const { return !o.part.empty(); }
};

// The options as typed (the chain file's values filled in), stored in run.json beside the
// identity so that `npend map merge DIR` can rebuild the run from the folder alone.
constexpr std::pair<const char*, std::string cli::chain_options::*> chain_texts[] = {
    {"masses", &cli::chain_options::masses},
    {"lengths", &cli::chain_options::lengths},
    {"g", &cli::chain_options::g},
    {"com", &cli::chain_options::com},
    {"inertia", &cli::chain_options::inertia},
    {"stiffness", &cli::chain_options::stiffness},
    {"rest_angles", &cli::chain_options::rest_angles},
    {"damping", &cli::chain_options::damping},
    {"pivot", &cli::chain_options::pivot}};
constexpr std::pair<const char*, std::string map_command_options::*> map_texts[] = {
    {"x", &map_command_options::x},
    {"y", &map_command_options::y},
    {"quantity", &map_command_options::quantity},
    {"component", &map_command_options::component},
    {"phi", &map_command_options::phi},
    {"p", &map_command_options::p},
    {"dphi", &map_command_options::dphi},
    {"stepper", &map_command_options::stepper},
    {"abs_tol", &map_command_options::abs_tol},
    {"rel_tol", &map_command_options::rel_tol},
    {"device", &map_command_options::device}};

nlohmann::json options_record(const map_command_options& o) {
  const cli::chain_options chain = o.chain.with_file();
  nlohmann::json j = {
      {"links", chain.links},     {"rods", chain.rods},         {"t_end", o.t_end}, {"dt", o.dt},
      {"flip_link", o.flip_link}, {"gali_order", o.gali_order}, {"tile", o.tile}};
  for (const auto& [key, member] : chain_texts) j[key] = chain.*member;
  for (const auto& [key, member] : map_texts) j[key] = o.*member;
  // Written only when given, so that a run without it keeps the record (and the folder it
  // resumes) of the versions before --tol.
  if (!o.tol.empty()) j["tol"] = o.tol;
  return j;
}

// Throws nlohmann::json::exception for a record that is not options_record's.
map_command_options options_from_record(const nlohmann::json& j) {
  map_command_options o;
  o.chain.links = j.at("links").get<int>();
  o.chain.rods = j.at("rods").get<bool>();
  o.t_end = j.at("t_end").get<double>();
  o.dt = j.at("dt").get<double>();
  o.flip_link = j.at("flip_link").get<int>();
  o.gali_order = j.at("gali_order").get<int>();
  o.tile = j.at("tile").get<int>();
  for (const auto& [key, member] : chain_texts) o.chain.*member = j.at(key).get<std::string>();
  // Records written before a key existed lack it: the option was not given.
  for (const auto& [key, member] : map_texts) o.*member = j.value(key, std::string());
  o.tol = j.value("tol", std::string());
  return o;
}

// --device, checked against the map (what the GPU maps take) and the machine (a usable GPU)
// before any file is touched. Throws input_error naming the option.
map_device device_of(const map_command_options& o, const chain& c, const map_cell_options& cell) {
  if (o.device.empty()) return map_device::cpu;
  map_device device{};
  try {
    device = parse_map_device(o.device);
  } catch (const std::invalid_argument& e) {
    throw cli::input_error(fmt::format("--device: {}", e.what()));
  }
  if (device == map_device::cpu) return device;
  try {
    check_cuda_map(c, cell);
  } catch (const std::invalid_argument& e) {
    throw cli::input_error(fmt::format("--device cuda: {}", e.what()));
  }
  if (const cuda_status s = find_cuda(); !s.usable)
    throw cli::input_error(fmt::format(
        "--device cuda: CUDA is not usable here: {} (--device cpu runs on the CPU)", s.problem));
  return device;
}

// Where the cells ran, for map.json and the summary line: the threads, or the GPU.
nlohmann::json device_facts(const map_job& job, int threads) {
  if (job.run.description().device == map_device::cpu)
    return {{"device", "cpu"}, {"threads", threads}};
  return {{"device", "cuda"},
          {"gpu", find_cuda().device},
          {"gpu_kernel_seconds", cuda_kernel_seconds()}};
}

std::string device_words(const map_job& job, int threads) {
  if (job.run.description().device == map_device::cpu) return fmt::format("on {} threads", threads);
  return fmt::format("on the GPU ({})", find_cuda().device);
}

// Checks the options and builds the run; touches no file.
map_job prepare_run(const map_command_options& o) {
  map_view view = describe_map(o);
  try {
    check_map_tile_size(o.tile);
  } catch (const std::invalid_argument& e) {
    throw cli::input_error(fmt::format("--{}", e.what()));
  }
  cli::check_thread_count(o.threads, "--threads");
  if (o.force && (o.resume || !o.part.empty()))
    throw cli::input_error(
        "--force: only for a fresh run (--resume and --part keep the folder's tiles)");
  const map_part part = o.part.empty() ? map_part{} : parse_part(o.part);
  const map_device device = device_of(o, chain(view.grid.parameters), view.cell);
  if (o.out.empty()) throw cli::input_error("--out: the folder for map.npy, map.png, map.json");
  return {o, map_run({std::move(view.grid), view.cell, o.tile, part, device}, fs::path(o.out))};
}

// run.json of a folder; input_error naming `option` if it is not readable.
map_run_record read_run_file(const fs::path& file, std::string_view option) {
  std::optional<map_run_record> record = read_map_run_record(file);
  if (!record) throw cli::input_error(fmt::format("{}: {} is not readable", option, file.string()));
  return *record;
}

// The folder made ready as the options say (map_run::open_folder); its refusals are bad
// input.
void prepare_folder(const map_job& job) {
  const map_folder_start start = job.parted()   ? map_folder_start::part
                                 : job.o.resume ? map_folder_start::resume
                                 : job.o.force  ? map_folder_start::force
                                                : map_folder_start::fresh;
  try {
    job.run.open_folder(start, options_record(job.o).dump());
  } catch (const std::invalid_argument& e) {
    throw cli::input_error(e.what());
  }
}

// A tile that is not sound, with what to do about it: a folder in a tile's place is bad
// input, anything else a failure.
[[noreturn]] void throw_tile_error(const map_tile_error& e) {
  const std::string what = std::string(e.what()) + "; remove it and finish with --resume";
  if (e.is_folder()) throw cli::input_error(what);
  throw std::runtime_error(what);
}

// The tiles this run computes; a tile a resumed run finds unsound is computed again, and
// stderr says why.
std::vector<int> pending_tiles(const map_job& job) {
  try {
    return job.run.pending_tiles(job.o.resume, [](const std::string& problem) {
      fmt::print(stderr, "npend map: note: {}; computing it again\n", problem);
    });
  } catch (const map_tile_error& e) {
    throw_tile_error(e);
  }
}

// The tiles as atomic output files, not synced: a tile is checked when read back (its size,
// the run's tag and the checksum), so one that a crash of the machine left incomplete or
// garbled is found, and the disk takes one fsync at a time, which would make the threads
// queue for it.
void write_tile_file(const fs::path& path, std::string_view bytes) {
  cli::write_file_atomically(path, bytes, cli::durability::cached);
}

// The tiles `queue` hands out, on `threads` threads (map_run::compute_tiles); the progress
// bar, shown with `show_progress`, counts `total` tiles.
map_tiles_outcome compute_tiles(const map_job& job, map_tile_queue& queue, int threads,
                                cli::terminal_run& control, long total, bool show_progress) {
  const map_tiles_outcome outcome =
      job.run.compute_tiles(queue, threads, control, write_tile_file, total, show_progress);
  control.finish();
  return outcome;
}

int report_interrupted(const map_job& job, int exit_code) {
  fmt::print(stderr,
             "npend map: interrupted: {} of {} tiles are in {}; finish with the same command "
             "and --resume\n",
             job.run.tiles_present(), job.run.layout().count(), job.run.tiles_folder().string());
  return exit_code;
}

// The heat map. `low`..`high` is the range of the finite values (for flip times dt..t_end, on
// a log scale). The palette is viridis between two thin bands: white at the top for the cells
// that never flipped (+inf), red at the bottom for failed cells (NaN). The colour bar runs
// from `bottom` to `top`, a hair beyond low and high, and those cells are given these ends.
// (Leaving them undefined needs gnuplot's `image pixels`, whose millions of sub-pixel
// rectangles wash the colours out.)
// `mask_header_bytes` > 0: forbidden.npy marks the cells the energy rules out, drawn grey.
// Without failed cells every NaN is a forbidden one, so the map's NaN are left transparent
// over a grey plot area; only with failed cells too (red) does forbidden.npy go over the map
// as a grey layer, whose per-cell `using` expressions cost gnuplot most of its time on a
// large map.
cli::plot_outcome write_png(const fs::path& dir, const map_command_options& o,
                            map_quantity quantity, const axis& ax, const axis& ay,
                            std::size_t header_bytes, double low, double high,
                            std::size_t mask_header_bytes, long failed) {
  quantity_style style = style_of(o, quantity);
  if (mask_header_bytes > 0) style.title += "; grey: ruled out by the energy";
  // A 900 x 800 picture shows at most ~1000 cells a side: beyond that gnuplot draws every
  // stride-th cell (a 4096² map drawn whole: gnuplot took over 4.5 minutes and 1.6 GB).
  const int stride = (std::max(ax.count, ay.count) + max_drawn_cells - 1) / max_drawn_cells;
  const std::string every = stride > 1 ? fmt::format(" every {0}:{0}", stride) : "";
  const bool logarithmic = style.logarithmic;
  const double dx = ax.count > 1 ? (ax.to - ax.from) / (ax.count - 1) : 1;
  const double dy = ay.count > 1 ? (ay.to - ay.from) / (ay.count - 1) : 1;
  // low and high sit at these fractions of the colour bar (the palette's indices -0.02..4.02
  // put viridis's ends at 0.00495 and 0.99505).
  constexpr double low_at = 0.005, high_at = 0.995;
  const auto scale = [&](double v) { return logarithmic ? std::log(v) : v; };
  const auto unscale = [&](double v) { return logarithmic ? std::exp(v) : v; };
  const double range = (scale(high) - scale(low)) / (high_at - low_at);
  const double bottom = unscale(scale(low) - low_at * range),
               top = unscale(scale(low) + (1 - low_at) * range);
  cli::plot_panel panel{
      .title = style.title,
      .xlabel = stride > 1 ? fmt::format("{0}   (drawn: 1 cell in {1} x {1}; map.npy has all)",
                                         ax.name, stride)
                           : ax.name,
      .ylabel = ay.name,
      // Equal scales where both axes are angles; a square otherwise (energy against a mass).
      .commands = {ax.kind == map_axis_kind::angle && ay.kind == map_axis_kind::angle
                       ? "set size ratio -1"
                       : "set size ratio 1",
                   // viridis, a perceptual colour map, then white for the cells without a value
                   "set palette defined (-0.02 '#d62728', -0.0001 '#d62728', 0 '#440154', "
                   "1 '#3b528b', 2 '#21918c', 3 '#5ec962', 4 '#fde725', 4.0001 'white', "
                   "4.02 'white')",
                   fmt::format("set cbrange [{:.17g}:{:.17g}]", bottom, top),
                   fmt::format("set cblabel '{}'", style.label),
                   fmt::format("set xrange [{}:{}]", std::min(ax.from, ax.to) - dx / 2,
                               std::max(ax.from, ax.to) + dx / 2),
                   fmt::format("set yrange [{}:{}]", std::min(ay.from, ay.to) - dy / 2,
                               std::max(ay.from, ay.to) + dy / 2)}};
  if (logarithmic) panel.commands.push_back("set logscale cb");
  const bool grey_behind = mask_header_bytes > 0 && failed == 0;
  if (grey_behind)
    panel.commands.push_back(
        "set object 1 rectangle from graph 0,0 to graph 1,1 behind fillcolor rgb '#a0a0a0' "
        "fillstyle solid noborder");
  // Values below `low` (a SALI that reached 0) take its colour; NaN is red (failed) or, over
  // the grey area, transparent.
  panel.curves.push_back(
      {"map.npy",
       fmt::format("($1 == $1 ? (abs($1) < 1e300 ? ($1 > {:.17g} ? $1 : {:.17g}) : {:.17g}) : "
                   "{})",
                   low, low, top, grey_behind ? "NaN" : fmt::format("{:.17g}", bottom)),
       "image", "",
       fmt::format("binary skip={} array=({},{}) format='%float64' dx={} dy={} origin=({},{}){}",
                   header_bytes, ax.count, ay.count, dx, dy, ax.from, ay.from, every)});
  if (mask_header_bytes > 0 && !grey_behind)
    panel.curves.push_back(
        {"forbidden.npy", "(160):(160):(160):($1 > 0 ? 255 : 0)", "rgbalpha", "",
         fmt::format("binary skip={} array=({},{}) format='%uint8' dx={} dy={} origin=({},{}){}",
                     mask_header_bytes, ax.count, ay.count, dx, dy, ax.from, ay.from, every)});
  return cli::write_plot(dir / "map", {.description = {"npend map: " + panel.title},
                                       .width = 900,
                                       .height = 800,
                                       .panels = {panel}});
}

// Reads every tile into the map and writes map.npy (and map.csv for small grids), map.png,
// map.gp and map.json, then removes the tiles; returns map.json's content. `facts`: how the
// run went (threads, ranks, merged), added to map.json. A signal (`control`) stops it before
// map.npy and before map.json, keeping the tiles: throws cli::interrupted saying so (the
// output files' temporaries go as they unwind).
nlohmann::json assemble_map(const map_job& job, const nlohmann::json& facts,
                            std::chrono::steady_clock::time_point started,
                            cli::terminal_run& control) {
  const map_run& run = job.run;
  const auto stopped = [&] {
    return cli::interrupted(
        fmt::format("interrupted while assembling the map; its tiles stay in {}: npend map "
                    "merge {} assembles it",
                    run.tiles_folder().string(), job.o.out),
        control.exit_code());
  };
  const map_command_options& o = job.o;
  const map_quantity quantity = run.cell().quantity;
  const axis &ax = run.grid().x, &ay = run.grid().y;
  std::optional<std::vector<double>> assembled;
  try {
    assembled = run.assemble(&control);
  } catch (const map_tile_error& e) {
    throw_tile_error(e);
  }
  if (!assembled) throw stopped();
  const std::vector<double>& grid = *assembled;  // row-major, row 0 = the first y value
  // The result files all or none (the tiles stay for --resume until they are in place).
  cli::output_batch batch;
  const std::string header = npy_header(ay.count, ax.count);
  cli::write_file_atomically(run.folder() / "map.npy", header + bytes_of(grid));
  const bool small = static_cast<long>(ax.count) * ay.count <= max_csv_cells;
  // NaN: ruled out by the energy (not integrated) or failed; +inf: no flip by t_end.
  const map_cell_counts counts = run.count_cells(grid);
  const long forbidden = counts.forbidden, failed = counts.failed;
  const std::string mask_header = forbidden > 0 ? npy_header(ay.count, ax.count, "|u1") : "";
  if (forbidden > 0)
    cli::write_file_atomically(
        run.folder() / "forbidden.npy",
        mask_header + std::string(counts.forbidden_mask.begin(), counts.forbidden_mask.end()));
  double low = std::numeric_limits<double>::infinity(), high = -low;
  for (const double v : grid)
    if (std::isfinite(v)) low = std::min(low, v), high = std::max(high, v);
  const bool indicator_to_zero = quantity == map_quantity::sali || quantity == map_quantity::gali;
  if (quantity ==
      map_quantity::flip) {  // dt..t_end on a log scale (a decade when t_end is one step)
    low = o.dt;
    high = o.t_end > o.dt ? o.t_end : 10 * o.dt;
  } else if (indicator_to_zero) {  // a log scale: from 1e-16 (or the least value) up
    low = std::max(low, 1e-16);
    if (!(high > low)) high = low * 10;
  } else if (!(high > low)) {  // no finite value, or all equal: any range that shows them
    low = std::isfinite(low) ? low - 1 : 0;
    high = low + 2;
  }
  // gnuplot draws from map.npy and forbidden.npy while this thread writes the rest, so that
  // its time overlaps the CSV's and the summary's.
  std::future<cli::plot_outcome> plot = std::async(std::launch::async, [&] {
    return write_png(run.folder(), o, quantity, ax, ay, header.size(), low, high,
                     mask_header.size(), failed);
  });
  if (small) write_csv(run.folder() / "map.csv", ax, ay, grid);
  nlohmann::json summary = nlohmann::json::parse(run.identity());
  summary.update(facts);
  summary["x"] = {{"name", ax.name}, {"from", ax.from}, {"to", ax.to}, {"count", ax.count}};
  summary["y"] = {{"name", ay.name}, {"from", ay.from}, {"to", ay.to}, {"count", ay.count}};
  summary["cells"] = ax.count * ay.count;
  summary["integrated"] = ax.count * ay.count - forbidden;
  summary["forbidden"] = forbidden;
  summary["failed"] = failed;
  if (quantity == map_quantity::flip) summary["no_flip"] = counts.no_flip;
  // The batch lanes the cells ran on (0: cell by cell), and the ISA they ran on.
  summary["batch"] = {{"isa", batch_lane_isa()}, {"lanes", batch_lanes(run.base_chain())}};
  summary["stepper"] = stepper_name(run.cell().stepping.stepper);
  summary["resumed"] = o.resume;
  summary["files"] = {"map.npy", "map.json", "map.gp", "map.png"};
  if (small) summary["files"].push_back("map.csv");
  if (forbidden > 0) summary["files"].push_back("forbidden.npy");
  std::error_code ec;
  if (forbidden == 0) fs::remove(run.folder() / "forbidden.npy", ec);  // an earlier map's
  const cli::plot_outcome drawn = plot.get();
  if (!drawn.rendered) fmt::print(stderr, "npend map: note: {}\n", drawn.message);
  summary["wall_seconds"] =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  if (control.interrupted()) throw stopped();
  cli::write_file_atomically(run.folder() / "map.json", summary.dump(2) + "\n");
  batch.commit_all();
  run.remove_own_tiles();
  return summary;
}

// `how`: where the map was computed ("on 8 threads"), for the line on stdout.
void print_map_summary(const map_job& job, const nlohmann::json& summary, const std::string& how) {
  const map_run& run = job.run;
  if (job.o.json) {
    std::cout << summary.dump(2) << "\n";
    return;
  }
  fmt::print("{} map of {} x {} cells ({} x {}) in {:.1f} s {}: {}\n",
             map_quantity_name(run.cell().quantity), run.grid().x.count, run.grid().y.count,
             run.grid().x.name, run.grid().y.name, summary["wall_seconds"].get<double>(), how,
             (run.folder() / "map.npy").string());
  if (summary["forbidden"].get<long>() > 0)
    fmt::print("{} cells ruled out by their energy, not integrated (NaN; forbidden.npy)\n",
               summary["forbidden"].get<long>());
  if (run.cell().quantity == map_quantity::flip)
    fmt::print("no flip by t = {:g} s: {} cells (+inf)\n", job.o.t_end,
               summary["no_flip"].get<long>());
  if (summary["failed"].get<long>() > 0)
    fmt::print("{} cells failed to integrate (NaN)\n", summary["failed"].get<long>());
}

// A part of a job array assembles nothing: it says what it did and how to merge.
void print_part_summary(const map_job& job, long computed, double seconds) {
  const long present = job.run.tiles_present();
  const int tiles = job.run.layout().count();
  if (job.o.json) {
    const nlohmann::json summary = {{"part", job.o.part},
                                    {"tiles_computed", computed},
                                    {"tiles_present", present},
                                    {"tiles", tiles},
                                    {"wall_seconds", seconds}};
    std::cout << summary.dump(2) << "\n";
    return;
  }
  fmt::print(
      "part {} of the map: {} tiles in {:.1f} s; {} of {} tiles are in {}; when every part is "
      "done: npend map merge {}\n",
      job.o.part, computed, seconds, present, tiles, job.run.tiles_folder().string(), job.o.out);
}

// After the tiles: a part stops here, a whole run assembles the map.
int finish_map(const map_job& job, long computed, const nlohmann::json& facts,
               const std::string& how, std::chrono::steady_clock::time_point started,
               cli::terminal_run& control) {
  if (job.parted()) {
    print_part_summary(
        job, computed,
        std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count());
    return 0;
  }
  print_map_summary(job, assemble_map(job, facts, started, control), how);
  return 0;
}

int thread_count(const map_command_options& o) {
  return o.threads > 0 ? o.threads : omp_get_max_threads();
}

// One process: its threads take the tiles from a shared counter.
int run_map(const map_command_options& o) {
  const auto started = std::chrono::steady_clock::now();
  const map_job job = prepare_run(o);
  prepare_folder(job);
  const int threads = thread_count(o);
  const std::vector<int> pending = pending_tiles(job);
  const long total = static_cast<long>(pending.size());
  local_map_tile_queue queue(pending);
  cli::terminal_run control;
  const map_tiles_outcome outcome = compute_tiles(job, queue, threads, control, total, true);
  if (outcome.error) std::rethrow_exception(outcome.error);
  if (outcome.stopped) return report_interrupted(job, control.exit_code());
  return finish_map(job, total, device_facts(job, threads), device_words(job, threads), started,
                    control);
}

// `npend map merge DIR`: the map from the tiles that --part runs left in DIR/tiles/, exactly
// as one uninterrupted run would have written it.
int run_merge(const std::string& folder, bool json) {
  const auto started = std::chrono::steady_clock::now();
  cli::terminal_run control;  // Ctrl-C stops the merge, keeping the tiles
  if (folder.empty()) throw cli::input_error("merge: the folder name is empty");
  const fs::path file = fs::path(folder) / "tiles" / "run.json";
  if (!fs::exists(file))
    throw cli::input_error(
        fmt::format("merge: {} holds no map's tiles (no {})", folder, file.string()));
  const map_run_record record = read_run_file(file, "merge");
  map_command_options o;
  try {
    o = options_from_record(nlohmann::json::parse(record.options));
  } catch (const nlohmann::json::exception&) {
    throw cli::input_error(fmt::format("merge: {} is not readable", file.string()));
  }
  o.out = folder;
  o.json = json;
  const map_job job = prepare_run(o);
  if (!job.run.same_map(record))
    throw cli::input_error(fmt::format(
        "merge: {} does not describe the map its options give (written by another npend?)",
        file.string()));
  const std::vector<int> missing = job.run.missing_tiles();
  if (!missing.empty()) {
    constexpr std::size_t shown = 8;
    std::string names;
    for (std::size_t k = 0; k < std::min(shown, missing.size()); ++k)
      names += (k > 0 ? ", " : "") + job.run.tile_path(missing[k]).filename().string();
    if (missing.size() > shown) names += ", ...";
    throw cli::input_error(fmt::format(
        "merge: {} of {} tiles are missing from {}: {} (run the parts that compute them, with "
        "--resume to keep the tiles that are there)",
        missing.size(), job.run.layout().count(), job.run.tiles_folder().string(), names));
  }
  return finish_map(job, 0, {{"merged", true}}, "by merging its tiles", started, control);
}

#ifdef NPEND_WITH_MPI
[[noreturn]] void abort_job(const mpi::session& mpi, const std::exception_ptr& error) {
  try {
    std::rethrow_exception(error);
  } catch (const std::exception& e) {
    mpi.abort(e.what(), 1);
  } catch (...) {
    mpi.abort("unknown error", 1);
  }
}

// One rank of an MPI job: rank 0 prepares the folder, hands out the tiles (its own threads
// compute too) and assembles the map; the others compute the tiles it hands them. Bad input
// is found by every rank alike and reported by rank 0 only.
int run_map_on_ranks(const map_command_options& o, mpi::session& mpi) {
  const auto started = std::chrono::steady_clock::now();
  const map_job job = prepare_run(o);
  if (mpi.rank() == 0) {
    try {
      prepare_folder(job);
    } catch (const cli::input_error&) {
      mpi.broadcast(2);
      throw;
    } catch (...) {
      mpi.broadcast(1);
      throw;
    }
  }
  if (const int failed = mpi.broadcast(0); failed != 0) return failed;
  const int threads = thread_count(o);
  cli::terminal_run control;
  long total = 0;
  map_tiles_outcome outcome;
  std::vector<long> tiles_per_rank;
  if (mpi.rank() == 0) {
    const std::vector<int> pending = pending_tiles(job);
    total = static_cast<long>(pending.size());
    local_map_tile_queue tiles(pending);
    mpi::tile_coordinator queue(tiles, mpi);
    outcome = compute_tiles(job, queue, threads, control, total, true);
    if (outcome.error) abort_job(mpi, outcome.error);
    queue.wait_for_ranks();
    tiles_per_rank = queue.tiles_per_rank();
  } else {
    mpi::tile_worker queue;
    outcome = compute_tiles(job, queue, threads, control, 0, false);
    if (outcome.error) abort_job(mpi, outcome.error);
    queue.done();
  }
  const int exit_code = mpi.max(outcome.stopped ? control.exit_code() : 0);
  if (mpi.rank() != 0) return exit_code;
  if (exit_code != 0) return report_interrupted(job, exit_code);
  // The ranks need each other no more. MPI_Finalize waits for mpirun, which takes a while;
  // rank 0 assembles the map meanwhile. (MPI_Finalize must be called by the thread that
  // initialised MPI, so the map goes to another thread.)
  std::future<int> finished = std::async(std::launch::async, [&] {
    nlohmann::json facts = device_facts(job, threads);
    facts["ranks"] = mpi.size();
    facts["tiles_per_rank"] = tiles_per_rank;
    return finish_map(job, total, facts,
                      fmt::format("on {} ranks, each {}", mpi.size(), device_words(job, threads)),
                      started, control);
  });
  mpi.finalize();
  return finished.get();
}
#endif

// MPI only under an MPI launcher: a plain start (a shell, a job array's task) never pays for
// MPI_Init, which in Open MPI starts a helper daemon even for a single process.
int run_map_command(const map_command_options& o) {
#ifdef NPEND_WITH_MPI
  if (mpi::launched()) {
    mpi::session mpi;
    try {
      return run_map_on_ranks(o, mpi);
    } catch (const cli::input_error& e) {
      // Rank 0 says it, and before MPI_Finalize: once the other ranks have exited with 2,
      // mpirun may end rank 0 at any moment, so a message printed after the session (by
      // main, as for one process) was sometimes lost.
      if (mpi.rank() == 0) {
        fmt::print(stderr, "npend map: error: {}\n", e.what());
        std::fflush(stderr);
      }
      return 2;
    }
  }
#endif
  return run_map(o);
}

// `npend map merge DIR` or `npend map ...`: --links, --x, --y and --out are checked here, not
// by CLI11, which would demand them of `npend map merge DIR` too.
int run_map_subcommand(const map_command_options& o, const CLI::App& cmd, const CLI::App& merge) {
  if (merge.parsed()) {
    for (const CLI::Option* option : cmd.get_options())
      if (option->count() > 0)
        throw cli::input_error(
            fmt::format("merge: takes the folder (and --json) only, not {}", option->get_name()));
    return run_merge(o.merge_dir, o.merge_json);
  }
  for (const char* name : {"--links", "--x", "--y", "--out"})
    if (cmd.get_option(name)->count() == 0)
      throw cli::input_error(fmt::format("{} is required (see npend map --help)", name));
  return run_map_command(o);
}

}  // namespace

void add_map_command(CLI::App& app, command_list& commands) {
  auto o = std::make_shared<map_command_options>();
  CLI::App* cmd = app.add_subcommand(
      "map",
      "A chaos map over a 2-D grid of starts, energies or chain parameters: time to the first "
      "flip (Heyl's fractal), the maximal Lyapunov exponent, a fast chaos indicator or the "
      "final state; tiles on every core, across MPI ranks (mpirun) or the jobs of "
      "an array (--part, then npend map merge DIR), resumable; map.npy, map.png, map.json");
  add_map_view_options(*cmd, *o);
  cmd->add_option("--threads", o->threads,
                  "Threads (default: every core; at most 4 x the hardware threads; per rank "
                  "under MPI)");
  cmd->add_option("--tile", o->tile, "Cells per tile side (default 16)");
  cmd->add_option("--device", o->device,
                  "cpu (default: the CPU's threads) or cuda: the cells on a GPU (every quantity; "
                  "rk4 or dopri5; the GPU of each MPI rank's local rank); needs the CUDA driver "
                  "and NVRTC at run time, not to build");
  cmd->add_option("--out", o->out, "The folder for map.npy, map.png and map.json (required)");
  cmd->add_flag("--resume", o->resume,
                "Finish an interrupted map in --out (same command): its finished tiles are kept");
  cmd->add_flag("--force", o->force,
                "Start afresh in an --out whose tiles/ holds another run (an unfinished map, "
                "a job array's parts): removes npend's tile files from it, nothing else");
  cmd->add_option("--part", o->part,
                  "I/N: compute only the tiles whose index is I-1 modulo N into --out's tiles/ "
                  "(one job of an array of N; no map: npend map merge DIR assembles it)");
  cmd->add_flag("--json", o->json, "Print the summary (map.json) to stdout");
  CLI::App* merge = cmd->add_subcommand(
      "merge", "Assemble map.npy, map.png, map.json from the tiles --part runs left in DIR");
  merge->add_option("dir", o->merge_dir, "The --out folder of the parts")->required();
  merge->add_flag("--json", o->merge_json, "Print the summary (map.json) to stdout");
  commands.push_back({cmd, [o, cmd, merge] { return run_map_subcommand(*o, *cmd, *merge); }});
}

}  // namespace npend::app
