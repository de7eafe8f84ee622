// The time-series commands on a simulated start (--links N, a start, --samples, --dt,
// --coordinate, --stepper): their JSON against the library on the same trajectory, and the
// message of every bad combination of options.
#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>

#include "csv_table.hpp"
#include "npend/analysis/chaos/poincare_section.hpp"
#include "npend/analysis/series/autocorrelation.hpp"
#include "npend/analysis/series/delay_embedding.hpp"
#include "npend/analysis/series/embedding_dimension.hpp"
#include "npend/analysis/series/power_spectrum.hpp"
#include "npend/analysis/series/spectral_peaks.hpp"
#include "npend/excitation.hpp"
#include "npend/integrators/integrate.hpp"
#include "support/test_support.hpp"

using namespace npend;
using npend::test::run_npend;

namespace {

// Coordinate `index` of the trajectory from x0 on the grid 0, dt, …, (samples − 1) dt.
std::vector<double> trajectory_coordinate(const chain& c, const std::vector<double>& x0,
                                          std::size_t index, std::size_t samples, double dt,
                                          stepper_kind stepper = stepper_kind::gauss6) {
  integration_options o;
  o.stepper = stepper;
  o.dt = dt;
  o.t_end = (static_cast<double>(samples) - 1) * dt;
  std::vector<double> values;
  integrate(c, x0, o, [&](double, std::span<const double> x) {
    if (values.size() < samples) values.push_back(x[index]);
  });
  REQUIRE(values.size() == samples);
  return values;
}

}  // namespace

TEST_CASE("npend spectrum: a simulated start's --json peaks are the library's, on phin") {
  const chain c(chain_parameters::uniform(3));
  const auto r = run_npend("spectrum --links 3 --phi 0.02,-0.03,0.05 --json");
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  // The paper's series: φ₃, 2¹⁴ samples at dt = 1 ms, from Gauss–Legendre 6.
  const auto phi3 = trajectory_coordinate(c, {0.02, -0.03, 0.05, 0, 0, 0}, 2, 16384, 1e-3);
  const auto peaks = find_spectral_peaks(power_spectrum(phi3, 1e-3));
  REQUIRE(peaks.size() >= 3);
  REQUIRE(j["peaks"].size() == peaks.size());
  for (std::size_t k = 0; k < peaks.size(); ++k) {
    CHECK(j["peaks"][k]["omega"].get<double>() == peaks[k].omega);
    CHECK(j["peaks"][k]["power"].get<double>() == peaks[k].power);
  }
  CHECK(j["signal"] == "phi3");
  CHECK(j["samples"] == 16384);
  CHECK(j["dt"].get<double>() == 1e-3);
  CHECK(j["source"].get<std::string>().find("simulation: 3 links, E = ") == 0);
}

TEST_CASE("npend autocorrelation and embed: --coordinate, --samples, --dt, --stepper, --energy") {
  const chain c(chain_parameters::uniform(2));
  const auto x0 = excited_state(c, 5.0, excitation::kick);
  const auto p2 = trajectory_coordinate(c, x0, 3, 4096, 2e-3, stepper_kind::rk4);
  const auto acf = autocorrelation(p2, 2e-3, 2048);
  const auto r = run_npend(
      "autocorrelation --links 2 --energy 5 --excitation kick --coordinate p_2 --samples 4096 "
      "--dt 0.002 --stepper rk4 --json");
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  CHECK(j["signal"] == "p2");
  CHECK(j["samples"] == 4096);
  REQUIRE(acf.first_zero);
  CHECK(j["first_zero"].get<double>() == *acf.first_zero);
  // --column is the same option.
  const auto again = nlohmann::json::parse(
      run_npend("autocorrelation --links 2 --energy 5 --excitation kick --column p2 --samples "
                "4096 --dt 0.002 --stepper rk4 --json")
          .out);
  CHECK(again["first_zero"] == j["first_zero"]);

  const auto phi2 = trajectory_coordinate(c, x0, 1, 16384, 1e-3);
  const delay_choice tau = choose_delay(phi2, 1e-3);
  const auto fnn = false_nearest_neighbours(phi2, tau.samples, 10, {.theiler_window = tau.samples});
  const auto e =
      nlohmann::json::parse(run_npend("embed --links 2 --energy 5 --excitation kick --json").out);
  CHECK(e["signal"] == "phi2");
  CHECK(e["tau"].get<double>() == tau.seconds);
  REQUIRE(fnn.found);
  CHECK(e["dimension"] == fnn.dimension);
}

