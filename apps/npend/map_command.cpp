// npend map: a quantity of chaos — the time to the first flip (Heyl's fractal) or the maximal
// Lyapunov exponent — over a 2-D grid of start states, computed in tiles on every core (and
// across the ranks of an MPI job, or the jobs of an array with --part and `npend map merge`),
// written as .npy, PNG and JSON, and resumable after an interruption.
#include <fmt/format.h>
#include <omp.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <future>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <limits>
#include <nlohmann/json.hpp>

#include "chain_options.hpp"
#include "command.hpp"
#include "input_parsing.hpp"
#include "integrator_options.hpp"
#include "map_tile_queue.hpp"
#include "npend/analysis/chaos/chaos_map.hpp"
#include "npend/analysis/chaos/map_grid.hpp"
#include "npend/batch_math.hpp"
#include "npend/integrators/integration_error.hpp"
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

struct map_command_options {
  cli::chain_options chain;
  std::string x, y, quantity = "flip", component, phi, p, dphi, out, part;
  std::string stepper, abs_tol, rel_tol;  // as typed; empty: rk4, tolerances 1e-10
  double t_end = 100, dt = 0.01;
  int flip_link = 0, gali_order = 0, threads = 0, tile = 16;
  bool resume = false, json = false, force = false;
  std::string merge_dir;  // npend map merge DIR [--json]
  bool merge_json = false;
};

using axis = map_axis;

// NAME:FROM:TO:COUNT: count values from `from` to `to`, both ends included, of a start
// coordinate, the energy or a parameter of the chain (map_grid.hpp).
axis parse_axis(const std::string& text, const char* option, int links) {
  const auto parts = cli::split_list(text, ':');
  if (parts.size() != 4)
    throw cli::input_error(fmt::format(
        "{}: expected NAME:FROM:TO:COUNT (e.g. phi1:-3.14:3.14:256), got '{}'", option, text));
  const double from = cli::parse_number(parts[1], option);
  const double to = cli::parse_number(parts[2], option);
  const double count = cli::parse_number(parts[3], option);
  if (!cli::is_whole_number(count, 1, 16384))
    throw cli::input_error(
        fmt::format("{}: the count must be a whole number 1..16384, got {}", option, parts[3]));
  try {
    return make_map_axis(cli::trim(parts[0]), from, to, static_cast<int>(count), links);
  } catch (const std::invalid_argument& e) {
    throw cli::input_error(fmt::format("{}: {}", option, e.what()));
  }
}

// The .npy format (version 1.0): a C-order array of shape (rows, cols) of `descr` ('<f8':
// little-endian float64, '|u1': bytes).
std::string npy_header(int rows, int cols, std::string_view descr = "<f8") {
  std::string dict = fmt::format("{{'descr': '{}', 'fortran_order': False, 'shape': ({}, {}), }}",
                                 descr, rows, cols);
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
constexpr int max_drawn_cells = 1024;   // cells a side that map.png draws

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

// Which tiles a run computes: all of them, or with --part I/N those whose index is I - 1
// modulo N — a fixed assignment, so that the jobs of an array need not talk to each other.
struct part_share {
  int index = 1, count = 1;
  bool has(int tile) const { return tile % count == index - 1; }
};

part_share parse_part(const std::string& text) {
  const auto whole = [](std::string_view piece, int& out) {
    const std::string digits(cli::trim(piece));
    if (digits.empty() || digits.size() > 6 ||
        digits.find_first_not_of("0123456789") != std::string::npos)
      return false;
    out = std::stoi(digits);
    return true;
  };
  const auto pieces = cli::split_list(text, '/');
  part_share share;
  if (pieces.size() != 2 || !whole(pieces[0], share.index) || !whole(pieces[1], share.count) ||
      share.index < 1 || share.index > share.count)
    throw cli::input_error(
        fmt::format("--part: expected I/N with 1 <= I <= N (e.g. 3/8), got '{}'", text));
  return share;
}

// The cells of one tile: columns x0..x1 - 1, rows y0..y1 - 1.
struct tile_bounds {
  int x0, x1, y0, y1;
  std::size_t cells() const { return static_cast<std::size_t>((x1 - x0) * (y1 - y0)); }
};

struct tile_layout {
  int size, tiles_x, tiles_y;
  int count() const { return tiles_x * tiles_y; }
  // Tile `index` (row-major over the tiles), clipped at the grid's edges.
  tile_bounds bounds(int index, const axis& ax, const axis& ay) const {
    const int x0 = index % tiles_x * size, y0 = index / tiles_x * size;
    return {x0, std::min(ax.count, x0 + size), y0, std::min(ay.count, y0 + size)};
  }
};

// FNV-1a (64 bit): of the run's identity, the tag at the head of every tile file, which ties
// the tile to its run.json without repeating the identity in each tile; and of each tile's
// data, its checksum.
std::uint64_t fnv1a(std::string_view text) {
  std::uint64_t hash = 0xcbf29ce484222325ULL;
  for (const unsigned char ch : text) {
    hash ^= ch;
    hash *= 0x100000001b3ULL;
  }
  return hash;
}

// Everything a run needs, checked: the chain, the grid (its axes and base start), the tiles,
// and the run's identity, which a resumed run, another part or a merge must share.
struct map_run {
  map_command_options o;
  chain c;
  map_grid grid;
  map_cell_options cell;
  tile_layout layout;
  part_share part;
  fs::path dir;
  nlohmann::json identity;
  std::uint64_t tag;

  bool parted() const { return !o.part.empty(); }
  fs::path tiles() const { return dir / "tiles"; }
  fs::path run_file() const { return dir / "tiles" / "run.json"; }
  fs::path tile_path(int index) const {
    return dir / "tiles" / fmt::format("tile_{:06d}.bin", index);
  }
};

// The run's identity: what makes two runs the same map.
nlohmann::json run_identity(const map_command_options& o, const chain& c, const map_grid& grid,
                            const map_cell_options& cell) {
  const auto spec = [](const axis& a) {
    return nlohmann::json{{"name", a.name}, {"from", a.from}, {"to", a.to}, {"count", a.count}};
  };
  nlohmann::json identity = {{"links", c.links()},
          {"packed_parameters", c.packed_parameters()},
          {"x", spec(grid.x)},
          {"y", spec(grid.y)},
          {"quantity", o.quantity},
          {"component", cell.component},
          {"t_end", o.t_end},
          {"dt", o.dt},
          {"flip_link", o.flip_link},
          {"gali_order", o.gali_order},
          {"tile", o.tile},
          {"base_angles", grid.angles},
          {grid.velocities ? "base_velocities" : "base_momenta", grid.momenta}};
  // rk4 maps keep the identity they had before dopri5 came, so that their folders resume.
  if (cell.stepping.stepper != stepper_kind::rk4)
    identity["stepper"] = stepper_name(cell.stepping.stepper);
  if (cell.stepping.stepper == stepper_kind::dopri5) {
    identity["abs_tol"] = cell.stepping.abs_tol;
    identity["rel_tol"] = cell.stepping.rel_tol;
  }
  return identity;
}

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
    {"rel_tol", &map_command_options::rel_tol}};

