// The chain as an odeint system, and the stepper names.
#include <doctest/doctest.h>

#include <numbers>
#include <span>

#include "npend/chain_system.hpp"
#include "npend/integrators/stepper_kind.hpp"
#include "support/test_support.hpp"

using npend::chain;

TEST_CASE("chain_system: calls the generated rhs for vectors, spans and Eigen vectors") {
  std::mt19937_64 rng(31);
  for (int n = 1; n <= 6; ++n) {
    const chain c(npend::test::random_parameters(n, rng));
    const auto x = npend::test::random_state(n, rng);
    const npend::chain_system sys(c);
    CHECK(sys.size() == 2 * n);
    const std::vector<double> expected = c.rhs(x);

    std::vector<double> dxdt(x.size());
    sys(x, dxdt, 0.0);
    CHECK(dxdt == expected);

    std::vector<double> via_span(x.size());
    std::span<double> out(via_span);
    sys(std::span<const double>(x), out, 1.0);
    CHECK(via_span == expected);

    const Eigen::VectorXd xe = npend::test::to_eigen(x);
    Eigen::VectorXd fe(2 * n);
    sys(xe, fe, 2.0);
    CHECK(npend::test::relative_error(std::span<const double>(fe.data(), x.size()), expected) == 0);
  }
}

TEST_CASE("chain_jacobian: fills a row-major Eigen matrix with the exact Jacobian, dfdt = 0") {
  std::mt19937_64 rng(32);
  for (int n = 1; n <= 6; ++n) {
    const chain c(npend::test::random_parameters(n, rng));
    const auto x = npend::test::random_state(n, rng);
    const auto [rhs, jac] = npend::make_implicit_system(c);
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> J(2 * n, 2 * n);
    std::vector<double> dfdt(x.size(), 1.0);
    jac(x, J, 0.0, dfdt);
    CHECK(npend::test::relative_error(J, npend::test::to_eigen(c.jacobian(x), 2 * n, 2 * n)) == 0);
    for (double v : dfdt) CHECK(v == 0);
  }
}

TEST_CASE("chain_system: wrong sizes are refused, naming the argument") {
  const chain c(npend::chain_parameters::uniform(2));
  const npend::chain_system sys(c);
  std::vector<double> x(3), dxdt(4);
  CHECK_THROWS_WITH_AS(sys(x, dxdt, 0.0), "state x has 3 entries; the system has dimension 4",
                       std::invalid_argument);
  x.resize(4);
  dxdt.resize(5);
  CHECK_THROWS_WITH_AS(sys(x, dxdt, 0.0), "dxdt has 5 entries; the system has dimension 4",
                       std::invalid_argument);
  const npend::chain_jacobian jac(c);
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> J(3, 4);
  std::vector<double> dfdt(4);
  CHECK_THROWS_WITH_AS(jac(x, J, 0.0, dfdt),
                       "jacobian (rows) has 3 entries; the system has dimension 4",
                       std::invalid_argument);
}

TEST_CASE("parse_stepper_kind: every name round-trips, an unknown one lists the valid names") {
  for (const auto k : npend::all_stepper_kinds()) {
    CHECK(npend::parse_stepper_kind(npend::stepper_name(k)) == k);
    CHECK_FALSE(npend::stepper_description(k).empty());
  }
  CHECK(npend::all_stepper_kinds().size() == 8);
  CHECK(npend::stepper_names() == "rk4, dopri5, rkf78, bs, rosenbrock4, gauss4, gauss6, taylor");
  CHECK(npend::stepper_names(npend::stepper_use::system) ==
        "rk4, dopri5, rkf78, bs, rosenbrock4, gauss4, gauss6");
  CHECK(npend::stepper_names(npend::stepper_use::adaptive) ==
        "dopri5, rkf78, bs, rosenbrock4, taylor");
  CHECK(npend::stepper_names(npend::stepper_use::monodromy) == "gauss6, taylor");
  CHECK(npend::stepper_names(npend::stepper_use::indicators) == "rk4, taylor");
  CHECK_THROWS_WITH_AS(
      npend::parse_stepper_kind("euler"),
      "unknown stepper 'euler': choose one of rk4, dopri5, rkf78, bs, rosenbrock4, "
      "gauss4, gauss6, taylor",
      std::invalid_argument);
}

TEST_CASE("model contract: every built kernel table takes the layout the runtime packs") {
  for (int n : npend::built_link_counts()) {
    CAPTURE(n);
    npend::chain_parameters p = npend::chain_parameters::uniform(n, 2.0, 3.0, 7.0);
    p.masses.back() = 5.0;
    p.lengths.front() = 11.0;
    const npend::chain c(p);
    CHECK(c.kernels().state_size == npend::chain_layout::state_size(n));
    CHECK(c.kernels().param_size == npend::chain_layout::param_size(n));
    const std::vector<double>& packed = c.packed_parameters();
    REQUIRE(packed.size() == static_cast<std::size_t>(npend::chain_layout::param_size(n)));
    CHECK(packed[static_cast<std::size_t>(npend::chain_layout::mass_index(n, n - 1))] == 5.0);
    CHECK(packed[static_cast<std::size_t>(npend::chain_layout::length_index(n, 0))] == 11.0);
    CHECK(packed[static_cast<std::size_t>(npend::chain_layout::gravity_index(n))] == 7.0);
    // The kernels read the parameters where the layout puts them: the hanging chain's
    // potential energy at phi_1 = pi/2 is m-weighted heights from the first length alone.
    std::vector<double> phi(static_cast<std::size_t>(n), 0.0);
    phi[0] = std::numbers::pi / 2;
    double total_mass = 0;
    for (double m : p.masses) total_mass += m;
    CHECK(c.potential_energy(phi) == doctest::Approx(7.0 * 11.0 * total_mass));
  }
}
