// The variational equations in Taylor form: the generated recurrences run on dual numbers
// (taylor_kernels::coefficients_dual) against the double kernels, the exact Jacobian and
// finite differences of the coefficients; taylor_tangents' vectors against central
// differences of the flow and the symplectic structure the exact flow keeps.
#include <doctest/doctest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "npend/chain.hpp"
#include "npend/integrators/taylor.hpp"
#include "npend/integrators/taylor_recurrences.hpp"

using npend::chain;
using npend::taylor::dual;

namespace taylor_tangents_test {

// The three models' kernels: point masses, rods with springs and damping on a shaken pivot
// (time-dependent inputs), and the chain on a cart.
std::vector<std::pair<std::string, npend::chain_parameters>> models() {
  npend::chain_parameters masses = npend::chain_parameters::uniform(3);
  masses.masses = {1.0, 2.0, 1.5};
  masses.lengths = {1.0, 0.7, 1.2};
  npend::chain_parameters physical = npend::chain_parameters::uniform(2, 1.0, 0.5);
  physical.make_uniform_rods();
  physical.stiffness = {0.0, 2.0};
  physical.damping = {0.01, 0.02};
  physical.pivot = npend::pivot_motion::vertical(0.01, 60);
  npend::chain_parameters cart = npend::chain_parameters::uniform(2);
  cart.cart_mass = 2.0;
  cart.cart_damping = 0.1;
  return {{"point masses", masses}, {"physical, shaken pivot", physical}, {"cart", cart}};
}

std::vector<double> start_of(const chain& c) {
  std::vector<double> x(static_cast<std::size_t>(c.state_size()));
  for (std::size_t i = 0; i < x.size(); ++i)
    x[i] = 0.7 * std::sin(1.3 * static_cast<double>(i) + 0.4);
  return x;
}

std::vector<double> direction_of(const chain& c) {
  std::vector<double> w(static_cast<std::size_t>(c.state_size()));
  for (std::size_t i = 0; i < w.size(); ++i) w[i] = std::cos(0.9 * static_cast<double>(i) + 0.2);
  return w;
}

// The double kernels' coefficients of order 0..order through x at t = 0.
std::vector<double> double_coefficients(const chain& c, const std::vector<double>& x, int order) {
  const npend::kernel_set& k = c.kernels_in_use();
  const npend::taylor_kernels& t = *k.taylor();
  const auto stride = static_cast<std::size_t>(order + 1);
  std::vector<double> inputs(static_cast<std::size_t>(t.input_size) * stride),
      series(x.size() * stride), work(static_cast<std::size_t>(t.work_slots) * stride);
  if (t.input_size > 0) k.input_series(0.0, order, inputs.data());
  for (std::size_t i = 0; i < x.size(); ++i) series[i * stride] = x[i];
  t.coefficients(k.packed().data(), inputs.data(), order, series.data(), work.data());
  return series;
}

// The dual kernels' coefficients through x with derivative w, at t = 0.
std::vector<dual> dual_coefficients(const chain& c, const std::vector<double>& x,
                                    const std::vector<double>& w, int order) {
  const npend::kernel_set& k = c.kernels_in_use();
  const npend::taylor_kernels& t = *k.taylor();
  const auto stride = static_cast<std::size_t>(order + 1);
  std::vector<double> input_values(static_cast<std::size_t>(t.input_size) * stride);
  if (t.input_size > 0) k.input_series(0.0, order, input_values.data());
  const std::vector<dual> params(k.packed().begin(), k.packed().end()),
      inputs(input_values.begin(), input_values.end());
  std::vector<dual> series(x.size() * stride),
      work(static_cast<std::size_t>(t.work_slots) * stride);
  for (std::size_t i = 0; i < x.size(); ++i) series[i * stride] = {x[i], w[i]};
  t.coefficients_dual(params.data(), inputs.data(), order, series.data(), work.data());
  return series;
}

}  // namespace taylor_tangents_test

using namespace taylor_tangents_test;

TEST_CASE(
    "taylor kernels on dual numbers: the values are the double kernels', the derivatives J w "
    "and the coefficients' own derivatives") {
  constexpr int order = 8;
  constexpr auto stride = static_cast<std::size_t>(order + 1);
  for (const auto& [name, parameters] : models()) {
    CAPTURE(name);
    const chain c(parameters);
    const auto x = start_of(c), w = direction_of(c);
    const std::size_t d = x.size();
    const auto plain = double_coefficients(c, x, order);
    const auto duals = dual_coefficients(c, x, w, order);
    // The values: the same operations in the same order as the double recurrences.
    double worst_value = 0;
    for (std::size_t i = 0; i < plain.size(); ++i)
      worst_value = std::max(worst_value,
                             std::fabs(duals[i].v - plain[i]) / std::max(1.0, std::fabs(plain[i])));
    CHECK(worst_value < 1e-14);
    // Order 1 of the tangent: w' = J(x) w, J the generated exact Jacobian.
    std::vector<double> jac(d * d);
    c.jacobian(x, jac, 0.0);
    double worst_jw = 0;
    for (std::size_t i = 0; i < d; ++i) {
      double jw = 0;
      for (std::size_t j = 0; j < d; ++j) jw += jac[i * d + j] * w[j];
      worst_jw = std::max(worst_jw,
                          std::fabs(duals[i * stride + 1].d - jw) / std::max(1.0, std::fabs(jw)));
    }
    CHECK(worst_jw < 1e-13);
    // Every order: the derivative of the double coefficient along w, by central differences
    // (error ≈ h² times the third derivative, and round-off/h).
    constexpr double h = 1e-5;
    std::vector<double> up = x, down = x;
    for (std::size_t i = 0; i < d; ++i) {
      up[i] += h * w[i];
      down[i] -= h * w[i];
    }
    const auto plus = double_coefficients(c, up, order),
               minus = double_coefficients(c, down, order);
    double worst_fd = 0, scale = 0;
    for (std::size_t i = 0; i < plain.size(); ++i) {
      worst_fd = std::max(worst_fd, std::fabs(duals[i].d - (plus[i] - minus[i]) / (2 * h)));
      scale = std::max(scale, std::fabs(duals[i].d));
    }
    INFO("largest derivative ", scale, ", central differences off by ", worst_fd);
    CHECK(worst_fd < 1e-7 * scale);
  }
}

