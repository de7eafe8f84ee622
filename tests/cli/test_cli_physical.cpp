// The physical chain's options on the command line: what eval prints for a rod pendulum
// against its closed form, simulate's energy report on a damped chain, and which commands
// refuse what.
#include <doctest/doctest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "support/test_support.hpp"

using npend::test::run_npend;

TEST_CASE("npend eval: a damped uniform rod on a shaken pivot, against its closed form") {
  // m = 1, l = 1: I = J + m c^2 = 1/12 + 1/4 = 1/3. phi' = p / I, and
  // p' = -m c (g - a_y(t)) sin phi - b phi', a_y = A W^2 cos(W t) for the vertical drive.
  const double phi = 1.0, p = 0.5, b = 0.2, A = 0.1, W = 10, t = 0.3;
  const auto r = run_npend(
      "eval --links 1 --rods --damping 0.2 --pivot vertical:0.1:10 --time 0.3 --state 1,0.5 "
      "--json");
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  const double rate = p / (1.0 / 3);
  const double a_y = A * W * W * std::cos(W * t);
  CHECK(j["rhs"][0].get<double>() == doctest::Approx(rate).epsilon(1e-14));
  CHECK(j["rhs"][1].get<double>() ==
        doctest::Approx(-0.5 * (9.81 - a_y) * std::sin(phi) - b * rate).epsilon(1e-13));
  // d(p')/dp = -b / I, and df/dt = (d p'/d a_y) * d a_y/dt.
  CHECK(j["jacobian"][1][1].get<double>() == doctest::Approx(-b * 3).epsilon(1e-14));
  const double jerk = -A * W * W * W * std::sin(W * t);
  CHECK(j["time_derivative"][1].get<double>() ==
        doctest::Approx(0.5 * std::sin(phi) * jerk).epsilon(1e-13));
  CHECK(j["com"][0].get<double>() == 0.5);
  CHECK(j["inertia"][0].get<double>() == doctest::Approx(1.0 / 12));
  CHECK(j["pivot"] == "vertical:0.1:10");
  CHECK_FALSE(j.contains("hamiltonian_closed_form"));
}

TEST_CASE("npend simulate: a damped chain's energy is reported as changing, not as an error") {
  const auto r = run_npend(
      "simulate --links 2 --rods --damping 0.3 --phi 1,1 --t-end 5 --stepper gauss6 --json");
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  CHECK(j["energy_conserved"] == false);
  CHECK(j["max_rel_energy_error"].is_null());
  CHECK(j["energy_final"].get<double>() < j["energy_initial"].get<double>());
  CHECK(r.err.find("not symplectic") != std::string::npos);
}

TEST_CASE("npend: commands refuse the physical features their premise excludes") {
  CHECK(npend::test::is_input_error(
      run_npend("lyapunov --links 2 --damping 0.1 --phi 1,1 --t-end 10"),
      "does not take --damping"));
  CHECK(npend::test::is_input_error(
      run_npend("spectrum --links 2 --pivot horizontal:0.1:5 --phi 1,1"), "does not take --pivot"));
  CHECK(npend::test::is_input_error(run_npend("modes --links 2 --stiffness 3"),
                                    "does not take --stiffness"));
  // Rigid links keep the equilibria at 0 and pi: the uniform rod's frequency is
  // sqrt(m g c / I) = sqrt(3 g / 2).
  const auto r = run_npend("modes --links 1 --rods --json");
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  CHECK(j["frequencies"][0].get<double>() == doctest::Approx(std::sqrt(1.5 * 9.81)).epsilon(1e-12));
}

