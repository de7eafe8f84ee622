// The strict parser of sections and events (`phi3=0`, `phi2=phi3`, `p1=0.5`), coordinate
// names and projections: what it accepts, the one-line message of everything it refuses, and
// that arbitrary text only ever gives such a message.
#include <doctest/doctest.h>

#include <random>
#include <string>
#include <vector>

#include "input_parsing.hpp"
#include "section_spec.hpp"

using npend::cli::input_error;
using npend::cli::parse_coordinate;
using npend::cli::parse_projection;
using npend::cli::parse_section_spec;
using npend::cli::section_from_spec;

namespace {

// The message `f` throws as input_error ("" if it does not throw).
template <class F>
std::string message_of(F&& f) {
  try {
    f();
  } catch (const input_error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("parse_section_spec: levels and names, spaces around them ignored") {
  const auto level = parse_section_spec("phi3=0", "--section");
  CHECK(level.left == "phi3");
  REQUIRE(level.level);
  CHECK(*level.level == 0.0);
  CHECK(level.right.empty());
  const auto names = parse_section_spec(" phi2 =\tphi3 ", "--section");
  CHECK(names.left == "phi2");
  CHECK_FALSE(names.level);
  CHECK(names.right == "phi3");
  CHECK(*parse_section_spec("p1=0.5", "--section").level == 0.5);
  CHECK(*parse_section_spec("p1=-1e-3", "--section").level == -1e-3);
  CHECK(*parse_section_spec("p1=+2", "--section").level == 2.0);
  CHECK(*parse_section_spec("x=.25", "--event").level == 0.25);
  // CSV column names may have inner spaces and non-ASCII letters.
  CHECK(parse_section_spec("angle 3=φ2", "--event").right == "φ2");
}

TEST_CASE("parse_section_spec: each malformed spec gets its one-line message") {
  const std::vector<std::pair<std::string, std::string>> cases{
      {"",
       "--section: '' is not NAME=VALUE (a level, e.g. phi3=0) or NAME=NAME (two "
       "coordinates, e.g. phi2=phi3): it needs exactly one '='"},
      {"phi3", "--section: 'phi3' is not NAME=VALUE"},
      {"phi3==0", "--section: 'phi3==0' is not NAME=VALUE"},
      {"phi3=0=1", "--section: 'phi3=0=1' is not NAME=VALUE"},
      {"=0", "--section: '=0' has no name left of '='"},
      {" \t=phi2", "--section: ' \\x09=phi2' has no name left of '='"},
      {"phi3=", "--section: 'phi3=' has nothing right of '='"},
      {"phi3=  ", "--section: 'phi3=  ' has nothing right of '='"},
      {"phi3=1.2.3", "--section: '1.2.3' is not a number"},
      {"phi3=-", "--section: '-' is not a number"},
      {"phi3=1e999", "--section: '1e999' is out of the range of a double"},
      {"phi3=0x10", "--section: '0x10' is not a number"},
      {"phi3=0\n", "--section: '0\\x0a' is not a number"},
      {"ph\x01i3=0", "--section: 'ph\\x01i3=0' has a control character or a quote in a name"},
      {"phi3=\"p1\"", "--section: 'phi3=\"p1\"' has a control character or a quote in a name"},
  };
  for (const auto& [text, message] : cases) {
    CAPTURE(text);
    const std::string got = message_of([&] { parse_section_spec(text, "--section"); });
    CHECK(got.find(message) == 0);
    CHECK(got.find('\n') == std::string::npos);
  }
}

TEST_CASE("parse_coordinate: phiK, phi_K, pK, p_K for K = 1..n, nothing else") {
  CHECK(parse_coordinate("phi1", 3, "--x") == 0);
  CHECK(parse_coordinate("phi3", 3, "--x") == 2);
  CHECK(parse_coordinate("phi_2", 3, "--x") == 1);
  CHECK(parse_coordinate("p1", 3, "--x") == 3);
  CHECK(parse_coordinate("p_3", 3, "--x") == 5);
  CHECK(parse_coordinate("p12", 12, "--x") == 23);
  for (const char* bad : {"phi0",  "phi4",  "p4",     "phi01",  "Phi1",           "PHI1",
                          "phi",   "p",     "p_",     "q1",     "phi1x",          "phi-1",
                          "phi+1", "phi 1", "phi__1", "phi1.0", "phi99999999999", "theta1",
                          "x",     ""}) {
    CAPTURE(bad);
    CHECK(message_of([&] { parse_coordinate(bad, 3, "--section"); }) ==
          "--section: '" + std::string(bad) +
              "' is not a coordinate of the 3-link chain; its coordinates are phi1..phi3 and "
              "p1..p3 (also written phi_1, p_1)");
  }
  CHECK(message_of([] { parse_coordinate("phi2", 1, "--x"); }) ==
        "--x: 'phi2' is not a coordinate of the 1-link chain; its coordinates are phi1 and p1 "
        "(also written phi_1, p_1)");
}

TEST_CASE("section_from_spec: level and equal-coordinate planes of the state") {
  const auto level = section_from_spec(parse_section_spec("p2=0.5", "--s"), 3, "--s");
  CHECK(level.normal == std::vector<double>{0, 0, 0, 0, 1, 0});
  CHECK(level.level == 0.5);
  const auto stretched = section_from_spec(parse_section_spec("phi2=phi_3", "--s"), 3, "--s");
  CHECK(stretched.normal == std::vector<double>{0, 1, -1, 0, 0, 0});
  CHECK(stretched.level == 0.0);
  CHECK(message_of([] { section_from_spec(parse_section_spec("phi2=phi_2", "--s"), 3, "--s"); }) ==
        "--s: 'phi2=phi_2' compares phi2 with itself");
  CHECK(message_of([] {
          section_from_spec(parse_section_spec("phi4=0", "--s"), 3, "--s");
        }).find("--s: 'phi4' is not a coordinate of the 3-link chain") == 0);
  CHECK(message_of([] {
          section_from_spec(parse_section_spec("phi1=nan", "--s"), 3, "--s");
        }).find("--s: 'nan' is not a coordinate") == 0);
}

TEST_CASE("parse_projection: two distinct coordinates") {
  CHECK(parse_projection("phi3,p3", 3, "--project") == std::pair<std::size_t, std::size_t>{2, 5});
  CHECK(parse_projection(" p1 , phi_2 ", 3, "--project") ==
        std::pair<std::size_t, std::size_t>{3, 1});
  CHECK(message_of([] { parse_projection("phi3", 3, "--project"); }) ==
        "--project: 'phi3' is not two coordinates A,B (e.g. phi3,p3)");
  CHECK(message_of([] { parse_projection("phi3,p3,p1", 3, "--project"); }) ==
        "--project: 'phi3,p3,p1' is not two coordinates A,B (e.g. phi3,p3)");
  CHECK(message_of([] { parse_projection("phi3,phi_3", 3, "--project"); }) ==
        "--project: 'phi3,phi_3' names phi3 twice");
  CHECK(message_of([] {
          parse_projection("phi3,", 3, "--project");
        }).find("--project: '' is not a coordinate") == 0);
}

TEST_CASE("parse_direction: up, down, both") {
  CHECK(npend::cli::parse_direction("up", "--d") == npend::crossing_direction::up);
  CHECK(npend::cli::parse_direction("down", "--d") == npend::crossing_direction::down);
  CHECK(npend::cli::parse_direction("both", "--d") == npend::crossing_direction::both);
  CHECK(message_of([] { npend::cli::parse_direction("Up", "--d"); }) ==
        "--d: 'Up' is not up, down or both");
}

TEST_CASE("parse_section_spec: arbitrary text gives a section or a one-line input_error") {
  // A cheap fuzz: valid specs with up to three random edits, built from the grammar's pieces
  // and from trouble (control characters, quotes, a second '=', non-ASCII letters).
  const std::vector<std::string> valid{"phi1=0",     "phi3=-0.5", "p2=1e-3",
                                       "phi_2=phi3", "p_1=p3",    "phi2=p1"};
  const std::vector<std::string> pieces{"phi",  "p",    "_",  "1",  "3",   "0", "4",       "=",
                                        "-",    "+",    ".",  "5e", "e9",  " ", "\t",      "\n",
                                        "\x01", "\x7f", "\"", ",",  "nan", "x", "\xcf\x86"};
  std::mt19937_64 rng(5);
  const auto pick = [&](std::size_t n) {
    return std::uniform_int_distribution<std::size_t>(0, n - 1)(rng);
  };
  std::size_t accepted = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    std::string text = valid[pick(valid.size())];
    for (std::size_t edit = pick(4); edit > 0; --edit) {
      const std::size_t at = pick(text.size() + 1);
      switch (pick(3)) {
        case 0:
          text.insert(at, pieces[pick(pieces.size())]);
          break;
        case 1:
          if (at < text.size()) text.erase(at, 1);
          break;
        default:
          if (at < text.size()) text.replace(at, 1, pieces[pick(pieces.size())]);
      }
    }
    CAPTURE(text);
    try {
      const auto plane = section_from_spec(parse_section_spec(text, "--section"), 3, "--section");
      REQUIRE(plane.normal.size() == 6);
      ++accepted;
    } catch (const input_error& e) {
      REQUIRE(std::string(e.what()).find('\n') == std::string::npos);
      REQUIRE(std::string(e.what()).find("--section: ") == 0);
    }
  }
  CHECK(accepted > 0);
}
