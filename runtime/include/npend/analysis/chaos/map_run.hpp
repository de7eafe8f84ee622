// A chaos map computed as a run: the grid cut into tiles, the tiles computed on every core
// (and by the other ranks or jobs that share the folder), each written to
// <folder>/tiles/tile_NNNNNN.bin as soon as it is done, so that an interrupted run resumes
// and the parts of a job array merge; then the tiles assembled into the map's values. The
// command line (npend map, its MPI ranks) drives it; npend.map and npend.map_cells, which
// keep no files, use map_values and map_cell_values.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <functional>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "npend/analysis/chaos/chaos_map.hpp"
#include "npend/analysis/chaos/map_device.hpp"
#include "npend/analysis/chaos/map_grid.hpp"
#include "npend/analysis/chaos/map_tile_queue.hpp"
#include "npend/chain.hpp"
#include "npend/run_control.hpp"

namespace npend {

/// Which tiles a run computes: all of them (1 of 1), or those whose index is index - 1
/// modulo count — a fixed assignment, so that the jobs of an array need not talk to each
/// other.
struct map_part {
  int index = 1, count = 1;
  bool has(int tile) const { return tile % count == index - 1; }
};

/// The cells of one tile: columns x0..x1 - 1, rows y0..y1 - 1.
struct map_tile_bounds {
  int x0, x1, y0, y1;
  std::size_t cells() const { return static_cast<std::size_t>((x1 - x0) * (y1 - y0)); }
};

/// Tiles of `size` × `size` cells over a grid, tiles_x × tiles_y of them, numbered row-major.
struct map_tile_layout {
  int size = 16, tiles_x = 1, tiles_y = 1;
  int count() const { return tiles_x * tiles_y; }
  /// Tile `index` (0 ≤ index < count()), clipped at the grid's edges.
  map_tile_bounds bounds(int index, const map_axis& x, const map_axis& y) const {
    const int x0 = index % tiles_x * size, y0 = index / tiles_x * size;
    return {x0, std::min(x.count, x0 + size), y0, std::min(y.count, y0 + size)};
  }
};

/// The most cells a tile's side may have.
inline constexpr int max_map_tile_size = 1024;

/// Throws std::invalid_argument "tile: 1..1024, got <size>" for a tile size outside
/// 1..max_map_tile_size.
void check_map_tile_size(int size);

/// What a map run computes: the grid, what each cell computes, the tiles' size and the
/// share of the tiles this run computes.
struct map_run_description {
  map_grid grid;
  map_cell_options cell;  ///< its `control` is not used: compute_tiles passes its own
  int tile = 16;          ///< cells per tile side, 1..max_map_tile_size
  map_part part;
  /// Where the cells run: the CPU's threads, or a GPU (map_device.hpp), which takes many
  /// tiles at once. Part of the run's identity where it is the GPU: its values agree with
  /// the CPU's to round-off, not bit for bit, and one map's tiles come from one of them.
  map_device device = map_device::cpu;
};

/// Writes `bytes` to `path` so that the file appears whole or not at all (the command line
/// passes its atomic output files). Called from many threads at once, for different paths.
using map_file_writer = std::function<void(const std::filesystem::path&, std::string_view)>;

/// A tile file that cannot be used: unreadable, cut short, written by another run, damaged,
/// or a folder in a tile's place (`is_folder`: nothing npend wrote, which a user must
/// remove).
class map_tile_error : public std::runtime_error {
 public:
  map_tile_error(const std::string& what, bool folder)
      : std::runtime_error(what), m_folder(folder) {}
  bool is_folder() const { return m_folder; }