nlohmann::json options_record(const map_command_options& o) {
  const cli::chain_options chain = o.chain.with_file();
  nlohmann::json j = {
      {"links", chain.links},     {"rods", chain.rods},         {"t_end", o.t_end}, {"dt", o.dt},
      {"flip_link", o.flip_link}, {"gali_order", o.gali_order}, {"tile", o.tile}};
  for (const auto& [key, member] : chain_texts) j[key] = chain.*member;
  for (const auto& [key, member] : map_texts) j[key] = o.*member;
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
  return o;
}

// --stepper, --abs-tol and --rel-tol. Throws input_error naming the option.
map_stepping map_stepping_of(const map_command_options& o, map_quantity quantity) {
  map_stepping stepping;
  if (!o.stepper.empty()) {
    try {
      stepping.stepper = parse_stepper_kind(o.stepper);
    } catch (const std::invalid_argument& e) {
      throw cli::input_error(fmt::format("--stepper: {}", e.what()));
    }
    if (!is_map_stepper(stepping.stepper))
      throw cli::input_error(fmt::format(
          "--stepper: a map integrates with one of {}, not {}", stepper_names(stepper_use::map),
          o.stepper));
  }
  if (!map_takes_stepper(quantity, stepping.stepper))
    throw cli::input_error(fmt::format(
        "--stepper: the chaos indicators ({}) integrate with rk4 only; {} takes flip, "
        "lyapunov and state",
        map_quantity_name(quantity), o.stepper));
  const auto tolerance = [&](const std::string& text, const char* option, double& value) {
    if (text.empty()) return;
    if (stepping.stepper != stepper_kind::dopri5)
      throw cli::input_error(
          fmt::format("{}: only with --stepper dopri5 (the others take a fixed --dt)", option));
    value = cli::parse_number(text, option);
    if (value < 0) throw cli::input_error(fmt::format("{}: must not be negative, got {}", option, value));
  };
  tolerance(o.abs_tol, "--abs-tol", stepping.abs_tol);
  tolerance(o.rel_tol, "--rel-tol", stepping.rel_tol);
  if (stepping.abs_tol == 0 && stepping.rel_tol == 0)
    throw cli::input_error("--abs-tol/--rel-tol: both are 0; at least one must be positive");
  return stepping;
}

// What each cell computes. Throws input_error for an unknown quantity or component.
map_cell_options cell_options(const map_command_options& o, int links) {
  map_cell_options cell;
  try {
    cell.quantity = parse_map_quantity(o.quantity);
  } catch (const std::invalid_argument& e) {
    throw cli::input_error(fmt::format("--{}", e.what()));
  }
  cell.t_end = o.t_end;
  cell.dt = o.dt;
  cell.flip_link = o.flip_link;
  cell.gali_order = o.gali_order;
  cell.stepping = map_stepping_of(o, cell.quantity);
  if (cell.quantity == map_quantity::state)
    cell.component = static_cast<int>(
        cli::parse_coordinate(o.component.empty() ? "phi1" : o.component, links, "--component"));
  else if (!o.component.empty())
    throw cli::input_error("--component: only with --quantity state");
  return cell;
}

// map_grid::validate's message with the option it is about: "--x: m2 = -1: ...".
std::string axis_message(const map_grid& grid, std::string_view what) {
  constexpr std::string_view both = "x and y: ";
  if (what.substr(0, both.size()) == both)
    return fmt::format("--x and --y: {}", what.substr(both.size()));
  const auto names = [&](const axis& a) {
    return what.substr(0, a.name.size()) == a.name &&
           what.find_first_of(": =") == a.name.size();
  };
  if (names(grid.x)) return fmt::format("--x: {}", what);
  if (names(grid.y)) return fmt::format("--y: {}", what);
  return std::string(what);
}

// The start every cell shares: --phi, and --p or --dphi (default 0).
void set_base_start(const map_command_options& o, int n, map_grid& grid) {
  grid.angles.assign(static_cast<std::size_t>(n), 0.0);
  grid.momenta.assign(static_cast<std::size_t>(n), 0.0);
  if (!o.phi.empty()) grid.angles = cli::parse_angle_list(o.phi, "--phi", n);
  if (!o.p.empty() && !o.dphi.empty())
    throw cli::input_error("--p and --dphi: give the start's momenta or its velocities, not both");
  grid.velocities = !o.dphi.empty();
  if (!o.p.empty())
    grid.momenta = cli::parse_number_list(o.p, "--p", static_cast<std::size_t>(n),
                                          fmt::format("p_1..p_{}", n));
  if (!o.dphi.empty())
    grid.momenta = cli::parse_number_list(o.dphi, "--dphi", static_cast<std::size_t>(n),
                                          fmt::format("dphi_1..dphi_{}", n));
}

