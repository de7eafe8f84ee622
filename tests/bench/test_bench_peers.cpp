// The benchmarks' implementations (bench/chain_implementation.hpp: the hand-written
// recursion and dense Eigen chains and SymPy's generated C) agree with the generated
// kernels, so that the benchmark never times a wrong answer. Not a timing test.
#include <doctest/doctest.h>

#include <optional>
#include <string>

#include "chain_implementation.hpp"
#include "support/test_support.hpp"
#include "sympy_kernels.hpp"
#include "workload.hpp"

using npend::bench::make_implementation;
using npend::test::relative_error;

namespace {

constexpr std::size_t states = 200;
constexpr double tolerance = 1e-12;

struct agreement {
  double rhs = 0;
  std::optional<double> jacobian;  ///< empty when the implementation has no Jacobian
};

// Worst relative errors of `impl` against the generated kernels over a pool of states.
agreement compare_with_generated(std::string_view impl, int n) {
  const auto params = npend::bench::random_parameters(n, 40u + static_cast<unsigned>(n));
  const npend::bench::state_pool pool(n, states, 50u + static_cast<unsigned>(n));
  auto reference = make_implementation("generated", params);
  auto peer = make_implementation(impl, params);
  REQUIRE(reference);
  REQUIRE(peer);
  const std::size_t d = pool.state_size;
  std::vector<double> f_ref(d), f(d), J_ref(d * d), J(d * d);
  agreement worst;
  for (std::size_t s = 0; s < pool.count; ++s) {
    reference->rhs(pool.state(s), f_ref.data());
    peer->rhs(pool.state(s), f.data());
    worst.rhs = std::max(worst.rhs, relative_error(f, f_ref));
    if (!peer->has_jacobian()) continue;
    reference->jacobian(pool.state(s), J_ref.data());
    peer->jacobian(pool.state(s), J.data());
    worst.jacobian = std::max(worst.jacobian.value_or(0.0), relative_error(J, J_ref));
  }
  return worst;
}

// Both kernels of `impl` against the generated ones at each of `links`.
void check_rhs_and_jacobian(const std::string& impl, const std::vector<int>& links) {
  for (const int n : links) {
    const agreement worst = compare_with_generated(impl, n);
    INFO(impl, " at n = ", n, ": worst relative error rhs ", worst.rhs, ", jacobian ",
         worst.jacobian.value_or(-1));
    CHECK(worst.rhs < tolerance);
    REQUIRE(worst.jacobian);
    CHECK(*worst.jacobian < tolerance);
  }
}

}  // namespace

TEST_CASE("make_implementation: the recursion's rhs agrees with the generated kernels") {
  for (const int n : npend::built_link_counts()) {
    const agreement worst = compare_with_generated("recursion", n);
    INFO("recursion at n = ", n, ": worst relative error ", worst.rhs);
    CHECK(worst.rhs < tolerance);
  }
}

TEST_CASE(
    "make_implementation: the physical chain's recursion on point masses agrees with the "
    "generated kernels") {
  for (const int n : npend::built_link_counts()) {
    const agreement worst = compare_with_generated("physical-recursion", n);
    INFO("physical-recursion at n = ", n, ": worst relative error ", worst.rhs);
    CHECK(worst.rhs < tolerance);
  }
}

TEST_CASE(
    "make_implementation: the dense Eigen rhs and Jacobian agree with the generated kernels") {
  check_rhs_and_jacobian("eigen", npend::built_link_counts());
}

TEST_CASE("make_implementation: SymPy's generated C agrees with the generated kernels") {
  const std::vector<int> links = npend::bench::sympy_link_counts();
  REQUIRE_MESSAGE(!links.empty(),
                  "no SymPy code in this build: install python3-sympy (tools/setup.sh) and "
                  "reconfigure, or set NPEND_SYMPY_PYTHON");
  check_rhs_and_jacobian("sympy", links);
}

TEST_CASE(
    "make_implementation: the physical kernels on point masses agree with the generated "
    "ones") {
  check_rhs_and_jacobian("physical", {1, 2, 3, 4, 5, 6});
}

TEST_CASE("make_implementation: knows its implementations and the link counts they cover") {
  const auto params = npend::chain_parameters::uniform(3);
  for (const auto name : npend::bench::implementation_names)
    CHECK_MESSAGE(make_implementation(name, params) != nullptr, name);
  CHECK_FALSE(make_implementation("recursion", params)->has_jacobian());
  CHECK_FALSE(make_implementation("physical-recursion", params)->has_jacobian());
  CHECK(make_implementation("generated", npend::chain_parameters::uniform(63)) == nullptr);
  CHECK(make_implementation("sympy", npend::chain_parameters::uniform(63)) == nullptr);
  CHECK(make_implementation("physical", npend::chain_parameters::uniform(63)) == nullptr);
  CHECK_THROWS_AS(make_implementation("pinocchio", params), std::invalid_argument);
}
