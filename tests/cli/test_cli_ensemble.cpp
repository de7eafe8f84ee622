// npend rope and npend partition as a user runs them: their JSON against the library, and
// the files of --out.
#include <doctest/doctest.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "npend/analysis/stability/hanging_chain.hpp"
#include "npend/analysis/statistical/partition_function.hpp"
#include "npend/chain.hpp"
#include "support/test_support.hpp"

namespace fs = std::filesystem;
using npend::test::run_npend;

TEST_CASE("npend partition: --json carries the library's numbers under the documented keys") {
  const auto r = run_npend("partition --links 2 --masses 1,2 --temperature 3 --json");
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  npend::chain_parameters p;
  p.masses = {1.0, 2.0};
  p.lengths = {1.0, 1.0};
  const double t[] = {3.0};
  const auto expected = npend::canonical_ensemble(npend::chain(p), t).states[0];
  CHECK(j["rule"] == "trapezoid");
  CHECK(j["partition_function"].get<double>() == doctest::Approx(expected.partition_function));
  CHECK(j["free_energy"].get<double>() == doctest::Approx(expected.free_energy));
  CHECK(j["mean_energy"].get<double>() == doctest::Approx(expected.mean_energy));
  CHECK(j["heat_capacity"].get<double>() == doctest::Approx(expected.heat_capacity));
  CHECK(j["error_estimate"]["heat_capacity"].get<double>() < 1e-10);
  CHECK(j["mean_cos"].size() == 2);
}

TEST_CASE("npend partition: --scan --out writes the table and the plot") {
  const fs::path dir = npend::test::temporary_directory("cli-partition");
  const auto r = run_npend("partition --links 3 --scan 0.5:50:5 --grid 32 --json --out " +
                           (dir / "z.csv").string());
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  CHECK(j["states"].size() == 5);
  CHECK(j["states"][4]["temperature"].get<double>() == 50.0);
  CHECK(fs::exists(dir / "z.csv"));
  CHECK(fs::exists(dir / "z.gp"));
}

TEST_CASE("npend rope: --json holds each chain's frequencies and errors against the rope") {
  const auto r = run_npend("rope --links 10,40 --modes 3 --length 2 --json");
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  CHECK(j["rope_frequencies"][1].get<double>() ==
        doctest::Approx(npend::rope_frequency(2, 2.0, 9.81)));
  REQUIRE(j["chains"].size() == 2);
  const std::vector<double> masses(40, 1.0 / 40), lengths(40, 2.0 / 40);
  const auto modes = npend::hanging_chain_modes(masses, lengths, 9.81, 3);
  CHECK(j["chains"][1]["frequencies"][2].get<double>() == doctest::Approx(modes[2].frequency));
  CHECK(j["order"].size() == 3);
}

TEST_CASE("npend partition: low temperatures give the harmonic limit C = n, <E> = n T") {
  // Two links at T = 1e-4 J: the well is far narrower than the grid's spacing over the
  // circle (C came out 1, <E> = T, with no note); n momenta and n angles each add k/2.
  for (const char* t : {"1e-4", "1e-300"}) {
    const auto r = run_npend(std::string("partition --links 2 --json --temperature ") + t);
    REQUIRE(r.exit_code == 0);
    const auto j = nlohmann::json::parse(r.out);
    const double temperature = std::stod(t);
    CAPTURE(t);
    CHECK(j["heat_capacity"].get<double>() == doctest::Approx(2.0).epsilon(1e-4));
    CHECK(j["mean_energy"].get<double>() == doctest::Approx(2 * temperature).epsilon(1e-4));
    CHECK(r.err.empty());
  }
}