 private:
  bool m_folder;
};

/// A tile read back: its values, or what is wrong with the file.
struct map_tile_contents {
  std::vector<double> values;
  std::string problem;  ///< empty: the values are the tile's
};

/// How compute_tiles ended.
struct map_tiles_outcome {
  bool stopped = false;      ///< the run control asked to stop
  std::exception_ptr error;  ///< the first tile that failed (not thrown: MPI must abort the job)
};

/// The NaN and +inf of a map's values, told apart.
struct map_cell_counts {
  long no_flip = 0;    ///< +inf: a flip map's cells that did not flip by t_end
  long failed = 0;     ///< NaN: the integration failed
  long forbidden = 0;  ///< NaN: the energy rules the cell out (map_cell_forbidden)
  /// 1 for a forbidden cell, 0 otherwise; row-major as the values.
  std::vector<unsigned char> forbidden_mask;
};

/// The contents of a run's run.json.
struct map_run_record {
  std::string identity;  ///< JSON text of map_run::identity
  std::string options;   ///< JSON text of the front end's record (how it was asked for)
};

/// Whether `name` is a file a map run writes in its tiles folder: run.json,
/// tile_NNNNNN.bin, or the hidden temporary of either (".<name>.npend-XXXXXX") that a killed
/// process may have left.
bool is_map_run_file(std::string name);

/// run.json at `file` read back, or nullopt where it is missing or not one that
/// map_run::run_file_text wrote.
std::optional<map_run_record> read_map_run_record(const std::filesystem::path& file);

/// How a front end opens a run's folder (map_run::open_folder).
enum class map_folder_start {
  fresh,   ///< a new run: refused where the tiles folder holds anything
  force,   ///< a new run that first removes the run files (is_map_run_file) from the tiles folder
  resume,  ///< finishing an interrupted run: its run.json must describe the same map
  part,    ///< a part of a job array: the first part writes run.json, the others check it
};

/// A front end's names for its options, as open_folder's messages cite them: the command
/// line's "--out", Python's "out" and so on.
struct map_folder_words {
  std::string out = "--out", resume = "--resume", force = "--force", part = "--part";
  /// How the messages tell a user to resume or to start afresh ("--resume", "resume=True").
  std::string resume_hint = "--resume", force_hint = "--force";
};

/// One map run in `folder`. Tiles go to <folder>/tiles/, with run.json beside them saying
/// which map they belong to; the tile files start with the run's tag (a hash of its
/// identity) and a checksum of their data, and are checked when read back.
class map_run {
 public:
  /// Checks the description (std::invalid_argument naming the problem: the cell options
  /// and grid as map_cell_options::validate and map_grid::validate, "tile: …",
  /// "part: …") and builds the run; touches no file.
  map_run(map_run_description description, std::filesystem::path folder);

  const map_run_description& description() const { return m_description; }
  const map_grid& grid() const { return m_description.grid; }
  const map_cell_options& cell() const { return m_description.cell; }
  /// The chain of the grid's parameters (where no axis changes it).
  const chain& base_chain() const { return m_chain; }
  const map_tile_layout& layout() const { return m_layout; }

  /// What makes two runs the same map, as JSON text (links, parameters, axes, quantity,
  /// times, tile size, base start, stepper): a resumed run, another part or a merge must
  /// share it. Its hash is the tag at the head of each tile file.
  const std::string& identity() const { return m_identity; }
  std::uint64_t tag() const { return m_tag; }
  /// Whether `record` (read_map_run_record) describes this map.
  bool same_map(const map_run_record& record) const;
  /// run.json's text: the identity and `options` (JSON text of the front end's record,
  /// from which it can rebuild the run from the folder alone).
  std::string run_file_text(std::string_view options) const;

  /// Makes the folder ready for the run's tiles, as `start` says, writing run.json (its
  /// text from run_file_text(options)) where the run is new. Bad input throws
  /// std::invalid_argument naming the option in `words`: a folder that cannot be created, a
  /// fresh run over a tiles folder that holds anything (an unfinished run of this map: resume
  /// or force it; another map's or other files: another folder, or force), a resume without
  /// run.json or of another map, a part whose run.json describes another map. A file that
  /// cannot be written throws std::runtime_error.
  void open_folder(map_folder_start start, std::string_view options,
                   const map_folder_words& words = {}) const;
  const std::filesystem::path& folder() const { return m_folder; }
  std::filesystem::path tiles_folder() const { return m_folder / "tiles"; }
  std::filesystem::path run_file() const { return tiles_folder() / "run.json"; }
  std::filesystem::path tile_path(int index) const;

  /// Writes tile `index`'s values (row-major within the tile) through `write`: the run's
  /// tag, the FNV-1a (64 bit) checksum of the data, then the values as float64 in the
  /// machine's byte order.
  void write_tile(int index, const std::vector<double>& values, const map_file_writer& write) const;
  /// Tile `index` read back and checked (its size, the run's tag, the checksum).
  /// Throws map_tile_error (is_folder) where a folder stands in its place.
  map_tile_contents load_tile(int index) const;
  /// The values of a tile that must be sound; map_tile_error naming the tile and what is
  /// wrong with it otherwise.
  std::vector<double> read_tile(int index) const;
  /// How many of tile `index`'s cells need integrating, estimated from up to 4 × 4 of
  /// them: the energy rules many flip-map cells out, and such a cell costs nothing.
  int tile_work_estimate(int index) const;
  /// This run's tiles (its part's), without those that `resume` finds done (present and
  /// sound; for one that is not, `redo` hears the problem and the tile is computed again),
  /// the most work first: whoever takes the last tiles then takes cheap ones, and no worker
  /// waits long for another at the end. Throws map_tile_error for a folder in a tile's place.
  std::vector<int> pending_tiles(bool resume,
                                 const std::function<void(const std::string&)>& redo) const;
  /// How many of the run's tile files are in the tiles folder (of every part).
  long tiles_present() const;
  /// The tiles whose files are missing (the parts still to run before a merge).
  std::vector<int> missing_tiles() const;

