// The commands on chains without unrolled kernels (the loop kernels), as a user runs them on
// a rope: one value for all links, the K largest Lyapunov exponents, chosen equilibria.
#include <doctest/doctest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <numbers>

#include "support/test_support.hpp"

using npend::test::run_npend;

TEST_CASE("npend simulate: a 100-link chain runs on the loop kernels and keeps its energy") {
  const auto r = run_npend(
      "simulate --links 100 --masses 0.01 --lengths 0.01 --phi 0.5 --t-end 0.5 --stepper dopri5 "
      "--abs-tol 1e-11 --rel-tol 1e-11 --every 100 --json");
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  CHECK(j["max_rel_energy_error"].get<double>() < 1e-8);
  // E = V at rest: g Σ μ_k l_k (1 − cos 0.5), Σ μ_k l_k = 1e-4 Σ_{j=1}^{100} j.
  const double energy = 9.81 * 1e-4 * 5050 * (1 - std::cos(0.5));
  CHECK(std::fabs(j["energy_initial"].get<double>() - energy) < 1e-12 * energy);
}

TEST_CASE("npend simulate: one --phi, --p or --dphi value stands for every link") {
  const auto one = run_npend("simulate --links 3 --phi 0.5 --dphi 0.1 --t-end 0.1 --dt 0.01");
  const auto all =
      run_npend("simulate --links 3 --phi 0.5,0.5,0.5 --dphi 0.1,0.1,0.1 --t-end 0.1 --dt 0.01");
  REQUIRE(one.exit_code == 0);
  CHECK(one.out == all.out);
}

TEST_CASE("npend lyapunov --exponents K: the K largest, as the first K of the spectrum") {
  const std::string start =
      "lyapunov --links 3 --phi 1.2,1.5,1.8 --t-end 20 --stepper rk4 --dt 0.002 --json";
  const auto full = run_npend(start);
  const auto two = run_npend(start + " --exponents 2");
  REQUIRE(full.exit_code == 0);
  REQUIRE(two.exit_code == 0);
  const auto f = nlohmann::json::parse(full.out), t = nlohmann::json::parse(two.out);
  REQUIRE(t["exponents"].size() == 2);
  // Gram–Schmidt is triangular: the first K tangent vectors never see the others.
  for (int i = 0; i < 2; ++i)
    CHECK(std::fabs(t["exponents"][i].get<double>() - f["exponents"][i].get<double>()) <
          1e-9 * std::fabs(f["exponents"][0].get<double>()));
  CHECK(f["exponents"][0].get<double>() > 0.1);  // a chaotic start, so the check means something
  CHECK_FALSE(t.contains("pair_sums"));
  CHECK(npend::test::is_input_error(run_npend(start + " --exponents 7"),
                                    "--exponents: must be a whole number 1..6, got 7"));
  CHECK(npend::test::is_input_error(run_npend(start + " --exponents 2 --maximal"),
                                    "give --exponents K or --maximal, not both"));
}

TEST_CASE("npend equilibria: a long chain lists the hanging and standing ones, or those asked") {
  const auto r = run_npend("equilibria --links 20 --masses 0.05 --lengths 0.05 --json");
  REQUIRE(r.exit_code == 0);
  const auto eq = nlohmann::json::parse(r.out)["equilibria"];
  REQUIRE(eq.size() == 2);
  CHECK(eq[0]["stable"] == true);
  CHECK(eq[1]["unstable_directions"] == 20);
  // Standing: V = 2 g Σ μ_k l_k = 2 · 9.81 · 0.05 · 0.05 · (1 + … + 20).
  const double standing = 2 * 9.81 * 0.0025 * 210;
  CHECK(std::fabs(eq[1]["energy"].get<double>() - standing) < 1e-12 * standing);
  const auto chosen = run_npend("equilibria --links 4 --at 0,pi,0,pi --at pi --json");
  REQUIRE(chosen.exit_code == 0);
  const auto two = nlohmann::json::parse(chosen.out)["equilibria"];
  REQUIRE(two.size() == 2);
  CHECK(two[0]["angles"][1].get<double>() == std::numbers::pi);
  CHECK(two[1]["unstable_directions"] == 4);
  CHECK(npend::test::is_input_error(run_npend("equilibria --links 3 --at 0,1,0"),
                                    "--at: angles are not an equilibrium"));
}
