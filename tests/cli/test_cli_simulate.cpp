// `npend simulate` as a user runs it: the CSV, the JSON summary, the start options, each bad
// input's message and exit status, and no partial file after a failure or an interrupt.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "npend/excitation.hpp"
#include "npend/integrators/integrate.hpp"
#include "support/test_support.hpp"

using npend::test::run_npend;

namespace {

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

std::vector<double> numbers(const std::string& line) {
  std::vector<double> out;
  std::istringstream in(line);
  for (std::string item; std::getline(in, item, ',');) out.push_back(std::stod(item));
  return out;
}

std::vector<std::string> files_in(const std::string& dir) {
  std::vector<std::string> out;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    out.push_back(e.path().filename().string());
  return out;
}

}  // namespace

TEST_CASE("npend simulate: CSV header, one row per output step, H and bob positions of each row") {
  const auto r =
      run_npend("simulate --links 3 --phi 0.3,-0.2,0.5 --p 0.1,0.2,-0.1 --t-end 0.1 --dt 0.01");
  REQUIRE(r.exit_code == 0);
  CHECK(r.err.empty());
  const auto rows = lines(r.out);
  REQUIRE(rows.size() == 12);
  CHECK(rows[0] == "t,phi_1,phi_2,phi_3,p_1,p_2,p_3,H,x_1,y_1,x_2,y_2,x_3,y_3");
  const npend::chain c(npend::chain_parameters::uniform(3));
  for (std::size_t k = 1; k < rows.size(); ++k) {
    const auto v = numbers(rows[k]);
    REQUIRE(v.size() == 14);
    CHECK(v[0] == doctest::Approx(0.01 * static_cast<double>(k - 1)).epsilon(1e-15));
    const std::vector<double> x(v.begin() + 1, v.begin() + 7);
    // The numbers read back exactly: H and the positions are those of the printed state.
    CHECK(v[7] == c.hamiltonian(x));
    std::vector<double> xy(6);
    c.positions(std::span(x).first(3), xy);
    CHECK(std::vector<double>(v.begin() + 8, v.end()) == xy);
  }
  CHECK(numbers(rows[1])[1] == 0.3);
  CHECK(numbers(rows[1])[6] == -0.1);
}

TEST_CASE("npend simulate: --out and --json, the summary agrees with the CSV and the library") {
  const std::string dir = npend::test::temporary_directory("simulate-json");
  const std::string path = dir + "/traj.csv";
  const auto r = run_npend(
      "simulate --links 2 --masses 1,2 --lengths 1,0.5 --phi 1.2,-0.4 --t-end 2 "
      "--dt 0.01 --stepper dopri5 --abs-tol 1e-9 --rel-tol 1e-8 --json --out " +
      path);
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  for (const char* key :
       {"steps", "t_end", "energy_initial", "energy_final", "max_rel_energy_error", "stepper",
        "outputs", "rows", "initial_state", "final_state", "dt", "out"})
    CHECK_MESSAGE(j.contains(key), key);
  CHECK(j["stepper"] == "dopri5");
  CHECK(j["t_end"].get<double>() == 2.0);
  CHECK(j["outputs"] == 201);
  CHECK(j["rows"] == 201);
  CHECK(j["out"] == path);
  CHECK(files_in(dir) == std::vector<std::string>{"traj.csv"});

  // The same run through the library.
  const npend::chain c(npend::chain_parameters{{1, 2}, {1, 0.5}, 9.81});
  npend::integration_options o;
  o.stepper = npend::stepper_kind::dopri5;
  o.t_end = 2;
  o.dt = 0.01;
  o.abs_tol = 1e-9;
  o.rel_tol = 1e-8;
  const std::vector<double> x0{1.2, -0.4, 0, 0};
  const auto result = npend::integrate(c, x0, o);
  CHECK(j["steps"] == result.steps);
  CHECK(j["final_state"].get<std::vector<double>>() == result.state);
  CHECK(j["energy_initial"].get<double>() == c.hamiltonian(x0));
  CHECK(j["energy_final"].get<double>() == c.hamiltonian(result.state));

  // The CSV's last row is the final state; the largest energy error is the CSV's.
  const auto rows = lines(npend::test::read_text(path));
  REQUIRE(rows.size() == 202);
  const auto last = numbers(rows.back());
  CHECK(std::vector<double>(last.begin() + 1, last.begin() + 5) == result.state);
  double worst = 0;
  for (std::size_t k = 1; k < rows.size(); ++k)
    worst = std::max(worst, std::fabs(numbers(rows[k])[5] - c.hamiltonian(x0)) / c.hamiltonian(x0));
  CHECK(j["max_rel_energy_error"].get<double>() == worst);
}

