// The hand-written O(n) recursion of the physical chain
// (tests/reference/include/reference/physical_recursion.hpp) against the dense hand-written
// chain at any n, and the generated physical kernels against it at every committed n — with
// every feature on: rigid links, springs, damping, a pivot's acceleration and joint torques.
#include <doctest/doctest.h>

#include <chain_index.hpp>
#include <random>
#include <stdexcept>

#include "npend/parameters.hpp"
#include "reference/dense_chain.hpp"
#include "reference/physical_recursion.hpp"
#include "support/test_support.hpp"

namespace {

struct physical_case {
  npend::chain_parameters params;
  double ax, ay;
  std::vector<double> torques;
};

physical_case random_case(int n, std::mt19937_64& rng) {
  physical_case out{npend::test::random_parameters(n, rng), 0, 0, {}};
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  auto& p = out.params;
  for (int i = 0; i < n; ++i) {
    const double l = p.lengths[static_cast<std::size_t>(i)];
    p.com.push_back((0.1 + 1.2 * unit(rng)) * l);  // also below the lower joint
    p.inertia.push_back(0.3 * unit(rng));
    p.stiffness.push_back(5 * unit(rng));
    p.rest_angles.push_back(unit(rng) - 0.5);
    p.damping.push_back(0.5 * unit(rng));
    out.torques.push_back(2 * unit(rng) - 1);
  }
  out.ax = 4 * unit(rng) - 2;
  out.ay = 4 * unit(rng) - 2;
  return out;
}

npend::reference::physical_recursion recursion_of(const physical_case& c) {
  const auto& p = c.params;
  npend::reference::physical_recursion r(p.masses, p.lengths, p.g, p.com, p.inertia, p.stiffness,
                                         p.rest_angles, p.damping);
  r.set_inputs(c.ax, c.ay, c.torques);
  return r;
}

}  // namespace

TEST_CASE("physical_recursion: equals the dense hand-written chain for n = 1 to 40") {
  std::mt19937_64 rng(1317);
  for (const int n : {1, 2, 3, 5, 9, 17, 40}) {
    const physical_case c = random_case(n, rng);
    const auto& p = c.params;
    auto dense = npend::reference::dense_chain::physical(p.masses, p.lengths, p.g, p.com, p.inertia,
                                                         p.stiffness, p.rest_angles, p.damping);
    dense.set_inputs(c.ax, c.ay, c.torques);
    auto recursion = recursion_of(c);
    const auto x = npend::test::random_state(n, rng);
    std::vector<double> f(x.size());
    recursion.rhs(x.data(), f.data());
    const Eigen::VectorXd expected = dense.rhs(npend::test::to_eigen(x));
    INFO("n = " << n);
    CHECK(npend::test::relative_error(f, std::span(expected.data(), x.size())) < 1e-11);
  }
}

TEST_CASE("physical_recursion: the generated physical kernels equal it at every committed n") {
  std::mt19937_64 rng(1319);
  for (int n = 1; n <= 6; ++n) {
    const npend::physical_kernels* kernels = npend::generated::find_physical(n);
    REQUIRE(kernels != nullptr);
    for (int trial = 0; trial < 4; ++trial) {
      const physical_case c = random_case(n, rng);
      auto recursion = recursion_of(c);
      const auto x = npend::test::random_state(n, rng);
      std::vector<double> expected(x.size()), f(x.size());
      recursion.rhs(x.data(), expected.data());
      std::vector<double> inputs{c.ax, c.ay};
      inputs.insert(inputs.end(), c.torques.begin(), c.torques.end());
      const auto packed = c.params.physical_packed();
      kernels->rhs(x.data(), packed.data(), inputs.data(), f.data());
      INFO("n = " << n << ", trial " << trial);
      CHECK(npend::test::relative_error(f, expected) < 1e-12);
    }
  }
}

TEST_CASE("physical_recursion: rejects mismatched sizes and an empty chain") {
  const std::vector<double> two{1.0, 1.0}, one{1.0}, none;
  using npend::reference::physical_recursion;
  CHECK_THROWS_AS(physical_recursion(two, one, 9.81, two, two, two, two, two),
                  std::invalid_argument);
  CHECK_THROWS_AS(physical_recursion(none, none, 9.81, none, none, none, none, none),
                  std::invalid_argument);
  physical_recursion r(one, one, 9.81, one, one, one, one, one);
  CHECK_THROWS_AS(r.set_inputs(0, 0, two), std::invalid_argument);
}
