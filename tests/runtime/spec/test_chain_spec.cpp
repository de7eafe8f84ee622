// The chain specification both front ends fill (npend/spec/chain_spec.hpp): the parameters
// it gives, the defaults it leaves, the messages of what it refuses in the spelling of each
// front end, and chain files.
#include <doctest/doctest.h>

#include <numbers>
#include <sstream>
#include <string>

#include "npend/spec/chain_spec.hpp"

using npend::chain_parameters;
using npend::spec::chain_spec;
using npend::spec::input_error;
using npend::spec::naming;

namespace {

// The message `f` throws as spec::input_error ("" if it does not throw).
template <class F>
std::string chain_spec_message(F&& f) {
  try {
    f();
  } catch (const input_error& e) {
    return e.what();
  }
  return "";
}

chain_spec links_spec(int links) {
  chain_spec s;
  s.links = links;
  return s;
}

}  // namespace

TEST_CASE("chain_spec: what is left out takes the paper's defaults") {
  const chain_parameters p = make_parameters(links_spec(3), naming::options);
  CHECK(p.masses == std::vector<double>{1, 1, 1});
  CHECK(p.lengths == std::vector<double>{1, 1, 1});
  CHECK(p.g == 9.81);
  CHECK(p.com.empty());
  CHECK(p.inertia.empty());
  CHECK(p.stiffness.empty());
  CHECK(p.rest_angles.empty());
  CHECK(p.damping.empty());
  CHECK_FALSE(p.pivot.moves());
  CHECK_FALSE(p.is_physical());
}

TEST_CASE("chain_spec: one value stands for every link, n values for one link each") {
  chain_spec s = links_spec(3);
  s.masses = {2};
  s.lengths = {0.5, 1, 1.5};
  s.g = 1.62;
  s.damping = {0.1};
  const chain_parameters p = make_parameters(s, naming::options);
  CHECK(p.masses == std::vector<double>{2, 2, 2});
  CHECK(p.lengths == std::vector<double>{0.5, 1, 1.5});
  CHECK(p.g == 1.62);
  CHECK(p.damping == std::vector<double>{0.1, 0.1, 0.1});
  CHECK(p.is_damped());
}

TEST_CASE("chain_spec: rods are uniform, c = l/2 and J = m l^2/12") {
  chain_spec s = links_spec(2);
  s.masses = {3, 2};
  s.lengths = {2, 0.6};
  s.rods = true;
  const chain_parameters p = make_parameters(s, naming::options);
  REQUIRE(p.com.size() == 2);
  REQUIRE(p.inertia.size() == 2);
  CHECK(p.com[0] == doctest::Approx(1.0).epsilon(1e-15));
  CHECK(p.com[1] == doctest::Approx(0.3).epsilon(1e-15));
  CHECK(p.inertia[0] == doctest::Approx(3.0 * 4.0 / 12.0).epsilon(1e-15));   // 1 kg m²
  CHECK(p.inertia[1] == doctest::Approx(2.0 * 0.36 / 12.0).epsilon(1e-15));  // 0.06 kg m²
}

TEST_CASE("chain_spec: a pivot drive is read with its amplitude and frequency") {
  chain_spec s = links_spec(1);
  s.pivot = "horizontal:0.25:40";
  const chain_parameters p = make_parameters(s, naming::options);
  CHECK(p.pivot.type == npend::pivot_motion::kind::horizontal);
  CHECK(p.pivot.amplitude == 0.25);
  CHECK(p.pivot.frequency == 40);
  CHECK(p.pivot.period() == doctest::Approx(2 * std::numbers::pi / 40).epsilon(1e-15));
}

TEST_CASE("chain_spec: refusals name the option or the keyword") {
  chain_spec counts = links_spec(3);
  counts.masses = {1, 2};
  CHECK(chain_spec_message([&] { make_parameters(counts, naming::options); }) ==
        "--masses: expected 3 values (m_1..m_3) or one for all links, got 2");
  CHECK(chain_spec_message([&] { make_parameters(counts, naming::keywords); }) ==
        "masses: expected 3 values (m_1..m_3) or one for all links, got 2");

  CHECK(chain_spec_message([] { make_parameters(links_spec(0), naming::options); }) ==
        "--links: must be at least 1, got 0");
  CHECK(chain_spec_message([] { make_parameters(links_spec(-2), naming::keywords); }) ==
        "links: must be at least 1, got -2");

  chain_spec rods = links_spec(1);
  rods.rods = true;
  rods.com = {0.3};
  CHECK(chain_spec_message([&] { make_parameters(rods, naming::options); }) ==
        "--rods sets the centres of mass and inertias: leave out --com and --inertia");

  chain_spec rest = links_spec(2);
  rest.rest_angles = {0.1};
  CHECK(chain_spec_message([&] { make_parameters(rest, naming::options); }) ==
        "--rest-angles: the rest angles of the joint springs need springs: give --stiffness "
        "(without it they change nothing)");
  rest.stiffness = {0};  // springs of stiffness 0 are no springs
  CHECK(chain_spec_message([&] { make_parameters(rest, naming::keywords); }) ==
        "rest_angles: the rest angles of the joint springs need springs: give stiffness "
        "(without it they change nothing)");

  chain_spec pivot = links_spec(1);
  pivot.pivot = "sideways:1:2";
  CHECK(chain_spec_message([&] { make_parameters(pivot, naming::options); }) ==
        "--pivot: expected vertical:A:OMEGA or horizontal:A:OMEGA, got 'sideways:1:2'");
  pivot.pivot = "vertical:x:2";
  CHECK(chain_spec_message([&] { make_parameters(pivot, naming::keywords); }) ==
        "pivot (amplitude): 'x' is not a number");
}