TEST_CASE("npend simulate: --tol sets both tolerances, as the library's run with them says") {
  const auto r = run_npend(
      "simulate --links 3 --phi 1.5,1.5,1.5 --t-end 2 --dt 0.5 --stepper taylor --tol 1e-13 "
      "--json");
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  const npend::chain c(npend::chain_parameters::uniform(3));
  npend::integration_options o;
  o.stepper = npend::stepper_kind::taylor;
  o.t_end = 2;
  o.dt = 0.5;
  o.abs_tol = 1e-13;
  o.rel_tol = 1e-13;
  const auto result = npend::integrate(c, std::vector<double>{1.5, 1.5, 1.5, 0, 0, 0}, o);
  CHECK(j["steps"] == result.steps);
  CHECK(j["final_state"].get<std::vector<double>>() == result.state);
  // A tolerance 1000 times looser takes other steps: --tol reached the stepper.
  o.abs_tol = o.rel_tol = 1e-10;
  CHECK(j["steps"] != npend::integrate(c, std::vector<double>{1.5, 1.5, 1.5, 0, 0, 0}, o).steps);
}

TEST_CASE("npend simulate: --tensions adds tau_i, the weight below each rod at rest") {
  const auto r = run_npend(
      "simulate --links 3 --masses 1,2,0.5 --phi 0,0,0 --t-end 0.01 "
      "--dt 0.01 --tensions");
  REQUIRE(r.exit_code == 0);
  std::istringstream lines(r.out);
  std::string header, first;
  std::getline(lines, header);
  std::getline(lines, first);
  CHECK(header.ends_with(",y_3,tau_1,tau_2,tau_3"));
  std::vector<double> values;
  std::istringstream cells(first);
  for (std::string cell; std::getline(cells, cell, ',');) values.push_back(std::stod(cell));
  REQUIRE(values.size() == 1 + 6 + 1 + 6 + 3);
  const double g = 9.81;
  CHECK(values[14] == doctest::Approx(3.5 * g).epsilon(1e-12));
  CHECK(values[15] == doctest::Approx(2.5 * g).epsilon(1e-12));
  CHECK(values[16] == doctest::Approx(0.5 * g).epsilon(1e-12));
}

TEST_CASE("npend simulate: --every thins the CSV, --json alone writes no CSV") {
  const std::string dir = npend::test::temporary_directory("simulate-every");
  const auto r =
      run_npend("simulate --links 2 --phi 0.5,0.5 --t-end 1 --dt 0.01 --every 7 --json --out " +
                dir + "/t.csv");
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  const auto rows = lines(npend::test::read_text(dir + "/t.csv"));
  // Output steps 0, 7, …, 98 of 0 … 100.
  CHECK(j["rows"] == 15);
  REQUIRE(rows.size() == 16);
  CHECK(numbers(rows[2])[0] == doctest::Approx(0.07).epsilon(1e-14));
  CHECK(numbers(rows.back())[0] == doctest::Approx(0.98).epsilon(1e-14));

  const auto summary_only =
      run_npend("simulate --links 2 --phi 0.5,0.5 --t-end 1 --dt 0.01 --json");
  REQUIRE(summary_only.exit_code == 0);
  const auto k = nlohmann::json::parse(summary_only.out);  // stdout holds the JSON only
  CHECK(k["rows"] == 0);
  CHECK(k["out"].is_null());
  CHECK(k["steps"] == 100);
  CHECK(k["stepper"] == "gauss6");
}