  /// The values of tile `index`, row-major within the tile, as map_grid_values computes
  /// them (a cell the energy rules out or whose integration fails is NaN). Its cells poll
  /// `stop` inside their steps (may be null); once it asks to stop, the values are not the
  /// tile's.
  std::vector<double> compute_tile(int index, run_control* stop) const;
  /// The values of the tiles `indices`, one after another, as compute_tile's, on the run's
  /// device.
  std::vector<double> compute_tile_values(std::span<const int> indices, run_control* stop) const;
  /// Computes the tiles `queue` hands out on `threads` (≥ 1) OpenMP threads (on the GPU:
  /// as many tiles at a time as make up to cuda_cells_per_launch cells, `threads` unused), each
  /// written through `write` as soon as it is done, until the queue runs dry, `control` asks to
  /// stop or a tile fails. A stop abandons the tiles in flight at once (their cells poll it inside
  /// their steps): they are not written, and a resumed run computes them. control.stop_requested()
  /// is polled from every thread at once; progress(finished, `total`) is reported by one thread,
  /// only with `show_progress`.
  map_tiles_outcome compute_tiles(map_tile_queue& queue, int threads, run_control& control,
                                  const map_file_writer& write, long total,
                                  bool show_progress) const;
  /// Every tile read back (read_tile) into the map's values: row-major over the grid,
  /// (y count) × (x count), row 0 the first y value. nullopt once `control` (may be null)
  /// asks to stop, polled between tiles. Throws map_tile_error for a tile that is not sound.
  std::optional<std::vector<double>> assemble(run_control* control) const;
  /// The +inf and NaN of the map's `values` (assemble's), counted.
  map_cell_counts count_cells(const std::vector<double>& values) const;
  /// Removes the run's own files from the tiles folder (is_map_run_file), then the folder
  /// if that left it empty: a file someone else put there stays, and so does the folder.
  void remove_own_tiles() const;

 private:
  map_tiles_outcome compute_tiles_on_gpu(map_tile_queue& queue, run_control& control,
                                         const map_file_writer& write, long total,
                                         bool show_progress) const;

  map_run_description m_description;
  chain m_chain;
  map_tile_layout m_layout;
  std::filesystem::path m_folder;
  std::string m_identity;
  std::uint64_t m_tag;
};

/// The OpenMP team for `threads`: threads itself, or every core for 0. Throws
/// std::invalid_argument "threads: …" for a negative count.
int map_team_size(int threads);

/// The map over `grid`, computed on `threads` OpenMP threads (0: every core), a row at a
/// time (the cells of one chain together, so that they fill the batch lanes): row-major,
/// (y count) × (x count), the values of map_grid_values. `control` (may be null) is polled
/// between rows and hears progress(cells done, cells) after each, from whichever thread
/// finished it; once it asks to stop, the rows not started stay NaN. Throws
/// std::invalid_argument as map_grid::validate (checked first) and for threads < 0.
/// With map_device::cuda, every cell on the GPU (map_grid_values; `threads` unused).
std::vector<double> map_values(const map_grid& grid, const map_cell_options& options,
                               int threads = 0, run_control* control = nullptr,
                               map_device device = map_device::cpu);

/// map_cells of `starts` (count × 2n), computed on `threads` OpenMP threads (0: every
/// core) in chunks of 8..256 cells (enough chunks to balance the threads, each enough cells
/// to keep the batch lanes full); the values do not depend on the thread count. `control`
/// as for map_values. Throws std::invalid_argument as map_cell_options::validate (checked
/// first), as map_cells (rethrown once the threads are done) and for threads < 0.
/// With map_device::cuda, on the GPU (cuda_map_cells; `threads` unused).
std::vector<double> map_cell_values(const chain& c, std::span<const double> starts,
                                    const map_cell_options& options, int threads = 0,
                                    run_control* control = nullptr,
                                    map_device device = map_device::cpu);

/// map_cell_options from the names the front ends take: `quantity` (parse_map_quantity) and
/// `stepper` (parse_stepper_kind) with its tolerances; the component of a state map is the
/// caller's to set. Throws std::invalid_argument "stepper: …" (checked first) or
/// "quantity: …"; map_cell_options::validate checks the rest.
map_cell_options make_map_cell_options(std::string_view quantity, double t_end, double dt,
                                       int flip_link, int gali_order, std::string_view stepper,
                                       double abs_tol, double rel_tol);

}  // namespace npend