TEST_CASE("npend floquet: --json keys, Kapitza's verdict and the scan's stable window") {
  // One link, a = 0.05 m: Kapitza's leading order puts the threshold at sqrt(2 g l)/a = 88.6.
  const auto below = run_npend("floquet --links 1 --pivot vertical:0.05:60 --at pi --json");
  const auto above = run_npend("floquet --links 1 --pivot vertical:0.05:130 --at pi --json");
  REQUIRE(below.exit_code == 0);
  REQUIRE(above.exit_code == 0);
  const auto jb = nlohmann::json::parse(below.out), ja = nlohmann::json::parse(above.out);
  CHECK(jb["stable"] == false);
  CHECK(ja["stable"] == true);
  CHECK(ja["period"].get<double>() == doctest::Approx(2 * 3.141592653589793 / 130));
  REQUIRE(ja["multipliers"].size() == 2);
  CHECK(ja["multipliers"][0].size() == 2);  // [re, im]
  const double re = ja["multipliers"][0][0], im = ja["multipliers"][0][1];
  CHECK(std::hypot(re, im) == doctest::Approx(1.0).epsilon(1e-9));  // on the unit circle

  const auto scan = run_npend("floquet --links 1 --pivot vertical:0.05:1 --scan 60:130:15 --json");
  REQUIRE(scan.exit_code == 0);
  const auto js = nlohmann::json::parse(scan.out);
  REQUIRE(js["stable_windows"].size() == 1);
  CHECK(js["stable_windows"][0][0].get<double>() == 90.0);  // the first grid point above 88.6
  CHECK(js["stable_windows"][0][1].get<double>() == 130.0);

  CHECK(npend::test::is_input_error(run_npend("floquet --links 1 --at pi"),
                                    "needs a periodic drive"));
  CHECK(npend::test::is_input_error(
      run_npend("floquet --links 2 --pivot vertical:0.1:50 --at 1,2,3"), "--at: expected 2"));
}

TEST_CASE("npend floquet --stepper taylor: Kapitza's verdicts, the run's record, and refusals") {
  const auto below = run_npend(
      "floquet --links 1 --pivot vertical:0.05:60 --at pi --stepper taylor --tol 1e-12 --json");
  const auto above =
      run_npend("floquet --links 1 --pivot vertical:0.05:130 --stepper taylor --json");
  REQUIRE(below.exit_code == 0);
  REQUIRE(above.exit_code == 0);
  const auto jb = nlohmann::json::parse(below.out), ja = nlohmann::json::parse(above.out);
  CHECK(jb["stable"] == false);
  CHECK(ja["stable"] == true);
  CHECK(jb["stepper"] == "taylor");
  CHECK(jb["tolerance"].get<double>() == 1e-12);
  CHECK(ja["tolerance"].get<double>() == 1e-13);  // the default
  CHECK(ja["steps"].get<int>() > 0);
  // The same multiplier as gauss6's, within both error estimates.
  const auto gauss = nlohmann::json::parse(
      run_npend("floquet --links 1 --pivot vertical:0.05:60 --at pi --json").out);
  CHECK(gauss["stepper"] == "gauss6");
  CHECK(gauss["steps"].get<int>() == 400);
  CHECK(std::fabs(jb["max_modulus"].get<double>() - gauss["max_modulus"].get<double>()) <=
        jb["modulus_error"].get<double>() + gauss["modulus_error"].get<double>());
  const auto text = run_npend("floquet --links 1 --pivot vertical:0.05:130 --stepper taylor");
  REQUIRE(text.exit_code == 0);
  CHECK(text.out.find("Taylor steps at tolerance 1e-13") != std::string::npos);
  CHECK(text.out.find("(the change from tolerance 1e-11, and rounding)") != std::string::npos);

  const std::string driven = "floquet --links 1 --pivot vertical:0.05:60 ";
  CHECK(npend::test::is_input_error(run_npend(driven + "--stepper rk4"),
                                    "--stepper: Floquet analysis integrates with gauss6, taylor, "
                                    "not rk4"));
  CHECK(npend::test::is_input_error(run_npend(driven + "--stepper euler"),
                                    "--stepper: unknown stepper 'euler'"));
  CHECK(npend::test::is_input_error(run_npend(driven + "--tol 1e-12"),
                                    "--tol: only with --stepper taylor (gauss6 takes --steps)"));
  CHECK(npend::test::is_input_error(run_npend(driven + "--stepper taylor --steps 800"),
                                    "--steps: taylor chooses its own steps"));
  CHECK(npend::test::is_input_error(run_npend(driven + "--stepper taylor --tol 1e-3"),
                                    "--tol: must lie in (0, 1e-6]"));
  CHECK(npend::test::is_input_error(run_npend(driven + "--stepper taylor --tol zero"), "--tol"));
}

