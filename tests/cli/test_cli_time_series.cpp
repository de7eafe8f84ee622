// npend spectrum / autocorrelation / recurrence / embed on CSV files, as a user runs them:
// the JSON against the library on the same data, the files --out writes, every input error's
// message and exit status, and that a failure leaves no file behind.
#include <doctest/doctest.h>
#include <fmt/format.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <optional>
#include <sstream>

#include "csv_table.hpp"
#include "npend/analysis/series/autocorrelation.hpp"
#include "npend/analysis/series/delay_embedding.hpp"
#include "npend/analysis/series/embedding_dimension.hpp"
#include "npend/analysis/series/event_times.hpp"
#include "npend/analysis/series/power_spectrum.hpp"
#include "npend/analysis/series/spectral_peaks.hpp"
#include "support/test_signals.hpp"
#include "support/test_support.hpp"
#include "time_series_source.hpp"

namespace fs = std::filesystem;
using npend::test::run_npend;
using npend::test::temporary_directory;
using std::numbers::pi;

namespace {

const double dt = 0.001;
const double omega_1 = 2 * pi * 1.3, omega_2 = 2 * pi * 3.51;

// A CSV with columns t, x (two sines) and y (one sine) of `n` samples; returns its path.
std::string write_sines(const fs::path& dir, std::size_t n = 8192) {
  std::vector<double> t(n);
  for (std::size_t j = 0; j < n; ++j) t[j] = static_cast<double>(j) * dt;
  const auto x = npend::test::sum_of_sines({{1, omega_1, 0.1}, {0.5, omega_2, 0.3}}, n, dt);
  const auto y = npend::test::sum_of_sines({{2, omega_1, -0.4}}, n, dt);
  const std::vector<std::string> names{"t", "x", "y"};
  const std::vector<std::vector<double>> columns{t, x, y};
  const fs::path path = dir / "sines.csv";
  std::ofstream(path) << npend::cli::format_csv(names, columns);
  return path.string();
}

std::string write_text(const fs::path& dir, const std::string& name, const std::string& text) {
  std::ofstream(dir / name) << text;
  return (dir / name).string();
}

// The file's signal as the commands read it.
npend::time_series load(const std::string& path, const std::string& column) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return npend::cli::select_signal(
      npend::cli::signals_from_csv(npend::cli::parse_csv(text.str(), path), path, std::nullopt, 2),
      column, "--column");
}

}  // namespace

TEST_CASE("npend spectrum: --json peaks are the library's, strongest first, at the sines") {
  const fs::path dir = temporary_directory("cli-spectrum");
  const std::string file = write_sines(dir);
  const auto r = run_npend("spectrum --input " + file + " --json");
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  const auto x = load(file, "x");
  const auto s = npend::power_spectrum(x.values, x.dt);
  const auto peaks = npend::find_spectral_peaks(s);
  REQUIRE(j["peaks"].size() == peaks.size());
  REQUIRE(peaks.size() == 2);
  for (std::size_t k = 0; k < peaks.size(); ++k) {
    CHECK(j["peaks"][k]["omega"].get<double>() == peaks[k].omega);
    CHECK(j["peaks"][k]["power"].get<double>() == peaks[k].power);
  }
  CHECK(std::fabs(peaks[0].omega - omega_1) < s.resolution);
  CHECK(std::fabs(peaks[1].omega - omega_2) < s.resolution);
  CHECK(j["signal"] == "x");
  CHECK(j["samples"] == 8192);
  CHECK(j["dt"].get<double>() == doctest::Approx(dt).epsilon(1e-12));
  CHECK(j["window"] == "hann");
  // Another column, window and Welch segments.
  const auto w = nlohmann::json::parse(
      run_npend("spectrum --input " + file + " --column 3 --window blackman --segment 2048 --json")
          .out);
  CHECK(w["signal"] == "y");
  CHECK(w["segments"] == 7);
  CHECK(std::fabs(w["peaks"][0]["omega"].get<double>() - omega_1) < w["resolution"].get<double>());
}

