// A map run (analysis/chaos/map_run.hpp): its tiles, computed in parallel, written, resumed,
// merged from parts and assembled, give the values map_cell computes cell by cell; its
// identity ties the tiles to their run.
#include <doctest/doctest.h>

#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "npend/analysis/chaos/map_run.hpp"
#include "support/test_support.hpp"

namespace map_run_test {

namespace fs = std::filesystem;

// A 7 x 5 flip map of the equal double pendulum over (phi1, phi2), 2 s: the middle rows hang
// low enough that the energy rules them out (NaN), the outer ones flip or not.
npend::map_run_description flip_map(int tile, npend::map_part part = {}) {
  npend::map_grid grid;
  grid.parameters = npend::chain_parameters::uniform(2);
  grid.angles = {0, 0};
  grid.momenta = {0, 0};
  grid.x = npend::make_map_axis("phi1", -3, 3, 7, 2);
  grid.y = npend::make_map_axis("phi2", -3, 3, 5, 2);
  npend::map_cell_options cell;
  cell.t_end = 2;
  cell.dt = 0.01;
  return {grid, cell, tile, part};
}

// map_cell of every cell, row-major: the reference, computed without tiles or threads.
std::vector<double> cell_by_cell(const npend::map_run_description& d) {
  const npend::chain c(d.grid.parameters);
  std::vector<double> values;
  for (int j = 0; j < d.grid.y.count; ++j)
    for (int i = 0; i < d.grid.x.count; ++i) {
      const std::vector<double> x0 = {d.grid.x.value(i), d.grid.y.value(j), 0, 0};
      values.push_back(npend::map_cell(c, x0, d.cell));
    }
  return values;
}

// Equal bit for bit, NaN equal to NaN.
bool same_values(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t k = 0; k < a.size(); ++k)
    if (!(a[k] == b[k] || (std::isnan(a[k]) && std::isnan(b[k])))) return false;
  return true;
}

