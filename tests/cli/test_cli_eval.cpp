// `npend eval` as a user runs it: JSON keys and values, and each bad input's message and
// exit status.
#include <doctest/doctest.h>

#include <chrono>
#include <fstream>
#include <nlohmann/json.hpp>

#include "npend/chain.hpp"
#include "support/test_support.hpp"

using npend::test::run_npend;

TEST_CASE("npend eval: --json prints the generated functions at the state") {
  const auto r = run_npend(
      "eval --links 3 --masses 1,2,1.5 --lengths 1,0.5,2 --g 9.81 "
      "--state 0.3,-0.2,0.5,0.1,0.2,-0.1 --json");
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.out);
  for (const char* key : {"links", "hamiltonian", "rhs", "jacobian", "mass_matrix",
                          "det_mass_matrix", "kinetic_energy", "potential_energy"})
    CHECK_MESSAGE(j.contains(key), key);
  CHECK(j["links"] == 3);
  CHECK(j["rhs"].size() == 6);
  REQUIRE(j["jacobian"].size() == 6);
  CHECK(j["jacobian"][0].size() == 6);
  CHECK(j["mass_matrix"].size() == 3);

  // The printed numbers round-trip to the library's values exactly.
  npend::chain_parameters params{{1, 2, 1.5}, {1, 0.5, 2}, 9.81};
  const npend::chain c(params);
  const std::vector<double> x{0.3, -0.2, 0.5, 0.1, 0.2, -0.1};
  CHECK(j["hamiltonian"].get<double>() == c.hamiltonian(x));
  CHECK(j["rhs"].get<std::vector<double>>() == c.rhs(x));
  const auto J = c.jacobian(x);
  CHECK(j["jacobian"][2][4].get<double>() == J[2 * 6 + 4]);
}

TEST_CASE("npend eval: readable output by default") {
  const auto r = run_npend("eval --links 2 --state 0.1,0.2,0,0");
  CHECK(r.exit_code == 0);
  CHECK(r.out.find("H = ") != std::string::npos);
  CHECK(r.out.find("J (Jacobian") != std::string::npos);
}

TEST_CASE("npend eval: bad input gets a one-line message naming the problem, exit status 2") {
  struct bad_case {
    const char* args;
    const char* message;
  };
  const bad_case cases[] = {
      {"eval --links 2 --state 0,0,0",
       "--state: expected 4 values (phi_1..phi_2, p_1..p_2), got 3"},
      {"eval --links 3 --masses 1,2 --state 0,0,0,0,0,0",
       "--masses: expected 3 values (m_1..m_3) or one for all links, got 2"},
      {"eval --links 2 --masses 1,-2 --state 0,0,0,0",
       "mass 2 is -2: it must be a positive finite number"},
      {"eval --links 2 --lengths 1,0 --state 0,0,0,0",
       "length 2 is 0: it must be a positive finite number"},
      {"eval --links 2 --g 0 --state 0,0,0,0", "g is 0: it must be a positive finite number"},
      {"eval --links 2 --state 0,nan,0,0",
       "--state: 'nan' is not a finite number (item 2 of '0,nan,0,0')"},
      {"eval --links 2 --state 0,inf,0,0", "--state: 'inf' is not a finite number"},
      {"eval --links 2 --state 0,x,0,0", "--state: 'x' is not a number (item 2 of '0,x,0,0')"},
      {"eval --links 2 --state 0,,0,0", "--state: empty value (item 2 of '0,,0,0')"},
      {"eval --links 2 --state 0,1e999,0,0", "--state: '1e999' is out of the range of a double"},
      {"eval --links 99 --damping 0.1 --state 0,0",
       "the physical chain of 99 links is not built into this program"},
      {"eval --links 0 --state 0,0", "--links: must be at least 1, got 0"},
      {"eval --links 2 --state 0,0,0,0 --bogus",
       "The following argument was not expected: --bogus"},
  };
  for (const auto& bad : cases) {
    const auto r = run_npend(bad.args);
    INFO("npend ", bad.args, " -> ", r.err);
    CHECK(r.exit_code == 2);
    CHECK(r.err.find(bad.message) != std::string::npos);
    CHECK(r.out.empty());
    // One line: the message and its newline.
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
  }
}