TEST_CASE("chain_spec: make_chain turns the chain's own refusal into input_error") {
  chain_spec s = links_spec(2);
  s.masses = {1, -1};
  const std::string message = chain_spec_message([&] { make_chain(s, naming::keywords); });
  CHECK(message.find("mass") != std::string::npos);
  CHECK_THROWS_AS(make_chain(s, naming::keywords), std::invalid_argument);
  CHECK(make_chain(links_spec(2), naming::keywords).links() == 2);
}

TEST_CASE("chain_spec: argument_name spells a key as an option or a keyword") {
  CHECK(argument_name("rest_angles", naming::options) == "--rest-angles");
  CHECK(argument_name("rest_angles", naming::keywords) == "rest_angles");
  CHECK(argument_name("g", naming::options) == "--g");
}

TEST_CASE("read_chain_file: keys fill the spec, one number stands for every link") {
  std::istringstream in(
      R"({"links": 2, "masses": [1.5, 2], "lengths": 0.5, "g": 3.7, "rods": true,
          "pivot": "vertical:0.01:100", "damping": [0, 0.25]})");
  const chain_spec s = npend::spec::read_chain_file(in, "--chain f.json", 2);
  CHECK(s.links == 2);
  CHECK(s.masses == std::vector<double>{1.5, 2});
  CHECK(s.lengths == std::vector<double>{0.5});
  REQUIRE(s.g);
  CHECK(*s.g == 3.7);
  CHECK(s.rods);
  CHECK(s.pivot == "vertical:0.01:100");
  CHECK(s.damping == std::vector<double>{0, 0.25});
  CHECK(s.com.empty());
  const chain_parameters p = make_parameters(s, naming::options);
  CHECK(p.lengths == std::vector<double>{0.5, 0.5});
  CHECK(p.com == std::vector<double>{0.25, 0.25});
}

TEST_CASE("read_chain_file: the cart's keys fill the spec's cart") {
  std::istringstream in(R"({"links": 1, "cart": 2.5, "cart_damping": 0.1})");
  const chain_spec s = npend::spec::read_chain_file(in, "--chain f.json", 1);
  REQUIRE(s.cart);
  CHECK(*s.cart == 2.5);
  REQUIRE(s.cart_damping);
  CHECK(*s.cart_damping == 0.1);
  const chain_parameters p = make_parameters(s, naming::options);
  REQUIRE(p.cart_mass);
  CHECK(*p.cart_mass == 2.5);
  CHECK(p.cart_damping == 0.1);
  std::istringstream bad(R"({"cart": "heavy"})");
  CHECK_THROWS_WITH_AS(npend::spec::read_chain_file(bad, "--chain f.json", 1),
                       "--chain f.json: \"cart\" must be a number", npend::spec::input_error);
}

TEST_CASE("read_chain_file: each problem of the file is one message naming it and the key") {
  const auto message = [](const std::string& text, int links) {
    std::istringstream in(text);
    return chain_spec_message([&] { npend::spec::read_chain_file(in, "--chain c.json", links); });
  };
  CHECK(message(R"({"masss": 1})", 1) ==
        "--chain c.json: unknown key \"masss\" (known: links, masses, lengths, g, com, inertia, "
        "rods, stiffness, rest_angles, damping, pivot, cart, cart_damping)");
  CHECK(message(R"({"masses": 1, "masses": 2})", 2) == "--chain c.json: \"masses\" is given twice");
  CHECK(message(R"({"com": [0.5]})", 2) ==
        "--chain c.json: \"com\": expected 2 values (c_1..c_2) or one number for all links, got "
        "a list of 1");
  CHECK(message(R"({"com": [0.5, 0.5, 0.5]})", 2) ==
        "--chain c.json: \"com\": expected 2 values (c_1..c_2) or one number for all links, got "
        "a longer list");
  CHECK(message(R"({"links": 3})", 2) ==
        "--chain c.json: the file describes 3 links, the command line asks for 2");
  CHECK(message(R"({"links": 2.5})", 2) == "--chain c.json: \"links\" must be a whole number");
  CHECK(message(R"({"rods": 1})", 2) == "--chain c.json: \"rods\" must be true or false");
  CHECK(message(R"({"g": "9.81"})", 2) == "--chain c.json: \"g\" must be a number");
  CHECK(message(R"({"masses": ["1", 2]})", 2) ==
        "--chain c.json: \"masses\" must be a number or a list of numbers");
  CHECK(message(R"([1, 2])", 2) == "--chain c.json: the file must hold one JSON object");
  CHECK(message(R"({"masses": )", 2).starts_with("--chain c.json: not valid JSON ("));
}

TEST_CASE("format_values: the text reads back as the same doubles") {
  const std::vector<double> values{0.1, 1.0 / 3.0, -2e-300, 6.02214076e23};
  const std::string text = npend::spec::format_values(values);
  std::vector<double> back;
  std::istringstream in(text);
  for (std::string item; std::getline(in, item, ',');) back.push_back(std::stod(item));
  CHECK(back == values);
  CHECK(npend::spec::format_values({}).empty());
}