void write_plain(const fs::path& path, std::string_view bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

// Computes `tiles` of the run on 3 threads.
npend::map_tiles_outcome compute(const npend::map_run& run, std::vector<int> tiles) {
  fs::create_directories(run.tiles_folder());
  npend::local_map_tile_queue queue(std::move(tiles));
  npend::run_control control;
  return run.compute_tiles(queue, 3, control, write_plain, 0, false);
}

std::vector<double> assembled(const npend::map_run& run) {
  const std::optional<std::vector<double>> values = run.assemble(nullptr);
  REQUIRE(values.has_value());
  return *values;
}

// Asks to stop once it has been polled `polls` times.
class stop_after final : public npend::run_control {
 public:
  explicit stop_after(int polls) : m_left(polls) {}
  bool stop_requested() override { return --m_left < 0; }

 private:
  std::atomic<int> m_left;
};

TEST_CASE("map_run: the tiles, computed in parallel and assembled, are map_cell's values") {
  const fs::path dir(npend::test::temporary_directory("map-run-whole"));
  const npend::map_run_description d = flip_map(3);
  const npend::map_run run(d, dir);
  CHECK(run.layout().count() == 3 * 2);  // ceil(7 / 3) x ceil(5 / 3)
  const std::vector<int> pending = run.pending_tiles(false, {});
  CHECK(pending.size() == 6);
  const npend::map_tiles_outcome outcome = compute(run, pending);
  CHECK_FALSE(outcome.stopped);
  CHECK_FALSE(outcome.error);
  CHECK(run.tiles_present() == 6);
  const std::vector<double> values = assembled(run);
  const std::vector<double> reference = cell_by_cell(d);
  CHECK(same_values(values, reference));
  // The map has all three kinds of cell: ruled out (NaN), flipped, and not flipped by 2 s.
  const npend::map_cell_counts counts = run.count_cells(values);
  long nan = 0, finite = 0;
  for (const double v : reference) {
    nan += std::isnan(v) ? 1 : 0;
    finite += std::isfinite(v) ? 1 : 0;
  }
  CHECK(counts.forbidden == nan);
  CHECK(counts.failed == 0);
  CHECK(counts.no_flip == static_cast<long>(reference.size()) - nan - finite);
  CHECK(counts.forbidden > 0);
  CHECK(finite > 0);
  run.remove_own_tiles();
  CHECK_FALSE(fs::exists(run.tiles_folder()));
}

TEST_CASE("map_run: a resumed run gives the uninterrupted run's values") {
  const fs::path dir(npend::test::temporary_directory("map-run-resume"));
  const npend::map_run_description d = flip_map(2);
  const npend::map_run first(d, dir);
  std::vector<int> pending = first.pending_tiles(false, {});
  REQUIRE(pending.size() == 4 * 3);
  // The first run finishes 5 tiles, and a stop abandons the one it computes next.
  compute(first, {pending.begin(), pending.begin() + 5});
  {
    stop_after stop(0);
    npend::local_map_tile_queue queue({pending[5]});
    const npend::map_tiles_outcome outcome =
        first.compute_tiles(queue, 1, stop, write_plain, 0, false);
    CHECK(outcome.stopped);
    CHECK_FALSE(fs::exists(first.tile_path(pending[5])));
  }
  // One finished tile damaged: the resumed run computes it again, and says why.
  {
    std::fstream tile(first.tile_path(pending[0]), std::ios::in | std::ios::out | std::ios::binary);
    tile.seekp(20);
    tile.put('\x7f');
  }
  const npend::map_run resumed(d, dir);
  std::vector<std::string> redone;
  const std::vector<int> rest =
      resumed.pending_tiles(true, [&](const std::string& problem) { redone.push_back(problem); });
  REQUIRE(redone.size() == 1);
  INFO(redone[0]);
  CHECK(redone[0].find(first.tile_path(pending[0]).string()) != std::string::npos);
  CHECK(redone[0].find("do not match its checksum") != std::string::npos);
  CHECK(rest.size() == pending.size() - 4);
  compute(resumed, rest);
  CHECK(same_values(assembled(resumed), cell_by_cell(d)));
}

TEST_CASE("map_run: two parts, merged, give the whole run's values") {
  const fs::path dir(npend::test::temporary_directory("map-run-parts"));
  for (const int index : {1, 2}) {
    const npend::map_run part(flip_map(2, {index, 2}), dir);
    const std::vector<int> tiles = part.pending_tiles(false, {});
    CHECK(tiles.size() == 6);
    for (const int t : tiles) CHECK(t % 2 == index - 1);
    compute(part, tiles);
  }
  const npend::map_run merge(flip_map(2), dir);
  CHECK(merge.missing_tiles().empty());
  CHECK(same_values(assembled(merge), cell_by_cell(flip_map(2))));
}

TEST_CASE("map_run: the identity ties the tiles to their run") {
  const fs::path dir(npend::test::temporary_directory("map-run-identity"));
  const npend::map_run run(flip_map(4), dir);
  CHECK(npend::map_run(flip_map(4), dir).tag() == run.tag());
  npend::map_run_description longer = flip_map(4);
  longer.cell.t_end = 3;
  const npend::map_run other(longer, dir);
  CHECK(other.tag() != run.tag());
  // The part is not the map's: the parts of one map share their identity.
  CHECK(npend::map_run(flip_map(4, {2, 3}), dir).identity() == run.identity());
  // run.json read back describes its run and no other.
  fs::create_directories(run.tiles_folder());
  write_plain(run.run_file(), run.run_file_text(R"({"how": "test"})"));
  const std::optional<npend::map_run_record> record = npend::read_map_run_record(run.run_file());
  REQUIRE(record.has_value());
  CHECK(run.same_map(*record));
  CHECK_FALSE(other.same_map(*record));
  // A tile of the other run is found out when read back as this run's.
  compute(other, {0});
  const npend::map_tile_contents tile = run.load_tile(0);
  CHECK(tile.problem.find("was written by another run") != std::string::npos);
  CHECK_THROWS_AS(run.read_tile(0), npend::map_tile_error);
  CHECK(npend::is_map_run_file("tile_000000.bin"));
  CHECK(npend::is_map_run_file(".run.json.npend-a1B2c3"));
  CHECK_FALSE(npend::is_map_run_file("notes.txt"));
}

TEST_CASE(
    "map_run::open_folder: fresh, resumed, forced and parted runs, in the front end's words") {
  const fs::path dir(npend::test::temporary_directory("map-run-folder"));
  using start = npend::map_folder_start;
  const npend::map_folder_words words{.out = "out",
                                      .resume = "resume",
                                      .force = "force",
                                      .part = "part",
                                      .resume_hint = "resume=True",
                                      .force_hint = "force=True"};
  const npend::map_run run(flip_map(4), dir / "a");
  CHECK_THROWS_WITH_AS(
      run.open_folder(start::resume, "{}", words),
      doctest::Contains(("resume: " + run.folder().string() + " holds no interrupted map").c_str()),
      std::invalid_argument);
  run.open_folder(start::fresh, "{}", words);
  REQUIRE(fs::exists(run.run_file()));
  compute(run, {0});
  // The tiles folder now holds this map's run: a fresh start is refused, a resume is not.
  CHECK_THROWS_WITH_AS(run.open_folder(start::fresh, "{}", words),
                       doctest::Contains("finish it with resume=True, or start afresh with "
                                         "force=True"),
                       std::invalid_argument);
  run.open_folder(start::resume, "{}", words);
  CHECK(run.tiles_present() == 1);
  npend::map_run_description longer = flip_map(4);
  longer.cell.t_end = 3;
  const npend::map_run other(longer, dir / "a");
  CHECK_THROWS_WITH_AS(
      other.open_folder(start::resume, "{}", words),
      doctest::Contains(("resume: " + run.folder().string() + " holds a different map").c_str()),
      std::invalid_argument);
  CHECK_THROWS_WITH_AS(other.open_folder(start::fresh, "{}", words),
                       doctest::Contains("holds another run's tiles"), std::invalid_argument);
  // Forced: npend's files go, a user's file stays, and run.json is the new run's.
  write_plain(run.tiles_folder() / "notes.txt", "mine");
  other.open_folder(start::force, "{}", words);
  CHECK(other.tiles_present() == 0);
  CHECK(fs::exists(run.tiles_folder() / "notes.txt"));
  CHECK(other.same_map(*npend::read_map_run_record(other.run_file())));
  // Parts: the first writes run.json, the next of the same map accepts it, another map's not.
  const npend::map_run part1(flip_map(4, {1, 2}), dir / "b"), part2(flip_map(4, {2, 2}), dir / "b");
  part1.open_folder(start::part, "{}", words);
  part2.open_folder(start::part, "{}", words);
  npend::map_run_description other_part = longer;
  other_part.part = {2, 2};
  CHECK_THROWS_WITH_AS(npend::map_run(other_part, dir / "b").open_folder(start::part, "{}", words),
                       doctest::Contains("part: "), std::invalid_argument);
  // The command line's words are the defaults.
  CHECK_THROWS_WITH_AS(run.open_folder(start::resume, "{}"), doctest::Contains("--resume: "),
                       std::invalid_argument);
}

TEST_CASE("map_run: bad arguments are refused, naming them") {
  const fs::path dir(npend::test::temporary_directory("map-run-bad"));
  CHECK_THROWS_WITH_AS(npend::map_run(flip_map(0), dir), doctest::Contains("tile: 1..1024"),
                       std::invalid_argument);
  CHECK_THROWS_WITH_AS(npend::map_run(flip_map(4, {3, 2}), dir), doctest::Contains("part:"),
                       std::invalid_argument);
  npend::map_run_description no_time = flip_map(4);
  no_time.cell.dt = 0;
  CHECK_THROWS_AS(npend::map_run(no_time, dir), std::invalid_argument);
  CHECK_THROWS_WITH_AS(npend::map_values(flip_map(4).grid, flip_map(4).cell, -1),
                       doctest::Contains("threads:"), std::invalid_argument);
}

TEST_CASE("map_values: the whole grid on any number of threads is map_cell's values") {
  const npend::map_run_description d = flip_map(4);
  const std::vector<double> reference = cell_by_cell(d);
  CHECK(same_values(npend::map_values(d.grid, d.cell, 1), reference));
  CHECK(same_values(npend::map_values(d.grid, d.cell, 3), reference));
}

// Progress as map_values reports it, from any thread: the reports seen and the most cells.
class progress_counter final : public npend::run_control {
 public:
  void progress(double done, double total) override {
    ++reports;
    double seen = most.load();
    while (done > seen && !most.compare_exchange_weak(seen, done)) {
    }
    cells = total;
  }
  std::atomic<int> reports{0};
  std::atomic<double> most{0}, cells{0};
};

TEST_CASE("map_values: progress counts the cells done, up to all of them") {
  const npend::map_run_description d = flip_map(4);
  for (int threads : {1, 3}) {
    progress_counter counter;
    npend::map_values(d.grid, d.cell, threads, &counter);
    INFO("threads = ", threads);
    const double cells = static_cast<double>(d.grid.x.count) * d.grid.y.count;
    CHECK(counter.cells.load() == cells);
    CHECK(counter.most.load() == cells);
    CHECK(counter.reports.load() == d.grid.y.count);  // a row at a time
  }
}

TEST_CASE("map_cell_values: a list of starts on any number of threads is map_cell's values") {
  const npend::map_run_description d = flip_map(4);
  const npend::chain c(d.grid.parameters);
  std::vector<double> starts;
  std::vector<double> reference;
  for (int k = 0; k < 40; ++k) {
    const std::vector<double> x0 = {-3 + 0.15 * k, 2.5 - 0.1 * k, 0, 0};
    starts.insert(starts.end(), x0.begin(), x0.end());
    reference.push_back(npend::map_cell(c, x0, d.cell));
  }
  CHECK(same_values(npend::map_cell_values(c, starts, d.cell, 1), reference));
  CHECK(same_values(npend::map_cell_values(c, starts, d.cell, 4), reference));
  CHECK_THROWS_WITH_AS(npend::map_cell_values(c, std::vector<double>(5, 0.0), d.cell),
                       doctest::Contains("starts:"), std::invalid_argument);
}

}  // namespace map_run_test
