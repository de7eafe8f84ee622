// `npend orbit --winding/--segments/--continue-to` and `npend orbits --segments/--continuation`
// as a user runs them: rotating orbits and their family against the single pendulum's closed
// form, multiple shooting on the double pendulum's unstable in-phase family, bad input.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "support/test_support.hpp"

using npend::test::run_npend;

namespace {

// One turn of a pendulum (mass m, length l) rotating with energy H over the hanging rest:
// 2κK(κ)/ω0, κ = √(2mgl/H).
double turn_period(double energy, double m, double l) {
  const double g = 9.81, kappa = std::sqrt(2 * m * g * l / energy);
  return 2 * kappa * std::comp_ellint_1(kappa) / std::sqrt(g / l);
}

}  // namespace

TEST_CASE("npend orbit --winding: a rotating single pendulum's period per turn, and its family") {
  // m = 1, l = 1: p = 8 at the bottom is H = 32 J, over the separatrix 2mgl = 19.62 J.
  const auto one = run_npend("orbit --links 1 --phi 0 --p 8 --period 0.6 --winding 1 --json");
  REQUIRE(one.exit_code == 0);
  const auto j = nlohmann::json::parse(one.out);
  CHECK(j["phase"] == "poincare");
  CHECK(j["orbit"]["winding"] == nlohmann::json::array({1}));
  CHECK(j["orbit"]["closure"].get<double>() <= 1e-11);
  CHECK(j["orbit"]["energy"].get<double>() == doctest::Approx(32.0).epsilon(1e-12));
  CHECK(std::fabs(j["orbit"]["period"].get<double>() / turn_period(32, 1, 1) - 1) <= 1e-10);

  const auto dir = std::filesystem::path(npend::test::temporary_directory("cli-family"));
  const auto family = run_npend(
      "orbit --links 1 --phi 0 --p 8 --period 0.6 --winding 1 --segments 4 "
      "--continue-to 19.7 --json --out " +
      (dir / "rot.csv").string());
  REQUIRE(family.exit_code == 0);
  const auto f = nlohmann::json::parse(family.out);
  CHECK(f["end_reason"] == "reached the end energy");
  REQUIRE(f["points"].size() > 3);
  CHECK(f["points"].back()["energy"].get<double>() == doctest::Approx(19.7).epsilon(1e-12));
  for (const auto& p : f["points"]) {
    const double energy = p["energy"].get<double>();
    CHECK(std::fabs(p["period"].get<double>() / turn_period(energy, 1, 1) - 1) <= 1e-10);
  }
  CHECK(npend::test::directory_listing(dir.string()) ==
        std::vector<std::string>{"rot.csv", "rot.gp", "rot.png"});
  std::ifstream csv(dir / "rot.csv");
  std::string header;
  std::getline(csv, header);
  CHECK(header ==
        "energy,period,frequency,amplitude_phi1,max_multiplier,stable,closure,iterations");
}

TEST_CASE("npend orbits --segments: the double pendulum's in-phase family past 56 J") {
  const auto r = run_npend(
      "orbits --links 2 --mode 1 --energy-max 56.5 --segments 8 --thresholds 0.01 --json");
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  CHECK(j["segments"] == 8);
  CHECK(j["continuation"] == "arclength");
  const auto& mode = j["modes"][0];
  CHECK(mode["end_reason"] == "reached energy_max");
  CHECK(mode["folds"].empty());
  const auto& top = mode["points"].back();
  CHECK(top["energy"].get<double>() == doctest::Approx(56.5).epsilon(1e-12));
  CHECK(top["closure"].get<double>() <= 1e-11);
  CHECK(top["max_multiplier"].get<double>() > 3e5);
  // One segment, stepping in the energy: the shooting loses the orbit before.
  const auto single = run_npend(
      "orbits --links 2 --mode 1 --energy-max 56.5 --continuation natural --thresholds 0.01 "
      "--json");
  REQUIRE(single.exit_code == 0);
  const auto s = nlohmann::json::parse(single.out);
  CHECK(s["modes"][0]["end_reason"].get<std::string>().find("stopped converging") !=
        std::string::npos);
}

TEST_CASE("npend orbit and orbits: bad winding, segments and continuation exit 2") {
  const std::string base = "orbit --links 2 --phi 0.3,0.4 --period 3";
  for (const std::string bad :
       {" --winding 1", " --winding 0.5,0", " --winding 1,0 --phase turning_point", " --segments 0",
        " --out x.csv", " --continue-to nan", " --periods 2"}) {
    CAPTURE(bad);
    const auto r = run_npend(base + bad);
    CHECK(r.exit_code == 2);
    CHECK(r.err.rfind("npend orbit: error: ", 0) == 0);
  }
  CHECK(run_npend("orbits --links 2 --energy-max 1 --continuation bogus").exit_code == 2);
  CHECK(run_npend("orbits --links 2 --energy-max 1 --segments 0").exit_code == 2);
}

TEST_CASE(
    "npend orbits --branches: the family born at the triple pendulum's third mode's branch point") {
  const auto dir = std::filesystem::path(npend::test::temporary_directory("cli-branches"));
  const auto r = run_npend(
      "orbits --links 3 --mode 3 --energy-max 6 --thresholds 0.01 --branches "
      "--json --out " +
      (dir / "nnm.csv").string());
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  const auto& change = j["modes"][0]["bifurcations"][0];
  CHECK(change["kind"] == "branch point");
  const auto& family = change["family"];
  CHECK(family["end_reason"] == "reached the end energy");
  REQUIRE(family["points"].size() > 5);
  // It leaves the old family at the bifurcation, with its period, and is stable there.
  const auto& first = family["points"][0];
  CHECK(first["energy"].get<double>() ==
        doctest::Approx(change["energy"].get<double>()).epsilon(1e-3));
  CHECK(first["period"].get<double>() ==
        doctest::Approx(change["stable_side"]["period"].get<double>()).epsilon(1e-5));
  CHECK(first["stable"] == true);
  for (const auto& p : family["points"]) CHECK(p["closure"].get<double>() <= 1e-11);
  CHECK(family["points"].back()["energy"].get<double>() == doctest::Approx(6.0).epsilon(1e-12));
  std::ifstream csv(dir / "nnm_families.csv");
  std::string header;
  std::getline(csv, header);
  CHECK(header == "mode,bifurcation_energy,energy,period,frequency,max_multiplier,stable");
}
