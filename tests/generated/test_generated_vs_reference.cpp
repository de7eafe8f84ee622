// Generated kernels against the independent hand-written dense implementation
// (tests/reference/include/reference/dense_chain.hpp) for n = 1 … 6, unequal masses and lengths.
#include <doctest/doctest.h>

#include "npend/chain.hpp"
#include "reference/dense_chain.hpp"
#include "support/test_support.hpp"

using npend::chain;
using npend::test::relative_error;
using npend::test::to_eigen;

namespace {
constexpr int samples = 200;
constexpr double tolerance = 1e-12;
}  // namespace

TEST_CASE("rhs: generated equations match the hand-written dense implementation, n = 1..6") {
  for (int n = 1; n <= 6; ++n) {
    std::mt19937_64 rng(100 + static_cast<unsigned>(n));
    double worst_f = 0, worst_h = 0, worst_j = 0;
    for (int s = 0; s < samples; ++s) {
      const auto params = npend::test::random_parameters(n, rng);
      const chain c(params);
      const npend::reference::dense_chain ref(params.masses, params.lengths, params.g);
      const auto x = npend::test::random_state(n, rng);
      const Eigen::VectorXd xe = to_eigen(x);
      worst_f = std::max(worst_f, relative_error(to_eigen(c.rhs(x)), ref.rhs(xe)));
      worst_h = std::max(worst_h, std::fabs(c.hamiltonian(x) - ref.hamiltonian(xe)) /
                                      std::fabs(ref.hamiltonian(xe)));
      worst_j = std::max(worst_j,
                         relative_error(to_eigen(c.jacobian(x), 2 * n, 2 * n), ref.jacobian(xe)));
    }
    INFO("n = ", n, ": worst relative error f ", worst_f, ", H ", worst_h, ", J ", worst_j);
    CHECK(worst_f < tolerance);
    CHECK(worst_h < tolerance);
    CHECK(worst_j < tolerance);
  }
}

TEST_CASE("mass_matrix: generated A, det A, T, V and positions match the dense formulas") {
  for (int n = 1; n <= 6; ++n) {
    std::mt19937_64 rng(200 + static_cast<unsigned>(n));
    for (int s = 0; s < 50; ++s) {
      const auto params = npend::test::random_parameters(n, rng);
      const chain c(params);
      const npend::reference::dense_chain ref(params.masses, params.lengths, params.g);
      const auto x = npend::test::random_state(n, rng);
      const std::span<const double> phi(x.data(), static_cast<std::size_t>(n));
      const Eigen::VectorXd phie = to_eigen(phi);
      const auto nn = static_cast<std::size_t>(n);

      std::vector<double> A(nn * nn), xy(2 * nn), dphi(nn);
      c.mass_matrix(phi, A);
      const Eigen::MatrixXd Aref = ref.mass_matrix(phie);
      CHECK(relative_error(to_eigen(A, n, n), Aref) < tolerance);
      CHECK(c.det_mass_matrix(phi) == doctest::Approx(Aref.determinant()).epsilon(1e-11));
      c.positions(phi, xy);
      CHECK(relative_error(to_eigen(xy), ref.positions(phie)) < tolerance);
      for (std::size_t i = 0; i < nn; ++i) dphi[i] = x[nn + i];  // any velocities will do
      CHECK(c.kinetic_energy(phi, dphi) ==
            doctest::Approx(ref.kinetic_energy(phie, to_eigen(dphi))).epsilon(tolerance));
      CHECK(c.potential_energy(phi) ==
            doctest::Approx(ref.potential_energy(phie)).epsilon(tolerance));
    }
  }
}

TEST_CASE("potential_gradient: gradient and Hessian of V match g mu_i l_i sin/cos phi_i") {
  // V = g Σ μ_j l_j (1 − cos φ_j) (eq. 6.12): ∂V/∂φ_i = g μ_i l_i sin φ_i, diagonal Hessian.
  std::mt19937_64 rng(7);
  for (int n = 1; n <= 6; ++n) {
    const auto params = npend::test::random_parameters(n, rng);
    const chain c(params);
    const npend::reference::dense_chain ref(params.masses, params.lengths, params.g);
    const auto x = npend::test::random_state(n, rng);
    const auto nn = static_cast<std::size_t>(n);
    const std::span<const double> phi(x.data(), nn);
    std::vector<double> grad(nn), hess(nn * nn);
    c.potential_gradient(phi, grad);
    c.potential_hessian(phi, hess);
    for (int i = 0; i < n; ++i) {
      const double k = params.g * ref.mu(i) * ref.l(i);
      CHECK(grad[static_cast<std::size_t>(i)] ==
            doctest::Approx(k * std::sin(x[static_cast<std::size_t>(i)])).epsilon(tolerance));
      for (int j = 0; j < n; ++j) {
        const double want = i == j ? k * std::cos(x[static_cast<std::size_t>(i)]) : 0.0;
        CHECK(hess[static_cast<std::size_t>(i * n + j)] ==
              doctest::Approx(want).epsilon(tolerance));
      }
    }
  }
}
