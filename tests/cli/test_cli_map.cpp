// npend map as a user runs it: the .npy grid against the library cell by cell, the same
// bytes for any thread count, and a run killed part way then finished with --resume giving
// the same bytes as an uninterrupted one.
#include <doctest/doctest.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string_view>
#include <vector>

#include "npend/analysis/chaos/chaos_map.hpp"
#include "support/test_support.hpp"

namespace fs = std::filesystem;
using npend::test::run_npend;

namespace {

struct npy {
  std::string header;
  std::vector<double> values;
};

npy read_npy(const fs::path& path) {
  const std::string bytes = npend::test::read_text(path.string());
  REQUIRE(bytes.size() > 10);
  REQUIRE(bytes.substr(0, 6) == "\x93NUMPY");
  const auto length = static_cast<std::size_t>(static_cast<unsigned char>(bytes[8])) +
                      256 * static_cast<std::size_t>(static_cast<unsigned char>(bytes[9]));
  REQUIRE((10 + length) % 64 == 0);
  npy out{bytes.substr(10, length), {}};
  out.values.resize((bytes.size() - 10 - length) / sizeof(double));
  std::memcpy(out.values.data(), bytes.data() + 10 + length, out.values.size() * sizeof(double));
  return out;
}

const std::string grid = "map --links 2 --x phi1:-3:3:12 --y phi2:-2.5:3:10 --t-end 10 --tile 4";

}  // namespace

TEST_CASE("npend map: the .npy grid holds the library's flip time of every cell") {
  const fs::path dir = fs::path(npend::test::temporary_directory("cli-map")) / "m";
  const auto r = run_npend(grid + " --json --out " + dir.string());
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  CHECK(j["cells"] == 120);
  // A point-mass chain's flip map runs on the batch lanes.
  CHECK(j["batch"]["lanes"].get<int>() ==
        npend::batch_lanes(npend::chain(npend::chain_parameters::uniform(2))));
  CHECK(j["batch"]["isa"] == npend::batch_lane_isa());
  const npy m = read_npy(dir / "map.npy");
  CHECK(m.header.find("'shape': (10, 12)") != std::string::npos);
  CHECK(m.header.find("'descr': '<f8'") != std::string::npos);
  REQUIRE(m.values.size() == 120);
  const npend::chain c(npend::chain_parameters::uniform(2));
  long never = 0, forbidden = 0;
  const npy mask = read_npy(dir / "forbidden.npy");
  CHECK(mask.header.find("'descr': '|u1'") != std::string::npos);
  const std::string mask_bytes = npend::test::read_text((dir / "forbidden.npy").string());
  for (int row = 0; row < 10; ++row)
    for (int col = 0; col < 12; ++col) {
      const double a = -3 + 6.0 * col / 11, b = -2.5 + 5.5 * row / 9;
      const std::vector<double> x{a, b, 0, 0};
      // From rest the energy rules a flip out where 2 cos a + cos b > 1: NaN, not integrated.
      const bool ruled_out = 2 * std::cos(a) + std::cos(b) > 1;
      const double got = m.values[static_cast<std::size_t>(row * 12 + col)];
      INFO("row " << row << ", column " << col);
      if (ruled_out) {
        CHECK(std::isnan(got));
      } else {
        // The lanes' value of this start alone (it depends on the start only); flip_time's
        // differs by round-off where SLEEF's sines and std::sin's do, now that the flip is
        // located inside its step rather than rounded up to the step's end.
        const double expected = npend::flip_times(c, x, {10.0, 0.01, 0}).front();
        CHECK((got == expected || (std::isinf(got) && std::isinf(expected))));
      }
      CHECK(mask_bytes[mask_bytes.size() - 120 + static_cast<std::size_t>(row * 12 + col)] ==
            (ruled_out ? 1 : 0));
      never += std::isinf(got) ? 1 : 0;
      forbidden += ruled_out ? 1 : 0;
    }
  CHECK(forbidden > 0);
  CHECK(j["no_flip"] == never);
  CHECK(j["forbidden"] == forbidden);
  CHECK(j["integrated"] == 120 - forbidden);
  CHECK(j["failed"] == 0);
  // A grid this small also gets map.csv: x, y, value in the .npy's order, values exact.
  std::istringstream csv(npend::test::read_text((dir / "map.csv").string()));
  std::string line;
  std::getline(csv, line);
  CHECK(line == "phi1,phi2,value");
  for (std::size_t k = 0; k < m.values.size(); ++k) {
    REQUIRE(std::getline(csv, line));
    const std::string value = line.substr(line.rfind(',') + 1);
    if (std::isnan(m.values[k]))
      CHECK(value == "nan");
    else
      CHECK(std::stod(value) == m.values[k]);
  }
  CHECK(fs::exists(dir / "map.png"));
  CHECK(fs::exists(dir / "map.json"));
  CHECK_FALSE(fs::exists(dir / "tiles"));
}

