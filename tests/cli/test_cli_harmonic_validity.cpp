// `npend backbone` and `npend corrections` as a user runs them: the JSON against the library
// and the single pendulum's exact frequency, the files and plots, bad input.
#include <doctest/doctest.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>

#include "npend/analysis/stability/backbone.hpp"
#include "npend/analysis/stability/harmonic_corrections.hpp"
#include "support/test_support.hpp"

using npend::test::run_npend;

TEST_CASE(
    "npend backbone: --json for the single pendulum, with the elliptic integral's frequency") {
  const auto r = run_npend("backbone --links 1 --lengths 2 --amplitudes 0.5:2.5:0.5 --json");
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  REQUIRE(j["modes"].size() == 1);
  const auto& mode = j["modes"][0];
  const double omega0 = std::sqrt(9.81 / 2);
  CHECK(mode["linear_frequency"].get<double>() == doctest::Approx(omega0).epsilon(1e-14));
  REQUIRE(mode["points"].size() == 5);
  for (const auto& p : mode["points"]) {
    const double a = p["amplitude"].get<double>();
    const double exact = omega0 * std::numbers::pi / (2 * std::comp_ellint_1(std::sin(a / 2)));
    CHECK(p["frequency"].get<double>() == doctest::Approx(exact).epsilon(1e-9));
    CHECK(p["exact_frequency"].get<double>() == doctest::Approx(exact).epsilon(1e-15));
    CHECK(p["measured"] == true);
  }
  REQUIRE(mode["thresholds"].size() == 2);
  CHECK(mode["thresholds"][0]["shift"].get<double>() == 0.01);
  CHECK(mode["thresholds"][0]["amplitude"].get<double>() == doctest::Approx(0.4).epsilon(0.01));
  CHECK(j["periods"].get<double>() == 20);
}

TEST_CASE("npend backbone: one mode of a chain agrees with the library, --out writes the plot") {
  const auto dir = std::filesystem::path(npend::test::temporary_directory("cli-backbone"));
  const auto r = run_npend(
      "backbone --links 2 --mode 2 --amplitudes 0.1,0.3 --periods 10 "
      "--thresholds 0.02 --json --out " +
      (dir / "bb.csv").string());
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  const npend::chain c(npend::chain_parameters::uniform(2));
  npend::backbone_options o;
  o.periods = 10;
  o.thresholds = {0.02};
  const auto lib = npend::backbone_curve(c, 2, std::vector<double>{0.1, 0.3}, o);
  REQUIRE(j["modes"].size() == 1);
  CHECK(j["modes"][0]["mode"] == 2);
  CHECK(j["modes"][0]["points"][1]["frequency"].get<double>() == lib.points[1].frequency);
  CHECK(j["modes"][0]["thresholds"][0]["amplitude"].get<double>() == *lib.thresholds[0].amplitude);
  CHECK_FALSE(j["modes"][0]["points"][0].contains("exact_frequency"));
  CHECK(npend::test::directory_listing(dir.string()) ==
        std::vector<std::string>{"bb.csv", "bb.gp", "bb.png", "bb_thresholds.csv"});
}

TEST_CASE("npend corrections: --json is the library's study, --out writes the plot") {
  const auto dir = std::filesystem::path(npend::test::temporary_directory("cli-corrections"));
  const auto r = run_npend(
      "corrections --links 2 --phi 0.2,-0.1 --dphi 0.5,1 --horizon 0.3 "
      "--samples 101 --json --out " +
      (dir / "c.csv").string());
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  // The command turns --dphi into momenta and back (as every start option does): the start it
  // reports is --dphi to round-off, and the library's study from that start is the same.
  const auto dphi0 = j["dphi0"].get<std::vector<double>>();
  CHECK(dphi0[0] == doctest::Approx(0.5).epsilon(1e-15));
  CHECK(dphi0[1] == doctest::Approx(1).epsilon(1e-15));
  CHECK(j["phi0"].get<std::vector<double>>() == std::vector<double>{0.2, -0.1});
  npend::correction_study_options o;
  o.horizon = 0.3;
  o.samples = 101;
  const auto lib = npend::harmonic_correction_study(
      npend::chain(npend::chain_parameters::uniform(2)), std::vector<double>{0.2, -0.1}, dphi0, o);
  CHECK(j["horizon"].get<double>() == 0.3);
  CHECK(j["samples"] == 101);
  REQUIRE(j["tracks"].size() == lib.tracks.size());
  for (std::size_t k = 0; k < lib.tracks.size(); ++k) {
    CHECK(j["tracks"][k]["name"] == lib.tracks[k].name);
    CHECK(j["tracks"][k]["max_error"].get<double>() == lib.tracks[k].max_error);
    CHECK(j["tracks"][k]["order"].get<double>() == lib.tracks[k].order);
    CHECK(j["tracks"][k]["q_pole"].get<double>() == lib.tracks[k].q_pole);
  }
  REQUIRE(j["acceleration_defects"].size() == 3);
  CHECK(j["acceleration_defects"][1]["truncation"] == "paper");
  CHECK(npend::test::directory_listing(dir.string()) ==
        std::vector<std::string>{"c.csv", "c.gp", "c.png"});
}

