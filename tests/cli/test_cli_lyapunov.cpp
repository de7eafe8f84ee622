// `npend lyapunov` as a user runs it: the JSON keys against the library, --maximal, the
// running values and their plot, bad input, and the progress bar and Ctrl-C on a terminal.
#include <doctest/doctest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "npend/analysis/chaos/lyapunov.hpp"
#include "npend/excitation.hpp"
#include "support/test_signals.hpp"
#include "support/test_support.hpp"

using npend::test::run_npend;

TEST_CASE("npend lyapunov: --json exponents, sum, pairs and convergence are the library's") {
  const auto r = run_npend(
      "lyapunov --links 3 --masses 1,2,1 --energy 30 --t-end 40 --dt 0.01 --transient 5 --json");
  REQUIRE(r.exit_code == 0);
  CHECK(r.err.empty());  // no progress bar off a terminal
  const auto j = nlohmann::json::parse(r.out);

  const npend::chain c(npend::chain_parameters{{1, 2, 1}, {1, 1, 1}, 9.81});
  const auto x0 = npend::deflected_state(c, 30);
  npend::lyapunov_options o;
  o.integration.t_end = 40;
  o.integration.dt = 0.01;
  o.transient = 5;
  const auto lib = npend::lyapunov_spectrum(c, x0, o);
  CHECK(j["exponents"].get<std::vector<double>>() == lib.exponents);
  CHECK(j["maximal_exponent"].get<double>() == lib.exponents[0]);
  CHECK(j["sum"].get<double>() == lib.sum);
  CHECK(j["spread"].get<std::vector<double>>() == lib.spread);
  CHECK(j["initial_state"].get<std::vector<double>>() == x0);
  CHECK(j["energy"].get<double>() == doctest::Approx(30).epsilon(1e-12));
  REQUIRE(j["pair_sums"].size() == 3);
  for (std::size_t i = 0; i < 3; ++i)
    CHECK(j["pair_sums"][i].get<double>() == lib.exponents[i] + lib.exponents[5 - i]);
  CHECK(j["t_end"].get<double>() == doctest::Approx(40));
  CHECK(j["transient"].get<double>() == doctest::Approx(5));
  CHECK(j["convergence_window"].get<double>() == doctest::Approx(0.25 * 35));
  CHECK(j["renormalisations"].get<std::size_t>() == 350);
  CHECK(j["stepper"] == "gauss6");
  CHECK(j["method"] == "tangent map");
  CHECK(j["renormalisation_interval"].get<double>() == doctest::Approx(0.1));
  CHECK(j["max_rel_energy_error"].get<double>() < 1e-8);
}

TEST_CASE(
    "npend lyapunov --cart: the spectrum of the pendulum on a cart, paired and summing to 0") {
  // Hamilton's flow on the cart's 6-dimensional phase space preserves volume and the
  // symplectic form: the exponents sum to 0 and pair as lambda_i = -lambda_(7-i) (to the
  // Gauss-Legendre integrator's round-off); the cart's position is cyclic, so the direction
  // of its momentum does not stretch, and a chaotic start has a positive largest exponent.
  const auto r = run_npend("lyapunov --links 2 --cart 1 --phi 1.5,1.5 --t-end 30 --json");
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  const auto exponents = j["exponents"].get<std::vector<double>>();
  REQUIRE(exponents.size() == 6);
  CHECK(j["initial_state"].size() == 6);
  CHECK(std::fabs(j["sum"].get<double>()) < 1e-10);
  for (const auto& pair : j["pair_sums"]) CHECK(std::fabs(pair.get<double>()) < 1e-6);
  CHECK(exponents.front() > 0.3);
  CHECK(j["max_rel_energy_error"].get<double>() < 1e-10);
  const auto damped = run_npend("lyapunov --links 2 --cart 1 --cart-damping 0.1 --t-end 1");
  CHECK(damped.exit_code == 2);
  CHECK(damped.err.find("--cart-damping") != std::string::npos);
}