TEST_CASE("npend map: the fast indicators, every cell the library's") {
  const fs::path dir(npend::test::temporary_directory("cli-map-indicators"));
  const npend::chain c(npend::chain_parameters::uniform(2));
  for (const std::string quantity : {"fli", "megno", "sali", "gali"}) {
    const auto r =
        run_npend("map --links 2 --x phi1:-3:3:5 --y phi2:-2:3:4 --t-end 20 --quantity " +
                  quantity + " --out " + (dir / quantity).string());
    REQUIRE(r.exit_code == 0);
    const npy m = read_npy(dir / quantity / "map.npy");
    REQUIRE(m.values.size() == 20);
    npend::map_cell_options o;
    o.quantity = npend::parse_map_quantity(quantity);
    o.t_end = 20;
    for (int row = 0; row < 4; ++row)
      for (int col = 0; col < 5; ++col) {
        const std::vector<double> x{npend::grid_value(-3, 3, 5, col),
                                    npend::grid_value(-2, 3, 4, row), 0, 0};
        INFO(quantity << ", row " << row << ", column " << col);
        CHECK(m.values[static_cast<std::size_t>(row * 5 + col)] == npend::map_cell(c, x, o));
      }
    CHECK(fs::exists(dir / quantity / "map.png"));
  }
  // GALI_k's order: n + 1 = 3 by default, so --gali-order 3 is the same map.
  REQUIRE(run_npend("map --links 2 --x phi1:-3:3:5 --y phi2:-2:3:4 --t-end 20 --quantity gali "
                    "--gali-order 3 --out " +
                    (dir / "gali3").string())
              .exit_code == 0);
  CHECK(npend::test::read_text((dir / "gali" / "map.npy").string()) ==
        npend::test::read_text((dir / "gali3" / "map.npy").string()));
}

TEST_CASE("npend map --stepper dopri5: every cell the library's dopri5 value, the run named") {
  const fs::path dir(npend::test::temporary_directory("cli-map-dopri5"));
  const npend::chain c(npend::chain_parameters::uniform(2));
  for (const std::string quantity : {"flip", "lyapunov", "state"}) {
    const auto r = run_npend(
        "map --links 2 --x phi1:-3:3:5 --y phi2:-2:3:4 --t-end 10 --p 0,1 "
        "--stepper dopri5 --abs-tol 1e-9 --rel-tol 1e-8 --json --quantity " +
        quantity + " --out " + (dir / quantity).string());
    REQUIRE(r.exit_code == 0);
    const auto j = nlohmann::json::parse(r.out);
    CHECK(j["stepper"] == "dopri5");
    CHECK(j["abs_tol"] == 1e-9);
    CHECK(j["rel_tol"] == 1e-8);
    const npy m = read_npy(dir / quantity / "map.npy");
    REQUIRE(m.values.size() == 20);
    npend::map_cell_options o;
    o.quantity = npend::parse_map_quantity(quantity);
    o.t_end = 10;
    o.stepping = {npend::stepper_kind::dopri5, 1e-9, 1e-8};
    int finite = 0;
    for (int row = 0; row < 4; ++row)
      for (int col = 0; col < 5; ++col) {
        const std::vector<double> x{npend::grid_value(-3, 3, 5, col),
                                    npend::grid_value(-2, 3, 4, row), 0, 1};
        INFO(quantity << ", row " << row << ", column " << col);
        const double got = m.values[static_cast<std::size_t>(row * 5 + col)];
        const double want = npend::map_cell(c, x, o);
        CHECK((got == want || (std::isnan(got) && std::isnan(want))));
        finite += std::isfinite(got) ? 1 : 0;
      }
    CHECK(finite > 0);
  }
  // The stepper and tolerances are part of the map's identity: an rk4 part is refused in a
  // dopri5 run's folder; the dopri5 parts, merged, give the single run's grid.
  const std::string parted =
      "map --links 2 --x phi1:-3:3:5 --y phi2:-2:3:4 --t-end 10 --p 0,1 "
      "--tile 2 --out " +
      (dir / "parted").string();
  const std::string tolerances = " --stepper dopri5 --abs-tol 1e-9 --rel-tol 1e-8";
  REQUIRE(run_npend(parted + tolerances + " --part 1/2").exit_code == 0);
  const auto rk4_part = run_npend(parted + " --part 2/2");
  CHECK(rk4_part.exit_code == 2);
  CHECK(rk4_part.err.find("holds a different map") != std::string::npos);
  REQUIRE(run_npend(parted + tolerances + " --part 2/2").exit_code == 0);
  REQUIRE(run_npend("map merge " + (dir / "parted").string()).exit_code == 0);
  CHECK(npend::test::read_text((dir / "parted" / "map.npy").string()) ==
        npend::test::read_text((dir / "flip" / "map.npy").string()));
}

TEST_CASE("npend map --stepper gauss6: every cell the library's Gauss-Legendre value") {
  const fs::path dir(npend::test::temporary_directory("cli-map-gauss"));
  const npend::chain c(npend::chain_parameters::uniform(2));
  for (const std::string quantity : {"flip", "state"}) {
    const auto r = run_npend(
        "map --links 2 --x phi1:-3:3:6 --y phi2:-2:3:4 --t-end 10 "
        "--stepper gauss6 --json --quantity " +
        quantity + " --out " + (dir / quantity).string());
    REQUIRE(r.exit_code == 0);
    CHECK(nlohmann::json::parse(r.out)["stepper"] == "gauss6");
    const npy m = read_npy(dir / quantity / "map.npy");
    REQUIRE(m.values.size() == 24);
    npend::map_cell_options o;
    o.quantity = npend::parse_map_quantity(quantity);
    o.t_end = 10;
    o.stepping.stepper = npend::stepper_kind::gauss6;
    for (int row = 0; row < 4; ++row)
      for (int col = 0; col < 6; ++col) {
        const std::vector<double> x{npend::grid_value(-3, 3, 6, col),
                                    npend::grid_value(-2, 3, 4, row), 0, 0};
        INFO(quantity << ", row " << row << ", column " << col);
        const double got = m.values[static_cast<std::size_t>(row * 6 + col)];
        const double want = npend::map_cell(c, x, o);
        CHECK((got == want || (std::isnan(got) && std::isnan(want))));
      }
  }
  CHECK(npend::test::is_input_error(
      run_npend("map --links 2 --x phi1:-3:3:6 --y phi2:-2:3:4 --stepper gauss6 --rel-tol 1e-9 "
                "--out " +
                (dir / "tol").string()),
      "--rel-tol: only with --stepper dopri5"));
}

