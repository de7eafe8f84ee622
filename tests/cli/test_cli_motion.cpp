// npend poincare, npend analyze and npend demo as a user runs them: the crossings' JSON
// against the library, the files and the index they write, and their input errors.
#include <doctest/doctest.h>
#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>

#include "csv_table.hpp"
#include "npend/analysis/chaos/poincare_section.hpp"
#include "npend/analysis/motion/rod_tensions.hpp"
#include "support/test_support.hpp"

namespace fs = std::filesystem;
using npend::test::run_npend;
using npend::test::temporary_directory;

namespace {}  // namespace

TEST_CASE("npend poincare: --json points are the library's crossings, each t and the full state") {
  const npend::chain c(npend::chain_parameters::uniform(3));
  const std::vector<double> x0{0.9, -0.6, 1.2, 0, 0, 0};
  npend::integration_options o;
  o.t_end = 20;
  const auto expected = npend::poincare_section(c, x0, npend::section_plane::coordinate(3, 0, 0.0),
                                                o, {.direction = npend::crossing_direction::down});
  const auto r = run_npend(
      "poincare --links 3 --phi 0.9,-0.6,1.2 --t-end 20 --section phi1=0 --direction down --json");
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  REQUIRE(j["points"].size() == expected.crossings.size());
  REQUIRE(j["count"] == expected.crossings.size());
  REQUIRE(expected.crossings.size() > 5);
  for (std::size_t k = 0; k < expected.crossings.size(); ++k) {
    CHECK(j["points"][k]["t"].get<double>() == expected.crossings[k].t);
    CHECK(j["points"][k]["state"].get<std::vector<double>>() == expected.crossings[k].state);
  }
  CHECK(j["direction"] == "down");
  CHECK(j["normal"].get<std::vector<double>>() == std::vector<double>{1, 0, 0, 0, 0, 0});
  CHECK(j["projection"] == nlohmann::json{"phi3", "p3"});
  CHECK(j["max_section_residual"].get<double>() < 1e-12);
  CHECK(j["max_rel_energy_error"].get<double>() < 1e-11);
  CHECK(j["unrefined"] == 0);
  // --max-points stops early; the section phi2=phi3 of stretched neighbours.
  const auto few = nlohmann::json::parse(
      run_npend("poincare --links 3 --phi 0.9,-0.6,1.2 --t-end 20 --section phi_2=phi3 "
                "--direction both --max-points 3 --json")
          .out);
  REQUIRE(few["count"] == 3);
  CHECK(few["t_end"].get<double>() < 20);
  for (const auto& p : few["points"]) {
    const auto x = p["state"].get<std::vector<double>>();
    CHECK(std::fabs(x[1] - x[2]) < 1e-12);
  }
}

TEST_CASE("npend poincare: --out writes the crossings, the script and the projection plot") {
  const fs::path dir = temporary_directory("cli-poincare-out");
  const auto r = run_npend(
      "poincare --links 2 --energy 8 --t-end 30 --section p1=0 --project "
      "phi1,phi2 --out " +
      (dir / "pts.csv").string());
  REQUIRE(r.exit_code == 0);
  CHECK(npend::test::directory_listing(dir) ==
        std::vector<std::string>{"pts.csv", "pts.gp", "pts.png"});
  const auto table = npend::cli::parse_csv(npend::test::read_text(dir / "pts.csv"), "pts.csv");
  CHECK(table.names == std::vector<std::string>{"t", "phi1", "phi2", "p1", "p2", "H"});
  REQUIRE(!table.columns[0].empty());
  for (const double p1 : table.columns[3]) CHECK(std::fabs(p1) < 1e-12);
  for (const double h : table.columns[5]) CHECK(h == doctest::Approx(8).epsilon(1e-11));
  // The plot shows the projection asked for, with units.
  const std::string script = npend::test::read_text(dir / "pts.gp");
  CHECK(script.find("using 2:3") != std::string::npos);
  CHECK(script.find("set xlabel \"φ_{1} (rad)\"") != std::string::npos);
  // The text output lists every crossing.
  CHECK(r.out.find(fmt::format("crossings: {}", table.columns[0].size())) != std::string::npos);
}