// Checks the options and builds the run; touches no file.
map_run prepare_run(const map_command_options& o) {
  // Any chain: damping, springs and a driven pivot are axes too; map_grid::validate refuses
  // what a quantity or axis cannot take (an energy axis on a chain that loses energy).
  const chain c = o.chain.make_chain(cli::model_support::any, "npend map");
  const int n = c.links();
  const map_cell_options cell = cell_options(o, n);
  map_grid grid;
  grid.parameters = c.parameters();
  grid.x = parse_axis(o.x, "--x", n);
  grid.y = parse_axis(o.y, "--y", n);
  if (!(o.t_end > 0) || !(o.dt > 0) || o.dt > o.t_end)
    throw cli::input_error(
        fmt::format("--t-end and --dt: need 0 < dt <= t-end, got {} and {}", o.dt, o.t_end));
  // Each cell steps dt (dopri5: lays its grid of dt) to t_end, the limit every command keeps.
  cli::check_step_count(o.t_end, o.dt, "--t-end/--dt",
                        "use a larger --dt (the limit is per cell)");
  if (o.flip_link < 0 || o.flip_link > n)
    throw cli::input_error(
        fmt::format("--flip-link: 1..{} (or 0: any arm), got {}", n, o.flip_link));
  if (o.tile < 1 || o.tile > 1024)
    throw cli::input_error(fmt::format("--tile: 1..1024, got {}", o.tile));
  cli::check_thread_count(o.threads, "--threads");
  if (o.force && (o.resume || !o.part.empty()))
    throw cli::input_error(
        "--force: only for a fresh run (--resume and --part keep the folder's tiles)");
  const part_share part = o.part.empty() ? part_share{} : parse_part(o.part);
  set_base_start(o, n, grid);
  // The chain and options a cell can take, checked before any thread starts.
  if (cell.quantity != map_quantity::gali && o.gali_order != 0)
    throw cli::input_error(fmt::format("--gali-order: only with --quantity gali, not {}",
                                       map_quantity_name(cell.quantity)));
  if (cell.quantity == map_quantity::gali && o.gali_order != 0 &&
      (o.gali_order < 2 || o.gali_order > 2 * n))
    throw cli::input_error(
        fmt::format("--gali-order: 2..{} (2n), or 0 for n + 1, got {}", 2 * n, o.gali_order));
  try {
    cell.validate(c);
  } catch (const std::invalid_argument& e) {
    throw cli::input_error(e.what());
  }
  try {
    grid.validate(cell);
  } catch (const std::invalid_argument& e) {
    throw cli::input_error(axis_message(grid, e.what()));
  }
  if (o.out.empty()) throw cli::input_error("--out: the folder for map.npy, map.png, map.json");
  const tile_layout layout{o.tile, (grid.x.count + o.tile - 1) / o.tile,
                           (grid.y.count + o.tile - 1) / o.tile};
  nlohmann::json identity = run_identity(o, c, grid, cell);
  const std::uint64_t tag = fnv1a(identity.dump());
  return {o,      c,    std::move(grid),      cell, layout, part, fs::path(o.out),
          std::move(identity), tag};
}

nlohmann::json run_file_content(const map_run& run) {
  return {{"identity", run.identity}, {"options", options_record(run.o)}};
}

// run.json of a folder; input_error naming `option` if it is not readable.
nlohmann::json read_run_file(const fs::path& file, std::string_view option) {
  std::ifstream in(file);
  nlohmann::json j;
  try {
    in >> j;
  } catch (const nlohmann::json::exception&) {
  }
  if (!j.is_object() || !j.contains("identity") || !j.contains("options"))
    throw cli::input_error(fmt::format("{}: {} is not readable", option, file.string()));
  return j;
}

void check_same_map(const map_run& run, std::string_view option) {
  if (read_run_file(run.run_file(), option)["identity"] != run.identity)
    throw cli::input_error(fmt::format(
        "{}: {} holds a different map (other chain, axes, quantity or times)", option, run.o.out));
}

// Whether `name` is a file npend map writes in DIR/tiles: run.json, tile_NNNNNN.bin, or the
// hidden temporary of either (".<name>.npend-XXXXXX", cli::temporary_sibling) that a killed
// process may have left.
bool own_tile_file(std::string name) {
  constexpr std::string_view temporary = ".npend-";
  if (name.size() > 1 + temporary.size() + 6 && name.front() == '.' &&
      name.compare(name.size() - 6 - temporary.size(), temporary.size(), temporary) == 0)
    name = name.substr(1, name.size() - 1 - 6 - temporary.size());
  if (name == "run.json") return true;
  return name.size() == 15 && name.rfind("tile_", 0) == 0 &&
         name.compare(11, 4, ".bin") == 0 &&
         name.find_first_not_of("0123456789", 5) == 11;
}

// Removes npend's own files from DIR/tiles (own_tile_file), then the folder if that left it
// empty: a file someone else put there stays, and so does the folder holding it.
void remove_own_tiles(const map_run& run) {
  std::error_code ec;
  std::vector<fs::path> own;
  for (const auto& entry : fs::directory_iterator(run.tiles(), ec))
    if (own_tile_file(entry.path().filename().string()) && !entry.is_directory(ec))
      own.push_back(entry.path());
  for (const fs::path& path : own) fs::remove(path, ec);
  fs::remove(run.tiles(), ec);  // only if empty
}