TEST_CASE("npend spectrum: --out writes the spectrum, its peaks, the script and the plot") {
  const fs::path dir = temporary_directory("cli-spectrum-out");
  const std::string file = write_sines(dir);
  const auto r = run_npend("spectrum --input " + file + " --out " + (dir / "s.csv").string());
  REQUIRE(r.exit_code == 0);
  CHECK(npend::test::directory_listing(dir) ==
        std::vector<std::string>{"s.csv", "s.gp", "s.png", "s_peaks.csv", "sines.csv"});
  std::ifstream in(dir / "s.csv");
  std::stringstream text;
  text << in.rdbuf();
  const auto table = npend::cli::parse_csv(text.str(), "s.csv");
  CHECK(table.names == std::vector<std::string>{"omega", "power"});
  CHECK(table.columns[0].size() == 8192 / 2 + 1);
  CHECK(r.out.find("Files: ") != std::string::npos);
}

TEST_CASE("npend autocorrelation: --json first zero and minimum of a sine") {
  const fs::path dir = temporary_directory("cli-acf");
  const std::string file = write_sines(dir);
  const auto r = run_npend("autocorrelation --input " + file + " --column y --json");
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  const auto y = load(file, "y");
  const auto c = npend::autocorrelation(y.values, y.dt, y.values.size() / 2);
  CHECK(j["first_zero"].get<double>() == *c.first_zero);
  CHECK(j["first_minimum"].get<double>() == *c.first_minimum);
  CHECK(j["first_zero"].get<double>() == doctest::Approx(pi / 2 / omega_1).epsilon(2e-3));
  CHECK(run_npend("autocorrelation --input " + file + " --max-lag 0.1 --json").exit_code == 0);
  const auto bad = run_npend("autocorrelation --input " + file + " --max-lag 100");
  CHECK(bad.exit_code == 2);
  CHECK(bad.err.find("--max-lag: must be between") != std::string::npos);
}

TEST_CASE("npend recurrence: --json intervals of a sine are its half period") {
  const fs::path dir = temporary_directory("cli-recurrence");
  const std::string file = write_sines(dir);
  const auto r = run_npend("recurrence --input " + file + " --event y=0 --json");
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  REQUIRE(j["intervals"].size() > 10);
  for (const auto& t : j["intervals"])
    CHECK(t.get<double>() == doctest::Approx(pi / omega_1).epsilon(1e-8));
  CHECK(j["mean"].get<double>() == doctest::Approx(pi / omega_1).epsilon(1e-9));
  CHECK(j["count"] == j["intervals"].size() + 1);
  // Upward crossings only: a whole period apart.
  const auto up = nlohmann::json::parse(
      run_npend("recurrence --input " + file + " --event y=0 --direction up --json").out);
  CHECK(up["mean"].get<double>() == doctest::Approx(2 * pi / omega_1).epsilon(1e-9));
  // Two signals crossing (the stretched-neighbours event) against the library.
  const auto pair =
      nlohmann::json::parse(run_npend("recurrence --input " + file + " --event x=y --json").out);
  const auto x = load(file, "x"), y = load(file, "y");
  std::vector<double> g(x.values.size());
  for (std::size_t k = 0; k < g.size(); ++k) g[k] = x.values[k] - y.values[k];
  CHECK(pair["times"].get<std::vector<double>>() == npend::event_times(g, x.dt, {.t0 = x.t0}));
}

TEST_CASE("npend recurrence: --out writes the intervals, histogram, spectrum and plot") {
  const fs::path dir = temporary_directory("cli-recurrence-out");
  const std::string file = write_sines(dir);
  const auto r = run_npend("recurrence --input " + file + " --event x=0 --bins 12 --out " +
                           (dir / "r.csv").string());
  REQUIRE(r.exit_code == 0);
  CHECK(npend::test::directory_listing(dir) ==
        std::vector<std::string>{"r.csv", "r.gp", "r.png", "r_histogram.csv", "r_spectrum.csv",
                                 "sines.csv"});
}