TEST_CASE("npend poincare: each bad input gets its message and exit status 2") {
  const std::string start = "poincare --links 3 --phi 0.1,0.2,0.3 --t-end 5";
  for (const auto& [args, message] : std::vector<std::pair<std::string, std::string>>{
           {start + " --section phi4=0", "--section: 'phi4' is not a coordinate of the 3-link"},
           {start + " --section phi1", "--section: 'phi1' is not NAME=VALUE"},
           {start + " --section phi1=phi1", "--section: 'phi1=phi1' compares phi1 with itself"},
           {start + " --section phi1=0 --direction sideways",
            "--direction: 'sideways' is not up, down or both"},
           {start + " --section phi1=0 --project phi3", "--project: 'phi3' is not two coordinates"},
           {start + " --section phi1=0 --max-points 0",
            "--max-points: must be a whole number >= 1, got 0"},
           {start + " --section phi1=0 --out x.png", "--out: 'x.png' must be a file name ending"},
           {"poincare --links 3 --t-end 5 --section phi1=0", "no start state"},
       }) {
    CAPTURE(args);
    const auto r = run_npend(args);
    CHECK(r.exit_code == 2);
    CHECK(r.err.find("error: " + message) != std::string::npos);
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
  }
  // --section is required.
  const auto r = run_npend(start);
  CHECK(r.exit_code == 2);
  CHECK(r.err.find("--section is required") != std::string::npos);
}

TEST_CASE("npend analyze: writes the data, the plots and an index that shows them") {
  const fs::path dir = fs::path(temporary_directory("cli-analyze")) / "run";
  const auto r =
      run_npend("analyze --links 3 --phi 0.72,-0.72,0.72 --samples 8192 --t-end 60 --json --out " +
                dir.string());
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  const std::vector<std::string> expected{"autocorrelation.csv",
                                          "autocorrelation.gp",
                                          "autocorrelation.png",
                                          "embedding.csv",
                                          "embedding.gp",
                                          "embedding.png",
                                          "embedding_dimension.csv",
                                          "index.md",
                                          "poincare.csv",
                                          "poincare.gp",
                                          "poincare.png",
                                          "recurrence.csv",
                                          "recurrence.gp",
                                          "recurrence.png",
                                          "recurrence_histogram.csv",
                                          "recurrence_spectrum.csv",
                                          "series.csv",
                                          "series.gp",
                                          "series.png",
                                          "spectrum.csv",
                                          "spectrum.gp",
                                          "spectrum.png",
                                          "spectrum_peaks.csv",
                                          "tensions.csv",
                                          "tensions.gp",
                                          "tensions.png"};
  CHECK(npend::test::directory_listing(dir) == expected);
  CHECK(j["files"].size() == expected.size());
  CHECK(j["signal"] == "phi3");
  CHECK(j["samples"] == 8192);
  CHECK(j["crossings"].get<std::size_t>() > 5);
  CHECK(j["events"].get<std::size_t>() > 10);
  CHECK(j["max_section_residual"].get<double>() < 1e-12);
  // Nothing was left out (the zigzag at ε ≈ 1.5 keeps every arm below the top).
  CHECK(j["notes"].empty());
  CHECK(j["dimension"].is_number());
  CHECK(j["tau"].get<double>() > 0);
  // The index shows every plot and links every data file.
  const std::string index = npend::test::read_text(dir / "index.md");
  for (const auto& name : expected) {
    CAPTURE(name);
    if (name.ends_with(".png")) CHECK(index.find("](" + name + ")") != std::string::npos);
    if (name.ends_with(".csv") || name.ends_with(".gp"))
      CHECK(index.find("[" + name + "](" + name + ")") != std::string::npos);
  }
  // The series is the first 8192 samples of phi3 on the grid.
  const auto series =
      npend::cli::parse_csv(npend::test::read_text(dir / "series.csv"), "series.csv");
  CHECK(series.names == std::vector<std::string>{"t", "phi1", "phi2", "phi3", "p1", "p2", "p3"});
  CHECK(series.columns[0].size() == 8192);
  CHECK(series.columns[3].front() == 0.72);
  // The tensions on the same samples, the first row the library's at the start (their
  // physics is tested in tests/runtime/motion/test_rod_tensions.cpp).
  const auto tensions =
      npend::cli::parse_csv(npend::test::read_text(dir / "tensions.csv"), "tensions.csv");
  CHECK(tensions.names == std::vector<std::string>{"t", "tau_1", "tau_2", "tau_3"});
  CHECK(tensions.columns[0].size() == 8192);
  const std::vector<double> x0{0.72, -0.72, 0.72, 0, 0, 0};
  const auto tau0 = npend::rod_tensions(npend::chain(npend::chain_parameters::uniform(3)), x0);
  for (std::size_t k = 0; k < 3; ++k)
    CHECK(tensions.columns[k + 1].front() == doctest::Approx(tau0[k]).epsilon(1e-15));
}

