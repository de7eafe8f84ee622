// `npend upo` as a user runs it: the JSON's orbits integrated again with rkf78 at the chain's
// energy, the table, the --out files, and bad input refused with exit status 2.
#include <doctest/doctest.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "npend/chain.hpp"
#include "npend/integrators/integrate.hpp"
#include "support/test_support.hpp"

using npend::test::is_input_error;
using npend::test::run_npend;

namespace {

// The double pendulum's orbit from x0, integrated again over its period by rkf78 at 1e-14,
// comes back to its start (each angle 2π·winding on) within 1e-9.
void check_closes_under_rkf78(const npend::chain& c, const std::vector<double>& x0,
                              const std::vector<int>& winding, double period) {
  npend::integration_options run;
  run.stepper = npend::stepper_kind::rkf78;
  run.t_end = run.dt = period;
  run.abs_tol = run.rel_tol = 1e-14;
  const auto back = npend::integrate(c, x0, run);
  for (std::size_t i = 0; i < x0.size(); ++i)
    CHECK(std::fabs(back.state[i] - x0[i] - (i < 2 ? 2 * std::numbers::pi * winding[i] : 0.0)) <=
          1e-9);
}

}  // namespace

TEST_CASE("npend upo: the double pendulum's orbits at 30 J close again under rkf78") {
  const auto r =
      run_npend("upo --links 2 --energy 30 --period-max 4.5 --time 300 --candidates 10 --json");
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  CHECK(j["energy"].get<double>() == doctest::Approx(30.0).epsilon(1e-12));
  const double lyapunov = j["lyapunov_exponent"].get<double>();
  CHECK(lyapunov > 0.3);
  REQUIRE(j["orbits"].size() >= 2);
  const npend::chain c(npend::chain_parameters::uniform(2));
  bool unstable = false;
  double last = 0;
  for (const auto& orbit : j["orbits"]) {
    const double period = orbit["period"].get<double>();
    CAPTURE(period);
    CHECK(period >= last);  // by period
    last = period;
    CHECK(period <= 4.5);
    const auto x0 = orbit["x0"].get<std::vector<double>>();
    const auto winding = orbit["winding"].get<std::vector<int>>();
    CHECK(c.hamiltonian(x0) == doctest::Approx(30.0).epsilon(1e-10));
    check_closes_under_rkf78(c, x0, winding, period);
    // One non-trivial pair μ, 1/μ.
    REQUIRE(orbit["multipliers"].size() == 2);
    const auto& m = orbit["multipliers"];
    const double product = std::hypot(m[0][0].get<double>(), m[0][1].get<double>()) *
                           std::hypot(m[1][0].get<double>(), m[1][1].get<double>());
    CHECK(product == doctest::Approx(1.0).epsilon(1e-6));
    const double mu = orbit["max_multiplier"].get<double>();
    CHECK(orbit["lyapunov_rate"].get<double>() == doctest::Approx(std::log(mu) / period));
    unstable = unstable || (!orbit["stable"].get<bool>() && std::log(mu) / period > 0.3);
  }
  CHECK(unstable);
}

TEST_CASE("npend upo --stepper taylor: gauss6's orbits, closed by rkf78, the run named") {
  const std::string search =
      "upo --links 2 --energy 30 --period-max 3 --time 300 --candidates 10 --json";
  const auto g = run_npend(search);
  const auto t = run_npend(search + " --stepper taylor --tol 1e-13");
  REQUIRE(g.exit_code == 0);
  REQUIRE(t.exit_code == 0);
  const auto jg = nlohmann::json::parse(g.out), jt = nlohmann::json::parse(t.out);
  CHECK(jg["stepper"] == "gauss6");
  CHECK_FALSE(jg.contains("integration_tolerance"));
  CHECK(jt["stepper"] == "taylor");
  CHECK(jt["integration_tolerance"].get<double>() == 1e-13);
  REQUIRE(jt["orbits"].size() >= 2);
  REQUIRE(jt["orbits"].size() == jg["orbits"].size());
  const npend::chain c(npend::chain_parameters::uniform(2));
  for (std::size_t k = 0; k < jt["orbits"].size(); ++k) {
    const auto& orbit = jt["orbits"][k];
    const double period = orbit["period"].get<double>();
    CAPTURE(period);
    CHECK(period == doctest::Approx(jg["orbits"][k]["period"].get<double>()).epsilon(1e-9));
    const auto x0 = orbit["x0"].get<std::vector<double>>();
    const auto winding = orbit["winding"].get<std::vector<int>>();
    check_closes_under_rkf78(c, x0, winding, period);
  }
  CHECK(is_input_error(run_npend("upo --links 2 --energy 30 --period-max 3 --stepper rk4"),
                       "--stepper: the shooting integrates with gauss6, taylor, not rk4"));
  CHECK(is_input_error(run_npend("upo --links 2 --energy 30 --period-max 3 --tol 1e-12"),
                       "--tol: only with --stepper taylor"));
}

TEST_CASE("npend upo: the table, and --out writes one row per orbit") {
  const auto dir = std::filesystem::path(npend::test::temporary_directory("cli-upo"));
  const auto r =
      run_npend("upo --links 2 --energy 30 --period-max 3.2 --time 200 --candidates 6 --out " +
                (dir / "upo.csv").string());
  REQUIRE(r.exit_code == 0);
  CHECK(r.out.find("maximal Lyapunov exponent of the trajectory: ") != std::string::npos);
  CHECK(r.out.find("ln|mu|/T") != std::string::npos);
  const auto files = npend::test::directory_listing(dir.string());
  CHECK(std::count(files.begin(), files.end(), "upo.csv") == 1);
  CHECK(std::count(files.begin(), files.end(), "upo.gp") == 1);
  std::ifstream csv(dir / "upo.csv");
  std::string header;
  std::getline(csv, header);
  CHECK(header ==
        "period,energy,max_multiplier,lyapunov_rate,stable,closure,copies,winding1,winding2,"
        "phi1,phi2,p1,p2");
  int rows = 0;
  for (std::string line; std::getline(csv, line);) rows += line.empty() ? 0 : 1;
  // The table's rows: the lines between its header and the note on copies.
  int listed = 0;
  std::istringstream out(r.out);
  bool in_table = false;
  for (std::string line; std::getline(out, line);) {
    if (line.find("period (s)") != std::string::npos) {
      in_table = true;
      continue;
    }
    if (line.rfind("copies:", 0) == 0) break;
    listed += in_table ? 1 : 0;
  }
  CHECK(rows >= 1);
  CHECK(rows == listed);
}

TEST_CASE("npend upo: bad input is refused with exit status 2") {
  CHECK(is_input_error(run_npend("upo --links 2 --energy 30"), "--period-max is required"));
  CHECK(is_input_error(run_npend("upo --links 2 --energy 30 --period-max 0"), "--period-max"));
  CHECK(is_input_error(run_npend("upo --links 2 --energy 30 --period-max 3 --period-min 3"),
                       "--period-min"));
  CHECK(is_input_error(run_npend("upo --links 2 --energy 30 --period-max 3 --tolerance 2"),
                       "--tolerance"));
  CHECK(is_input_error(run_npend("upo --links 2 --energy 30 --period-max 3 --candidates 0"),
                       "--candidates"));
  CHECK(is_input_error(run_npend("upo --links 2 --energy 30 --period-max 3 --time 0.001 --dt 0.01"),
                       "--dt"));
  CHECK(
      is_input_error(run_npend("upo --links 2 --damping 0.1 --energy 30 --period-max 3"), "damp"));
  CHECK(run_npend("upo --links 2 --period-max 3").exit_code == 2);  // no start
}