TEST_CASE("npend embed: --json tau and dimension of a sine") {
  const fs::path dir = temporary_directory("cli-embed");
  const std::string file = write_sines(dir, 16384);
  const auto r = run_npend("embed --input " + file + " --column y --json");
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  const auto y = load(file, "y");
  const auto tau = npend::choose_delay(y.values, y.dt);
  CHECK(j["tau"].get<double>() == tau.seconds);
  CHECK(j["tau_samples"] == tau.samples);
  CHECK(j["tau_method"] == "ami");
  CHECK(j["dimension"] == 2);
  CHECK(j["dimension_method"] == "fnn");
  CHECK(j["false_neighbours"].size() == 10);
  // Each method, Cao's criterion, a given delay and a given dimension.
  const auto quarter = nlohmann::json::parse(
      run_npend("embed --input " + file + " --column y --tau T/4 --dim-method cao --json").out);
  CHECK(quarter["tau"].get<double>() == doctest::Approx(pi / 2 / omega_1).epsilon(0.01));
  CHECK(quarter["tau_method"] == "T/4");
  CHECK(quarter["dimension"] == 2);
  const auto given = nlohmann::json::parse(
      run_npend("embed --input " + file + " --column y --tau 0.1 --dim 3 --json").out);
  CHECK(given["tau"].get<double>() == doctest::Approx(0.1));
  CHECK(given["tau_method"] == "given");
  CHECK(given["dimension"] == 3);
  CHECK(run_npend("embed --input " + file + " --column y --out " + (dir / "e.csv").string())
            .exit_code == 0);
  CHECK(npend::test::directory_listing(dir) ==
        std::vector<std::string>{"e.csv", "e.gp", "e.png", "e_ami.csv", "e_dimension.csv",
                                 "sines.csv"});
}

TEST_CASE("npend time series: each bad input gets its message and exit status 2") {
  const fs::path dir = temporary_directory("cli-errors");
  const std::string sines = write_sines(dir, 64);
  const std::string text_cell = write_text(dir, "cell.csv", "t,x\n0,1\n0.1,2\n0.2,oops\n");
  std::string nan_rows = "t,x\n0,1\n0.1,NaN\n";
  for (int j = 2; j < 20; ++j) nan_rows += fmt::format("{},{}\n", 0.1 * j, j);
  const std::string nan_cell = write_text(dir, "nan.csv", nan_rows);
  const std::string short_file = write_text(dir, "short.csv", "t,x\n0,1\n0.1,2\n");
  std::string jitter = "t,x\n";
  for (int j = 0; j < 40; ++j)
    jitter += std::to_string(j == 20 ? 2.04 : 0.1 * j) + "," + std::to_string(j % 3) + "\n";
  const std::string uneven = write_text(dir, "uneven.csv", jitter);
  std::string bare;
  for (int j = 0; j < 40; ++j) bare += std::to_string(j % 5) + "\n";
  const std::string no_time = write_text(dir, "bare.csv", bare);
  const std::vector<std::pair<std::string, std::string>> cases{
      {"spectrum --input " + (dir / "missing.csv").string(),
       "--input: cannot read '" + (dir / "missing.csv").string() + "': No such file or directory"},
      {"spectrum --input " + sines + " --column z",
       "--column: " + sines + " has no column 'z'; its signals are x (2), y (3)"},
      {"spectrum --input " + text_cell, text_cell + ":4: column 'x': 'oops' is not a number"},
      {"autocorrelation --input " + nan_cell,
       "--column: column 'x' of " + nan_cell +
           " is nan at t = 0.1 s (data row 2); the columns analysed must be finite"},
      {"embed --input " + short_file, short_file + ": 2 samples; at least 64 are needed"},
      {"spectrum --input " + uneven, uneven + ":22: time column 't' is not uniformly spaced"},
      {"spectrum --input " + no_time,
       no_time +
           " has no time column (a header named t or time); give the sample spacing with --dt"},
      {"spectrum --input " + sines + " --dt 0.5", "--dt: 0.5 s disagrees with the time column 't'"},
      {"spectrum --input " + sines + " --window kaiser",
       "--window: 'kaiser' is not one of none, hann, hamming, blackman"},
      {"spectrum", "no time series: give --input FILE.csv, or a simulated start: --links N"},
      {"recurrence --input " + sines + " --event x", "--event: 'x' is not NAME=VALUE"},
      {"recurrence --input " + sines + " --event x=1e9",
       "--event: x=1e9 has 0 events in " + sines + "; at least 3 are needed"},
      {"embed --input " + sines + " --tau sometimes",
       "--tau: 'sometimes' is not auto, T/4, acf-zero, acf-min, ami or a delay in seconds"},
      {"spectrum --input " + sines + " --out " + (dir / "x.png").string(),
       "--out: '" + (dir / "x.png").string() + "' must be a file name ending in .csv"},
  };
  for (const auto& [args, message] : cases) {
    CAPTURE(args);
    const auto r = run_npend(args);
    CHECK(r.exit_code == 2);
    CHECK(r.err.find("error: " + message) != std::string::npos);
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);  // one line
  }
  CHECK(run_npend("spectrum --input " + no_time + " --dt 0.01 --json").exit_code == 0);
}