TEST_CASE("npend lyapunov: --maximal, another stepper, and the readable table") {
  const auto m = run_npend(
      "lyapunov --links 2 --phi 2,-1 --t-end 30 --dt 0.01 --stepper dopri5 --rel-tol 1e-9 "
      "--renormalise-every 0.5 --maximal --json");
  REQUIRE(m.exit_code == 0);
  const auto j = nlohmann::json::parse(m.out);
  CHECK(j["exponents"].size() == 1);
  CHECK(j["maximal_exponent"] == j["exponents"][0]);
  CHECK_FALSE(j.contains("sum"));
  CHECK(j["method"] == "variational equations");
  CHECK(j["renormalisation_interval"].get<double>() == doctest::Approx(0.5));

  // taylor: the Taylor series of the variational equations, the library's numbers.
  const auto t = run_npend(
      "lyapunov --links 2 --phi 2,-1 --t-end 10 --dt 0.01 --stepper taylor --abs-tol 1e-12 "
      "--rel-tol 1e-12 --json");
  REQUIRE(t.exit_code == 0);
  const auto tj = nlohmann::json::parse(t.out);
  CHECK(tj["method"] == "Taylor series of the variational equations");
  npend::lyapunov_options o;
  o.integration.t_end = 10;
  o.integration.dt = 0.01;
  o.integration.stepper = npend::stepper_kind::taylor;
  o.integration.abs_tol = o.integration.rel_tol = 1e-12;
  const auto library = npend::lyapunov_spectrum(npend::chain(npend::chain_parameters::uniform(2)),
                                                std::vector<double>{2, -1, 0, 0}, o);
  CHECK(tj["exponents"].get<std::vector<double>>() == library.exponents);

  const auto table = run_npend("lyapunov --links 2 --phi 2,-1 --t-end 10 --dt 0.01");
  REQUIRE(table.exit_code == 0);
  for (const char* text : {"Lyapunov spectrum of the 2-link chain", "lambda_i (1/s)",
                           "spread (last 2.5 s)", "sum = ", "pairs lambda_i", "max |H - H0|"})
    CHECK_MESSAGE(table.out.find(text) != std::string::npos, text);
}

TEST_CASE("npend lyapunov: --out writes the running values and their plot") {
  const auto dir = std::filesystem::path(npend::test::temporary_directory("cli-lyapunov"));
  const auto r = run_npend("lyapunov --links 2 --phi 1,1 --t-end 20 --dt 0.01 --json --out " +
                           (dir / "run.csv").string());
  REQUIRE(r.exit_code == 0);
  CHECK(npend::test::directory_listing(dir.string()) ==
        std::vector<std::string>{"run.csv", "run.gp", "run.png"});
  std::ifstream in(dir / "run.csv");
  std::string header, line, last;
  std::getline(in, header);
  CHECK(header == "t,lambda_1,lambda_2,lambda_3,lambda_4");
  while (std::getline(in, line)) last = line;
  const auto j = nlohmann::json::parse(r.out);
  CHECK(last.rfind("20,", 0) == 0);
  CHECK(j["files"].size() == 3);
}

TEST_CASE("npend lyapunov: bad input gets a one-line message naming the problem, exit status 2") {
  const std::vector<std::pair<std::string, std::string>> cases{
      {"lyapunov --links 3 --t-end 10", "no start state"},
      {"lyapunov --links 3 --phi 1,1,1 --t-end 10 --stepper rosenbrock4", "--stepper: rosenbrock4"},
      {"lyapunov --links 3 --phi 1,1,1 --t-end 10 --transient 10",
       "--transient: 10 s leaves no time"},
      {"lyapunov --links 3 --phi 1,1,1 --t-end 10 --transient 9.95 --renormalise-every 1",
       "leaves no time to average"},
      {"lyapunov --links 3 --phi 1,1,1 --t-end 10 --renormalise-every 0",
       "--renormalise-every: must be positive"},
      {"lyapunov --links 3 --phi 1,1,1 --t-end 10 --convergence-fraction 2",
       "--convergence-fraction: must be in (0, 1]"},
      {"lyapunov --links 3 --phi 1,1,1 --t-end 10 --out x.txt", "--out"},
      {"lyapunov --links 3 --phi 1,1 --t-end 10", "--phi"},
  };
  for (const auto& [args, message] : cases) {
    CAPTURE(args);
    const auto r = run_npend(args);
    INFO(r.err);
    CHECK(npend::test::is_input_error(r, message));
  }
}