TEST_CASE("npend simulate: --energy, --excitation and --dphi set the start state") {
  const npend::chain c(npend::chain_parameters::uniform(3));
  for (const char* style : {"deflection", "kick"}) {
    const auto r = run_npend(
        std::string("simulate --links 3 --energy 12.5 --t-end 0.01 --json --excitation ") + style);
    REQUIRE(r.exit_code == 0);
    const auto j = nlohmann::json::parse(r.out);
    const auto x0 = j["initial_state"].get<std::vector<double>>();
    CHECK(x0 == npend::excited_state(c, 12.5, npend::parse_excitation(style)));
    CHECK(j["energy_initial"].get<double>() == doctest::Approx(12.5).epsilon(1e-14));
  }
  const auto r =
      run_npend("simulate --links 3 --phi 0.1,0.2,0.3 --dphi 1,-1,0.5 --t-end 0.01 --json");
  REQUIRE(r.exit_code == 0);
  const auto x0 = nlohmann::json::parse(r.out)["initial_state"].get<std::vector<double>>();
  const std::vector<double> phi{0.1, 0.2, 0.3}, dphi{1, -1, 0.5};
  CHECK(x0 == c.state_from_velocities(phi, dphi));
}

TEST_CASE("npend simulate: bad input gets a one-line message naming the problem, exit status 2") {
  const std::string dir = npend::test::temporary_directory("simulate-bad");
  const std::string out = " --out " + dir + "/traj.csv";
  struct bad_case {
    std::string args;
    const char* message;
  };
  const std::string base = "simulate --links 3 --phi 1,1,1 --t-end 1";
  const bad_case cases[] = {
      {"simulate --links 3 --t-end 1",
       "no start state: give --phi (with --p or --dphi), or --energy E"},
      {"simulate --links 3 --phi 1,1 --t-end 1",
       "--phi: expected 3 values (phi_1..phi_3) or one for all links, got 2"},
      {"simulate --links 3 --phi 1,1,1 --p 1,1 --t-end 1",
       "--p: expected 3 values (p_1..p_3) or one for all links, got 2"},
      {"simulate --links 3 --phi 1,1,1 --dphi 1,1,1,1 --t-end 1", "--dphi: expected 3 values"},
      {"simulate --links 3 --phi 1,1,1 --p 0,0,0 --dphi 0,0,0 --t-end 1",
       "--p and --dphi exclude each other"},
      {"simulate --links 3 --phi 1,nan,1 --t-end 1", "--phi: 'nan' is not a finite number"},
      {"simulate --links 3 --masses 1,0,1 --phi 1,1,1 --t-end 1",
       "mass 2 is 0: it must be a positive finite number"},
      {"simulate --links 3 --lengths 1,1,-1 --phi 1,1,1 --t-end 1",
       "length 3 is -1: it must be a positive finite number"},
      {"simulate --links 3 --masses 1,1 --phi 1,1,1 --t-end 1",
       "--masses: expected 3 values (m_1..m_3) or one for all links, got 2"},
      {"simulate --links 99 --damping 0.1 --phi 1 --t-end 1",
       "the physical chain of 99 links is not built into this program"},
      {base + " --dt 0", "--dt: must be positive, got 0"},
      {base + " --dt -0.1", "--dt: must be positive, got -0.1"},
      {base + " --dt 2", "--dt: 2 is longer than --t-end 1"},
      {"simulate --links 3 --phi 1,1,1 --t-end 0", "--t-end: must be positive, got 0"},
      {"simulate --links 3 --phi 1,1,1 --t-end -5", "--t-end: must be positive, got -5"},
      {"simulate --links 3 --phi 1,1,1 --t-end inf", "--t-end: 'inf' is not a finite number"},
      {"simulate --links 3 --phi 1,1,1 --t-end 1e7 --dt 1e-4",
       "--t-end/--dt: 1e+11 steps is more than the limit"},
      {base + " --stepper euler",
       "--stepper: unknown stepper 'euler': choose one of rk4, dopri5, rkf78, bs, rosenbrock4, "
       "gauss4, gauss6"},
      {base + " --stepper rk4 --rel-tol 1e-8",
       "--rel-tol: only the adaptive steppers (dopri5, rkf78, bs, rosenbrock4, taylor) take "
       "tolerances, "
       "not rk4"},
      {base + " --stepper dopri5 --abs-tol -1", "--abs-tol: must not be negative, got -1"},
      {base + " --stepper dopri5 --abs-tol 0 --rel-tol 0", "--abs-tol/--rel-tol: both are 0"},
      {base + " --every 0", "--every: must be a whole number >= 1, got 0"},
      {base + " --every 2.5", "--every: must be a whole number >= 1, got 2.5"},
      {"simulate --links 3 --energy -1 --t-end 1",
       "--energy: energy -1 J is below the minimum 0 J of the potential"},
      {"simulate --links 3 --energy 500 --t-end 1",
       "--energy: energy 500 J is out of reach of a deflection from rest: at most 117.72 J"},
      {"simulate --links 3 --energy 5 --excitation push --t-end 1",
       "--excitation: unknown excitation 'push': choose one of deflection, kick"},
      {"simulate --links 3 --energy 5 --phi 1,1,1 --t-end 1",
       "--energy: give either --energy or --phi"},
      {base + " --excitation kick", "--excitation: only applies with --energy"},
      {"simulate --links 3 --phi 1,1,1", "--t-end is required"},
      {base + " --bogus", "The following argument was not expected: --bogus"},
  };
  for (const auto& bad : cases) {
    for (const std::string& extra : {std::string(), out}) {
      const auto r = run_npend(bad.args + extra);
      INFO("npend ", bad.args + extra, " -> ", r.err);
      CHECK(r.exit_code == 2);
      CHECK(r.err.find(bad.message) != std::string::npos);
      CHECK(r.out.empty());
      CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
      CHECK(files_in(dir).empty());
    }
  }
  const auto r =
      run_npend("simulate --links 2 --phi 1,1 --t-end 1 --out /nonexistent-dir/traj.csv");
  CHECK(r.exit_code == 2);
  CHECK(r.err ==
        "npend simulate: error: --out: cannot create a file in '/nonexistent-dir': No such file or "
        "directory\n");
}