// A new run: run.json says which map the new tiles belong to. A tiles folder that holds
// anything (an interrupted run of this or another map, a part of a job array, files of the
// user's) is refused, and with --force only npend's own files are removed from it.
void start_fresh_folder(const map_run& run) {
  std::error_code ec;
  fs::create_directories(run.dir, ec);
  if (ec)
    throw cli::input_error(fmt::format("--out: cannot create '{}': {}", run.o.out, ec.message()));
  if (fs::is_directory(run.tiles(), ec) && !fs::is_empty(run.tiles(), ec)) {
    if (!run.o.force) {
      nlohmann::json record;
      if (fs::exists(run.run_file(), ec)) try {
          record = read_run_file(run.run_file(), "--out");
        } catch (const cli::input_error&) {
        }
      if (record.is_object() && record["identity"] == run.identity)
        throw cli::input_error(fmt::format(
            "--out: {} holds an unfinished run of this map: finish it with --resume, or start "
            "afresh with --force",
            run.tiles().string()));
      throw cli::input_error(fmt::format(
          "--out: {} holds another run's tiles or other files: give another --out, or --force "
          "to remove npend's tiles from it (other files stay)",
          run.tiles().string()));
    }
    remove_own_tiles(run);
  }
  fs::create_directories(run.tiles(), ec);
  if (ec)
    throw cli::input_error(fmt::format("--out: cannot write in '{}': {}", run.o.out, ec.message()));
  cli::write_file_atomically(run.run_file(), run_file_content(run).dump(2) + "\n");
}

// The parts of a job array may start at the same moment on one shared folder, so none of
// them clears it: the first to get there writes run.json — complete under a temporary name,
// then hard-linked into place, which fails atomically (also on NFS) when another part was
// first — and every part checks that run.json describes its own map.
void claim_run_file(const map_run& run) {
  std::error_code ec;
  fs::create_directories(run.tiles(), ec);
  if (ec)
    throw cli::input_error(fmt::format("--out: cannot write in '{}': {}", run.o.out, ec.message()));
  const fs::path temporary = cli::temporary_sibling(run.run_file());
  {
    std::ofstream out(temporary);
    out << run_file_content(run).dump(2) << "\n";
    out.close();
    if (!out) {
      fs::remove(temporary, ec);
      throw std::runtime_error(fmt::format("writing '{}' failed", temporary.string()));
    }
  }
  const int linked = ::link(temporary.c_str(), run.run_file().c_str());
  const int error = errno;
  fs::remove(temporary, ec);
  if (linked != 0 && error != EEXIST)
    throw std::runtime_error(
        fmt::format("cannot create '{}': {}", run.run_file().string(), std::strerror(error)));
  if (linked != 0) check_same_map(run, "--part");
}

void prepare_folder(const map_run& run) {
  if (run.parted()) return claim_run_file(run);
  if (!run.o.resume) return start_fresh_folder(run);
  if (!fs::exists(run.run_file()))
    throw cli::input_error(fmt::format("--resume: {} holds no interrupted map (no {})", run.o.out,
                                       run.run_file().string()));
  check_same_map(run, "--resume");
}

// A tile file: the run's tag, the FNV-1a (64 bit) checksum of the data, then the data: the
// values as float64 in the machine's byte order.
void write_tile(const map_run& run, int index, const std::vector<double>& values) {
  const std::string data = bytes_of(values);
  const std::uint64_t checksum = fnv1a(data);
  std::string bytes(reinterpret_cast<const char*>(&run.tag), sizeof run.tag);
  bytes.append(reinterpret_cast<const char*>(&checksum), sizeof checksum);
  bytes += data;
  // Not synced: a tile is checked when read back (its size, the run's tag and the checksum),
  // so one that a crash of the machine left incomplete or garbled is found; syncing each cost
  // 0.2 ms a tile, 60 ms on a 256^2 map, all of it serial (the disk takes one fsync at a time).
  cli::write_file_atomically(run.tile_path(index), bytes, cli::durability::cached);
}

// A tile read back: its values, or what is wrong with the file.
struct tile_contents {
  std::vector<double> values;
  std::string problem;  // empty: the values are the tile's
};

tile_contents load_tile(const map_run& run, int index) {
  const fs::path path = run.tile_path(index);
  // A folder opens, and fails on the first read with a message about stream buffers.
  std::error_code ec;
  if (fs::is_directory(path, ec))
    throw cli::input_error(fmt::format(
        "tile {} is a directory, not a tile file; remove it and finish with --resume",
        path.string()));
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (!in) return {{}, fmt::format("tile {} cannot be read", path.string())};
  std::vector<double> values(run.layout.bounds(index, run.grid.x, run.grid.y).cells());
  constexpr std::size_t head = 2 * sizeof(std::uint64_t);  // the tag and the checksum
  const std::size_t expected = head + values.size() * sizeof(double);
  if (bytes.size() != expected)
    return {{},
            fmt::format("tile {} is incomplete ({} bytes, expected {}: a crash may have cut it "
                        "short)",
                        path.string(), bytes.size(), expected)};
  std::uint64_t tag = 0, checksum = 0;
  std::memcpy(&tag, bytes.data(), sizeof tag);
  std::memcpy(&checksum, bytes.data() + sizeof tag, sizeof checksum);
  if (tag != run.tag)
    return {{},
            fmt::format("tile {} was written by another run (of another map than {})",
                        path.string(), run.run_file().string())};
  const std::string_view data(bytes.data() + head, bytes.size() - head);
  if (fnv1a(data) != checksum)
    return {{},
            fmt::format("tile {} is damaged: its data do not match its checksum", path.string())};
  std::memcpy(values.data(), data.data(), data.size());
  return {std::move(values), {}};
}