TEST_CASE("npend control: the standing triple pendulum's LQR design, and simulate under it") {
  const auto r = run_npend("control --links 3 --at pi --json");
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  CHECK(j["controllable"] == true);
  REQUIRE(j["gain"].size() == 3);  // one row per motor
  CHECK(j["gain"][0].size() == 6);
  REQUIRE(j["closed_loop_eigenvalues"].size() == 6);
  for (const auto& l : j["closed_loop_eigenvalues"]) CHECK(l[0].get<double>() < 0);
  CHECK(j["open_loop_eigenvalues"][0][0].get<double>() > 0);  // unstable without control
  CHECK(j["riccati_residual"].get<double>() < 1e-13);

  const auto single = run_npend("control --links 3 --at pi --actuated 1 --json");
  REQUIRE(single.exit_code == 0);
  CHECK(nlohmann::json::parse(single.out)["gain"].size() == 1);

  // Started 0.1 rad off every angle, the nonlinear chain returns upright.
  const auto sim = run_npend(
      "simulate --links 3 --phi 3.2416,3.2416,3.2416 --controller lqr --at pi --t-end 20 --json");
  REQUIRE(sim.exit_code == 0);
  const auto js = nlohmann::json::parse(sim.out);
  CHECK(js["final_deviation"].get<double>() < 1e-6);
  CHECK(js["energy_conserved"] == false);

  CHECK(
      npend::test::is_input_error(run_npend("control --links 2 --at 1,pi"), "not an equilibrium"));
  CHECK(npend::test::is_input_error(
      run_npend("simulate --links 2 --phi 3,3 --t-end 1 --controller pid --at pi"),
      "the one controller is lqr"));
  CHECK(npend::test::is_input_error(run_npend("simulate --links 2 --phi 3,3 --t-end 1 --at pi"),
                                    "go with --controller lqr"));
  CHECK(npend::test::is_input_error(run_npend("control --links 2 --at pi --actuated 3"),
                                    "--actuated: 3 is not a joint 1..2"));
}

TEST_CASE("npend --chain FILE.json: the file's chain, with command-line options over it") {
  const std::string dir = npend::test::temporary_directory("chain-file");
  const std::string file = dir + "/lab.json";
  {
    std::ofstream out(file);
    out << R"({"links": 2, "masses": [1, 2], "lengths": 0.5, "rods": true, "damping": 0.3,
              "pivot": "horizontal:0.01:20"})";
  }
  const auto r = run_npend("eval --links 2 --chain " + file + " --state 0.1,0.2,0,0 --json");
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  CHECK(j["masses"][1].get<double>() == 2.0);
  CHECK(j["lengths"][0].get<double>() == 0.5);
  CHECK(j["com"][0].get<double>() == 0.25);
  CHECK(j["inertia"][1].get<double>() == doctest::Approx(2 * 0.25 / 12));
  CHECK(j["damping"][1].get<double>() == 0.3);
  CHECK(j["pivot"] == "horizontal:0.01:20");
  // The same chain from flags gives the same numbers; a flag overrides the file.
  const auto flags = run_npend(
      "eval --links 2 --masses 1,2 --lengths 0.5 --rods --damping 0.3 --pivot horizontal:0.01:20 "
      "--state 0.1,0.2,0,0 --json");
  CHECK(nlohmann::json::parse(flags.out)["rhs"] == j["rhs"]);
  const auto over =
      run_npend("eval --links 2 --chain " + file + " --damping 0 --state 0.1,0.2,0,0 --json");
  CHECK(nlohmann::json::parse(over.out)["damping"][0].get<double>() == 0.0);
  CHECK(npend::test::is_input_error(
      run_npend("eval --links 3 --chain " + file + " --state 0,0,0,0,0,0"),
      "the file describes 2 links"));
  CHECK(npend::test::is_input_error(
      run_npend("eval --links 2 --chain " + dir + "/missing.json --state 0,0,0,0"), "cannot read"));
}