TEST_CASE("npend simulate: a failed run leaves no file behind and keeps an existing one") {
  const std::string dir = npend::test::temporary_directory("simulate-fail");
  const std::string path = dir + "/traj.csv";
  // rk4 with steps far too long for a violent motion: the state overflows after a few steps,
  // when the temporary file exists already. (The interrupt test below stops a run whose
  // temporary file holds many rows.)
  const std::string args =
      "simulate --links 2 --phi 2.5,-2.5 --p 10,10 --stepper rk4 --dt 0.5 --t-end 100 --out " +
      path;
  const auto r = run_npend(args);
  INFO(r.err);
  CHECK(r.exit_code == 1);
  CHECK(r.err.find(
            "npend simulate: error: the state became non-finite in the rk4 step from t = ") == 0);
  CHECK(r.err.find("try a smaller dt") != std::string::npos);
  CHECK(files_in(dir).empty());

  { std::ofstream(path) << "an older result\n"; }
  CHECK(run_npend(args).exit_code == 1);
  CHECK(npend::test::read_text(path) == "an older result\n");
  CHECK(files_in(dir) == std::vector<std::string>{"traj.csv"});
}

TEST_CASE("npend simulate: SIGINT stops the run cleanly, without a file under the requested name") {
  const std::string dir = npend::test::temporary_directory("simulate-sigint");
  const std::string path = dir + "/traj.csv";
  const auto r =
      npend::test::run_shell("timeout --preserve-status -s INT 1 " + std::string(NPEND_CLI_PATH) +
                             " simulate --links 6 --energy 50 --t-end 100000 --out " + path);
  INFO(r.err);
  CHECK(r.exit_code == 130);
  CHECK(r.err.find("npend simulate: interrupted at t = ") == 0);
  CHECK(r.err.find("nothing written to " + path) != std::string::npos);
  CHECK(files_in(dir).empty());
}