TEST_CASE("npend map --stepper taylor: the indicators' cells are the library's, the run named") {
  const fs::path dir(npend::test::temporary_directory("cli-map-taylor"));
  const auto r = run_npend(
      "map --links 2 --x phi1:-2:2:4 --y phi2:-1:1:3 --quantity megno --t-end 10 --stepper taylor "
      "--tol 1e-11 --json --out " +
      (dir / "megno").string());
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  CHECK(j["stepper"] == "taylor");
  const npy m = read_npy(dir / "megno" / "map.npy");
  REQUIRE(m.values.size() == 12);
  const npend::chain c(npend::chain_parameters::uniform(2));
  npend::map_cell_options o;
  o.quantity = npend::map_quantity::megno;
  o.t_end = 10;
  o.stepping.stepper = npend::stepper_kind::taylor;
  o.stepping.abs_tol = o.stepping.rel_tol = 1e-11;
  for (int row = 0; row < 3; ++row)
    for (int col = 0; col < 4; ++col) {
      const std::vector<double> x{npend::grid_value(-2, 2, 4, col),
                                  npend::grid_value(-1, 1, 3, row), 0, 0};
      INFO("row " << row << ", column " << col);
      CHECK(m.values[static_cast<std::size_t>(row * 4 + col)] == npend::map_cell(c, x, o));
    }
  CHECK(npend::test::is_input_error(
      run_npend("map --links 2 --x phi1:0:1:4 --y phi2:0:1:4 --stepper taylor --out " +
                (dir / "flip").string()),
      "--stepper: taylor maps only the chaos indicators (fli, megno, sali, gali), not flip"));
}

TEST_CASE("npend map: energy, mass and length axes start each cell as the closed form says") {
  // The hanging double pendulum pushed with p = s (l1, l2) has the kinetic energy ½ pᵀA⁻¹p,
  // which for l1 = l2 = 1 and m1 = 1 is s² / (2 m2); so the energy axis must start each cell at
  // s = √(2 m2 E), and the final p2 is then map_cell's on that chain.
  const fs::path dir(npend::test::temporary_directory("cli-map-axes"));
  const auto r = run_npend(
      "map --links 2 --x energy:0:40:5 --y m2:0.5:2:3 --quantity state --component p2 "
      "--t-end 3 --json --out " +
      (dir / "em").string());
  REQUIRE(r.exit_code == 0);
  const npy m = read_npy(dir / "em" / "map.npy");
  REQUIRE(m.values.size() == 15);
  npend::map_cell_options o;
  o.quantity = npend::map_quantity::state;
  o.component = 3;
  o.t_end = 3;
  for (int row = 0; row < 3; ++row)
    for (int col = 0; col < 5; ++col) {
      const double m2 = npend::grid_value(0.5, 2, 3, row), e = npend::grid_value(0, 40, 5, col);
      auto p = npend::chain_parameters::uniform(2);
      p.masses[1] = m2;
      const double s = std::sqrt(2 * m2 * e);
      INFO("row " << row << ", column " << col);
      CHECK(m.values[static_cast<std::size_t>(row * 5 + col)] ==
            doctest::Approx(npend::map_cell(npend::chain(p), std::vector<double>{0, 0, s, s}, o))
                .epsilon(1e-12));
    }
  // Angles of energy V = g (2 (1 - cos 1) + (1 - cos 1)) ≈ 13.53 J: energies below it have no
  // start, those cells are NaN and counted as ruled out.
  const auto r2 = run_npend(
      "map --links 2 --phi 1,1 --x energy:0:40:5 --y l2:0.5:1.5:3 --quantity state --t-end 1 "
      "--json --out " +
      (dir / "el").string());
  REQUIRE(r2.exit_code == 0);
  const auto j = nlohmann::json::parse(r2.out);
  const npy el = read_npy(dir / "el" / "map.npy");
  long below = 0;
  for (int row = 0; row < 3; ++row)
    for (int col = 0; col < 5; ++col) {
      const double l2 = npend::grid_value(0.5, 1.5, 3, row), e = npend::grid_value(0, 40, 5, col);
      const double v = 9.81 * (2 * (1 - std::cos(1.0)) + l2 * (1 - std::cos(1.0)));
      INFO("row " << row << ", column " << col);
      CHECK(std::isnan(el.values[static_cast<std::size_t>(row * 5 + col)]) == (e < v));
      below += e < v ? 1 : 0;
    }
  CHECK(below > 0);
  CHECK(j["forbidden"] == below);
  CHECK(fs::exists(dir / "el" / "forbidden.npy"));
  CHECK(fs::exists(dir / "el" / "map.png"));
}