// The values of a tile that must be sound (assembling the map); std::runtime_error naming the
// tile and what is wrong with it otherwise.
std::vector<double> read_tile(const map_run& run, int index) {
  tile_contents tile = load_tile(run, index);
  if (!tile.problem.empty())
    throw std::runtime_error(tile.problem + "; remove it and finish with --resume");
  return std::move(tile.values);
}

// How many of a tile's cells need integrating, estimated from up to 4 x 4 of them: the
// energy rules many flip-map cells out, and such a cell costs nothing.
int tile_work_estimate(const map_run& run, int index) {
  const tile_bounds b = run.layout.bounds(index, run.grid.x, run.grid.y);
  const int stride = std::max(1, run.layout.size / 4);
  int work = 0;
  for (int j = b.y0; j < b.y1; j += stride)
    for (int i = b.x0; i < b.x1; i += stride)
      work += map_cell_forbidden(run.grid, i, j, run.cell) ? 0 : 1;
  return work;
}

// A tile a resumed run finds is kept if it reads back sound (load_tile); one that does not is
// computed again, and stderr says why.
bool tile_done(const map_run& run, int index) {
  if (!run.o.resume || !fs::exists(run.tile_path(index))) return false;
  const std::string problem = load_tile(run, index).problem;
  if (problem.empty()) return true;
  fmt::print(stderr, "npend map: note: {}; computing it again\n", problem);
  return false;
}

// This run's tiles (its part's), without those a resumed run finds done, the most work
// first: whoever takes the last tiles then takes cheap ones, and no worker waits long for
// another at the end. (Each tile's values do not depend on the order.)
std::vector<int> pending_tiles(const map_run& run) {
  std::vector<std::pair<int, int>> pending;  // (-work, tile)
  for (int t = 0; t < run.layout.count(); ++t)
    if (run.part.has(t) && !tile_done(run, t))
      pending.emplace_back(-tile_work_estimate(run, t), t);
  std::sort(pending.begin(), pending.end());
  std::vector<int> tiles;
  tiles.reserve(pending.size());
  for (const auto& entry : pending) tiles.push_back(entry.second);
  return tiles;
}

long tiles_present(const map_run& run) {
  long present = 0;
  for (int t = 0; t < run.layout.count(); ++t) present += fs::exists(run.tile_path(t)) ? 1 : 0;
  return present;
}

// The values of tile `index`, row-major within the tile; a cell the energy rules out or
// whose integration fails is NaN. The tile's cells go to the library together, so that they
// run on the batch kernels' lanes together (each value the same as map_cell's). The cells
// poll `stop` inside their steps; once it asks to stop, the values are not the tile's.
std::vector<double> compute_tile(const map_run& run, int index, run_control& stop) {
  const tile_bounds b = run.layout.bounds(index, run.grid.x, run.grid.y);
  std::vector<int> columns, rows;
  for (int j = b.y0; j < b.y1; ++j)
    for (int i = b.x0; i < b.x1; ++i) {
      columns.push_back(i);
      rows.push_back(j);
    }
  map_cell_options cell = run.cell;
  cell.control = &stop;
  return map_grid_values(run.grid, columns, rows, cell);
}

struct tiles_outcome {
  bool interrupted = false;
  std::exception_ptr error;  // the first tile that failed (not thrown: MPI must abort the job)
};

// What the cells of every thread poll inside their steps: a signal (the command line's
// control), or a tile that failed on another thread. Polled from many threads at once, it
// only reads flags.
class cells_stop final : public run_control {
 public:
  cells_stop(const cli::terminal_run& control, const std::atomic<bool>& failed)
      : m_control(control), m_failed(failed) {}
  bool stop_requested() override { return m_failed.load() || m_control.interrupted(); }

 private:
  const cli::terminal_run& m_control;
  const std::atomic<bool>& m_failed;
};

// Computes the tiles `queue` hands out on `threads` threads, each written as soon as it is
// done, until the queue runs dry, a signal asks to stop or a tile fails. A signal abandons
// the tiles in flight at once (their cells poll it inside their steps): they are not
// written, and a resumed run computes them. `total`: the tiles the progress bar counts
// (shown only with `show_progress`).
tiles_outcome compute_tiles(const map_run& run, tile_queue& queue, int threads,
                            cli::terminal_run& control, long total, bool show_progress) {
  std::atomic<bool> stop{false};
  cells_stop cells(control, stop);
  std::exception_ptr error;
#pragma omp parallel num_threads(threads)
  {
    bool finished = false;
    for (int index; !stop.load() && (index = queue.next(finished)) >= 0;) {
      try {
        std::vector<double> values = compute_tile(run, index, cells);
        if (cells.stop_requested()) {  // abandoned part way: not this tile's values
          stop = true;
          queue.stop();
          break;
        }
        write_tile(run, index, values);
      } catch (...) {
#pragma omp critical(npend_map_error)
        if (!error) error = std::current_exception();
        stop = true;
        queue.stop();
        break;
      }
      finished = true;
      if (omp_get_thread_num() == 0) {
        if (show_progress)
          control.progress(static_cast<double>(queue.finished()), static_cast<double>(total));
        if (control.stop_requested()) {
          stop = true;
          queue.stop();
        }
      }
    }
  }
  control.finish();
  return {control.interrupted(), error};
}

int report_interrupted(const map_run& run, int exit_code) {
  fmt::print(stderr,
             "npend map: interrupted: {} of {} tiles are in {}; finish with the same command "
             "and --resume\n",
             tiles_present(run), run.layout.count(), run.tiles().string());
  return exit_code;
}