TEST_CASE("npend recurrence: a simulated start's events are the Poincare crossings") {
  const chain c(chain_parameters::uniform(3));
  const std::vector<double> x0{0.9, -0.6, 1.2, 0, 0, 0};
  integration_options o;
  o.t_end = 30;
  const auto crossings = poincare_section(c, x0, section_plane::equal_coordinates(3, 1, 2), o,
                                          {.direction = crossing_direction::both});
  const auto r =
      run_npend("recurrence --links 3 --phi 0.9,-0.6,1.2 --t-end 30 --event phi2=phi3 --json");
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  const auto times = j["times"].get<std::vector<double>>();
  REQUIRE(times.size() == crossings.crossings.size());
  REQUIRE(times.size() > 10);
  for (std::size_t k = 0; k < times.size(); ++k) CHECK(times[k] == crossings.crossings[k].t);
  CHECK(j["interpolation"] == "steps");
  CHECK(j["direction"] == "both");
}

TEST_CASE("npend time series: each bad simulated start gets its message and exit status 2") {
  const std::string dir = npend::test::temporary_directory("cli-simulated-errors");
  const std::string csv = dir + "/x.csv";
  std::ofstream(csv) << "t,x\n0,1\n0.1,2\n";
  const std::string start = " --links 3 --phi 0.1,0.2,0.3";
  const std::vector<std::pair<std::string, std::string>> cases{
      {"spectrum --input " + csv + start,
       "--input and --links exclude each other: analyse a CSV file or a simulated start"},
      {"spectrum --input " + csv + " --samples 100",
       "--samples: only for a simulated start (--links N), not with --input"},
      {"recurrence --input " + csv + " --event x=0 --t-end 5",
       "--t-end: only for a simulated start (--links N), not with --input"},
      {"embed --input " + csv + " --energy 3",
       "--energy: only for a simulated start (--links N), not with --input"},
      {"spectrum --links 3", "no start state: give --phi (with --p or --dphi), or --energy E"},
      {"spectrum" + start + " --coordinate phi4",
       "--coordinate: 'phi4' is not a coordinate of the 3-link chain"},
      {"spectrum" + start + " --samples 10",
       "--samples: must be a whole number 16..4194304, got 10"},
      {"embed" + start + " --samples 5e6",
       "--samples: must be a whole number 64..4194304, got 5e6"},
      {"spectrum" + start + " --samples 100.5", "--samples: must be a whole number"},
      {"autocorrelation" + start + " --dt 0", "--dt: must be positive, got 0"},
      {"spectrum" + start + " --stepper euler", "--stepper: unknown stepper 'euler'"},
      {"spectrum" + start + " --abs-tol 1e-8", "--abs-tol: only the adaptive steppers"},
      {"spectrum --links 0 --phi 0.1", "--links: must be at least 1, got 0"},
      {"recurrence" + start + " --event phi4=0",
       "--event: 'phi4' is not a coordinate of the 3-link chain"},
      {"recurrence" + start + " --event phi1=phi_1",
       "--event: 'phi1=phi_1' compares phi1 with itself"},
      {"recurrence" + start + " --event phi1=0 --interpolation linear",
       "--interpolation: only for --input; a simulation's events are located on the integrator's "
       "steps"},
      {"recurrence" + start + " --event phi1=0 --t-end -1", "--t-end: must be positive, got -1"},
      {"recurrence" + start + " --event phi1=5 --t-end 2",
       "--event: phi1=5 has 0 events in simulation: 3 links"},
  };
  for (const auto& [args, message] : cases) {
    CAPTURE(args);
    const auto r = run_npend(args);
    CHECK(r.exit_code == 2);
    CHECK(r.err.find("error: " + message) != std::string::npos);
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
  }
}