TEST_CASE(
    "taylor_tangents: the vectors are the flow's derivative, symplectic, and the state the "
    "taylor stepper's") {
  const chain c(npend::chain_parameters::uniform(3));
  const std::vector<double> x0{0.5, -0.3, 0.4, 0.1, 0.0, -0.2};
  constexpr double t_end = 5, tol = 1e-14;
  const auto d = static_cast<Eigen::Index>(x0.size());
  const Eigen::MatrixXd identity = Eigen::MatrixXd::Identity(d, d);
  npend::taylor_tangents tangents(c.kernels_in_use(), tol, tol, static_cast<int>(d));
  tangents.reset(0, x0.data(), identity.data());
  while (t_end - tangents.time() > 1e-13) tangents.step(1, t_end - tangents.time(), 0.1);
  const Eigen::Map<const Eigen::MatrixXd> M(tangents.tangents().data(), d, d);

  // The flow φ_t by the state-only taylor integrator at the same tolerance.
  const auto flow = [&](const std::vector<double>& x) {
    npend::taylor_integrator<double> integrator(c.kernels_in_use(), 1e-15, 1e-15);
    integrator.reset(0, x.data());
    while (t_end - integrator.time() > 1e-13) integrator.step(1, t_end - integrator.time(), 0.1);
    return integrator.state();
  };
  const auto end = flow(x0);
  double state_difference = 0;
  for (std::size_t i = 0; i < x0.size(); ++i)
    state_difference = std::max(state_difference, std::fabs(tangents.state()[i] - end[i]));
  INFO("state against the taylor stepper's ", state_difference);
  CHECK(state_difference < 1e-11);

  // Column j of M against (φ(x0 + h e_j) − φ(x0 − h e_j)) / 2h.
  constexpr double h = 1e-5;
  double worst = 0;
  for (Eigen::Index j = 0; j < d; ++j) {
    std::vector<double> up = x0, down = x0;
    up[static_cast<std::size_t>(j)] += h;
    down[static_cast<std::size_t>(j)] -= h;
    const auto plus = flow(up), minus = flow(down);
    for (Eigen::Index i = 0; i < d; ++i)
      worst = std::max(worst, std::fabs(M(i, j) - (plus[static_cast<std::size_t>(i)] -
                                                   minus[static_cast<std::size_t>(i)]) /
                                                      (2 * h)));
  }
  const double scale = M.cwiseAbs().maxCoeff();
  INFO("largest entry ", scale, ", central differences off by ", worst);
  CHECK(worst < 1e-6 * scale);

  // The exact flow of a Hamiltonian system is symplectic: MᵀΩM = Ω, det M = 1.
  Eigen::MatrixXd Omega = Eigen::MatrixXd::Zero(d, d);
  Omega.topRightCorner(d / 2, d / 2) = Eigen::MatrixXd::Identity(d / 2, d / 2);
  Omega.bottomLeftCorner(d / 2, d / 2) = -Eigen::MatrixXd::Identity(d / 2, d / 2);
  CHECK((M.transpose() * Omega * M - Omega).cwiseAbs().maxCoeff() < 1e-11 * scale * scale);
  CHECK(std::fabs(M.determinant() - 1) < 1e-10);
}

TEST_CASE("taylor_tangents: refusals name the problem") {
  using doctest::Contains;
  const chain c(npend::chain_parameters::uniform(2));
  CHECK_THROWS_WITH_AS(npend::taylor_tangents(c.kernels_in_use(), 1e-10, 1e-10, 0),
                       Contains("at least one"), std::invalid_argument);
  CHECK_THROWS_WITH_AS(npend::taylor_tangents(c.kernels_in_use(), -1, 1e-10, 1),
                       Contains("tolerances"), std::invalid_argument);
  const chain loops(npend::chain_parameters::uniform(8));
  CHECK_THROWS_WITH_AS(npend::taylor_tangents(loops.kernels_in_use(), 1e-10, 1e-10, 1),
                       Contains("Taylor kernels"), std::invalid_argument);
}