TEST_CASE("npend analyze: an arm going over the top is a note on the unwrapped angles") {
  const fs::path dir = fs::path(temporary_directory("cli-analyze-flip")) / "run";
  // A start whose arm goes over at t ≈ 5 s, before chaos can amplify the kernels' rounding
  // (from 0.9,-0.6,1.2 the first flip came at 113 s, or never, as the last bits fell).
  const std::string start =
      "analyze --links 3 --phi 1.4,-0.6,1.2 --samples 1024 --t-end 200 --json ";
  // On the circle (the default) a flip changes nothing about the sections: no note.
  const auto circle = run_npend(start + "--out " + dir.string() + "-circle");
  REQUIRE(circle.exit_code == 0);
  const auto c = nlohmann::json::parse(circle.out);
  CHECK(c["angles"] == "circle");
  for (const auto& note : c["notes"])
    CHECK(note.get<std::string>().find("an arm passed the upright position") == std::string::npos);
  const auto r = run_npend(start + "--unwrapped --out " + dir.string());
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  CHECK(j["angles"] == "unwrapped");
  REQUIRE(!j["notes"].empty());
  CHECK(j["notes"][0].get<std::string>().find("an arm passed the upright position") == 0);
  CHECK(
      npend::test::read_text(dir / "index.md").find("> Note: an arm passed the upright position") !=
      std::string::npos);
  CHECK(r.err.find("note: an arm passed the upright position") == 0);
}

TEST_CASE("npend analyze: bad input gets its message and exit status 2, before any file") {
  const fs::path dir = temporary_directory("cli-analyze-errors");
  std::ofstream(dir / "file") << "x\n";
  for (const auto& [args, message] : std::vector<std::pair<std::string, std::string>>{
           {"analyze --links 3 --phi 0.1,0.2,0.3 --out " + (dir / "file").string(),
            "--out: '" + (dir / "file").string() + "' exists and is not a directory"},
           {"analyze --links 3 --phi 0.1,0.2,0.3 --section phi9=0 --out " + (dir / "a").string(),
            "--section: 'phi9' is not a coordinate"},
           {"analyze --links 3 --phi 0.1,0.2,0.3 --coordinate q --out " + (dir / "b").string(),
            "--coordinate: 'q' is not a coordinate"},
           {"analyze --links 3 --phi 0,0,0 --out " + (dir / "c").string(),
            "phi3 stays at 0 over the whole series: nothing moves"},
       }) {
    CAPTURE(args);
    const auto r = run_npend(args);
    CHECK(r.exit_code == 2);
    CHECK(r.err.find("error: " + message) != std::string::npos);
  }
  for (const char* folder : {"a", "b", "c"})
    if (fs::exists(dir / folder)) CHECK(fs::is_empty(dir / folder));
}

TEST_CASE("npend demo: writes the paper's figures 6.8-6.13 and an index to --out") {
  const fs::path dir = fs::path(temporary_directory("cli-demo")) / "figures";
  const auto r = run_npend("demo --out " + dir.string());
  REQUIRE(r.exit_code == 0);
  const std::vector<std::string> figures{"time_series",
                                         "fig6_8_poincare",
                                         "fig6_9_spectral_density",
                                         "fig6_10_autocorrelation",
                                         "fig6_11_recurrence_histogram",
                                         "fig6_12_recurrence_spectrum",
                                         "fig6_13_delay_plot"};
  const std::string index = npend::test::read_text(dir / "index.md");
  for (const auto& f : figures) {
    CAPTURE(f);
    CHECK(fs::file_size(dir / (f + ".png")) > 10000);
    CHECK(fs::exists(dir / (f + ".gp")));
    CHECK(index.find("](" + f + ".png)") != std::string::npos);
    CHECK(r.out.find("-> " + (dir / (f + ".png")).string()) != std::string::npos);
  }
  // Every data file the scripts read is there.
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".gp") {
      const std::string script = npend::test::read_text(e.path());
      for (std::size_t at = 0; (at = script.find(".csv\"", at)) != std::string::npos; ++at) {
        const std::size_t open = script.rfind('"', at);
        CHECK(fs::exists(dir / script.substr(open + 1, at + 4 - open - 1)));
      }
    }
  // The two motions animated: a GIF each (121 frames: 6 s at 20 fps), with its frames'
  // table, in the index without a plot script.
  for (const std::string f : {"animation_weak", "animation_strong"}) {
    CAPTURE(f);
    const std::string gif = npend::test::read_text(dir / (f + ".gif"));
    CHECK(gif.rfind("GIF89a", 0) == 0);
    CHECK(gif.size() > 10000);
    const std::string frames = npend::test::read_text(dir / (f + "_frames.csv"));
    CHECK(std::count(frames.begin(), frames.end(), '\n') == 122);
    CHECK(index.find("](" + f + ".gif)") != std::string::npos);
    CHECK(index.find("[" + f + ".gp]") == std::string::npos);
    CHECK(r.out.find("-> " + (dir / (f + ".gif")).string()) != std::string::npos);
  }
  CHECK(r.out.find("## 5. Forms of motion") != std::string::npos);
  CHECK(r.out.find("open " + (dir / "index.md").string()) != std::string::npos);

  // Section 6: the physical pendulum, in its own folder with its own index.
  const fs::path physical = dir / "physical";
  const std::string physical_index = npend::test::read_text(physical / "index.md");
  for (const char* f : {"rods_vs_points", "damped", "kapitza_acheson", "standing_lqr"}) {
    CAPTURE(f);
    CHECK(fs::file_size(physical / (std::string(f) + ".png")) > 10000);
    CHECK(physical_index.find("](" + std::string(f) + ".png)") != std::string::npos);
  }
  CHECK(r.out.find("## 6. The physical pendulum") != std::string::npos);
}