// The heat map. `low`..`high` is the range of the finite values (for flip times dt..t_end, on
// a log scale). The palette is viridis between two thin bands: white at the top for the cells
// that never flipped (+inf), red at the bottom for failed cells (NaN). The colour bar runs
// from `bottom` to `top`, a hair beyond low and high, and those cells are given these ends.
// (Leaving them undefined needs gnuplot's `image pixels`, whose millions of sub-pixel
// rectangles wash the colours out.)
// How a quantity is shown: the plot's title, the colour bar's label and whether its scale is
// logarithmic (times and the indicators that fall exponentially).
struct quantity_style {
  std::string title, label;
  bool logarithmic = false;
};

quantity_style style_of(const map_command_options& o) {
  const auto over = fmt::format(" over {:g} s; red: failed", o.t_end);
  switch (parse_map_quantity(o.quantity)) {
    case map_quantity::flip:
      return {
          fmt::format("Time to the first flip (s); white: no flip by {:g} s; red: failed", o.t_end),
          "t_{flip} (s)", true};
    case map_quantity::lyapunov:
      return {"Maximal Lyapunov exponent (1/s)" + over, "λ_1 (1/s)"};
    case map_quantity::fli:
      return {"Fast Lyapunov indicator" + over, "FLI"};
    case map_quantity::megno:
      return {"MEGNO <Y> (2: regular, growing: chaotic)" + over, "<Y>"};
    case map_quantity::sali:
      return {"SALI (0: chaotic)" + over + "; below 1e-16 shown as 1e-16", "SALI", true};
    case map_quantity::gali:
      return {"GALI (0: chaotic)" + over + "; below 1e-16 shown as 1e-16", "GALI", true};
    case map_quantity::state: {
      const std::string name = o.component.empty() ? "phi1" : o.component;
      const bool angle = name.rfind("phi", 0) == 0;
      return {fmt::format("{} at t = {:g} s ({}); red: failed", name, o.t_end,
                          angle ? "rad, not wrapped" : "kg m^2/s"),
              fmt::format("{} ({})", name, angle ? "rad" : "kg m^2/s")};
    }
  }
  return {};
}

