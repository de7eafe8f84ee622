// npend orbit on a driven pivot: the forced orbit, its continuation in the drive frequency
// (Kapitza's branch of the inverted pendulum, checked against npend floquet and the Mathieu
// equation), its files and its bad input.
#include <doctest/doctest.h>
#include <fmt/format.h>

#include <cmath>
#include <complex>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>
#include <vector>

#include "support/test_support.hpp"

using npend::test::run_npend;

namespace {

std::vector<std::complex<double>> forced_cli_multipliers(const nlohmann::json& list) {
  std::vector<std::complex<double>> out;
  for (const auto& m : list) out.emplace_back(m[0].get<double>(), m[1].get<double>());
  return out;
}

}  // namespace

TEST_CASE("npend orbit: Kapitza's branch over the drive frequency agrees with npend floquet") {
  const auto r = run_npend(
      "orbit --links 1 --pivot vertical:0.05:60 --phi 3.141592653589793 --continue-to 130 "
      "--json");
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  CHECK(j["end_reason"] == "reached frequency_end");
  CHECK(j["periods"] == 1);
  const auto& points = j["points"];
  REQUIRE(points.size() >= 20);
  // The upright orbit's multipliers at a few frequencies, against npend floquet's there.
  for (const std::size_t i : {std::size_t{0}, std::size_t{6}, std::size_t{14}, points.size() - 1}) {
    const auto& p = points[i];
    const double w = p["frequency"].get<double>();
    CAPTURE(w);
    CHECK(p["closure"].get<double>() <= 1e-11);
    const auto f =
        run_npend(fmt::format("floquet --links 1 --pivot vertical:0.05:{:.17g} --at pi --json", w));
    REQUIRE(f.exit_code == 0);
    const auto fj = nlohmann::json::parse(f.out);
    const auto ours = forced_cli_multipliers(p["multipliers"]);
    const auto theirs = forced_cli_multipliers(fj["multipliers"]);
    REQUIRE(ours.size() == 2);
    REQUIRE(theirs.size() == 2);
    const double direct = std::abs(ours[0] - theirs[0]) + std::abs(ours[1] - theirs[1]);
    const double swapped = std::abs(ours[0] - theirs[1]) + std::abs(ours[1] - theirs[0]);
    CHECK(std::min(direct, swapped) <= 1e-9 * (1 + p["max_multiplier"].get<double>()));
  }
  // One change: Kapitza's threshold, on the Mathieu transition curve
  // g/(lΩ²) = ε²/2 − 7ε⁴/32 + 29ε⁶/144 (ε = a/l = 0.05).
  REQUIRE(j["changes"].size() == 1);
  const auto& k = j["changes"][0];
  CHECK(k["kind"] == "branch point");
  CHECK(k["stable_above"] == true);
  const double e2 = 0.05 * 0.05;
  const double mathieu = std::sqrt(9.81 / (e2 / 2 - 7 * e2 * e2 / 32 + 29 * e2 * e2 * e2 / 144));
  CHECK(std::fabs(k["frequency"].get<double>() / mathieu - 1) <= 5e-8);
  CHECK(k["a_omega"].get<double>() == doctest::Approx(0.05 * k["frequency"].get<double>()));
}

TEST_CASE("npend orbit: the forced swing of a double pendulum, --periods and --out") {
  const auto one = run_npend("orbit --links 2 --pivot horizontal:0.15:1.5 --phi 0,0 --json");
  REQUIRE(one.exit_code == 0);
  const auto j = nlohmann::json::parse(one.out);
  const auto& orbit = j["orbit"];
  CHECK(orbit["closure"].get<double>() <= 1e-11);
  CHECK(orbit["period"].get<double>() ==
        doctest::Approx(2 * std::numbers::pi / 1.5).epsilon(1e-15));
  CHECK(orbit["amplitudes"][1].get<double>() > 0.05);  // swings with the drive
  CHECK(orbit["multipliers"].size() == 4);
  CHECK(orbit["stable"] == true);
  const auto two =
      run_npend("orbit --links 2 --pivot horizontal:0.15:1.5 --phi 0,0 --periods 2 --json");
  REQUIRE(two.exit_code == 0);
  const auto j2 = nlohmann::json::parse(two.out);
  CHECK(j2["periods"] == 2);
  CHECK(j2["orbit"]["period"].get<double>() ==
        doctest::Approx(2 * orbit["period"].get<double>()).epsilon(1e-15));
  CHECK(j2["orbit"]["x0"][0].get<double>() ==
        doctest::Approx(orbit["x0"][0].get<double>()).epsilon(1e-9));
  const auto text = run_npend("orbit --links 2 --pivot horizontal:0.15:1.5 --phi 0,0");
  REQUIRE(text.exit_code == 0);
  CHECK(text.out.find("Forced orbit of the 2-link chain, pivot horizontal:0.15:1.5") == 0);

  const auto dir = std::filesystem::path(npend::test::temporary_directory("cli-forced-orbit"));
  const auto branch = run_npend(
      "orbit --links 1 --pivot vertical:0.05:100 --phi 3.141592653589793 "
      "--continue-to 80 --out " +
      (dir / "kapitza.csv").string());
  REQUIRE(branch.exit_code == 0);
  CHECK(branch.out.find("branch point at Omega = 88.63731") != std::string::npos);
  CHECK(std::filesystem::exists(dir / "kapitza.csv"));
  CHECK(std::filesystem::exists(dir / "kapitza_changes.csv"));
  CHECK(std::filesystem::exists(dir / "kapitza.gp"));
  std::ifstream csv(dir / "kapitza.csv");
  std::string header;
  std::getline(csv, header);
  CHECK(header == "omega,a_omega,period,amplitude_phi1,max_multiplier,stable,closure,iterations");
}