TEST_CASE("npend --chain FILE.json: a chain on a cart, as --cart and --cart-damping give it") {
  const std::string dir = npend::test::temporary_directory("cart-file");
  const std::string file = dir + "/cart.json";
  {
    std::ofstream out(file);
    out << R"({"links": 2, "rods": true, "cart": 1.5, "cart_damping": 0.2})";
  }
  const std::string state = " --state 0.1,0.3,-0.2,0.4,0.5,-0.1 --json";
  const auto r = run_npend("eval --links 2 --chain " + file + state);
  REQUIRE(r.exit_code == 0);
  const auto flags = run_npend("eval --links 2 --rods --cart 1.5 --cart-damping 0.2" + state);
  REQUIRE(flags.exit_code == 0);
  CHECK(nlohmann::json::parse(r.out)["rhs"] == nlohmann::json::parse(flags.out)["rhs"]);
  // The command line's --cart overrides the file's mass; a command on a fixed pivot refuses
  // the file's cart as it refuses --cart.
  const auto over = run_npend("eval --links 2 --chain " + file + " --cart 3" + state);
  const auto heavier = run_npend("eval --links 2 --rods --cart 3 --cart-damping 0.2" + state);
  CHECK(nlohmann::json::parse(over.out)["rhs"] == nlohmann::json::parse(heavier.out)["rhs"]);
  CHECK(npend::test::is_input_error(run_npend("modes --links 2 --chain " + file),
                                    "npend modes does not take --cart"));
}

TEST_CASE("npend floquet: a slowly unstable damped orbit is unstable, with its error") {
  // Overdamped inverted link: max |mu| - 1 = m g l T / b = 4.93e-7, under the old fixed
  // tolerance of 1e-6 but far above the integration's error.
  const auto r =
      run_npend("floquet --links 1 --lengths 0.2 --pivot vertical:0.01:250 --damping 1e5 --json");
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  CHECK(j["verdict"] == "unstable");
  CHECK(j["stable"] == false);
  const double excess = j["max_modulus"].get<double>() - 1;
  CHECK(excess == doctest::Approx(1.962e-5 * 2 * 3.141592653589793 / 250).epsilon(1e-2));
  CHECK(j["modulus_error"].get<double>() < 1e-2 * excess);
  const auto text =
      run_npend("floquet --links 1 --lengths 0.2 --pivot vertical:0.01:250 --damping 1e5");
  REQUIRE(text.exit_code == 0);
  CHECK(text.out.find("unstable: max |mu| = ") != std::string::npos);
}

