// Structural properties of the generated Jacobian: it is the derivative of the generated
// right-hand side, traceless (phase-space volume is conserved), and Hamiltonian (ΩJ is the
// symmetric Hessian of H).
#include <doctest/doctest.h>

#include <cmath>

#include "npend/chain.hpp"
#include "support/test_support.hpp"

using npend::chain;

namespace {

// Central differences with one Richardson step: error O(h⁴), so h = 1e-3 gives ≈1e-10
// relative truncation and rounding of ≈1e-12 — far below the size of any wrong entry.
Eigen::MatrixXd richardson_jacobian(const chain& c, const std::vector<double>& x) {
  const int d = c.state_size();
  Eigen::MatrixXd J(d, d);
  auto central = [&](int k, double h) -> Eigen::VectorXd {
    std::vector<double> xp = x, xm = x;
    xp[static_cast<std::size_t>(k)] += h;
    xm[static_cast<std::size_t>(k)] -= h;
    return (npend::test::to_eigen(c.rhs(xp)) - npend::test::to_eigen(c.rhs(xm))) / (2 * h);
  };
  const double h = 1e-3;
  for (int k = 0; k < d; ++k) J.col(k) = (4 * central(k, h / 2) - central(k, h)) / 3;
  return J;
}

Eigen::MatrixXd omega(int n) {
  Eigen::MatrixXd O = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  O.topRightCorner(n, n) = Eigen::MatrixXd::Identity(n, n);
  O.bottomLeftCorner(n, n) = -Eigen::MatrixXd::Identity(n, n);
  return O;
}

}  // namespace

TEST_CASE("jacobian: agrees with Richardson-extrapolated differences of the rhs, n = 1..6") {
  for (int n = 1; n <= 6; ++n) {
    std::mt19937_64 rng(300 + static_cast<unsigned>(n));
    double worst = 0;
    for (int s = 0; s < 40; ++s) {
      const chain c(npend::test::random_parameters(n, rng));
      const auto x = npend::test::random_state(n, rng, 1.5);
      const Eigen::MatrixXd J = npend::test::to_eigen(c.jacobian(x), 2 * n, 2 * n);
      worst = std::max(worst, npend::test::relative_error(J, richardson_jacobian(c, x)));
    }
    INFO("n = ", n, ": worst relative difference ", worst);
    CHECK(worst < 1e-9);
  }
}

// An emitter guard, not a physics check: the emitter writes the Hamiltonian structure in by
// construction (W and C symmetric, D = −Bᵀ; articulated_form.hpp), so this can only fail if
// the emitter stops doing so. The physics of the same entries is checked above against
// Richardson-extrapolated differences of the rhs.
TEST_CASE("jacobian (emitter guard): trace is zero and Omega J is symmetric, as written in") {
  for (int n = 1; n <= 6; ++n) {
    std::mt19937_64 rng(400 + static_cast<unsigned>(n));
    for (int s = 0; s < 50; ++s) {
      const chain c(npend::test::random_parameters(n, rng));
      const auto x = npend::test::random_state(n, rng);
      const Eigen::MatrixXd J = npend::test::to_eigen(c.jacobian(x), 2 * n, 2 * n);
      const double scale = J.cwiseAbs().maxCoeff();
      CHECK(std::fabs(J.trace()) <= 1e-13 * scale * 2 * n);
      // −ΩJ = ∇²H must be symmetric.
      const Eigen::MatrixXd hess = -omega(n) * J;
      CHECK((hess - hess.transpose()).cwiseAbs().maxCoeff() <= 1e-13 * scale);
    }
  }
}

TEST_CASE("jacobian: at the hanging equilibrium it is [[0, A^-1], [-K, 0]] exactly") {
  // At φ = 0, p = 0 the blocks ∂φ̇/∂φ and ∂ṗ/∂p vanish and ∂ṗ/∂φ = −diag(g μ_i l_i).
  std::mt19937_64 rng(5);
  for (int n = 1; n <= 6; ++n) {
    const auto params = npend::test::random_parameters(n, rng);
    const chain c(params);
    const std::vector<double> x(static_cast<std::size_t>(2 * n), 0.0);
    const Eigen::MatrixXd J = npend::test::to_eigen(c.jacobian(x), 2 * n, 2 * n);
    CHECK(J.topLeftCorner(n, n).cwiseAbs().maxCoeff() == 0.0);
    CHECK(J.bottomRightCorner(n, n).cwiseAbs().maxCoeff() == 0.0);
    double mu = 0;
    for (int i = n - 1; i >= 0; --i) {
      mu += params.masses[static_cast<std::size_t>(i)];
      const double k = params.g * mu * params.lengths[static_cast<std::size_t>(i)];
      CHECK(J(n + i, i) == doctest::Approx(-k).epsilon(1e-14));
    }
  }
}