TEST_CASE("npend poincare, analyze and demo: --help names every option") {
  for (const auto& [command, options] :
       std::vector<std::pair<std::string, std::vector<std::string>>>{
           {"poincare",
            {"--links", "--phi", "--energy", "--t-end", "--dt", "--stepper", "--section",
             "--direction", "--project", "--max-points", "--json", "--out"}},
           {"analyze",
            {"--links", "--phi", "--energy", "--samples", "--dt", "--t-end", "--coordinate",
             "--stepper", "--section", "--direction", "--event", "--event-direction", "--project",
             "--json", "--out"}},
           {"demo", {"--out"}},
           {"spectrum",
            {"--input", "--links", "--phi", "--energy", "--samples", "--coordinate", "--stepper"}},
           {"recurrence", {"--input", "--links", "--phi", "--energy", "--t-end", "--event"}}}) {
    const auto r = run_npend(command + " --help");
    CHECK(r.exit_code == 0);
    for (const auto& o : options)
      CHECK_MESSAGE(r.out.find(o) != std::string::npos, command, " ", o);
  }
}

TEST_CASE("npend poincare: sections of angles are on the circle unless --unwrapped") {
  // Above the flip energy the arms turn over: φ₃ = 0 on the circle is passed every turn,
  // while the plane of the unwrapped angle is met only while φ₃ stays near 0.
  const std::string run =
      "poincare --links 3 --phi 1.5,1.5,1.5 --t-end 200 --section phi3=0 --json";
  const auto circle = nlohmann::json::parse(run_npend(run).out);
  const auto plane = nlohmann::json::parse(run_npend(run + " --unwrapped").out);
  CHECK(circle["angles"] == "circle");
  CHECK(plane["angles"] == "unwrapped");
  const auto on_circle = circle["count"].get<std::size_t>();
  const auto on_plane = plane["count"].get<std::size_t>();
  CHECK(on_circle > 5 * on_plane);
  // Every crossing of the plane is one of the circle's (the branch j = 0), at the same time.
  std::vector<double> times;
  for (const auto& p : circle["points"]) times.push_back(p["t"].get<double>());
  for (const auto& p : plane["points"]) {
    const double t = p["t"].get<double>();
    CHECK(
        std::any_of(times.begin(), times.end(), [&](double s) { return std::fabs(s - t) < 1e-9; }));
  }
  // The circle's points are reported with their angles in [-π, π], on the section to rounding.
  for (const auto& p : circle["points"]) {
    const auto x = p["state"].get<std::vector<double>>();
    for (std::size_t i = 0; i < 3; ++i) CHECK(std::fabs(x[i]) <= std::numbers::pi);
    CHECK(std::fabs(x[2]) < 1e-9);
  }
  CHECK(circle["max_section_residual"].get<double>() < 1e-9);
}

TEST_CASE("npend poincare: without crossings the energy error is the run's, not 0") {
  // Small swings never reach φ1 = 2: no crossing. The energy error is then the run's over
  // its grid, the same drift `npend simulate` measures on the same run.
  const std::string start = "--links 2 --phi 0.1,0.1 --t-end 5 --stepper rk4 --dt 0.01";
  const auto r = run_npend("poincare " + start + " --section phi1=2 --json");
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  REQUIRE(j["count"] == 0);
  const auto sim = run_npend("simulate " + start + " --json");
  REQUIRE(sim.exit_code == 0);
  const double expected = nlohmann::json::parse(sim.out)["max_rel_energy_error"];
  CHECK(expected > 0);
  CHECK(j["max_rel_energy_error"].get<double>() == expected);
}
