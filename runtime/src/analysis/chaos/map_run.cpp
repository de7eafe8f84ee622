// A map run: its identity, its tiles' layout and order, computing them on every core and
// assembling the map. The tile files themselves are map_tiles.cpp's.
#include "npend/analysis/chaos/map_run.hpp"

#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <utility>

#include "analysis/chaos/map_tiles.hpp"

namespace npend {

namespace {

map_tile_layout layout_of(const map_grid& grid, int size) {
  return {size, (grid.x.count + size - 1) / size, (grid.y.count + size - 1) / size};
}

// The run's identity: what makes two runs the same map.
nlohmann::json identity_of(const chain& c, const map_run_description& d) {
  const auto spec = [](const map_axis& a) {
    return nlohmann::json{{"name", a.name}, {"from", a.from}, {"to", a.to}, {"count", a.count}};
  };
  const map_grid& grid = d.grid;
  const map_cell_options& cell = d.cell;
  nlohmann::json identity = {{"links", c.links()},
                             {"packed_parameters", c.packed_parameters()},
                             {"x", spec(grid.x)},
                             {"y", spec(grid.y)},
                             {"quantity", std::string(map_quantity_name(cell.quantity))},
                             {"component", cell.component},
                             {"t_end", cell.t_end},
                             {"dt", cell.dt},
                             {"flip_link", cell.flip_link},
                             {"gali_order", cell.gali_order},
                             {"tile", d.tile},
                             {"base_angles", grid.angles},
                             {grid.velocities ? "base_velocities" : "base_momenta", grid.momenta}};
  // The stepper and its tolerances enter only where they are not rk4's: an rk4 run's
  // identity, and with it the tag in its tile files, stays the one written by runs from
  // when rk4 was the maps' only stepper, so that their folders still resume and merge.
  if (cell.stepping.stepper != stepper_kind::rk4)
    identity["stepper"] = stepper_name(cell.stepping.stepper);
  if (cell.stepping.stepper == stepper_kind::dopri5 ||
      cell.stepping.stepper == stepper_kind::taylor) {
    identity["abs_tol"] = cell.stepping.abs_tol;
    identity["rel_tol"] = cell.stepping.rel_tol;
  }
  // Likewise the device: a CPU run's identity is the one it always was.
  if (d.device != map_device::cpu) identity["device"] = std::string(map_device_name(d.device));
  return identity;
}

map_run_description checked(map_run_description d) {
  check_map_tile_size(d.tile);
  if (d.part.count < 1 || d.part.index < 1 || d.part.index > d.part.count)
    throw std::invalid_argument(
        fmt::format("part: I/N with 1 <= I <= N, got {}/{}", d.part.index, d.part.count));
  d.grid.validate(d.cell);
  if (d.device == map_device::cuda) check_cuda_map(chain(d.grid.parameters), d.cell);
  d.cell.control = nullptr;
  return d;
}

// What the cells of every thread poll inside their steps: the caller's stop request, or a
// tile that failed on another thread. Polled from many threads at once.
class cells_stop final : public run_control {
 public:
  cells_stop(run_control& control, const std::atomic<bool>& failed)
      : m_control(control), m_failed(failed) {}
  bool stop_requested() override { return m_failed.load() || m_control.stop_requested(); }

