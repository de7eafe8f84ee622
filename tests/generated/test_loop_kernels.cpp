// The loop kernels (generated/chain_loop.*), which serve every link count without unrolled
// kernels: against the unrolled kernels (checked exactly by npend-gen --verify) for n = 1..6,
// against the hand-written dense implementation and O(n) recursion for long chains, J·u
// against J and finite differences, and the chain class choosing them.
#include <doctest/doctest.h>

#include <chain_index.hpp>
#include <chain_loop.hpp>
#include <cmath>
#include <string>
#include <vector>

#include "npend/chain.hpp"
#include "npend/integrators/integrate.hpp"
#include "reference/chain_recursion.hpp"
#include "reference/dense_chain.hpp"
#include "support/test_support.hpp"

using npend::chain;
using npend::test::relative_error;
using npend::test::to_eigen;
namespace loops = npend::generated::chain_loop;

namespace {

// Exactly the sizes the header promises, so that the sanitized build catches a kernel that
// reads or writes past them.
std::vector<double> workspace(int n) {
  return std::vector<double>(static_cast<std::size_t>(loops::workspace_size(n)));
}
std::vector<double> jacobian_workspace(int n) {
  return std::vector<double>(loops::jacobian_workspace_size(n));
}

// The worst relative error of each loop kernel against the unrolled one of n links.
struct kernel_errors {
  double rhs = 0, jacobian = 0, hamiltonian = 0, velocities = 0, momenta = 0, kinetic = 0,
         potential = 0, lagrangian = 0, mass_matrix = 0, det = 0, gradient = 0, hessian = 0,
         positions = 0;
};

double scalar_error(double a, double b) { return std::fabs(a - b) / std::max(std::fabs(b), 1.0); }

void compare_with_unrolled(int n, std::mt19937_64& rng, kernel_errors& e) {
  const npend::chain_kernels& k = *npend::generated::find_chain(n);
  const auto params = npend::test::random_parameters(n, rng).packed();
  const auto x = npend::test::random_state(n, rng);
  const double* phi = x.data();
  const double* p = x.data() + n;
  const auto dim = static_cast<std::size_t>(2 * n), nn = static_cast<std::size_t>(n);
  auto work = workspace(n);
  std::vector<double> a(dim * dim), b(dim * dim);
  const auto compare = [&](std::size_t size, double& worst) {
    worst = std::max(worst, relative_error(std::span(a).first(size), std::span(b).first(size)));
  };
  loops::rhs(n, x.data(), params.data(), a.data(), work.data());
  k.rhs(x.data(), params.data(), b.data());
  compare(dim, e.rhs);
  auto jacobian_work = jacobian_workspace(n);
  loops::jacobian(n, x.data(), params.data(), a.data(), jacobian_work.data());
  k.jacobian(x.data(), params.data(), b.data());
  compare(dim * dim, e.jacobian);
  e.hamiltonian = std::max(e.hamiltonian,
                           scalar_error(loops::hamiltonian(n, x.data(), params.data(), work.data()),
                                        k.hamiltonian(x.data(), params.data())));
  loops::velocities(n, phi, p, params.data(), a.data(), work.data());
  k.velocities(phi, p, params.data(), b.data());
  compare(nn, e.velocities);
  const std::vector<double> dphi(b.begin(), b.begin() + n);  // φ̇ of the state
  loops::momenta(n, phi, dphi.data(), params.data(), a.data(), work.data());
  k.momenta(phi, dphi.data(), params.data(), b.data());
  compare(nn, e.momenta);
  e.kinetic =
      std::max(e.kinetic,
               scalar_error(loops::kinetic_energy(n, phi, dphi.data(), params.data(), work.data()),
                            k.kinetic_energy(phi, dphi.data(), params.data())));
  e.potential = std::max(e.potential,
                         scalar_error(loops::potential_energy(n, phi, params.data(), work.data()),
                                      k.potential_energy(phi, params.data())));
  e.lagrangian = std::max(
      e.lagrangian, scalar_error(loops::lagrangian(n, phi, dphi.data(), params.data(), work.data()),
                                 k.lagrangian(phi, dphi.data(), params.data())));
  loops::mass_matrix(n, phi, params.data(), a.data(), work.data());
  k.mass_matrix(phi, params.data(), b.data());
  compare(nn * nn, e.mass_matrix);
  const double det = k.det_mass_matrix(phi, params.data());
  e.det =
      std::max(e.det, std::fabs(loops::det_mass_matrix(n, phi, params.data(), work.data()) - det) /
                          std::fabs(det));
  loops::potential_gradient(n, phi, params.data(), a.data(), work.data());
  k.potential_gradient(phi, params.data(), b.data());
  compare(nn, e.gradient);
  loops::potential_hessian(n, phi, params.data(), a.data(), work.data());
  k.potential_hessian(phi, params.data(), b.data());
  compare(nn * nn, e.hessian);
  loops::positions(n, phi, params.data(), a.data(), work.data());
  k.positions(phi, params.data(), b.data());
  compare(dim, e.positions);
}

}  // namespace

