// npend map under `mpirun -np 2` (built only when npend is built with MPI): the ranks share
// the tiles and rank 0 writes the same bytes as one process; --resume works across ranks;
// bad input ends every rank with one message instead of a hang.
#include <doctest/doctest.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "support/test_support.hpp"

namespace fs = std::filesystem;

namespace {

// mpirun, with the environment these tests need set for this command only: CI runs as root,
// which Open MPI refuses without the two variables, and Open MPI never frees what MPI_Init
// allocates, which LeakSanitizer would report in the sanitized build. `timeout`: a hang
// fails the test instead of blocking it.
npend::test::command_result mpirun(int ranks, const std::string& args) {
  return npend::test::run_shell(
      "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 ASAN_OPTIONS=detect_leaks=0 "
      "OMPI_MCA_rmaps_base_oversubscribe=1 timeout 300 " NPEND_MPIEXEC " -np " +
      std::to_string(ranks) + " --oversubscribe " + NPEND_CLI_PATH + " " + args);
}

const std::string grid =
    "map --links 2 --x phi1:-3:3:24 --y phi2:-3:3:20 --t-end 20 --tile 4 --threads 1";

}  // namespace

TEST_CASE("npend map under mpirun: two ranks write the bytes of one process") {
  const fs::path dir(npend::test::temporary_directory("cli-map-mpi"));
  REQUIRE(npend::test::run_npend(grid + " --out " + (dir / "one").string()).exit_code == 0);
  const auto r = mpirun(2, grid + " --json --out " + (dir / "two").string());
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const auto summary = nlohmann::json::parse(r.out);  // rank 0 alone prints
  CHECK(summary["ranks"] == 2);
  CHECK(npend::test::read_text((dir / "one" / "map.npy").string()) ==
        npend::test::read_text((dir / "two" / "map.npy").string()));
  CHECK_FALSE(fs::exists(dir / "two" / "tiles"));
}

TEST_CASE("npend map under mpirun: --resume finishes the tiles a --part run left") {
  const fs::path dir(npend::test::temporary_directory("cli-map-mpi-resume"));
  REQUIRE(npend::test::run_npend(grid + " --out " + (dir / "one").string()).exit_code == 0);
  const fs::path part = dir / "part";
  REQUIRE(npend::test::run_npend(grid + " --part 2/3 --out " + part.string()).exit_code == 0);
  const auto r = mpirun(2, grid + " --resume --json --out " + part.string());
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK(nlohmann::json::parse(r.out)["resumed"] == true);
  CHECK(npend::test::read_text((dir / "one" / "map.npy").string()) ==
        npend::test::read_text((part / "map.npy").string()));
}

TEST_CASE("npend map under mpirun: bad input ends every rank, with one message") {
  const fs::path dir(npend::test::temporary_directory("cli-map-mpi-bad"));
  // Found by rank 0 alone (the folder), and by every rank alike (the axis).
  const auto resume = mpirun(2, grid + " --resume --out " + (dir / "none").string());
  CHECK(resume.exit_code == 2);
  CHECK(resume.out.empty());
  const std::string message =
      "npend map: error: --resume: " + (dir / "none").string() + " holds no interrupted map";
  CHECK(resume.err.find(message) != std::string::npos);
  CHECK(resume.err.find(message) == resume.err.rfind(message));
  const auto axis =
      mpirun(2, "map --links 2 --x theta1:0:1:4 --y phi2:0:1:4 --out " + (dir / "m").string());
  CHECK(axis.exit_code == 2);
  const std::string refused = "'theta1' is not an axis of the 2-link chain";
  CHECK(axis.err.find(refused) != std::string::npos);
  CHECK(axis.err.find(refused) == axis.err.rfind(refused));
}

TEST_CASE("npend map under mpirun: a rank that cannot write its tile ends the whole job") {
  const fs::path dir(npend::test::temporary_directory("cli-map-mpi-abort"));
  // A folder where tile 5 should go: whichever rank is handed tile 5 fails to write it.
  fs::create_directories(dir / "tiles" / "tile_000005.bin");
  const auto r = mpirun(2, grid + " --part 1/1 --out " + dir.string());
  INFO(r.err);
  CHECK(r.exit_code == 1);
  CHECK(r.err.find("npend map: error: rank ") != std::string::npos);
  CHECK(r.err.find("tile_000005.bin' names a directory, not a file") != std::string::npos);
}

TEST_CASE("npend map under mpirun: killed part way and resumed, the bytes of one process") {
  const fs::path dir(npend::test::temporary_directory("cli-map-mpi-kill"));
  // Uniform rods (--rods) go cell by cell, not on the batch lanes: about 5 s of work, long
  // enough to be killed part way.
  const std::string big =
      "map --links 2 --rods --x phi1:-3.1:3.1:32 --y phi2:-3.1:3.1:32 --quantity lyapunov "
      "--t-end 100 --tile 4 --threads 1";
  REQUIRE(npend::test::run_npend(big + " --out " + (dir / "one").string()).exit_code == 0);
  // mpirun passes the SIGTERM on to the ranks (here after a second or two), which abandon
  // the tiles in flight; --t-end 100 keeps the run going that long.
  const fs::path part = dir / "part";
  const auto killed = npend::test::run_shell(
      "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 "
      "ASAN_OPTIONS=detect_leaks=0 " NPEND_MPIEXEC " -np 2 --oversubscribe " +
      std::string(NPEND_CLI_PATH) + " " + big + " --out " + part.string() +
      " >/dev/null 2>&1 & pid=$!; for i in $(seq 600); do [ \"$(ls " + (part / "tiles").string() +
      " 2>/dev/null | wc -l)\" -ge 4 ] && break; sleep 0.05; done; kill -TERM $pid; wait $pid");
  const auto tiles = std::distance(fs::directory_iterator(part / "tiles"), {});
  INFO("tiles left by the killed run: " << tiles);
  CHECK(tiles >= 4);
  CHECK(tiles < 1 + 64);  // run.json + some of the 64 tiles: it did not finish
  CHECK_FALSE(fs::exists(part / "map.npy"));
  const auto resumed = mpirun(2, big + " --resume --out " + part.string());
  INFO(resumed.err);
  REQUIRE(resumed.exit_code == 0);
  CHECK(npend::test::read_text((dir / "one" / "map.npy").string()) ==
        npend::test::read_text((part / "map.npy").string()));
}