TEST_CASE("npend orbit: bad input on a driven pivot exits 2 naming the problem") {
  using npend::test::is_input_error;
  const std::string base = "orbit --links 1 --pivot vertical:0.05:100 --phi 3.141592653589793";
  CHECK(is_input_error(run_npend(base + " --damping 0.1"), "damping is excluded"));
  CHECK(is_input_error(run_npend(base + " --period 1"), "--period: not with a driven pivot"));
  CHECK(is_input_error(run_npend(base + " --phase poincare"), "--phase: not with a driven pivot"));
  CHECK(is_input_error(run_npend(base + " --periods 0"), "--periods"));
  CHECK(is_input_error(run_npend(base + " --continue-to -5"), "--continue-to"));
  CHECK(is_input_error(run_npend(base + " --continue-to 100"), "equals the chain's drive"));
  CHECK(is_input_error(run_npend(base + " --out x.csv"), "--out: only with --continue-to"));
  CHECK(is_input_error(run_npend("orbit --links 1 --phi 0.3 --period 2 --periods 2"),
                       "--periods: only with a driven pivot"));
  CHECK(is_input_error(run_npend(base + " --winding 1"), "--winding: not with a driven pivot"));
  CHECK(is_input_error(run_npend(base + " --segments 4"), "--segments: not with a driven pivot"));
  CHECK(is_input_error(run_npend(base + " --stepper rk4"),
                       "--stepper: the shooting integrates with gauss6, taylor, not rk4"));
  CHECK(is_input_error(run_npend(base + " --tol 1e-12"),
                       "--tol: only with --stepper taylor (gauss6 takes --steps)"));
  CHECK(is_input_error(run_npend(base + " --stepper taylor --steps 800"),
                       "--steps: taylor chooses its own steps"));
  CHECK(is_input_error(run_npend(base + " --stepper taylor --tol 1e-4"),
                       "--tol: must lie in (0, 1e-6], got 1e-4"));
}

TEST_CASE("npend orbit --stepper taylor: the forced swing is gauss6's, and the run says how") {
  const std::string swing = "orbit --links 2 --pivot horizontal:0.15:2 --phi 0 --json";
  const auto t = run_npend(swing + " --stepper taylor --tol 1e-13");
  const auto g = run_npend(swing + " --steps 1600");
  REQUIRE(t.exit_code == 0);
  REQUIRE(g.exit_code == 0);
  const auto jt = nlohmann::json::parse(t.out), jg = nlohmann::json::parse(g.out);
  CHECK(jt["stepper"] == "taylor");
  CHECK(jt["integration_tolerance"].get<double>() == 1e-13);
  // The Taylor steps of the last pass: a dozen or so per drive period.
  CHECK(jt["steps"].get<int>() > 0);
  CHECK(jt["steps"].get<int>() < 100);
  CHECK(jg["stepper"] == "gauss6");
  CHECK(jg["steps"].get<int>() == 1600);
  const auto& xt = jt["orbit"]["x0"];
  const auto& xg = jg["orbit"]["x0"];
  REQUIRE(xt.size() == 4);
  for (std::size_t i = 0; i < 4; ++i)
    CHECK(std::fabs(xt[i].get<double>() - xg[i].get<double>()) <= 1e-9);
  const auto text = run_npend("orbit --links 2 --pivot horizontal:0.15:2 --phi 0 --stepper taylor");
  REQUIRE(text.exit_code == 0);
  CHECK(text.out.find("taylor at tolerance 1e-14, ") != std::string::npos);
  CHECK(text.out.find(" steps over T)") != std::string::npos);
}