TEST_CASE("npend simulate: a progress bar on a terminal after a second, never otherwise") {
  const std::string dir = npend::test::temporary_directory("simulate-progress");
  const std::string run = "timeout --preserve-status -s INT 2 " + std::string(NPEND_CLI_PATH) +
                          " simulate --links 6 --energy 50 --t-end 100000 --json --out " + dir +
                          "/traj.csv";
  // `script` runs the command on a pseudo-terminal and copies what it shows to stdout.
  const auto on_terminal = npend::test::run_shell("script -qec '" + run + "' /dev/null");
  INFO(on_terminal.out);
  CHECK(on_terminal.out.find("% ") != std::string::npos);
  CHECK(on_terminal.out.find("s left") != std::string::npos);
  const auto piped = npend::test::run_shell(run);
  CHECK(piped.exit_code == 130);
  CHECK(piped.err.find("s left") == std::string::npos);
  CHECK(piped.err.find("npend simulate: interrupted at t = ") == 0);
}

TEST_CASE("npend simulate: --help describes every option") {
  const auto r = run_npend("simulate --help");
  CHECK(r.exit_code == 0);
  for (const char* option : {"--links", "--masses", "--lengths", "--g", "--phi", "--p", "--dphi",
                             "--energy", "--excitation", "--t-end", "--dt", "--stepper",
                             "--abs-tol", "--rel-tol", "--out", "--every", "--json"})
    CHECK_MESSAGE(r.out.find(option) != std::string::npos, option);
}

TEST_CASE("npend simulate: a large relative energy error is a warning on stderr") {
  // φ_1 = 1e15 rad: its rounding is a sizeable part of a turn, and H drifts by hundreds of
  // times itself. Its own energy error from the JSON decides whether a warning is due.
  const auto bad = run_npend("simulate --links 2 --phi 1e15,0 --t-end 1 --json");
  REQUIRE(bad.exit_code == 0);
  const auto jb = nlohmann::json::parse(bad.out);
  REQUIRE(jb["max_rel_energy_error"].get<double>() > 1e-2);
  CHECK(bad.err.find("npend simulate: warning: the energy drifted by up to") == 0);
  CHECK(bad.err.find("more than 0.01") != std::string::npos);
  const auto good = run_npend("simulate --links 2 --phi 1,0 --t-end 1 --json");
  REQUIRE(good.exit_code == 0);
  CHECK(nlohmann::json::parse(good.out)["max_rel_energy_error"].get<double>() < 1e-2);
  CHECK(good.err.empty());
}

TEST_CASE("npend simulate: bs shrinks a trial step that overflows, as rkf78 does") {
  // The first trial step is the whole 10 s; it overflows. bs used to accept it and stop
  // with "the state became non-finite".
  const std::string run =
      "simulate --links 3 --phi 1.5,1.5,1.5 --t-end 10 --dt 10 --abs-tol 1e-10 --rel-tol 1e-10 "
      "--json --stepper ";
  const auto bs = run_npend(run + "bs"), rkf78 = run_npend(run + "rkf78");
  REQUIRE(bs.exit_code == 0);
  REQUIRE(rkf78.exit_code == 0);
  const auto jb = nlohmann::json::parse(bs.out), jr = nlohmann::json::parse(rkf78.out);
  CHECK(jb["t_end"].get<double>() == 10);
  const double eb = jb["max_rel_energy_error"], er = jr["max_rel_energy_error"];
  // The same order as rkf78's at the same tolerances (both far below 1e-6).
  CHECK(eb < 1e-6);
  CHECK(eb < 100 * er + 1e-12);
}