// `mask_header_bytes` > 0: forbidden.npy marks the cells the energy rules out, drawn grey.
// Without failed cells every NaN is a forbidden one, so the map's NaN are left transparent
// over a grey plot area; only with failed cells too (red) does forbidden.npy go over the map
// as a grey layer, whose per-cell `using` expressions took gnuplot 0.9 of the 1.3 s it spent
// on a 256² map.
cli::plot_outcome write_png(const fs::path& dir, const map_command_options& o, const axis& ax,
                            const axis& ay, std::size_t header_bytes, double low, double high,
                            std::size_t mask_header_bytes, long failed) {
  quantity_style style = style_of(o);
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
nlohmann::json assemble_map(const map_run& run, const nlohmann::json& facts,
                            std::chrono::steady_clock::time_point started,
                            const cli::terminal_run& control) {
  const auto stop_if_interrupted = [&] {
    if (control.interrupted())
      throw cli::interrupted(
          fmt::format("interrupted while assembling the map; its tiles stay in {}: npend map "
                      "merge {} assembles it",
                      run.tiles().string(), run.o.out),
          control.exit_code());
  };
  const map_command_options& o = run.o;
  const axis &ax = run.grid.x, &ay = run.grid.y;
  // Row-major, row 0 = the first y value.
  std::vector<double> grid(static_cast<std::size_t>(ax.count) * static_cast<std::size_t>(ay.count));
  const auto cell = [&](int i, int j) -> double& {
    return grid[static_cast<std::size_t>(j) * static_cast<std::size_t>(ax.count) +
                static_cast<std::size_t>(i)];
  };
  for (int t = 0; t < run.layout.count(); ++t) {
    stop_if_interrupted();
    const std::vector<double> values = read_tile(run, t);
    const tile_bounds b = run.layout.bounds(t, ax, ay);
    std::size_t k = 0;
    for (int j = b.y0; j < b.y1; ++j)
      for (int i = b.x0; i < b.x1; ++i) cell(i, j) = values[k++];
  }
  stop_if_interrupted();
  // The result files all or none (the tiles stay for --resume until they are in place).
  cli::output_batch batch;
  const std::string header = npy_header(ay.count, ax.count);
  cli::write_file_atomically(run.dir / "map.npy", header + bytes_of(grid));
  const bool small = static_cast<long>(ax.count) * ay.count <= max_csv_cells;
  // NaN: ruled out by the energy (not integrated) or failed; +inf: no flip by t_end.
  long never = 0, failed = 0, forbidden = 0;
  std::string mask(grid.size(), '\0');
  for (int j = 0; j < ay.count; ++j)
    for (int i = 0; i < ax.count; ++i) {
      const double v = cell(i, j);
      if (std::isinf(v)) ++never;
      if (!std::isnan(v)) continue;
      if (map_cell_forbidden(run.grid, i, j, run.cell)) {
        ++forbidden;
        mask[static_cast<std::size_t>(j) * static_cast<std::size_t>(ax.count) +
             static_cast<std::size_t>(i)] = 1;
      } else {
        ++failed;
      }
    }
  const std::string mask_header = forbidden > 0 ? npy_header(ay.count, ax.count, "|u1") : "";
  if (forbidden > 0) cli::write_file_atomically(run.dir / "forbidden.npy", mask_header + mask);
  double low = std::numeric_limits<double>::infinity(), high = -low;
  for (const double v : grid)
    if (std::isfinite(v)) low = std::min(low, v), high = std::max(high, v);
  const bool indicator_to_zero = o.quantity == "sali" || o.quantity == "gali";
  if (o.quantity == "flip") {  // dt..t_end on a log scale (a decade when t_end is one step)
    low = o.dt;
    high = o.t_end > o.dt ? o.t_end : 10 * o.dt;
  } else if (indicator_to_zero) {  // a log scale: from 1e-16 (or the least value) up
    low = std::max(low, 1e-16);
    if (!(high > low)) high = low * 10;
  } else if (!(high > low)) {  // no finite value, or all equal: any range that shows them
    low = std::isfinite(low) ? low - 1 : 0;
    high = low + 2;
  }
  // gnuplot draws from map.npy and forbidden.npy while this thread writes the rest: gnuplot
  // takes about 0.1 s, a part of a short map's wall time that no thread count shortens.
  std::future<cli::plot_outcome> plot = std::async(std::launch::async, [&] {
    return write_png(run.dir, o, ax, ay, header.size(), low, high, mask_header.size(), failed);
  });
  if (small) write_csv(run.dir / "map.csv", ax, ay, grid);
  nlohmann::json summary = run.identity;
  summary.update(facts);
  summary["x"] = {{"name", ax.name}, {"from", ax.from}, {"to", ax.to}, {"count", ax.count}};
  summary["y"] = {{"name", ay.name}, {"from", ay.from}, {"to", ay.to}, {"count", ay.count}};
  summary["cells"] = ax.count * ay.count;
  summary["integrated"] = ax.count * ay.count - forbidden;
  summary["forbidden"] = forbidden;
  summary["failed"] = failed;
  if (o.quantity == "flip") summary["no_flip"] = never;
  // The batch lanes the cells ran on (0: cell by cell), and the ISA they were built for.
  summary["batch"] = {{"isa", batch_isa()}, {"lanes", batch_lanes(run.c)}};
  summary["stepper"] = stepper_name(run.cell.stepping.stepper);
  summary["resumed"] = o.resume;
  summary["files"] = {"map.npy", "map.json", "map.gp", "map.png"};
  if (small) summary["files"].push_back("map.csv");
  if (forbidden > 0) summary["files"].push_back("forbidden.npy");
  std::error_code ec;
  if (forbidden == 0) fs::remove(run.dir / "forbidden.npy", ec);  // an earlier map's
  const cli::plot_outcome drawn = plot.get();
  if (!drawn.rendered) fmt::print(stderr, "npend map: note: {}\n", drawn.message);
  summary["wall_seconds"] =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  stop_if_interrupted();
  cli::write_file_atomically(run.dir / "map.json", summary.dump(2) + "\n");
  batch.commit_all();
  remove_own_tiles(run);
  return summary;
}

// `how`: where the map was computed ("on 8 threads"), for the line on stdout.
void print_map_summary(const map_run& run, const nlohmann::json& summary, const std::string& how) {
  if (run.o.json) {
    std::cout << summary.dump(2) << "\n";
    return;
  }
  fmt::print("{} map of {} x {} cells ({} x {}) in {:.1f} s {}: {}\n", run.o.quantity, run.grid.x.count,
             run.grid.y.count, run.grid.x.name, run.grid.y.name, summary["wall_seconds"].get<double>(), how,
             (run.dir / "map.npy").string());
  if (summary["forbidden"].get<long>() > 0)
    fmt::print("{} cells ruled out by their energy, not integrated (NaN; forbidden.npy)\n",
               summary["forbidden"].get<long>());
  if (run.o.quantity == "flip")
    fmt::print("no flip by t = {:g} s: {} cells (+inf)\n", run.o.t_end,
               summary["no_flip"].get<long>());
  if (summary["failed"].get<long>() > 0)
    fmt::print("{} cells failed to integrate (NaN)\n", summary["failed"].get<long>());
}

// A part of a job array assembles nothing: it says what it did and how to merge.
void print_part_summary(const map_run& run, long computed, double seconds) {
  const long present = tiles_present(run);
  if (run.o.json) {
    const nlohmann::json summary = {{"part", run.o.part},
                                    {"tiles_computed", computed},
                                    {"tiles_present", present},
                                    {"tiles", run.layout.count()},
                                    {"wall_seconds", seconds}};
    std::cout << summary.dump(2) << "\n";
    return;
  }
  fmt::print(
      "part {} of the map: {} tiles in {:.1f} s; {} of {} tiles are in {}; when every part is "
      "done: npend map merge {}\n",
      run.o.part, computed, seconds, present, run.layout.count(), run.tiles().string(), run.o.out);
}

// After the tiles: a part stops here, a whole run assembles the map.
int finish_map(const map_run& run, long computed, const nlohmann::json& facts,
               const std::string& how, std::chrono::steady_clock::time_point started,
               const cli::terminal_run& control) {
  if (run.parted()) {
    print_part_summary(
        run, computed,
        std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count());
    return 0;
  }
  print_map_summary(run, assemble_map(run, facts, started, control), how);
  return 0;
}

int thread_count(const map_command_options& o) {
  return o.threads > 0 ? o.threads : omp_get_max_threads();
}

// One process: its threads take the tiles from a shared counter.
int run_map(const map_command_options& o) {
  const auto started = std::chrono::steady_clock::now();
  const map_run run = prepare_run(o);
  prepare_folder(run);
  const int threads = thread_count(o);
  const std::vector<int> pending = pending_tiles(run);
  const long total = static_cast<long>(pending.size());
  local_tile_queue queue(pending);
  cli::terminal_run control;
  const tiles_outcome outcome = compute_tiles(run, queue, threads, control, total, true);
  if (outcome.error) std::rethrow_exception(outcome.error);
  if (outcome.interrupted) return report_interrupted(run, control.exit_code());
  return finish_map(run, total, {{"threads", threads}}, fmt::format("on {} threads", threads),
                    started, control);
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
  const nlohmann::json record = read_run_file(file, "merge");
  map_command_options o;
  try {
    o = options_from_record(record["options"]);
  } catch (const nlohmann::json::exception&) {
    throw cli::input_error(fmt::format("merge: {} is not readable", file.string()));
  }
  o.out = folder;
  o.json = json;
  const map_run run = prepare_run(o);
  if (run.identity != record["identity"])
    throw cli::input_error(fmt::format(
        "merge: {} does not describe the map its options give (written by another npend?)",
        file.string()));
  std::vector<std::string> missing;
  for (int t = 0; t < run.layout.count(); ++t)
    if (!fs::exists(run.tile_path(t))) missing.push_back(run.tile_path(t).filename().string());
  if (!missing.empty()) {
    constexpr std::size_t shown = 8;
    std::string names;
    for (std::size_t k = 0; k < std::min(shown, missing.size()); ++k)
      names += (k > 0 ? ", " : "") + missing[k];
    if (missing.size() > shown) names += ", ...";
    throw cli::input_error(fmt::format(
        "merge: {} of {} tiles are missing from {}: {} (run the parts that compute them, with "
        "--resume to keep the tiles that are there)",
        missing.size(), run.layout.count(), run.tiles().string(), names));
  }
  return finish_map(run, 0, {{"merged", true}}, "by merging its tiles", started, control);
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
  const map_run run = prepare_run(o);
  if (mpi.rank() == 0) {
    try {
      prepare_folder(run);
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
  tiles_outcome outcome;
  std::vector<long> tiles_per_rank;
  if (mpi.rank() == 0) {
    const std::vector<int> pending = pending_tiles(run);
    total = static_cast<long>(pending.size());
    local_tile_queue tiles(pending);
    mpi::tile_coordinator queue(tiles, mpi);
    outcome = compute_tiles(run, queue, threads, control, total, true);
    if (outcome.error) abort_job(mpi, outcome.error);
    queue.wait_for_ranks();
    tiles_per_rank = queue.tiles_per_rank();
  } else {
    mpi::tile_worker queue;
    outcome = compute_tiles(run, queue, threads, control, 0, false);
    if (outcome.error) abort_job(mpi, outcome.error);
    queue.done();
  }
  const int exit_code = mpi.max(outcome.interrupted ? control.exit_code() : 0);
  if (mpi.rank() != 0) return exit_code;
  if (exit_code != 0) return report_interrupted(run, exit_code);
  // The ranks need each other no more. MPI_Finalize waits some 45 ms for mpirun (measured
  // with Open MPI 4.1 on one machine); rank 0 assembles the map meanwhile. (MPI_Finalize
  // must be called by the thread that initialised MPI, so the map goes to another thread.)
  std::future<int> finished = std::async(std::launch::async, [&] {
    return finish_map(
        run, total,
        {{"threads", threads}, {"ranks", mpi.size()}, {"tiles_per_rank", tiles_per_rank}},
        fmt::format("on {} ranks x {} threads", mpi.size(), threads), started, control);
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
  o->chain.add_to(*cmd, false);  // --links is required all the same: run_map_subcommand
  cmd->add_option("--x", o->x,
                  "NAME:FROM:TO:COUNT (required), NAME a start coordinate (phiK, pK, or dphiK with "
                  "--dphi), energy (J: the start's momenta scaled to it), or a parameter of the "
                  "chain (mK, lK, g, kK, bK: joint K's stiffness and damping, drive-amplitude and "
                  "drive-frequency of a --pivot drive)");
  cmd->add_option("--y", o->y, "NAME:FROM:TO:COUNT for the rows (row 0 = FROM) (required)");
  cmd->add_option("--quantity", o->quantity,
                  "flip (default: the time to the first flip), lyapunov (the maximal exponent), "
                  "a fast indicator at --t-end: fli, megno (<Y>), sali, gali (GALI_k), or state "
                  "(a coordinate of the state at --t-end, see --component)");
  cmd->add_option("--component", o->component,
                  "state: which coordinate at --t-end, phi1..phiN or p1..pN (default phi1)");
  cmd->add_option("--gali-order", o->gali_order,
                  "--quantity gali only: k of GALI_k, 2..2n (default 0: n + 1, the least k "
                  "beyond a torus's dimension)");
  cmd->add_option("--phi", o->phi, "The start's other angles (rad; default 0)");
  cmd->add_option("--p", o->p, "The start's other momenta (kg m^2/s; default 0)");
  cmd->add_option("--dphi", o->dphi,
                  "The start's velocities instead of momenta (rad/s; p = A(phi) dphi per cell)");
  cmd->add_option("--t-end", o->t_end, "Integration time per cell in s (default 100)");
  cmd->add_option("--dt", o->dt,
                  "The step in s of rk4, gauss4 and gauss6; dopri5's first trial step (default "
                  "0.01)");
  cmd->add_option("--stepper", o->stepper,
                  "rk4 (default: fixed step --dt), dopri5 (adaptive, each cell under its own "
                  "step control; flip times located inside the step by its dense output), or "
                  "the symplectic gauss4 or gauss6 (fixed step --dt); other than rk4 for flip, "
                  "lyapunov and state only");
  cmd->add_option("--abs-tol", o->abs_tol, "dopri5: absolute error tolerance (default 1e-10)");
  cmd->add_option("--rel-tol", o->rel_tol, "dopri5: relative error tolerance (default 1e-10)");
  cmd->add_option("--flip-link", o->flip_link, "flip: only arm K counts (default 0: any arm)");
  cmd->add_option("--threads", o->threads,
                  "Threads (default: every core; at most 4 x the hardware threads; per rank "
                  "under MPI)");
  cmd->add_option("--tile", o->tile, "Cells per tile side (default 16)");
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