TEST_CASE("npend equations: prints the derived LaTeX for a link count") {
  const auto r = run_npend("equations --links 2");
  CHECK(r.exit_code == 0);
  CHECK(r.out.find("\\begin{align*}") != std::string::npos);
  CHECK(r.out.find("A_{12} &= \\mu_{2} l_{1} l_{2} \\cos(\\varphi_{1} - \\varphi_{2})") !=
        std::string::npos);
}

TEST_CASE("npend eval: one value of --masses or --lengths is every link's") {
  const auto one =
      run_npend("eval --links 3 --masses 2 --lengths 0.5 --state 0.3,-0.2,0.5,0.1,0.2,-0.1 --json");
  const auto all = run_npend(
      "eval --links 3 --masses 2,2,2 --lengths 0.5,0.5,0.5 --state 0.3,-0.2,0.5,0.1,0.2,-0.1 "
      "--json");
  REQUIRE(one.exit_code == 0);
  REQUIRE(all.exit_code == 0);
  CHECK(one.out == all.out);
  const auto j = nlohmann::json::parse(one.out);
  CHECK(j["masses"] == std::vector<double>{2, 2, 2});
  CHECK(j["lengths"] == std::vector<double>{0.5, 0.5, 0.5});
}

namespace {

// A --chain file with `text` in a fresh folder; returns its path.
std::string chain_file(const std::string& folder, const std::string& text) {
  const std::string file = npend::test::temporary_directory(folder) + "/chain.json";
  std::ofstream(file) << text;
  return file;
}

}  // namespace

TEST_CASE("npend eval --chain: a list longer than the link count is refused as it is read") {
  // 300000 items took 27 s (a superlinear path) before the length was checked while parsing;
  // now item 4 of a 3-link chain's list stops the parse.
  std::string list = "1";
  list.reserve(2 * 300000);
  for (int i = 1; i < 300000; ++i) list += ",1";
  const std::string file = chain_file("chain-long-list", R"({"masses": [)" + list + "]}");
  const auto start = std::chrono::steady_clock::now();
  const auto r = run_npend("eval --links 3 --chain " + file + " --state 0,0,0,0,0,0");
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  CHECK(npend::test::is_input_error(
      r,
      "\"masses\": expected 3 values (m_1..m_3) or one number for all links, got a longer "
      "list"));
  CHECK(seconds < 2.0);
}

TEST_CASE("npend eval --chain: --no-rods and --rods override the file's rods, com and inertia") {
  const std::string rods = chain_file("chain-rods", R"({"lengths": 0.5, "rods": true})");
  const std::string state = " --state 0.3,-0.2,0.1,0.2 --json";
  const auto rhs = [](const npend::test::command_result& r) {
    REQUIRE(r.exit_code == 0);
    return nlohmann::json::parse(r.out)["rhs"].get<std::vector<double>>();
  };
  // --no-rods: the point masses of the same lengths, as without the file.
  const npend::chain point({{1, 1}, {0.5, 0.5}, 9.81});
  const std::vector<double> x{0.3, -0.2, 0.1, 0.2};
  CHECK(rhs(run_npend("eval --links 2 --chain " + rods + " --no-rods" + state)) == point.rhs(x));
  // --no-rods --com: the command line's centres of mass.
  npend::chain_parameters p{{1, 1}, {0.5, 0.5}, 9.81};
  p.com = {0.3, 0.3};
  CHECK(rhs(run_npend("eval --links 2 --chain " + rods + " --no-rods --com 0.3" + state)) ==
        npend::chain(p).rhs(x));
  // The file's rods with --com from the command line: refused, pointing to --no-rods.
  CHECK(npend::test::is_input_error(
      run_npend("eval --links 2 --chain " + rods + " --com 0.3" + state), "add --no-rods"));
  // --rods over a file's com and inertia: uniform rods.
  const std::string com =
      chain_file("chain-com", R"({"lengths": 0.5, "com": [0.1, 0.2], "inertia": 0.01})");
  p.make_uniform_rods();
  CHECK(rhs(run_npend("eval --links 2 --chain " + com + " --rods" + state)) ==
        npend::chain(p).rhs(x));
}