TEST_CASE("npend map: damping and drive axes give each cell its chain, a drive rules nothing out") {
  const fs::path dir(npend::test::temporary_directory("cli-map-drive"));
  // The drive's amplitude and frequency: every cell is the library's flip time on a chain
  // built here with that drive, and none is ruled out (a drive feeds energy in).
  const auto r = run_npend(
      "map --links 2 --pivot vertical:0.1:20 --phi 1.2,0 --x drive-amplitude:0:0.3:4 "
      "--y drive-frequency:10:40:3 --t-end 15 --json --out " +
      (dir / "drive").string());
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  CHECK(j["forbidden"] == 0);
  const npy d = read_npy(dir / "drive" / "map.npy");
  REQUIRE(d.values.size() == 12);
  const npend::flip_options flip{15.0, 0.01, 0};
  int flipped = 0;
  for (int row = 0; row < 3; ++row)
    for (int col = 0; col < 4; ++col) {
      auto p = npend::chain_parameters::uniform(2);
      p.pivot = npend::pivot_motion::vertical(npend::grid_value(0, 0.3, 4, col),
                                              npend::grid_value(10, 40, 3, row));
      const double t = npend::flip_time(npend::chain(p), std::vector<double>{1.2, 0, 0, 0}, flip);
      INFO("row " << row << ", column " << col);
      CHECK(d.values[static_cast<std::size_t>(row * 4 + col)] == t);
      flipped += std::isfinite(t) ? 1 : 0;
    }
  // From 1.2 rad at rest the fixed pivot (amplitude 0) cannot flip; strong drives can.
  CHECK(std::isinf(d.values[0]));
  CHECK(flipped > 0);
  // Damping at both joints: the library's values, and NaN exactly where the energy falls
  // short of a flip (2 cos φ1 + cos φ2 > 1 at rest), damping or not.
  const auto r2 = run_npend(
      "map --links 2 --phi 1,0 --x b1:0:0.6:3 --y phi2:-3:3:5 --damping 0,0.2 --t-end 10 --out " +
      (dir / "damped").string());
  REQUIRE(r2.exit_code == 0);
  const npy b = read_npy(dir / "damped" / "map.npy");
  REQUIRE(b.values.size() == 15);
  int ruled_out = 0;
  for (int row = 0; row < 5; ++row)
    for (int col = 0; col < 3; ++col) {
      const double phi2 = npend::grid_value(-3, 3, 5, row);
      auto p = npend::chain_parameters::uniform(2);
      p.damping = {npend::grid_value(0, 0.6, 3, col), 0.2};
      const double value = b.values[static_cast<std::size_t>(row * 3 + col)];
      INFO("row " << row << ", column " << col);
      if (2 * std::cos(1.0) + std::cos(phi2) > 1) {
        CHECK(std::isnan(value));
        ++ruled_out;
      } else {
        CHECK(value == npend::flip_time(npend::chain(p), std::vector<double>{1.0, phi2, 0, 0},
                                        {10.0, 0.01, 0}));
      }
    }
  CHECK(ruled_out == 9);  // φ2 = −1.5, 0, 1.5 in each of the three columns
}

TEST_CASE("npend map: a map of one step, every cell ruled out, still draws its PNG") {
  // t-end = dt leaves the flip times' colour range dt..t-end empty; gnuplot refuses that.
  const fs::path dir(npend::test::temporary_directory("cli-map-one-step"));
  const auto r = run_npend(
      "map --links 2 --x phi1:0:0.1:2 --y phi2:0:0.1:2 --t-end 0.01 --json "
      "--out " +
      (dir / "m").string());
  REQUIRE(r.exit_code == 0);
  CHECK(r.err.find("gnuplot failed") == std::string::npos);
  CHECK(nlohmann::json::parse(r.out)["forbidden"] == 4);
  CHECK(fs::exists(dir / "m" / "map.png"));
}

TEST_CASE("npend map: forbidden cells are grey with failed cells red, and without any") {
  // Without failed cells the map's NaN are left transparent over a grey plot area; with
  // failed cells too (here: steps far too long for rk4) forbidden.npy is drawn over the map.
  const fs::path dir(npend::test::temporary_directory("cli-map-grey"));
  const auto both = run_npend(
      "map --links 2 --x energy:0:100:6 --y phi1:0:3:6 --quantity state --dt 2 --t-end 1000 "
      "--json --out " +
      (dir / "both").string());
  REQUIRE(both.exit_code == 0);
  const auto jb = nlohmann::json::parse(both.out);
  REQUIRE(jb["failed"] > 0);
  REQUIRE(jb["forbidden"] > 0);
  const std::string script = npend::test::read_text((dir / "both" / "map.gp").string());
  CHECK(script.find("forbidden.npy") != std::string::npos);
  CHECK(script.find("set object 1 rectangle") == std::string::npos);
  const auto lens =
      run_npend("map --links 2 --x phi1:-3:3:8 --y phi2:-3:3:8 --t-end 10 --json --out " +
                (dir / "lens").string());
  REQUIRE(lens.exit_code == 0);
  const auto jl = nlohmann::json::parse(lens.out);
  CHECK(jl["failed"] == 0);
  CHECK(jl["forbidden"] == 16);
  const std::string grey = npend::test::read_text((dir / "lens" / "map.gp").string());
  CHECK(grey.find("set object 1 rectangle") != std::string::npos);
  CHECK(grey.find("\"forbidden.npy\"") == std::string::npos);
  CHECK(both.err.find("gnuplot failed") == std::string::npos);
  CHECK(lens.err.find("gnuplot failed") == std::string::npos);
  for (const char* folder : {"both", "lens"}) CHECK(fs::exists(dir / folder / "map.png"));
}

TEST_CASE("npend map: beyond 1024 cells a side map.png draws a subsample, map.npy keeps all") {
  const fs::path dir(npend::test::temporary_directory("cli-map-subsample"));
  const auto r = run_npend("map --links 2 --x phi1:-3:3:1100 --y phi2:-3:3:3 --t-end 0.01 --out " +
                           (dir / "m").string());
  REQUIRE(r.exit_code == 0);
  CHECK(read_npy(dir / "m" / "map.npy").values.size() == 3300);
  const std::string script = npend::test::read_text((dir / "m" / "map.gp").string());
  CHECK(script.find("every 2:2") != std::string::npos);
  CHECK(script.find("1 cell in 2 x 2") != std::string::npos);
  CHECK(fs::exists(dir / "m" / "map.png"));
}