TEST_CASE("npend time series: a failure leaves no output file, and an old one untouched") {
  const fs::path dir = temporary_directory("cli-atomic");
  const std::string bad = write_text(dir, "bad.csv", "t,x\n0,1\n0.1,zzz\n");
  const fs::path out = dir / "out";
  fs::create_directories(out);
  for (const char* command : {"spectrum", "autocorrelation", "embed"}) {
    const auto r =
        run_npend(std::string(command) + " --input " + bad + " --out " + (out / "a.csv").string());
    CHECK(r.exit_code == 2);
  }
  CHECK(run_npend("recurrence --input " + bad + " --event x=0 --out " + (out / "a.csv").string())
            .exit_code == 2);
  CHECK(npend::test::directory_listing(out).empty());
  std::ofstream(out / "a.csv") << "previous\n";
  CHECK(run_npend("spectrum --input " + bad + " --out " + (out / "a.csv").string()).exit_code == 2);
  std::ifstream in(out / "a.csv");
  std::string line;
  std::getline(in, line);
  CHECK(line == "previous");
  CHECK(npend::test::directory_listing(out) == std::vector<std::string>{"a.csv"});
}

TEST_CASE("npend spectrum: without gnuplot the data and script are written, with a note") {
  const fs::path dir = temporary_directory("cli-no-gnuplot");
  const std::string file = write_sines(dir);
  const std::string saved = std::getenv("PATH");
  ::setenv("PATH", temporary_directory("cli-empty-path").c_str(), 1);
  const auto r =
      run_npend("spectrum --input " + file + " --json --out " + (dir / "s.csv").string());
  ::setenv("PATH", saved.c_str(), 1);
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  CHECK(j["files"].size() == 3);  // s.csv, s_peaks.csv, s.gp
  CHECK(j["notes"][0].get<std::string>().find("gnuplot is not installed") == 0);
  CHECK(r.err.find("note: gnuplot is not installed") == 0);
  CHECK(npend::test::directory_listing(dir) ==
        std::vector<std::string>{"s.csv", "s.gp", "s_peaks.csv", "sines.csv"});
}

TEST_CASE("npend time series: --help names every option") {
  for (const auto& [command, options] :
       std::vector<std::pair<std::string, std::vector<std::string>>>{
           {"spectrum",
            {"--input", "--column", "--dt", "--window", "--segment", "--overlap", "--peaks",
             "--threshold", "--prominence", "--omega-max", "--json", "--out"}},
           {"autocorrelation", {"--input", "--column", "--dt", "--max-lag", "--json", "--out"}},
           {"recurrence",
            {"--input", "--dt", "--event", "--direction", "--interpolation", "--bins", "--json",
             "--out"}},
           {"embed",
            {"--input", "--column", "--dt", "--tau", "--dim", "--dim-method", "--max-dim",
             "--theiler", "--json", "--out"}}}) {
    const auto r = run_npend(command + " --help");
    CHECK(r.exit_code == 0);
    for (const auto& o : options)
      CHECK_MESSAGE(r.out.find(o) != std::string::npos, command, " ", o);
  }
}