TEST_CASE("loop kernels: every function agrees with the unrolled kernels, n = 1..6") {
  for (int n = 1; n <= 6; ++n) {
    std::mt19937_64 rng(700 + static_cast<unsigned>(n));
    kernel_errors e;
    for (int sample = 0; sample < 100; ++sample) compare_with_unrolled(n, rng, e);
    INFO("n = ", n, ": rhs ", e.rhs, ", jacobian ", e.jacobian, ", H ", e.hamiltonian,
         ", velocities ", e.velocities, ", momenta ", e.momenta, ", T ", e.kinetic, ", V ",
         e.potential, ", L ", e.lagrangian, ", A ", e.mass_matrix, ", det A ", e.det, ", dV ",
         e.gradient, ", d2V ", e.hessian, ", positions ", e.positions);
    for (const double err :
         {e.rhs, e.jacobian, e.hamiltonian, e.velocities, e.momenta, e.kinetic, e.potential,
          e.lagrangian, e.mass_matrix, e.det, e.gradient, e.hessian, e.positions})
      CHECK(err < 1e-12);
  }
}

TEST_CASE("loop kernels: long chains against the dense implementation and the O(n) recursion") {
  std::mt19937_64 rng(811);
  for (const int n : {7, 12, 30}) {
    const auto params = npend::test::random_parameters(n, rng);
    const npend::reference::dense_chain dense(params.masses, params.lengths, params.g);
    const chain c(params);
    REQUIRE(c.runs_on_loops());
    const auto x = npend::test::random_state(n, rng);
    const Eigen::VectorXd xe = to_eigen(x);
    INFO("n = ", n);
    CHECK(relative_error(to_eigen(c.rhs(x)), dense.rhs(xe)) < 1e-11);
    CHECK(relative_error(to_eigen(c.jacobian(x), 2 * n, 2 * n), dense.jacobian(xe)) < 1e-10);
    CHECK(std::fabs(c.hamiltonian(x) - dense.hamiltonian(xe)) / std::fabs(dense.hamiltonian(xe)) <
          1e-12);
  }
  for (const int n : {100, 1000}) {
    const auto params = npend::test::random_parameters(n, rng);
    npend::reference::chain_recursion recursion(params.masses, params.lengths, params.g);
    const chain c(params);
    const auto x = npend::test::random_state(n, rng, 0.3);
    std::vector<double> want(x.size());
    recursion.rhs(x.data(), want.data());
    INFO("n = ", n);
    CHECK(relative_error(c.rhs(x), want) < 1e-10);
  }
}