TEST_CASE("npend map --tol: both tolerances, a part of the run's identity that merge keeps") {
  const fs::path dir(npend::test::temporary_directory("cli-map-tol"));
  const std::string map =
      "map --links 2 --x phi1:-3:3:5 --y phi2:-2:3:4 --t-end 10 --p 0,1 --stepper dopri5 "
      "--tile 2 --json --out ";
  const auto both = run_npend(map + (dir / "both").string() + " --abs-tol 1e-9 --rel-tol 1e-9");
  REQUIRE(both.exit_code == 0);
  const auto tol = run_npend(map + (dir / "tol").string() + " --tol 1e-9");
  REQUIRE(tol.exit_code == 0);
  const auto j = nlohmann::json::parse(tol.out);
  CHECK(j["abs_tol"] == 1e-9);
  CHECK(j["rel_tol"] == 1e-9);
  CHECK(npend::test::read_text((dir / "both" / "map.npy").string()) ==
        npend::test::read_text((dir / "tol" / "map.npy").string()));
  // Parts of a --tol run merge into its bytes: the folder's record keeps the option.
  const std::string parted = map + (dir / "parted").string() + " --tol 1e-9 --part ";
  REQUIRE(run_npend(parted + "1/2").exit_code == 0);
  REQUIRE(run_npend(parted + "2/2").exit_code == 0);
  REQUIRE(run_npend("map merge " + (dir / "parted").string()).exit_code == 0);
  CHECK(npend::test::read_text((dir / "parted" / "map.npy").string()) ==
        npend::test::read_text((dir / "tol" / "map.npy").string()));
}

TEST_CASE("npend map: one thread or two, the same bytes") {
  const fs::path dir(npend::test::temporary_directory("cli-map-threads"));
  REQUIRE(run_npend(grid + " --threads 1 --out " + (dir / "one").string()).exit_code == 0);
  REQUIRE(run_npend(grid + " --threads 2 --out " + (dir / "two").string()).exit_code == 0);
  CHECK(npend::test::read_text((dir / "one" / "map.npy").string()) ==
        npend::test::read_text((dir / "two" / "map.npy").string()));
}

TEST_CASE("npend map: killed part way and resumed, the same bytes as one run") {
  const fs::path dir(npend::test::temporary_directory("cli-map-resume"));
  // Uniform rods (--rods) go cell by cell, not on the batch lanes: slow enough (about half a
  // second) to be killed part way.
  const std::string big =
      " map --links 2 --rods --x phi1:-3.1:3.1:32 --y phi2:-3.1:3.1:32 --quantity lyapunov "
      "--t-end 10 --tile 4 --threads 1";
  REQUIRE(run_npend(big + " --out " + (dir / "whole").string()).exit_code == 0);
  // Start it in the background, wait for its first tiles, kill it.
  const fs::path part = dir / "part";
  const auto killed =
      npend::test::run_shell(std::string(NPEND_CLI_PATH) + big + " --out " + part.string() +
                             " >/dev/null 2>&1 & pid=$!; for i in $(seq 600); do "
                             "[ \"$(ls " +
                             (part / "tiles").string() +
                             " 2>/dev/null | wc -l)\" -ge 4 ] && break; "
                             "sleep 0.05; done; kill -TERM $pid; wait $pid; echo $?");
  const auto tiles = std::distance(fs::directory_iterator(part / "tiles"), {});
  INFO("tiles left by the killed run: " << tiles << ", its exit status " << killed.out);
  CHECK(tiles >= 4);
  CHECK(tiles < 1 + 64);  // run.json + some of the 64 tiles: it did not finish
  CHECK_FALSE(fs::exists(part / "map.npy"));
  const auto resumed = run_npend(big + " --resume --json --out " + part.string());
  REQUIRE(resumed.exit_code == 0);
  CHECK(nlohmann::json::parse(resumed.out)["resumed"] == true);
  CHECK(npend::test::read_text((dir / "whole" / "map.npy").string()) ==
        npend::test::read_text((part / "map.npy").string()));
}

namespace {

// `grid` in folder `dir` as part `part` (I/N) of a job array.
npend::test::command_result run_part(const fs::path& dir, const std::string& part,
                                     const std::string& extra = "") {
  return run_npend(grid + extra + " --threads 1 --part " + part + " --out " + dir.string());
}

}  // namespace

TEST_CASE("npend map --part and merge: the parts, merged, give the bytes of one run") {
  const fs::path dir(npend::test::temporary_directory("cli-map-parts"));
  REQUIRE(run_npend(grid + " --out " + (dir / "whole").string()).exit_code == 0);
  const fs::path parts = dir / "parts";
  for (const std::string part : {"1/3", "2/3", "3/3"}) {
    const auto r = run_part(parts, part);
    REQUIRE(r.exit_code == 0);
    CHECK(r.out.find("npend map merge") != std::string::npos);
    CHECK_FALSE(fs::exists(parts / "map.npy"));  // a part assembles nothing
  }
  const auto merged = run_npend("map merge " + parts.string() + " --json");
  REQUIRE(merged.exit_code == 0);
  CHECK(nlohmann::json::parse(merged.out)["merged"] == true);
  CHECK(npend::test::read_text((dir / "whole" / "map.npy").string()) ==
        npend::test::read_text((parts / "map.npy").string()));
  CHECK(npend::test::read_text((dir / "whole" / "map.csv").string()) ==
        npend::test::read_text((parts / "map.csv").string()));
  CHECK(fs::exists(parts / "map.png"));
  CHECK_FALSE(fs::exists(parts / "tiles"));
}