TEST_CASE("npend embed: a given dimension needs no dimension scan") {
  // 20 s at 1 ms with τ = 6 s: the scan up to --max-dim 10 would need 10 τ plus a Theiler
  // window of samples; two delay coordinates need just more than τ.
  const fs::path dir = temporary_directory("cli-embed-given");
  const std::string file = write_sines(dir, 20000);
  const auto scan = run_npend("embed --input " + file + " --column y --tau 6 --json");
  CHECK(scan.exit_code == 2);
  const auto r = run_npend("embed --input " + file + " --column y --tau 6 --dim 2 --json");
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  CHECK(j["dimension"] == 2);
  CHECK(j["vectors"] == 20000 - 6000);
  CHECK(j["false_neighbours"].is_null());
  CHECK(j["cao_e1"].is_null());
}

TEST_CASE("npend embed: the tau found by ami survives a failing dimension step") {
  const fs::path dir = temporary_directory("cli-embed-keep-tau");
  const std::string file = write_sines(dir, 2000);
  const auto found = nlohmann::json::parse(
      run_npend("embed --input " + file + " --column y --tau ami --dim 2 --json").out);
  const double tau = found["tau"].get<double>();
  const auto r = run_npend("embed --input " + file + " --column y --tau ami --max-dim 20");
  CHECK(r.exit_code == 2);
  CHECK(r.err.find(fmt::format("pass --tau {:.6g} to keep it", tau)) != std::string::npos);
}

TEST_CASE("npend embed: the mutual information curve, its bins and its first local minimum") {
  // A rotating arm: the unwrapped φ₃ of the chain started at 1.5, 1.5, 1.5 rad. Its I(τ)
  // has a first local minimum near 17 s and a deeper one later; the first is the one
  // Fraser & Swinney's rule takes (the former rule, a minimum on the scale of its own lag,
  // skipped it and reported 49.7 s).
  const fs::path dir = temporary_directory("cli-embed-ami");
  const auto r = run_npend(
      "embed --links 3 --phi 1.5,1.5,1.5 --coordinate phi3 --samples 65536 --dt 0.01 "
      "--tau ami --dim 2 --json --out " +
      (dir / "e.csv").string());
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  const auto& ami = j["mutual_information"];
  const auto tau = ami["tau"].get<std::vector<double>>();
  const auto info = ami["information"].get<std::vector<double>>();
  const auto h = ami["minimum_window"].get<std::size_t>();
  REQUIRE(tau.size() == info.size());
  // The first lag below its predecessor and lowest within ±h lags, scanned here afresh.
  std::optional<double> first;
  for (std::size_t k = 1; k + h < info.size() && !first; ++k) {
    bool lowest = info[k] < info[k - 1];
    for (std::size_t i = k > h ? k - h : 0; i <= k + h; ++i) lowest = lowest && info[i] >= info[k];
    if (lowest) first = tau[k];
  }
  REQUIRE(first);
  CHECK(ami["first_minimum"].get<double>() == doctest::Approx(*first));
  CHECK(j["tau"].get<double>() == doctest::Approx(*first));
  CHECK(*first < 25);
  // The written curve is the JSON's.
  const auto table = npend::cli::parse_csv(
      [&] {
        std::ifstream in(dir / "e_ami.csv");
        std::stringstream s;
        s << in.rdbuf();
        return s.str();
      }(),
      "e_ami.csv");
  CHECK(table.names == std::vector<std::string>{"tau", "I"});
  CHECK(table.columns[1].size() == info.size());
  // I(0) is the entropy of the binned series, at most log₂ of the bins.
  const auto coarse = nlohmann::json::parse(
      run_npend("embed --links 3 --phi 1.5,1.5,1.5 --coordinate phi3 --samples 4096 --dt 0.01 "
                "--tau ami --bins 4 --dim 2 --json")
          .out);
  CHECK(coarse["mutual_information"]["bins"] == 4);
  CHECK(coarse["mutual_information"]["information"][0].get<double>() <= 2 + 1e-12);
}