TEST_CASE("npend lyapunov: a progress bar on a terminal, and Ctrl-C stops the run") {
  const std::string run = "timeout --preserve-status -s INT 2 " + std::string(NPEND_CLI_PATH) +
                          " lyapunov --links 6 --energy 50 --t-end 100000";
  // `script` runs the command on a pseudo-terminal and copies what it shows to stdout.
  const auto on_terminal = npend::test::run_shell("script -qec '" + run + "' /dev/null");
  INFO(on_terminal.out);
  CHECK(on_terminal.out.find("s left") != std::string::npos);
  CHECK(on_terminal.out.find("npend lyapunov: interrupted at t = ") != std::string::npos);
}

TEST_CASE("npend lyapunov: the uncertainty is a block standard error, or an ensemble's") {
  const auto r = run_npend("lyapunov --links 3 --energy 14.7 --t-end 50 --dt 0.01 --json");
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  CHECK(j["uncertainty_method"] == "block standard error");
  CHECK(j["blocks"]["count"] == 10);
  CHECK(j["uncertainty"].get<double>() == j["standard_errors"][0].get<double>());
  CHECK(j["blocks"]["exponents"].size() == 10);

  const auto e = run_npend(
      "lyapunov --links 3 --phi 0.72,-0.72,0.72 --t-end 50 --dt 0.01 --maximal --ensemble 3 "
      "--json");
  REQUIRE(e.exit_code == 0);
  const auto k = nlohmann::json::parse(e.out);
  CHECK(k["uncertainty_method"] == "ensemble standard error");
  CHECK(k["ensemble"]["members"] == 3);
  CHECK(k["ensemble"]["starts"].size() == 3);
  CHECK(k["maximal_exponent"].get<double>() == k["ensemble"]["mean"][0].get<double>());
  CHECK(k["uncertainty"].get<double>() == k["ensemble"]["standard_error"][0].get<double>());

  const auto text = run_npend("lyapunov --links 2 --phi 2,-1 --t-end 20 --dt 0.01");
  REQUIRE(text.exit_code == 0);
  CHECK(text.out.find("+- is the standard error from 10 blocks of 2 s") != std::string::npos);
}

TEST_CASE("npend lyapunov --input: the maximal exponent of a measured series, with its curve") {
  const auto dir = std::filesystem::path(npend::test::temporary_directory("cli-lyapunov-series"));
  const std::string trajectory = (dir / "weak.csv").string();
  REQUIRE(
      run_npend("simulate --links 3 --phi 0.2,-0.2,0.2 --t-end 300 --dt 0.01 --out " + trajectory)
          .exit_code == 0);
  const auto r = run_npend("lyapunov --input " + trajectory + " --column x_3 --json --out " +
                           (dir / "s.csv").string());
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  CHECK(j["method"] == "Kantz");
  CHECK(j["signal"] == "x_3");
  CHECK(j["dt"].get<double>() == doctest::Approx(0.01));
  // Regular motion: no stretching.
  CHECK(std::fabs(j["maximal_exponent"].get<double>()) < 0.02);
  CHECK(j["uncertainty"].get<double>() >= 0);
  CHECK(j["curve"]["t"].size() == j["curve"]["s"][0].size());
  CHECK(j["fit_range_method"] == "automatic");
  CHECK(npend::test::directory_listing(dir.string()) ==
        std::vector<std::string>{"s.csv", "s.gp", "s.png", "weak.csv"});

  const auto given = run_npend("lyapunov --input " + trajectory +
                               " --column x_3 --tau 0.5 --dim 4 --fit 2:10 --json");
  REQUIRE(given.exit_code == 0);
  const auto g = nlohmann::json::parse(given.out);
  CHECK(g["fit_range_method"] == "given");
  CHECK(g["fit_range"][1].get<double>() == 10);
  CHECK(g["dimension"] == 4);
  CHECK(g["tau"].get<double>() == doctest::Approx(0.5));
}