TEST_CASE("npend backbone and corrections: bad input gets a one-line message, exit status 2") {
  const std::vector<std::pair<std::string, std::string>> cases{
      {"backbone --links 2 --mode 3", "--mode: must be a whole number 1..2, got 3"},
      {"backbone --links 2 --amplitudes 0.1,4", "--amplitudes: 4 rad is not in (0, pi)"},
      {"backbone --links 2 --amplitudes 1:0.5:0.1", "FROM <= TO"},
      {"backbone --links 2 --amplitudes 0.1:0.5", "neither a list"},
      {"backbone --links 2 --periods 2", "--periods: must be in 3..1e5"},
      {"backbone --links 2 --steps-per-period 10", "--steps-per-period"},
      {"backbone --links 2 --thresholds 0.01,1", "--thresholds: 1 is not"},
      {"corrections --links 1", "at least 2 links"},
      {"corrections --links 2 --phi 0,0", "at rest"},
      {"corrections --links 2 --phi 0.1,0 --amplitude 0.2", "--amplitude: only for the default"},
      {"corrections --links 2 --amplitude 2", "--amplitude: must be in (0, 1.5)"},
      {"corrections --links 2 --horizon -1", "--horizon: must be positive"},
      {"corrections --links 2 --samples 1", "--samples"},
  };
  for (const auto& [args, message] : cases) {
    CAPTURE(args);
    const auto r = run_npend(args);
    INFO(r.err);
    CHECK(npend::test::is_input_error(r, message));
  }
}

TEST_CASE("npend orbits: the single pendulum's branch and its 1 % departure from K(k)") {
  const double l = 2, g = 9.81, m = 1;
  const double top = 2.5;  // rad
  const auto r = run_npend(fmt::format("orbits --links 1 --lengths {} --energy-max {} --json", l,
                                       m * g * l * (1 - std::cos(top))));
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  REQUIRE(j["modes"].size() == 1);
  const auto& mode = j["modes"][0];
  const double omega0 = std::sqrt(g / l);
  CHECK(mode["linear_frequency"].get<double>() == doctest::Approx(omega0).epsilon(1e-14));
  CHECK(mode["end_reason"] == "reached energy_max");
  REQUIRE(mode["points"].size() > 5);
  for (const auto& p : mode["points"]) {
    const double a = p["amplitudes"][0].get<double>();
    const double exact = omega0 * std::numbers::pi / (2 * std::comp_ellint_1(std::sin(a / 2)));
    CHECK(std::fabs(p["frequency"].get<double>() / exact - 1) <= 1e-10);
    CHECK(p["closure"].get<double>() <= 1e-11);
    CHECK(p["stable"] == true);
  }
  // Where ω/ω0 = 0.99 and 0.95, by bisection on the closed form.
  REQUIRE(mode["departures"].size() == 2);
  for (const auto& d : mode["departures"]) {
    const double shift = d["shift"].get<double>();
    double lo = 0.01, hi = top;
    for (int k = 0; k < 200; ++k) {
      const double mid = (lo + hi) / 2;
      (std::numbers::pi / (2 * std::comp_ellint_1(std::sin(mid / 2))) > 1 - shift ? lo : hi) = mid;
    }
    CAPTURE(shift);
    CHECK(d["orbit"]["amplitudes"][0].get<double>() == doctest::Approx(lo).epsilon(1e-8));
    CHECK(d["orbit"]["energy"].get<double>() ==
          doctest::Approx(m * g * l * (1 - std::cos(lo))).epsilon(1e-8));
  }
}

TEST_CASE("npend orbits: --out writes the branch, the departures and the plot, bad input") {
  const auto dir = std::filesystem::path(npend::test::temporary_directory("cli-orbits"));
  const auto r =
      run_npend("orbits --links 2 --mode 2 --energy-max 1 --out " + (dir / "nnm.csv").string());
  REQUIRE(r.exit_code == 0);
  CHECK(r.out.find("1 % departure from omega_2: E = ") != std::string::npos);
  CHECK(npend::test::directory_listing(dir.string()) ==
        std::vector<std::string>{"nnm.csv", "nnm.gp", "nnm.png", "nnm_bifurcations.csv",
                                 "nnm_departures.csv"});
  // Equal masses and lengths: the first orbit's frequency is ω_2 = √((g/l)(2 + √2)) to the
  // first point's small amplitude (0.01 rad: a relative shift of order 1e-5).
  std::ifstream csv(dir / "nnm.csv");
  std::string header, first;
  std::getline(csv, header);
  std::getline(csv, first);
  CHECK(header.rfind("mode,energy,period,frequency,ratio,amplitude_phi1,amplitude_phi2,", 0) == 0);
  const double omega2 = std::sqrt(9.81 * (2 + std::sqrt(2.0)));
  const double frequency = std::stod(first.substr(first.find(',', first.find(',', 2) + 1) + 1));
  CHECK(frequency == doctest::Approx(omega2).epsilon(1e-4));
  const auto damped = run_npend("orbits --links 2 --damping 0.1 --energy-max 1");
  CHECK(damped.exit_code == 2);
  CHECK(run_npend("orbits --links 2").exit_code == 2);
  CHECK(run_npend("orbits --links 2 --mode 3 --energy-max 1").exit_code == 2);
}

