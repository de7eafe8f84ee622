// npend equilibria / modes / toda-brumer as a user runs them.
#include <doctest/doctest.h>

#include <nlohmann/json.hpp>
#include <numbers>

#include "npend/analysis/stability/equilibria.hpp"
#include "npend/analysis/stability/normal_modes.hpp"
#include "support/test_support.hpp"

using npend::test::run_npend;

TEST_CASE("npend equilibria: --json lists the 2^n equilibria with the library's values") {
  const auto r = run_npend("equilibria --links 3 --masses 1,2,3 --json");
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  REQUIRE(j["equilibria"].size() == 8);
  const auto& standing = j["equilibria"][7];
  for (const auto& a : standing["angles"]) CHECK(a.get<double>() == std::numbers::pi);
  CHECK(standing["stable"] == false);
  CHECK(standing["unstable_directions"] == 3);
  CHECK(standing["eigenvalues"].size() == 6);
  CHECK(standing["eigenvalues"][0].size() == 2);  // [re, im]
  CHECK(j["equilibria"][0]["stable"] == true);
  CHECK(j["equilibria"][0]["energy"].get<double>() == 0.0);
  // V at the standing position: 2 g Σ μ_j l_j = 2·9.81·(6 + 5 + 3).
  CHECK(standing["energy"].get<double>() == doctest::Approx(2 * 9.81 * 14).epsilon(1e-14));
}

TEST_CASE("npend modes: --json frequencies ascending, shapes, and the --at equilibrium") {
  const auto r = run_npend("modes --links 3 --json");
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  const auto lin = npend::normal_modes(npend::chain(npend::chain_parameters::uniform(3)),
                                       std::vector<double>{0, 0, 0});
  REQUIRE(j["frequencies"].size() == 3);
  for (std::size_t k = 0; k < 3; ++k)
    CHECK(j["frequencies"][k].get<double>() == lin.modes[k].frequency);
  CHECK(j["shapes"].size() == 3);
  // The standing double pendulum has no oscillating mode: two growth rates.
  const auto top = nlohmann::json::parse(
      run_npend("modes --links 2 --at 3.141592653589793,3.141592653589793 --json").out);
  CHECK(top["frequencies"].empty());
  CHECK(top["growth_rates"].size() == 2);
  const auto bad = run_npend("modes --links 2 --at 0,1");
  CHECK(bad.exit_code == 2);
  CHECK(bad.err.find("--at: angles are not an equilibrium") != std::string::npos);
}

TEST_CASE("npend toda-brumer: the paper's critical energy and the unstable region") {
  const auto r = run_npend(
      "toda-brumer --links 3 --masses 1,1,2 --lengths 1,1,0.5 --fixed 1,2 --phi 0,0,2 --json");
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  CHECK(j["critical_energy"].get<double>() == doctest::Approx(2 * 9.81 * 0.5).epsilon(1e-14));
  CHECK(j["unstable"] == true);
  CHECK(j["per_link"].size() == 3);
  const auto all_fixed = run_npend("toda-brumer --links 2 --fixed 1,2");
  CHECK(all_fixed.exit_code == 2);
  CHECK(all_fixed.err.find("every link is fixed") != std::string::npos);
  const auto out_of_range = run_npend("toda-brumer --links 2 --fixed 3");
  CHECK(out_of_range.exit_code == 2);
  CHECK(out_of_range.err.find("--fixed: 3 is not a link number 1..2") != std::string::npos);
}