 private:
  run_control& m_control;
  const std::atomic<bool>& m_failed;
};

// `total` values over `team` OpenMP threads, computed `chunk` at a time by
// compute(first, count); `control` polled before each chunk (the chunks not started stay
// NaN) and told the cells done after each. The first exception a chunk throws is rethrown
// once the threads are done.
template <class Compute>
std::vector<double> values_in_parallel(std::size_t total, std::size_t chunk, int team,
                                       run_control* control, const Compute& compute) {
  std::vector<double> out(total, std::numeric_limits<double>::quiet_NaN());
  const auto chunks = static_cast<long>((total + chunk - 1) / chunk);
  std::exception_ptr error;
  std::atomic<bool> failed{false};
  std::atomic<std::size_t> done{0};
#pragma omp parallel for schedule(dynamic, 1) num_threads(team)
  for (long k = 0; k < chunks; ++k) {
    if (failed.load() || stop_requested(control)) continue;
    try {
      const std::size_t first = static_cast<std::size_t>(k) * chunk;
      const std::vector<double> values = compute(first, std::min(chunk, total - first));
      std::copy(values.begin(), values.end(), out.begin() + static_cast<long>(first));
      const std::size_t cells = done += values.size();
      if (control != nullptr)
        control->progress(static_cast<double>(cells), static_cast<double>(total));
    } catch (...) {
#pragma omp critical(npend_map_values_error)
      if (!error) error = std::current_exception();
      failed = true;
    }
  }
  if (error) std::rethrow_exception(error);
  return out;
}

}  // namespace

void check_map_tile_size(int size) {
  if (size < 1 || size > max_map_tile_size)
    throw std::invalid_argument(fmt::format("tile: 1..{}, got {}", max_map_tile_size, size));
}

map_run::map_run(map_run_description description, std::filesystem::path folder)
    : m_description(checked(std::move(description))),
      m_chain(m_description.grid.parameters),
      m_layout(layout_of(m_description.grid, m_description.tile)),
      m_folder(std::move(folder)),
      m_identity(identity_of(m_chain, m_description).dump()),
      m_tag(detail::fnv1a(m_identity)) {}

bool map_run::same_map(const map_run_record& record) const {
  return nlohmann::json::parse(record.identity) == nlohmann::json::parse(m_identity);
}

std::string map_run::run_file_text(std::string_view options) const {
  const nlohmann::json content = {{"identity", nlohmann::json::parse(m_identity)},
                                  {"options", nlohmann::json::parse(options)}};
  return content.dump(2) + "\n";
}

int map_run::tile_work_estimate(int index) const {
  const map_tile_bounds b = m_layout.bounds(index, grid().x, grid().y);
  const int stride = std::max(1, m_layout.size / 4);
  int work = 0;
  for (int j = b.y0; j < b.y1; j += stride)
    for (int i = b.x0; i < b.x1; i += stride)
      work += map_cell_forbidden(grid(), i, j, cell()) ? 0 : 1;
  return work;
}

// Each tile's values do not depend on the order in which the tiles are computed.
std::vector<int> map_run::pending_tiles(bool resume,
                                        const std::function<void(const std::string&)>& redo) const {
  const auto done = [&](int index) {
    if (!resume || !std::filesystem::exists(tile_path(index))) return false;
    const std::string problem = load_tile(index).problem;
    if (problem.empty()) return true;
    if (redo) redo(problem);
    return false;
  };
  std::vector<std::pair<int, int>> pending;  // (-work, tile)
  for (int t = 0; t < m_layout.count(); ++t)
    if (m_description.part.has(t) && !done(t)) pending.emplace_back(-tile_work_estimate(t), t);
  std::sort(pending.begin(), pending.end());
  std::vector<int> tiles;
  tiles.reserve(pending.size());
  for (const auto& entry : pending) tiles.push_back(entry.second);
  return tiles;
}

// The tile's cells go to the library together, so that they run on the batch kernels'
// lanes together (each value the same as map_cell's).
std::vector<double> map_run::compute_tile(int index, run_control* stop) const {
  return compute_tile_values(std::span<const int>(&index, 1), stop);
}

std::vector<double> map_run::compute_tile_values(std::span<const int> indices,
                                                 run_control* stop) const {
  std::vector<int> columns, rows;
  for (const int index : indices) {
    const map_tile_bounds b = m_layout.bounds(index, grid().x, grid().y);
    for (int j = b.y0; j < b.y1; ++j)
      for (int i = b.x0; i < b.x1; ++i) {
        columns.push_back(i);
        rows.push_back(j);
      }
  }
  map_cell_options options = cell();
  options.control = stop;
  return map_grid_values(grid(), columns, rows, options, m_description.device);
}

// The GPU takes many tiles at once (a launch fills it only with many cells) and computes
// them in one go: one thread here hands them over and writes them back. `queue.next` hears
// of the tiles finished one call at a time, as the calls that take the next ones.
map_tiles_outcome map_run::compute_tiles_on_gpu(map_tile_queue& queue, run_control& control,
                                                const map_file_writer& write, long total,
                                                bool show_progress) const {
  std::atomic<bool> failed{false};
  cells_stop cells(control, failed);
  long unreported = 0, finished = 0;
  for (;;) {
    if (control.stop_requested()) {
      queue.stop();
      break;
    }
    std::vector<int> tiles;
    std::size_t count = 0;
    while (count < cuda_cells_per_launch) {
      const int index = queue.next(unreported > 0);
      if (unreported > 0) --unreported;
      if (index < 0) break;
      tiles.push_back(index);
      count += m_layout.bounds(index, grid().x, grid().y).cells();
    }
    if (tiles.empty()) break;
    try {
      const std::vector<double> values = compute_tile_values(tiles, &cells);
      if (cells.stop_requested()) {  // abandoned part way: not these tiles' values
        queue.stop();
        break;
      }
      std::size_t at = 0;
      for (const int index : tiles) {
        const std::size_t n = m_layout.bounds(index, grid().x, grid().y).cells();
        write_tile(index,
                   std::vector<double>(values.begin() + static_cast<std::ptrdiff_t>(at),
                                       values.begin() + static_cast<std::ptrdiff_t>(at + n)),
                   write);
        at += n;
      }
    } catch (...) {
      queue.stop();
      return {control.stop_requested(), std::current_exception()};
    }
    unreported += static_cast<long>(tiles.size());
    finished += static_cast<long>(tiles.size());
    if (show_progress) control.progress(static_cast<double>(finished), static_cast<double>(total));
  }
  return {control.stop_requested(), nullptr};
}

map_tiles_outcome map_run::compute_tiles(map_tile_queue& queue, int threads, run_control& control,
                                         const map_file_writer& write, long total,
                                         bool show_progress) const {
  if (threads < 1) throw std::invalid_argument(fmt::format("threads: at least 1, got {}", threads));
  if (m_description.device == map_device::cuda)
    return compute_tiles_on_gpu(queue, control, write, total, show_progress);
  std::atomic<bool> stop{false};
  cells_stop cells(control, stop);
  std::exception_ptr error;
#pragma omp parallel num_threads(threads)
  {
    bool finished = false;
    for (int index; !stop.load() && (index = queue.next(finished)) >= 0;) {
      try {
        std::vector<double> values = compute_tile(index, &cells);
        if (cells.stop_requested()) {  // abandoned part way: not this tile's values
          stop = true;
          queue.stop();
          break;
        }
        write_tile(index, values, write);
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
  return {control.stop_requested(), error};
}

std::optional<std::vector<double>> map_run::assemble(run_control* control) const {
  const map_axis &ax = grid().x, &ay = grid().y;
  const auto cols = static_cast<std::size_t>(ax.count);
  std::vector<double> values(cols * static_cast<std::size_t>(ay.count));
  for (int t = 0; t < m_layout.count(); ++t) {
    if (stop_requested(control)) return std::nullopt;
    const std::vector<double> tile = read_tile(t);
    const map_tile_bounds b = m_layout.bounds(t, ax, ay);
    std::size_t k = 0;
    for (int j = b.y0; j < b.y1; ++j)
      for (int i = b.x0; i < b.x1; ++i)
        values[static_cast<std::size_t>(j) * cols + static_cast<std::size_t>(i)] = tile[k++];
  }
  if (stop_requested(control)) return std::nullopt;
  return values;
}

map_cell_counts map_run::count_cells(const std::vector<double>& values) const {
  const map_axis &ax = grid().x, &ay = grid().y;
  map_cell_counts counts;
  counts.forbidden_mask.assign(values.size(), 0);
  // The NaN cells, told apart by their energy (the one check that costs anything here), a
  // row of the grid at a time on every core.
  long no_flip = 0, failed = 0, forbidden = 0;
#pragma omp parallel for schedule(dynamic) reduction(+ : no_flip, failed, forbidden)
  for (int j = 0; j < ay.count; ++j) {
    const std::size_t row = static_cast<std::size_t>(j) * static_cast<std::size_t>(ax.count);
    std::vector<int> columns, rows;
    for (int i = 0; i < ax.count; ++i) {
      const double v = values[row + static_cast<std::size_t>(i)];
      if (std::isinf(v)) ++no_flip;
      if (!std::isnan(v)) continue;
      columns.push_back(i);
      rows.push_back(j);
    }
    const std::vector<unsigned char> ruled_out = map_cells_forbidden(grid(), columns, rows, cell());
    for (std::size_t k = 0; k < columns.size(); ++k) {
      counts.forbidden_mask[row + static_cast<std::size_t>(columns[k])] = ruled_out[k];
      if (ruled_out[k] != 0)
        ++forbidden;
      else
        ++failed;
    }
  }
  counts.no_flip = no_flip;
  counts.failed = failed;
  counts.forbidden = forbidden;
  return counts;
}

int map_team_size(int threads) {
  if (threads < 0)
    throw std::invalid_argument(
        fmt::format("threads: 0 (every core) or a positive count, got {}", threads));
  return threads > 0 ? threads : omp_get_max_threads();
}

std::vector<double> map_values(const map_grid& grid, const map_cell_options& options, int threads,
                               run_control* control, map_device device) {
  grid.validate(options);
  const int team = map_team_size(threads);
  if (device == map_device::cuda) {
    std::vector<int> columns, rows;
    for (int j = 0; j < grid.y.count; ++j)
      for (int i = 0; i < grid.x.count; ++i) {
        columns.push_back(i);
        rows.push_back(j);
      }
    map_cell_options o = options;
    o.control = control;
    return map_grid_values(grid, columns, rows, o, device);
  }
  const auto cols = static_cast<std::size_t>(grid.x.count);
  return values_in_parallel(cols * static_cast<std::size_t>(grid.y.count), cols, team, control,
                            [&](std::size_t first, std::size_t) {
                              const int row = static_cast<int>(first / cols);
                              std::vector<int> columns(cols), rows(cols, row);
                              for (std::size_t i = 0; i < cols; ++i)
                                columns[i] = static_cast<int>(i);
                              return map_grid_values(grid, columns, rows, options);
                            });
}

std::vector<double> map_cell_values(const chain& c, std::span<const double> starts,
                                    const map_cell_options& options, int threads,
                                    run_control* control, map_device device) {
  options.validate(c);
  if (device == map_device::cuda) {
    map_cell_options o = options;
    o.control = control;
    return cuda_map_cells(c, starts, o);
  }
  const auto width = static_cast<std::size_t>(c.state_size());
  if (starts.size() % width != 0)
    throw std::invalid_argument(fmt::format(
        "starts: {} numbers are not a whole number of states of {}", starts.size(), width));
  const std::size_t count = starts.size() / width;
  const int team = map_team_size(threads);
  const std::size_t chunk =
      std::clamp<std::size_t>(count / (4 * static_cast<std::size_t>(team)), 8, 256);
  return values_in_parallel(count, chunk, team, control, [&](std::size_t first, std::size_t n) {
    return map_cells(c, starts.subspan(first * width, n * width), options);
  });
}

map_cell_options make_map_cell_options(std::string_view quantity, double t_end, double dt,
                                       int flip_link, int gali_order, std::string_view stepper,
                                       double abs_tol, double rel_tol) {
  map_cell_options o;
  try {
    o.stepping.stepper = parse_stepper_kind(stepper);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(fmt::format("stepper: {}", e.what()));
  }
  o.stepping.abs_tol = abs_tol;
  o.stepping.rel_tol = rel_tol;
  o.quantity = parse_map_quantity(quantity);
  o.t_end = t_end;
  o.dt = dt;
  o.flip_link = flip_link;
  o.gali_order = gali_order;
  return o;
}

}  // namespace npend