TEST_CASE("npend embed: false-neighbour tolerances and their per-criterion fractions") {
  const fs::path dir = temporary_directory("cli-embed-fnn");
  const std::string file = write_sines(dir);
  const auto at = [&](const std::string& options) {
    return nlohmann::json::parse(
        run_npend("embed --input " + file + " --column x --tau 0.1 --max-dim 4 --json " + options)
            .out);
  };
  const auto base = at("");
  CHECK(base["false_neighbours_options"]["rtol"] == 15.0);
  const auto fraction = base["false_neighbours"].get<std::vector<double>>();
  const auto by_distance = base["false_neighbours_distance"].get<std::vector<double>>();
  const auto by_attractor = base["false_neighbours_attractor"].get<std::vector<double>>();
  REQUIRE(fraction.size() == 4);
  for (std::size_t m = 0; m < 4; ++m) {
    // Either criterion: at least each one alone, at most both together.
    CHECK(fraction[m] >= std::max(by_distance[m], by_attractor[m]) - 1e-15);
    CHECK(fraction[m] <= by_distance[m] + by_attractor[m] + 1e-15);
  }
  // A huge R_tol and A_tol flag nothing; a tiny R_tol flags every neighbour in 1 dimension
  // whose added coordinate differs at all.
  const auto lax = at("--rtol 1e9 --atol 1e9");
  for (const double f : lax["false_neighbours"].get<std::vector<double>>()) CHECK(f == 0);
  const auto strict = at("--rtol 1e-9 --references 500");
  CHECK(strict["false_neighbours_options"]["reference_points"] == 500);
  CHECK(strict["false_neighbours_distance"][0].get<double>() > 0.99);
}

TEST_CASE("npend time series: a NaN in a column not analysed blocks nothing") {
  const fs::path dir = temporary_directory("cli-nan-column");
  std::string text = "t,x,y\n";
  for (int j = 0; j < 64; ++j)
    text += fmt::format("{},{},{}\n", 0.01 * j, std::sin(0.3 * j), j == 20 ? "nan" : "1e-3");
  const std::string file = write_text(dir, "nan.csv", text);
  const auto r = run_npend("autocorrelation --input " + file + " --column x --json");
  CHECK(r.exit_code == 0);
  CHECK(npend::test::is_input_error(run_npend("autocorrelation --input " + file + " --column y"),
                                    "--column: column 'y' of " + file +
                                        " is nan at t = 0.2 s (data row 21); the columns "
                                        "analysed must be finite"));
}

TEST_CASE("npend lyapunov: SIGTERM while reading an endless --input stops it, with a message") {
  // A pipe that delivers two rows and then nothing, without ever ending.
  const auto r = npend::test::run_shell(
      "(printf 't,x\\n0,1\\n'; sleep 4) | timeout --preserve-status -s TERM 1 " +
      std::string(NPEND_CLI_PATH) + " lyapunov --input /dev/stdin");
  INFO(r.err);
  CHECK(r.exit_code == 128 + 15);
  CHECK(r.err == "npend lyapunov: interrupted while reading '/dev/stdin'; nothing analysed\n");
}