TEST_CASE("npend orbit: one orbit of the single pendulum at 4K(k)/ω0, no orbit near a bad guess") {
  const auto r =
      run_npend("orbit --links 1 --lengths 0.5 --phi 2.5 --period 1.8 --steps 2000 --json");
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  const double exact = 4 * std::comp_ellint_1(std::sin(1.25)) / std::sqrt(9.81 / 0.5);
  CHECK(std::fabs(j["orbit"]["period"].get<double>() / exact - 1) <= 1e-10);
  CHECK(j["orbit"]["closure"].get<double>() <= 1e-11);
  CHECK(j["orbit"]["x0"][0].get<double>() == doctest::Approx(2.5).epsilon(1e-12));
  const auto far = run_npend("orbit --links 2 --phi 0.3,0.42 --period 0.1");
  CHECK(far.exit_code == 1);
  CHECK(far.err.find("npend orbit: error: the shooting did not converge") == 0);
  CHECK(run_npend("orbit --links 2 --damping 0.1 --phi 0.3,0.4 --period 3").exit_code == 2);
  CHECK(run_npend("orbit --links 2 --phi 0.3,0.4").exit_code == 2);
  CHECK(run_npend("orbit --links 2 --phi 0.3,0.4 --period 3 --phase diagonal").exit_code == 2);
}

TEST_CASE("npend orbit and orbits --stepper taylor: the flow's period, and the run says how") {
  // gauss6 at 2000 steps above: 1e-10 of 4K(k)/ω0; Taylor's orbit is the flow's.
  const auto r = run_npend(
      "orbit --links 1 --lengths 0.5 --phi 2.5 --period 1.8 --stepper taylor --tol 1e-15 --json");
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  const double exact = 4 * std::comp_ellint_1(std::sin(1.25)) / std::sqrt(9.81 / 0.5);
  CHECK(std::fabs(j["orbit"]["period"].get<double>() / exact - 1) <= 1e-12);
  CHECK(j["stepper"] == "taylor");
  CHECK(j["integration_tolerance"].get<double>() == 1e-15);
  CHECK(j["steps"].get<int>() > 0);
  CHECK(j["steps"].get<int>() < 200);
  const auto text =
      run_npend("orbit --links 1 --lengths 0.5 --phi 2.5 --period 1.8 --stepper taylor");
  REQUIRE(text.exit_code == 0);
  CHECK(text.out.find("taylor at tolerance 1e-14, ") != std::string::npos);
  const auto family = run_npend(
      "orbits --links 1 --lengths 0.5 --energy-max 2 --stepper taylor --tol 1e-13 --json");
  REQUIRE(family.exit_code == 0);
  const auto f = nlohmann::json::parse(family.out);
  CHECK(f["stepper"] == "taylor");
  CHECK(f["integration_tolerance"].get<double>() == 1e-13);
  CHECK_FALSE(f.contains("steps"));
  const auto& points = f["modes"][0]["points"];
  REQUIRE(points.size() > 3);
  for (const auto& p : points) {
    const double phi0 = std::fabs(p["x0"][0].get<double>());
    const double period = 4 * std::comp_ellint_1(std::sin(phi0 / 2)) / std::sqrt(9.81 / 0.5);
    CHECK(std::fabs(p["period"].get<double>() / period - 1) <= 1e-9);
  }
  using npend::test::is_input_error;
  CHECK(is_input_error(run_npend("orbits --links 1 --energy-max 1 --stepper taylor --tol 1e-3"),
                       "--tol: must lie in (0, 1e-6], got 1e-3"));
  CHECK(is_input_error(run_npend("orbits --links 1 --energy-max 1 --stepper rk4"),
                       "--stepper: the shooting integrates with gauss6, taylor, not rk4"));
  CHECK(is_input_error(run_npend("orbit --links 1 --phi 0.3 --period 2 --tol 1e-12"),
                       "--tol: only with --stepper taylor (gauss6 takes --steps)"));
  CHECK(
      is_input_error(run_npend("orbit --links 1 --phi 0.3 --period 2 --stepper taylor --steps 90"),
                     "--steps: taylor chooses its own steps"));
}