TEST_CASE("npend map --part: parts started at the same moment on one folder share it") {
  const fs::path dir(npend::test::temporary_directory("cli-map-parts-race"));
  REQUIRE(run_npend(grid + " --out " + (dir / "whole").string()).exit_code == 0);
  // Four parts race to create the folder and its run.json; none may clear another's tiles.
  std::string jobs;
  for (int i = 1; i <= 4; ++i)
    jobs += std::string(NPEND_CLI_PATH) + " " + grid + " --threads 1 --part " + std::to_string(i) +
            "/4 --out " + (dir / "shared").string() + " >/dev/null & ";
  const auto started = npend::test::run_shell(jobs + "wait");
  REQUIRE(started.exit_code == 0);
  REQUIRE(run_npend("map merge " + (dir / "shared").string()).exit_code == 0);
  CHECK(npend::test::read_text((dir / "whole" / "map.npy").string()) ==
        npend::test::read_text((dir / "shared" / "map.npy").string()));
}

TEST_CASE("npend map merge: names the missing tiles, and --part --resume computes only those") {
  const fs::path dir(npend::test::temporary_directory("cli-map-merge-missing"));
  REQUIRE(run_part(dir, "1/2").exit_code == 0);  // tiles 0, 2, 4, 6, 8 of 9
  const auto r = run_npend("map merge " + dir.string());
  CHECK(npend::test::is_input_error(
      r, "merge: 4 of 9 tiles are missing from " + (dir / "tiles").string() +
             ": tile_000001.bin, tile_000003.bin, tile_000005.bin, tile_000007.bin"));
  CHECK_FALSE(fs::exists(dir / "map.npy"));
  const auto resumed =
      run_npend(grid + " --threads 1 --part 2/2 --resume --json --out " + dir.string());
  REQUIRE(resumed.exit_code == 0);
  CHECK(nlohmann::json::parse(resumed.out)["tiles_computed"] == 4);
  CHECK(run_npend("map merge " + dir.string()).exit_code == 0);
}

TEST_CASE("npend map --part and merge: a folder or a tile of another map is refused") {
  const fs::path dir(npend::test::temporary_directory("cli-map-parts-other"));
  const fs::path mine = dir / "mine", other = dir / "other";
  REQUIRE(run_part(mine, "1/2").exit_code == 0);
  // Another part with other times cannot join the folder.
  const auto joined = run_part(mine, "2/2", " --dt 0.02");
  CHECK(npend::test::is_input_error(
      joined, "--part: " + mine.string() +
                  " holds a different map (other chain, axes, quantity or times)"));
  REQUIRE(run_part(mine, "2/2").exit_code == 0);
  // A tile of another map copied in is found when merging.
  REQUIRE(run_part(other, "1/1", " --dt 0.02").exit_code == 0);
  fs::copy_file(other / "tiles" / "tile_000003.bin", mine / "tiles" / "tile_000003.bin",
                fs::copy_options::overwrite_existing);
  const auto merged = run_npend("map merge " + mine.string());
  CHECK(merged.exit_code == 1);
  CHECK(merged.err == "npend map: error: tile " + (mine / "tiles" / "tile_000003.bin").string() +
                          " was written by another run (of another map than " +
                          (mine / "tiles" / "run.json").string() +
                          "); remove it and finish with --resume\n");
  CHECK_FALSE(fs::exists(mine / "map.npy"));
  // A tile cut short (as a crash of the machine may leave it) is named as such.
  const fs::path cut = mine / "tiles" / "tile_000001.bin";
  const std::string whole_tile = npend::test::read_text(cut.string());
  std::ofstream(cut, std::ios::binary | std::ios::trunc) << whole_tile.substr(0, 20);
  const auto cut_merge = run_npend("map merge " + mine.string());
  CHECK(cut_merge.exit_code == 1);
  CHECK(cut_merge.err.find("tile " + cut.string() + " is incomplete (20 bytes, expected " +
                           std::to_string(whole_tile.size()) +
                           ": a crash may have cut it short)") != std::string::npos);
}

namespace {

// The names of the files in `dir` (none if it does not exist).
std::vector<std::string> file_names(const fs::path& dir) {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec))
    names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

// Whether `dir` or its tiles/ holds a hidden temporary (".<name>.npend-XXXXXX").
bool has_temporaries(const fs::path& dir) {
  for (const fs::path& folder : {dir, dir / "tiles"})
    for (const std::string& name : file_names(folder))
      if (name.find(".npend-") != std::string::npos) return true;
  return false;
}

struct signalled_run {
  int status = -1;
  double seconds = -1;  // from the signal to the process's end
};

// Starts npend with `args` in the background, sends it `signal` `delay` seconds after
// `ready` (a file) appears, and measures how long it takes to end. A watchdog kills it after
// 60 s, so that a run that ignores the signal fails the test instead of hanging it.
signalled_run signal_after(const std::string& args, const fs::path& ready, double delay,
                           const std::string& signal = "TERM") {
  const auto r = npend::test::run_shell(
      std::string(NPEND_CLI_PATH) + " " + args +
      " >/dev/null 2>&1 & pid=$!; for i in $(seq 1200); do [ -e " + ready.string() +
      " ] && break; sleep 0.01; done; sleep " + std::to_string(delay) +
      "; (sleep 60; kill -KILL $pid) >/dev/null 2>&1 & dog=$!; t0=$(date +%s.%N); kill -" + signal +
      " $pid; wait $pid; status=$?; t1=$(date +%s.%N); kill $dog 2>/dev/null; "
      "echo $status $(awk -v a=$t0 -v b=$t1 'BEGIN { print b - a }')");
  signalled_run out;
  std::istringstream(r.out) >> out.status >> out.seconds;
  return out;
}

}  // namespace