namespace {

// TISEAN's `mutual`, written out independently: the series scaled to [0, 1] cut into `bins`
// equal boxes (the maximum in the last), and for each lag k the pairs (x_j, x_{j+k}):
// I = Σ p_ij ln(p_ij / (p_i p_j)) over bins × bins boxes, marginals of the same pairs (nats).
std::vector<double> tisean_mutual(const std::vector<double>& x, int bins, std::size_t lags) {
  const auto [lo, hi] = std::minmax_element(x.begin(), x.end());
  std::vector<int> box(x.size());
  for (std::size_t j = 0; j < x.size(); ++j)
    box[j] = std::min(bins - 1, static_cast<int>((x[j] - *lo) / (*hi - *lo) * bins));
  std::vector<double> information;
  for (std::size_t k = 0; k < lags; ++k) {
    std::vector<double> joint(static_cast<std::size_t>(bins * bins)), first(bins), second(bins);
    const std::size_t pairs = x.size() - k;
    for (std::size_t j = 0; j < pairs; ++j) {
      joint[static_cast<std::size_t>(box[j] * bins + box[j + k])] += 1.0 / pairs;
      first[static_cast<std::size_t>(box[j])] += 1.0 / pairs;
      second[static_cast<std::size_t>(box[j + k])] += 1.0 / pairs;
    }
    double sum = 0;
    for (int a = 0; a < bins; ++a)
      for (int b = 0; b < bins; ++b) {
        const double p = joint[static_cast<std::size_t>(a * bins + b)];
        if (p > 0) sum += p * std::log(p / (first[a] * second[b]));
      }
    information.push_back(sum);
  }
  return information;
}

}  // namespace

TEST_CASE("npend embed: the mutual-information delay of the weak triple pendulum is TISEAN's") {
  // The paper's weak excitation, as the demo starts it: the triple pendulum (1 kg, 1 m) at
  // rest in a zigzag (s, -s, s) with E = eps m g l, eps = 0.01; its potential
  // m g l (3 + 2 + 1)(1 - cos s) gives cos s = 1 - eps/6. 2^14 samples at 1 ms of x3.
  const fs::path dir = temporary_directory("cli-embed-weak-ami");
  const double s = std::acos(1 - 0.01 / 6);
  const std::string file = (dir / "weak.csv").string();
  REQUIRE(run_npend(fmt::format("simulate --links 3 --phi {0:.17g},{1:.17g},{0:.17g} --t-end "
                                "16.383 --dt 0.001 --out {2}",
                                s, -s, file))
              .exit_code == 0);
  const auto x = load(file, "x_3");
  REQUIRE(x.values.size() == 16384);
  const auto r = run_npend("embed --input " + file + " --column x_3 --tau ami --dim 2 --json");
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  const auto& ami = j["mutual_information"];
  CHECK(ami["estimator"] == "tisean");
  CHECK(ami["bins"] == 16);
  // The curve is TISEAN's histogram estimate at every lag (npend's in bits, TISEAN's in nats).
  const auto info = ami["information"].get<std::vector<double>>();
  const auto reference = tisean_mutual(x.values, 16, info.size());
  for (std::size_t k = 0; k < info.size(); ++k) {
    CAPTURE(k);
    CHECK(info[k] * std::log(2.0) == doctest::Approx(reference[k]).epsilon(1e-12));
  }
  // TISEAN's curve dips at 0.35-0.42 s: lower there than before and after.
  const auto lowest = [&](double from, double to) {
    double v = INFINITY;
    for (std::size_t k = 0; k < reference.size(); ++k)
      if (k * 0.001 >= from && k * 0.001 <= to) v = std::min(v, reference[k]);
    return v;
  };
  CHECK(lowest(0.35, 0.42) < lowest(0.25, 0.30));
  CHECK(lowest(0.35, 0.42) < lowest(0.42, 0.46));
  // And the delay is that first minimum.
  const double first = ami["first_minimum"].get<double>();
  CHECK(first >= 0.35);
  CHECK(first <= 0.42);
  CHECK(j["tau"].get<double>() == doctest::Approx(first));
  // The averaged shifted histograms smooth that dip away and take a later minimum.
  const auto averaged =
      nlohmann::json::parse(run_npend("embed --input " + file +
                                      " --column x_3 --tau ami --dim 2 --mi-estimator "
                                      "averaged --json")
                                .out);
  CHECK(averaged["mutual_information"]["estimator"] == "averaged");
  CHECK(averaged["mutual_information"]["first_minimum"].get<double>() > 0.42);
}