TEST_CASE("npend lyapunov --input --column a,b: several observables embedded together") {
  // The Hénon map's whole state (x, y = b x_prev) as two columns: with the state itself as
  // the coordinates (--dim 1, the default for several columns) the neighbours are true ones
  // and the slope is the map's 0.419 per step.
  const auto dir = std::filesystem::path(npend::test::temporary_directory("cli-lyapunov-mv"));
  const std::vector<double> x = npend::test::henon_x(20001);
  const std::string data = (dir / "henon.csv").string();
  {
    std::ofstream out(data);
    out << "x y\n";
    out.precision(17);
    for (std::size_t n = 1; n < x.size(); ++n) out << x[n] << ' ' << 0.3 * x[n - 1] << '\n';
  }
  const auto r = run_npend("lyapunov --input " + data + " --dt 1 --column x,y --horizon 12 --json");
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  CHECK(j["columns"] == std::vector<std::string>{"x", "y"});
  CHECK(j["dimension"] == 1);
  CHECK(j["linear_region"] == true);
  CAPTURE(j["maximal_exponent"].get<double>());
  CAPTURE(j["uncertainty"].get<double>());
  CHECK(std::fabs(j["maximal_exponent"].get<double>() - 0.41922) <=
        3 * j["uncertainty"].get<double>());
  CHECK(npend::test::is_input_error(run_npend("lyapunov --input " + data + " --dt 1 --column x,,y"),
                                    "--column: an empty name in 'x,,y'"));
  CHECK(npend::test::is_input_error(run_npend("lyapunov --input " + data + " --dt 1 --column x,z"),
                                    "--column"));
}

TEST_CASE("npend lyapunov --input: no linear region, no exponent (null) and the reason") {
  // A chaotic motion seen through one coordinate with too short a delay window: the
  // neighbours separate at once and saturate, and the command says so instead of a slope.
  const auto dir = std::filesystem::path(npend::test::temporary_directory("cli-lyapunov-nolin"));
  const std::string trajectory = (dir / "strong.csv").string();
  REQUIRE(
      run_npend("simulate --links 3 --phi 1.5,1.5,1.5 --t-end 1000 --dt 0.01 --out " + trajectory)
          .exit_code == 0);
  const auto r = run_npend("lyapunov --input " + trajectory + " --column x_3 --json");
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  CHECK(j["linear_region"] == false);
  CHECK(j["maximal_exponent"].is_null());
  CHECK(j["uncertainty"].is_null());
  CHECK(j["fit_slope"].is_number());
  REQUIRE(!j["warnings"].empty());
  CHECK(j["warnings"][0].get<std::string>().find("no estimate: ") == 0);
  const auto text = run_npend("lyapunov --input " + trajectory + " --column x_3");
  REQUIRE(text.exit_code == 0);
  CHECK(text.out.find("no estimate of the maximal exponent") != std::string::npos);
}

TEST_CASE("npend lyapunov --input --fit: a given range is judged as the automatic one") {
  // The chaotic start of the test above: its x3 curve rises steeply within the embedding
  // window (5 tau) and saturates there, so no range of it is linear. A range given inside
  // that window looked straight enough to the bend test alone (0:3 s gave 0.31 +- 0.12 /s
  // as a linear region, while the equations give a maximal exponent near 1.5 /s).
  const auto dir = std::filesystem::path(npend::test::temporary_directory("cli-lyapunov-fit"));
  const std::string trajectory = (dir / "strong.csv").string();
  REQUIRE(
      run_npend("simulate --links 3 --phi 1.5,1.5,1.5 --t-end 1000 --dt 0.01 --out " + trajectory)
          .exit_code == 0);
  const auto r = run_npend("lyapunov --input " + trajectory + " --column x_3 --fit 0:3 --json");
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  CHECK(j["fit_range_method"] == "given");
  CHECK(j["linear_region"] == false);
  CHECK(j["maximal_exponent"].is_null());
  REQUIRE(!j["warnings"].empty());
  CHECK(j["warnings"][0].get<std::string>().find("no estimate: ") == 0);
}

TEST_CASE("npend lyapunov: SIGTERM stops a long chain inside a re-orthonormalisation interval") {
  // One interval of 50 s (50000 rk4 steps of 1000 links, tens of seconds): the run used to poll
  // for a stop only between intervals, so SIGTERM after 3 s went unheeded until the end (exit 0).
  const auto start = std::chrono::steady_clock::now();
  const auto r = npend::test::run_shell(
      "{ timeout --preserve-status -s TERM 3 " + std::string(NPEND_CLI_PATH) +
      " lyapunov --links 1000 --phi 0.1 --t-end 50 --maximal --stepper rk4 "
      "--renormalise-every 50; echo \"exit $?\"; }");
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  INFO(r.out, r.err);
  CHECK(r.out.find("exit 143") != std::string::npos);
  CHECK(r.err.find("npend lyapunov: interrupted at t = ") == 0);
  CHECK(seconds < 8);
}