TEST_CASE(
    "npend map: SIGTERM abandons the tiles in flight at once, on the lanes and cell by cell") {
  const fs::path dir(npend::test::temporary_directory("cli-map-abandon"));
  // One tile of 4 cells, each 1e8 steps (minutes): the run can only end in time by leaving
  // its tile unfinished. --rods goes cell by cell; point masses on the batch lanes.
  const std::string one_tile =
      "map --links 2 --x phi1:1:2:2 --y phi2:1:2:2 --tile 2 --threads 1 --t-end 1e6 ";
  const std::vector<std::pair<std::string, std::string>> runs = {
      {"lanes, rk4", "--quantity state"},
      {"lanes, dopri5", "--quantity state --stepper dopri5"},
      {"lanes, lyapunov", "--quantity lyapunov"},
      {"lanes, megno", "--quantity megno"},
      {"cell by cell, rk4", "--rods --quantity state"},
      {"cell by cell, megno", "--rods --quantity megno"},
      {"cell by cell, gauss6 lyapunov", "--rods --quantity lyapunov --stepper gauss6"}};
  int k = 0;
  for (const auto& [what, options] : runs) {
    CAPTURE(what);
    const fs::path out = dir / std::to_string(k++);
    const auto killed = signal_after(one_tile + options + " --out " + out.string(),
                                     out / "tiles" / "run.json", 0.3);
    CHECK(killed.status == 128 + 15);
    CHECK(killed.seconds >= 0);
    CHECK(killed.seconds < 1.5);
    CHECK(file_names(out / "tiles") == std::vector<std::string>{"run.json"});
    CHECK_FALSE(fs::exists(out / "map.npy"));
  }
}

TEST_CASE(
    "npend map: killed in its only tile, the run ends at once and --resume gives one run's "
    "bytes") {
  const fs::path dir(npend::test::temporary_directory("cli-map-abandon-resume"));
  // Uniform rods go cell by cell: 4 cells of 2e6 rk4 steps, a tile of some 3 s of CPU time
  // (0.33 s at --t-end 2000), so that a run that finished its tile before it ended took
  // seconds after the signal.
  const std::string map =
      "map --links 2 --rods --x phi1:1:2:2 --y phi2:1:2:2 --quantity state --t-end 20000 "
      "--tile 2 --threads 1";
  REQUIRE(run_npend(map + " --out " + (dir / "whole").string()).exit_code == 0);
  const fs::path part = dir / "part";
  const auto killed =
      signal_after(map + " --out " + part.string(), part / "tiles" / "run.json", 0.3);
  CHECK(killed.status == 128 + 15);
  CHECK(killed.seconds < 1.5);
  CHECK(file_names(part / "tiles") == std::vector<std::string>{"run.json"});
  const auto resumed = run_npend(map + " --resume --out " + part.string());
  REQUIRE(resumed.exit_code == 0);
  CHECK(npend::test::read_text((dir / "whole" / "map.npy").string()) ==
        npend::test::read_text((part / "map.npy").string()));
}

TEST_CASE(
    "npend map: a fresh run refuses a folder holding another run, --force removes only "
    "npend's files") {
  const fs::path dir(npend::test::temporary_directory("cli-map-fresh-folder"));
  REQUIRE(run_npend(grid + " --out " + (dir / "whole").string()).exit_code == 0);
  const fs::path mine = dir / "mine", tiles = mine / "tiles";
  REQUIRE(run_part(mine, "1/2").exit_code == 0);   // half a job array of this map
  std::ofstream(tiles / "notes.txt") << "mine\n";  // and a file that is not npend's
  const std::vector<std::string> before = file_names(tiles);
  REQUIRE(before.size() == 1 + 1 + 5);  // run.json, notes.txt, tiles 0, 2, 4, 6, 8
  const auto again = run_npend(grid + " --out " + mine.string());
  CHECK(npend::test::is_input_error(
      again, "--out: " + tiles.string() +
                 " holds an unfinished run of this map: finish it with --resume, or start "
                 "afresh with --force"));
  const auto other = run_npend(grid + " --dt 0.02 --out " + mine.string());
  CHECK(npend::test::is_input_error(
      other, "--out: " + tiles.string() +
                 " holds another run's tiles or other files: give another --out, or --force to "
                 "remove npend's tiles from it (other files stay)"));
  CHECK(file_names(tiles) == before);
  // --force starts afresh: the map of one run, npend's tile files gone, the user's file kept.
  REQUIRE(run_npend(grid + " --force --out " + mine.string()).exit_code == 0);
  CHECK(npend::test::read_text((dir / "whole" / "map.npy").string()) ==
        npend::test::read_text((mine / "map.npy").string()));
  CHECK(file_names(tiles) == std::vector<std::string>{"notes.txt"});
  CHECK(npend::test::read_text((tiles / "notes.txt").string()) == "mine\n");
}

