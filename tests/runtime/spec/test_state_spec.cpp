// The number parsers of the specification library (npend/spec/number_parsing.hpp), the state
// and start-state specifications (state_spec.hpp) and the thread-count check: what they
// read, and the one-line message of what they refuse.
#include <doctest/doctest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "npend/chain.hpp"
#include "npend/spec/number_parsing.hpp"
#include "npend/spec/state_spec.hpp"
#include "npend/spec/thread_count.hpp"

using npend::spec::input_error;

namespace {

// The message `f` throws as spec::input_error ("" if it does not throw).
template <class F>
std::string state_spec_message(F&& f) {
  try {
    f();
  } catch (const input_error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("parse_number: finite numbers, a leading plus, spaces around") {
  using npend::spec::parse_number;
  CHECK(parse_number("1.5", "--x") == 1.5);
  CHECK(parse_number(" -2e-3\t", "--x") == -2e-3);
  CHECK(parse_number("+4", "--x") == 4);
  CHECK(state_spec_message([] { parse_number("nan", "--x"); }) ==
        "--x: 'nan' is not a finite number");
  CHECK(state_spec_message([] { parse_number("1e999", "--x"); }) ==
        "--x: '1e999' is out of the range of a double");
  CHECK(state_spec_message([] { parse_number("1,5", "--x"); }) == "--x: '1,5' is not a number");
  CHECK(state_spec_message([] { parse_number(" ", "--x"); }) == "--x: empty value");
}

TEST_CASE("parse_number_list: items by position in the message") {
  using npend::spec::parse_number_list;
  CHECK(parse_number_list("1, 2.5 ,-3", "--m") == std::vector<double>{1, 2.5, -3});
  CHECK(state_spec_message([] { parse_number_list("1,,2", "--m"); }) ==
        "--m: empty value (item 2 of '1,,2')");
  CHECK(state_spec_message([] { parse_number_list("1,2", "--m", 3, "three"); }) ==
        "--m: expected 3 values (three), got 2");
}

TEST_CASE("parse_angle_list: pi by name, one angle for every link") {
  using npend::spec::parse_angle_list;
  const double pi = std::numbers::pi;
  CHECK(parse_angle_list("pi,0,-pi", "--at", 3) == std::vector<double>{pi, 0, -pi});
  CHECK(parse_angle_list("pi", "--at", 2) == std::vector<double>{pi, pi});
  CHECK(state_spec_message([] { parse_angle_list("1,2", "--at", 3); }) ==
        "--at: expected 3 angles (phi_1..phi_3, numbers or pi) or one for all links, got 2");
}

TEST_CASE("parse_whole_number: whole numbers in the range, each other number refused") {
  using npend::spec::is_whole_number;
  using npend::spec::parse_whole_number;
  CHECK(is_whole_number(3, 1, 3));
  CHECK_FALSE(is_whole_number(2.5, 1, 3));
  CHECK_FALSE(is_whole_number(0, 1, 3));
  CHECK_FALSE(is_whole_number(4, 1, 3));
  CHECK_FALSE(is_whole_number(std::nan(""), 1, 3));
  CHECK(parse_whole_number("1e3", "--n", 2, 10000) == 1000);
  CHECK(state_spec_message([] { parse_whole_number("1", "--ensemble", 2, 10000); }) ==
        "--ensemble: must be a whole number 2..10000, got 1");
  CHECK(state_spec_message([] { parse_whole_number("2.5", "--seed", 0, 9.0e15); }) ==
        "--seed: must be a whole number 0..9e+15, got 2.5");
  CHECK(state_spec_message([] { parse_whole_number("x", "--n", 1, 2); }) ==
        "--n: 'x' is not a number");
}

TEST_CASE("parse_state: 2n numbers, phi then p") {
  CHECK(npend::spec::parse_state("1,2,3,4", npend::chain(npend::chain_parameters::uniform(2))) ==
        std::vector<double>{1, 2, 3, 4});
  CHECK(state_spec_message([] {
          npend::spec::parse_state("1,2,3", npend::chain(npend::chain_parameters::uniform(2)));
        }) == "--state: expected 4 values (phi_1..phi_2, p_1..p_2), got 3");
}

TEST_CASE("start_spec: angles with momenta or with angular velocities, p = m l^2 dphi") {
  // One link of 2 kg and 0.5 m: A = m l² = 0.5 kg m².
  npend::chain_parameters params = npend::chain_parameters::uniform(1, 2.0, 0.5);
  const npend::chain c(params);
  npend::spec::start_spec s;
  s.phi = "0.3";
  CHECK(s.make_state(c) == std::vector<double>{0.3, 0});
  s.p = "-1.5";
  CHECK(s.make_state(c) == std::vector<double>{0.3, -1.5});
  s.p.clear();
  s.dphi = "4";
  const std::vector<double> x = s.make_state(c);
  REQUIRE(x.size() == 2);
  CHECK(x[1] == doctest::Approx(0.5 * 4).epsilon(1e-14));
  s.p = "1";
  CHECK(state_spec_message([&] { s.make_state(c); }) ==
        "--p and --dphi exclude each other: give momenta or angular velocities");
  CHECK(state_spec_message([&] { npend::spec::start_spec{}.make_state(c); }) ==
        "no start state: give --phi (with --p or --dphi), or --energy E (see --help)");
}

TEST_CASE("start_spec: an energy with its excitation") {
  // The hanging pendulum of 1 kg and 1 m deflected to H = E: m g l (1 − cos φ) = E.
  const npend::chain c(npend::chain_parameters::uniform(1));
  npend::spec::start_spec s;
  s.energy = "2";
  const std::vector<double> x = s.make_state(c);
  REQUIRE(x.size() == 2);
  CHECK(9.81 * (1 - std::cos(x[0])) == doctest::Approx(2).epsilon(1e-12));
  CHECK(x[1] == 0);
  s.style = "sideways";
  CHECK(state_spec_message([&] { s.make_state(c); }).starts_with("--excitation: "));
  s.style.clear();
  s.energy = "-1";
  CHECK(state_spec_message([&] { s.make_state(c); }).starts_with("--energy: energy -1 J is below"));
}

TEST_CASE("check_thread_count: 0 (every core) or 1..4 x the hardware threads") {
  using npend::spec::check_thread_count;
  using npend::spec::max_threads;
  CHECK(max_threads() >= 4);
  CHECK(max_threads() % 4 == 0);
  CHECK_NOTHROW(check_thread_count(0, "threads"));
  CHECK_NOTHROW(check_thread_count(max_threads(), "threads"));
  const int bound = max_threads();
  CHECK(state_spec_message([] { check_thread_count(-1, "threads"); }) ==
        "threads: 0 (every core) or 1.." + std::to_string(bound) + " (4 x the " +
            std::to_string(bound / 4) + " hardware threads), got -1");
  CHECK_THROWS_AS(check_thread_count(bound + 1, "--threads"), std::invalid_argument);
}