TEST_CASE("npend eval: a single pendulum on a cart against its closed form") {
  // m = M = l = 1 at rest at φ = 0.3: T = ½(M + m)ẋ² + m l cos φ ẋφ̇ + ½ m l² φ̇², so
  // A = [[M + m, m l cos φ], [m l cos φ, m l²]]; ṗ_x = 0 (no force), ṗ_φ = −m g l sin φ.
  const double phi = 0.3, g = 9.81;
  const auto r = run_npend("eval --links 1 --cart 1 --state 0,0.3,0,0 --json");
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  REQUIRE(j["rhs"].size() == 4);
  CHECK(j["rhs"][0].get<double>() == 0.0);
  CHECK(j["rhs"][1].get<double>() == 0.0);
  CHECK(std::fabs(j["rhs"][2].get<double>()) < 1e-15);
  CHECK(j["rhs"][3].get<double>() == doctest::Approx(-g * std::sin(phi)).epsilon(1e-14));
  CHECK(j["mass_matrix"][0][0].get<double>() == doctest::Approx(2.0).epsilon(1e-15));
  CHECK(j["mass_matrix"][0][1].get<double>() == doctest::Approx(std::cos(phi)).epsilon(1e-15));
  CHECK(j["mass_matrix"][1][1].get<double>() == doctest::Approx(1.0).epsilon(1e-15));
  CHECK(j["hamiltonian"].get<double>() == doctest::Approx(g * (1 - std::cos(phi))).epsilon(1e-14));
  CHECK(j["cart_mass"].get<double>() == 1.0);
  // w = [F, u_1]: F drives ṗ_x, u_1 drives ṗ_φ.
  CHECK(j["input_matrix"][2] == nlohmann::json::array({1.0, 0.0}));
  CHECK(j["input_matrix"][3] == nlohmann::json::array({0.0, 1.0}));
}

TEST_CASE("npend control: the double inverted pendulum on a cart, pushed at the cart") {
  const auto r = run_npend("control --links 2 --cart 1 --at pi --actuated cart --json");
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  CHECK(j["controllable"] == true);
  CHECK(j["actuated"] == nlohmann::json::array({"cart"}));
  REQUIRE(j["gain"].size() == 1);
  CHECK(j["gain"][0].size() == 6);
  // The force enters the cart's momentum alone.
  for (int i = 0; i < 6; ++i) CHECK(j["B"][i][0].get<double>() == (i == 3 ? 1.0 : 0.0));
  REQUIRE(j["closed_loop_eigenvalues"].size() == 6);
  for (const auto& l : j["closed_loop_eigenvalues"]) CHECK(l[0].get<double>() < 0);
  CHECK(j["open_loop_eigenvalues"][0][0].get<double>() > 0);

  CHECK(npend::test::is_input_error(run_npend("control --links 2 --cart 1 --at pi --actuated 3"),
                                    "--actuated: 3 is not a joint 1..2 or cart"));
}

TEST_CASE("npend simulate: the triple pendulum on a cart held upright by LQR") {
  // Started 0.05 rad off every angle with the cart at rest at 0, it returns to upright and
  // the cart to x_c = 0.
  const auto r = run_npend(
      "simulate --links 3 --cart 2 --controller lqr --at pi --phi 3.1916 --t-end 30 --json");
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  REQUIRE(j["final_state"].size() == 8);
  CHECK(j["final_deviation"].get<double>() < 1e-6);
  CHECK(j["cart_mass"].get<double>() == 2.0);
}

TEST_CASE("npend: the cart's options and the commands that refuse a cart") {
  CHECK(npend::test::is_input_error(run_npend("eval --links 1 --cart 0 --state 0,0,0,0"),
                                    "--cart: the cart's mass must be a positive finite number"));
  CHECK(npend::test::is_input_error(
      run_npend("eval --links 1 --cart 1 --cart-damping -1 --state 0,0,0,0"),
      "--cart-damping: the cart's damping must be a finite number >= 0"));
  CHECK(npend::test::is_input_error(run_npend("eval --links 1 --cart-damping 1 --state 0,0"),
                                    "--cart-damping: the cart's damping needs a cart"));
  CHECK(npend::test::is_input_error(
      run_npend("eval --links 1 --cart 1 --pivot vertical:0.1:10 --state 0,0,0,0"),
      "--cart and --pivot exclude each other"));
  CHECK(npend::test::is_input_error(run_npend("eval --links 1 --cart 1 --state 0,0"),
                                    "x_c, phi_1..phi_1, p_x, p_1..p_1"));
  CHECK(npend::test::is_input_error(run_npend("equilibria --links 2 --cart 1"),
                                    "npend equilibria does not take --cart"));
  CHECK(npend::test::is_input_error(run_npend("modes --links 2 --cart 1"),
                                    "npend modes does not take --cart"));
}