TEST_CASE("npend map merge and --resume: a tile whose data changed fails its checksum") {
  const fs::path dir(npend::test::temporary_directory("cli-map-checksum"));
  REQUIRE(run_npend(grid + " --out " + (dir / "whole").string()).exit_code == 0);
  const fs::path parts = dir / "parts", tile = parts / "tiles" / "tile_000003.bin";
  REQUIRE(run_part(parts, "1/1").exit_code == 0);
  // One bit of the tile's last value flipped: the size and the run's tag stay right.
  std::string bytes = npend::test::read_text(tile.string());
  REQUIRE(bytes.size() == 16 + 16 * sizeof(double));  // tag, checksum, 4 x 4 values
  bytes[bytes.size() - 3] = static_cast<char>(bytes[bytes.size() - 3] ^ 0x10);
  std::ofstream(tile, std::ios::binary | std::ios::trunc) << bytes;
  const auto merged = run_npend("map merge " + parts.string());
  CHECK(merged.exit_code == 1);
  CHECK(merged.err == "npend map: error: tile " + tile.string() +
                          " is damaged: its data do not match its checksum; remove it and finish "
                          "with --resume\n");
  CHECK_FALSE(fs::exists(parts / "map.npy"));
  // Resuming computes that tile again, and says so.
  const auto resumed =
      run_npend(grid + " --threads 1 --part 1/1 --resume --json --out " + parts.string());
  REQUIRE(resumed.exit_code == 0);
  CHECK(resumed.err == "npend map: note: tile " + tile.string() +
                           " is damaged: its data do not match its checksum; computing it "
                           "again\n");
  CHECK(nlohmann::json::parse(resumed.out)["tiles_computed"] == 1);
  REQUIRE(run_npend("map merge " + parts.string()).exit_code == 0);
  CHECK(npend::test::read_text((dir / "whole" / "map.npy").string()) ==
        npend::test::read_text((parts / "map.npy").string()));
}

TEST_CASE(
    "npend map merge: Ctrl-C while assembling keeps the tiles, says so, leaves no "
    "temporary") {
  const fs::path dir(npend::test::temporary_directory("cli-map-merge-interrupt"));
  // 1024^2 cells the energy rules out: nothing to integrate, an 8 MB map.npy and a picture
  // of a million cells to make: a second or more.
  const std::string big =
      "map --links 2 --x phi1:-0.1:0.1:1024 --y phi2:-0.1:0.1:1024 "
      "--t-end 1 --tile 256 --threads 2";
  REQUIRE(run_npend(big + " --part 1/1 --out " + dir.string()).exit_code == 0);
  const std::vector<std::string> tiles = file_names(dir / "tiles");
  REQUIRE(tiles.size() == 1 + 4 * 4);
  // In a subshell, so that the stderr run_shell captures is the merge's.
  const auto merge = npend::test::run_shell(
      "(" + std::string(NPEND_CLI_PATH) + " map merge " + dir.string() +
      " >/dev/null & pid=$!; sleep 0.3; kill -INT $pid; wait $pid; echo $?)");
  CHECK(merge.out == "130\n");
  CHECK(merge.err == "npend map: interrupted while assembling the map; its tiles stay in " +
                         (dir / "tiles").string() + ": npend map merge " + dir.string() +
                         " assembles it\n");
  CHECK_FALSE(has_temporaries(dir));
  CHECK_FALSE(fs::exists(dir / "map.json"));
  CHECK(file_names(dir / "tiles") == tiles);
  REQUIRE(run_npend("map merge " + dir.string()).exit_code == 0);
  CHECK(fs::exists(dir / "map.json"));
  CHECK_FALSE(fs::exists(dir / "tiles"));
}

TEST_CASE("npend map: NPEND_LANE_ISA picks the lanes' ISA, and a name it cannot run is refused") {
  const fs::path dir = fs::path(npend::test::temporary_directory("cli-map-isa"));
  const std::vector<std::string_view> isas = npend::batch_lane_isas();
  const auto run_on = [&](std::string_view isa, const fs::path& out) {
    return npend::test::run_shell(fmt::format("NPEND_LANE_ISA={} {} {} --json --out {}", isa,
                                              NPEND_CLI_PATH, grid, out.string()));
  };
  const auto baseline = run_on(isas.front(), dir / "baseline");
  REQUIRE(baseline.exit_code == 0);
  CHECK(nlohmann::json::parse(baseline.out)["batch"]["isa"] == isas.front());
  const npy first = read_npy(dir / "baseline" / "map.npy");
  for (const std::string_view isa : isas) {
    CAPTURE(isa);
    const auto r = run_on(isa, dir / std::string(isa));
    REQUIRE(r.exit_code == 0);
    CHECK(nlohmann::json::parse(r.out)["batch"]["isa"] == isa);
    // The cells' flip times agree to round-off (each ISA's own sines; fused multiply-adds).
    const npy m = read_npy(dir / std::string(isa) / "map.npy");
    REQUIRE(m.values.size() == first.values.size());
    int differing = 0;
    for (std::size_t i = 0; i < m.values.size(); ++i) {
      const double a = m.values[i], b = first.values[i];
      const bool same = std::isnan(a)   ? std::isnan(b)
                        : std::isinf(a) ? a == b
                                        : std::fabs(a - b) <= 1e-7 * std::max(1.0, std::fabs(a));
      differing += same ? 0 : 1;
    }
    CHECK(differing == 0);
  }
  const auto refused = run_on("neon", dir / "neon");
  CHECK(refused.exit_code == 2);
  CHECK(refused.out.empty());
  CHECK(refused.err.find("npend map: error: NPEND_LANE_ISA: the maps' lanes run on one of") == 0);
  CHECK(refused.err.find("not 'neon'") != std::string::npos);
  CHECK_FALSE(fs::exists(dir / "neon"));
}