TEST_CASE("loop kernels: ln det A of a long chain of short links, where det A underflows") {
  npend::chain_parameters params;
  const int n = 100;
  std::mt19937_64 rng(813);
  params = npend::test::random_parameters(n, rng);
  for (auto& l : params.lengths) l *= 0.01;
  const chain c(params);
  const auto x = npend::test::random_state(n, rng);
  const std::span<const double> phi(x.data(), static_cast<std::size_t>(n));
  std::vector<double> a(static_cast<std::size_t>(n * n));
  c.mass_matrix(phi, a);
  // Independent: the Cholesky factor of A itself.
  const Eigen::LLT<Eigen::MatrixXd> llt(to_eigen(a, n, n));
  REQUIRE(llt.info() == Eigen::Success);
  const double want = 2 * llt.matrixL().toDenseMatrix().diagonal().array().log().sum();
  CHECK(c.det_mass_matrix(phi) == 0.0);  // underflows: why the log exists
  CHECK(std::fabs(c.log_det_mass_matrix(phi) - want) < 1e-10 * std::fabs(want));
}

TEST_CASE("loop kernels: J u equals the Jacobian times u and a central difference of f") {
  std::mt19937_64 rng(812);
  const int n = 40;
  const chain c(npend::test::random_parameters(n, rng));
  const auto x = npend::test::random_state(n, rng);
  const auto u = npend::test::random_state(n, rng, 1.0);
  std::vector<double> ju(x.size());
  c.jacobian_vector(x, u, ju);
  const Eigen::VectorXd product = to_eigen(c.jacobian(x), 2 * n, 2 * n) * to_eigen(u);
  CHECK(relative_error(to_eigen(ju), product) < 1e-13);
  // f(x + h u) − f(x − h u) = 2h J u + O(h³).
  const double h = 1e-6;
  std::vector<double> plus(x), minus(x);
  for (std::size_t i = 0; i < x.size(); ++i) {
    plus[i] += h * u[i];
    minus[i] -= h * u[i];
  }
  const auto fp = c.rhs(plus), fm = c.rhs(minus);
  std::vector<double> difference(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) difference[i] = (fp[i] - fm[i]) / (2 * h);
  CHECK(relative_error(difference, ju) < 1e-7);
}

TEST_CASE("loop kernels: a 100-link chain conserves its energy") {
  npend::chain_parameters params;
  const int n = 100;
  params.masses.assign(n, 0.01);
  params.lengths.assign(n, 0.01);
  params.g = 9.81;
  const chain c(params);
  REQUIRE(c.runs_on_loops());
  std::vector<double> phi(n), dphi(n, 0.0);
  for (int k = 0; k < n; ++k) phi[static_cast<std::size_t>(k)] = 0.8 * std::sin(0.05 * k);
  const auto x0 = c.state_from_velocities(phi, dphi);
  npend::integration_options o;
  o.stepper = npend::stepper_kind::dopri5;
  o.t_end = 1.0;
  o.dt = 1e-3;
  o.abs_tol = o.rel_tol = 1e-11;
  const auto result = npend::integrate(c, x0, o);
  const double h0 = c.hamiltonian(x0), h1 = c.hamiltonian(result.state);
  const double scale = params.g * 1.0 * 1.0;  // M g L of the whole rope
  CHECK(std::fabs(h1 - h0) / scale < 1e-8);
  // It moved: the rope swings.
  CHECK(std::fabs(result.state[0] - x0[0]) > 1e-3);
}

TEST_CASE("loop kernels: a physical chain of a count not built is refused, with the remedy") {
  npend::chain_parameters params;
  params.masses.assign(9, 1.0);
  params.lengths.assign(9, 1.0);
  params.damping.assign(9, 0.1);
  CHECK_THROWS_WITH_AS(chain{params},
                       doctest::Contains("the physical chain of 9 links is not built"),
                       std::invalid_argument);
  params.damping.clear();
  const chain c(params);
  CHECK(c.runs_on_loops());
  std::vector<double> B(static_cast<std::size_t>(18 * 11));
  CHECK_THROWS_WITH_AS(c.input_matrix(std::vector<double>(9, 0.0), B),
                       doctest::Contains("needs the physical kernels"), std::invalid_argument);
}