namespace {

// The series a command analyses, read back from `npend embed --dim 2 --tau dt --out`: the
// column x(t) of its delay vectors, at t = dt, 2 dt, …
std::vector<double> analysed_series(const std::string& start, const std::string& coordinate) {
  const std::string dir = npend::test::temporary_directory("cli-observable-" + coordinate);
  const std::string out = (std::filesystem::path(dir) / "e.csv").string();
  const auto r = run_npend("embed " + start + " --coordinate " + coordinate +
                           " --tau 0.01 --dim 2 --out " + out);
  REQUIRE(r.exit_code == 0);
  const auto table = npend::cli::parse_csv(npend::test::read_text(out), out);
  REQUIRE(table.names.at(1) == "x(t)");
  return table.columns[1];
}

}  // namespace

TEST_CASE("npend spectrum/embed: the bounded observables of a rotating chain") {
  // Above the flip energy: φ₃ winds; sin, cos, the wrapped angle and the bob positions stay
  // bounded. Each is checked against the trajectory integrated here and eq. 6.1 written out.
  const std::string start =
      "--links 3 --lengths 1,0.5,0.8 --phi 1.5,1.5,1.5 --dt 0.01 --samples 512";
  const chain c(chain_parameters{{1, 1, 1}, {1, 0.5, 0.8}, 9.81});
  const std::vector<double> x0{1.5, 1.5, 1.5, 0, 0, 0};
  std::vector<std::vector<double>> phi;
  for (std::size_t i = 0; i < 3; ++i) phi.push_back(trajectory_coordinate(c, x0, i, 512, 0.01));
  const auto x3 = analysed_series(start, "x3");
  const auto y2 = analysed_series(start, "y_2");
  const auto s3 = analysed_series(start, "sin_phi3");
  const auto c1 = analysed_series(start, "cos_phi_1");
  const auto w3 = analysed_series(start, "wrapped_phi3");
  REQUIRE(x3.size() == 511);
  for (std::size_t j = 1; j < 512; ++j) {
    const std::size_t row = j - 1;  // the first delay vector is at t = dt
    CHECK(x3[row] == doctest::Approx(std::sin(phi[0][j]) + 0.5 * std::sin(phi[1][j]) +
                                     0.8 * std::sin(phi[2][j]))
                         .epsilon(1e-12));
    CHECK(y2[row] ==
          doctest::Approx(std::cos(phi[0][j]) + 0.5 * std::cos(phi[1][j])).epsilon(1e-12));
    CHECK(s3[row] == doctest::Approx(std::sin(phi[2][j])).epsilon(1e-12));
    CHECK(c1[row] == doctest::Approx(std::cos(phi[0][j])).epsilon(1e-12));
    CHECK(std::fabs(w3[row]) <= std::numbers::pi);
    const double turns = (phi[2][j] - w3[row]) / (2 * std::numbers::pi);
    CHECK(std::fabs(turns - std::round(turns)) < 1e-9);
  }
}

TEST_CASE("npend spectrum: a winding angle's series is noted on stderr, a bounded one is not") {
  const std::string rotating =
      "spectrum --links 3 --phi 1.5,1.5,1.5 --dt 0.01 --samples 4096 --json";
  const auto winding = run_npend(rotating + " --coordinate phi3");
  REQUIRE(winding.exit_code == 0);
  CHECK(winding.err.find("note: phi3 runs from") == 0);
  CHECK(std::count(winding.err.begin(), winding.err.end(), '\n') == 1);
  CHECK(run_npend(rotating + " --coordinate x3").err.empty());
  // The weak start swings without turning over: nothing to note.
  CHECK(run_npend("spectrum --links 3 --phi 0.1,-0.1,0.1 --dt 0.01 --samples 1024 --json")
            .err.empty());
}

TEST_CASE("npend spectrum: Ctrl-C during the simulation stops it, analyses nothing, exits 130") {
  const std::string dir = npend::test::temporary_directory("spectrum-interrupt");
  const auto r = npend::test::run_shell(
      "timeout --preserve-status -s INT 2 " + std::string(NPEND_CLI_PATH) +
      " spectrum --links 6 --energy 50 --samples 4000000 --out " + dir + "/s.csv");
  INFO(r.err);
  CHECK(r.exit_code == 130);
  CHECK(r.err.find("npend spectrum: interrupted at t = ") == 0);
  CHECK(std::filesystem::is_empty(dir));
}
