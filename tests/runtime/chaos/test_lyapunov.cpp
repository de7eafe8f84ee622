// Lyapunov exponents (paper §6.5.1) and the exact tangent map of a Gauss–Legendre step: the
// properties every spectrum of the chain must have (sum 0, ± pairs, two zeros), the bounded
// growth of small oscillations, chaos at the paper's strong excitation, and the maximal
// exponent against the spectrum.
#include <doctest/doctest.h>

#include <cmath>
#include <stdexcept>

#include "npend/analysis/chaos/lyapunov.hpp"
#include "npend/chain_system.hpp"
#include "npend/excitation.hpp"
#include "npend/integrators/gauss_legendre.hpp"
#include "support/test_support.hpp"

using npend::chain;
using npend::chain_parameters;
using npend::lyapunov_options;
using npend::stepper_kind;

namespace {

// The demo's excitations of the triple pendulum: every arm deflected from rest by the same
// angle, alternately left and right, with ε = E/(m g l) = 0.1 (weak) and 1.5 (strong).
std::vector<double> zigzag(const chain& c, double epsilon) {
  return npend::deflected_state(c, npend::energy_from_epsilon(c, epsilon),
                                std::vector<double>{1, -1, 1});
}

lyapunov_options short_run(double t_end, stepper_kind stepper = stepper_kind::gauss6,
                           double dt = 0.01) {
  lyapunov_options o;
  o.integration.t_end = t_end;
  o.integration.dt = dt;
  o.integration.stepper = stepper;
  return o;
}

// The largest |λ_i + λ_{2n+1−i}|.
double pair_defect(const std::vector<double>& lambda) {
  double worst = 0;
  for (std::size_t i = 0; i < lambda.size(); ++i)
    worst = std::max(worst, std::fabs(lambda[i] + lambda[lambda.size() - 1 - i]));
  return worst;
}

}  // namespace

TEST_CASE("gauss_legendre::do_step_with_tangent: the state advances exactly as do_step") {
  const chain c(chain_parameters::uniform(3));
  const auto system = npend::make_implicit_system(c);
  npend::gauss_legendre6 plain, tangent;
  std::vector<double> x = zigzag(c, 1.5), y = x;
  Eigen::MatrixXd W = Eigen::MatrixXd::Identity(6, 6);
  for (int k = 0; k < 200; ++k) {
    plain.do_step(system, x, k * 0.01, 0.01);
    tangent.do_step_with_tangent(system, y, k * 0.01, 0.01, W);
  }
  CHECK(x == y);  // bit for bit: the tangent work has its own matrices
  Eigen::MatrixXd wrong(5, 6);
  CHECK_THROWS_AS(tangent.do_step_with_tangent(system, y, 0.0, 0.01, wrong), std::invalid_argument);
}

TEST_CASE("gauss_legendre::do_step_with_tangent: the derivative of the step, symplectic") {
  std::mt19937_64 rng(41);
  const chain c(npend::test::random_parameters(3, rng));
  const auto system = npend::make_implicit_system(c);
  const std::vector<double> x0 = npend::test::random_state(3, rng, 1.0);
  const double dt = 0.02;
  const int steps = 10;
  // The flow of `steps` steps from x (a fresh stepper each time: no history).
  const auto flow = [&](std::vector<double> x) {
    npend::gauss_legendre6 stepper;
    for (int k = 0; k < steps; ++k) stepper.do_step(system, x, k * dt, dt);
    return x;
  };
  npend::gauss_legendre6 stepper;
  std::vector<double> x = x0;
  Eigen::MatrixXd M = Eigen::MatrixXd::Identity(6, 6);
  for (int k = 0; k < steps; ++k) stepper.do_step_with_tangent(system, x, k * dt, dt, M);

  // Against Richardson-extrapolated central differences of the map itself.
  Eigen::MatrixXd D(6, 6);
  for (int j = 0; j < 6; ++j) {
    const auto column = [&](double h) {
      std::vector<double> plus = x0, minus = x0;
      plus[static_cast<std::size_t>(j)] += h;
      minus[static_cast<std::size_t>(j)] -= h;
      const auto a = flow(plus), b = flow(minus);
      Eigen::VectorXd d(6);
      for (int i = 0; i < 6; ++i)
        d(i) = (a[static_cast<std::size_t>(i)] - b[static_cast<std::size_t>(i)]) / (2 * h);
      return d;
    };
    D.col(j) = (4 * column(5e-4) - column(1e-3)) / 3;
  }
  CHECK(npend::test::relative_error(M, D) < 1e-8);

  // Mᵀ Ω M = Ω to round-off: the discrete flow of a symplectic method is symplectic.
  Eigen::MatrixXd Omega = Eigen::MatrixXd::Zero(6, 6);
  Omega.topRightCorner(3, 3) = Eigen::MatrixXd::Identity(3, 3);
  Omega.bottomLeftCorner(3, 3) = -Eigen::MatrixXd::Identity(3, 3);
  const double scale = M.squaredNorm();
  CHECK((M.transpose() * Omega * M - Omega).cwiseAbs().maxCoeff() < 1e-14 * scale);
  CHECK(std::fabs(M.determinant() - 1) < 1e-13 * scale);
}

TEST_CASE("lyapunov_spectrum: sum 0 and exact pairs with the Gauss-Legendre tangent map") {
  const chain c(chain_parameters::uniform(3));
  for (const stepper_kind stepper : {stepper_kind::gauss6, stepper_kind::gauss4}) {
    CAPTURE(npend::stepper_name(stepper));
    const auto r = npend::lyapunov_spectrum(c, zigzag(c, 1.5), short_run(100, stepper));
    REQUIRE(r.exponents.size() == 6);
    CHECK(r.method == "tangent map");
    for (std::size_t i = 1; i < 6; ++i) CHECK(r.exponents[i] <= r.exponents[i - 1]);
    // div f = 0, and the tangent map's determinant is 1: the volume stays to round-off.
    CHECK(std::fabs(r.sum) < 1e-13);
    // The exact symplectic map keeps the pairs at every finite time (see lyapunov_spectrum).
    CHECK(pair_defect(r.exponents) < 1e-12);
    CHECK(r.exponents[0] > 0.1);
  }
}

TEST_CASE(
    "lyapunov_spectrum: the variational equations pair and sum to 0 up to the integration error") {
  const chain c(chain_parameters::uniform(3));
  const auto x0 = zigzag(c, 1.5);
  // rk4 is not symplectic: its pairs and sum miss 0 by its integration error, which shows at
  // dt = 0.01 — so the Gauss-Legendre pairs above are not an artefact of the method.
  const auto rk4 = npend::lyapunov_spectrum(c, x0, short_run(100, stepper_kind::rk4));
  CHECK(rk4.method == "variational equations");
  CHECK(pair_defect(rk4.exponents) > 1e-9);
  CHECK(pair_defect(rk4.exponents) < 1e-4);
  CHECK(std::fabs(rk4.sum) > 1e-9);
  CHECK(std::fabs(rk4.sum) < 1e-4);
  // An adaptive stepper at 1e-10 gets both to the level of its tolerance.
  const auto dopri5 = npend::lyapunov_spectrum(c, x0, short_run(100, stepper_kind::dopri5));
  CHECK(pair_defect(dopri5.exponents) < 1e-8);
  CHECK(std::fabs(dopri5.sum) < 1e-8);
}

TEST_CASE("lyapunov_spectrum: every stepper gives the same spectrum of a regular orbit") {
  // At weak excitation the trajectory is not sensitive to the integration error, so the
  // tangent-map and variational routes must agree.
  const chain c(chain_parameters::uniform(3));
  const auto x0 = zigzag(c, 0.1);
  const auto reference = npend::lyapunov_spectrum(c, x0, short_run(50));
  for (const stepper_kind stepper :
       {stepper_kind::gauss4, stepper_kind::rk4, stepper_kind::dopri5, stepper_kind::rkf78,
        stepper_kind::bulirsch_stoer, stepper_kind::taylor}) {
    CAPTURE(npend::stepper_name(stepper));
    const auto r = npend::lyapunov_spectrum(c, x0, short_run(50, stepper));
    for (std::size_t i = 0; i < 6; ++i)
      CHECK(std::fabs(r.exponents[i] - reference.exponents[i]) < 1e-5);
  }
}

TEST_CASE(
    "lyapunov_spectrum: taylor's variational series pair and sum to 0 on the chaotic start, "
    "with gauss6's exponents") {
  const chain c(chain_parameters::uniform(3));
  const auto x0 = zigzag(c, 1.5);
  auto o = short_run(100, stepper_kind::taylor);
  o.integration.abs_tol = o.integration.rel_tol = 1e-13;
  const auto taylor = npend::lyapunov_spectrum(c, x0, o);
  CHECK(taylor.method == "Taylor series of the variational equations");
  INFO("pairs off by ", pair_defect(taylor.exponents), ", sum ", taylor.sum);
  CHECK(pair_defect(taylor.exponents) < 1e-10);
  CHECK(std::fabs(taylor.sum) < 1e-10);
  CHECK(taylor.exponents[0] > 0.1);
  // Over 10 s both integrators follow the same chaotic trajectory (to 1e-9), so their
  // finite-time exponents agree far below the exponents' own spread.
  o.integration.t_end = 10;
  const auto short_taylor = npend::lyapunov_spectrum(c, x0, o);
  const auto gauss = npend::lyapunov_spectrum(c, x0, short_run(10, stepper_kind::gauss6, 1e-3));
  for (std::size_t i = 0; i < 6; ++i) {
    CAPTURE(i);
    CHECK(std::fabs(short_taylor.exponents[i] - gauss.exponents[i]) < 1e-7);
  }
}

TEST_CASE("lyapunov_spectrum: the result does not depend on when it re-orthonormalises") {
  // The QR decomposition of the tangent map's product telescopes: Π R_ii is the same for
  // any renormalisation times, as long as the vectors stay numerically independent.
  const chain c(chain_parameters::uniform(3));
  const auto x0 = zigzag(c, 1.5);
  lyapunov_options often = short_run(40), rarely = short_run(40);
  often.renormalisation_interval = 0.01;
  rarely.renormalisation_interval = 1;
  const auto a = npend::lyapunov_spectrum(c, x0, often),
             b = npend::lyapunov_spectrum(c, x0, rarely);
  CHECK(a.renormalisations == 4000);
  CHECK(b.renormalisations == 40);
  for (std::size_t i = 0; i < 6; ++i) CHECK(std::fabs(a.exponents[i] - b.exponents[i]) < 1e-9);
}

TEST_CASE("lyapunov_spectrum: small oscillations around the hanging position do not grow") {
  // The linearised flow keeps H₂(Z) = ½ Zᵀ diag(K, A⁰⁻¹) Z, so its singular values are at
  // most √cond (cond: the condition number of diag(K, A⁰⁻¹)). The accumulated R of the QR
  // steps is triangular with the flow's singular values, so by Weyl's inequality each
  // |Π R_ii| ≤ √cond as well: every running value has λ_i(t) · t ≤ ½ ln cond.
  std::mt19937_64 rng(43);
  const chain c(npend::test::random_parameters(3, rng));
  const std::vector<double> zero(3, 0.0);
  std::vector<double> K(9), A(9);
  c.potential_hessian(zero, K);
  c.mass_matrix(zero, A);
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(6, 6);
  H.topLeftCorner(3, 3) = npend::test::to_eigen(K, 3, 3);
  H.bottomRightCorner(3, 3) = npend::test::to_eigen(A, 3, 3).inverse();
  const Eigen::VectorXd h = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(H).eigenvalues();
  const double bound = 0.5 * std::log(h.maxCoeff() / h.minCoeff());

  const std::vector<double> x0{1e-3, -2e-3, 1.5e-3, 0, 0, 0};
  auto o = short_run(200);
  const auto spectrum = npend::lyapunov_spectrum(c, x0, o);
  const auto maximal = npend::maximal_lyapunov_exponent(c, x0, o);
  for (const auto* r : {&spectrum, &maximal}) {
    REQUIRE(r->history_t.size() > 100);
    for (std::size_t j = 0; j < r->history_t.size(); ++j)
      for (double lambda : r->history[j]) CHECK(lambda * r->history_t[j] <= bound * 1.001);
  }
  CHECK(spectrum.exponents[0] < bound / 200 * 1.001);
  CHECK(spectrum.exponents[0] >= 0);
}

TEST_CASE("lyapunov_spectrum: the paper's strong excitation is chaotic, with two zero exponents") {
  const chain c(chain_parameters::uniform(3));
  auto o = short_run(200);
  const auto strong = npend::lyapunov_spectrum(c, zigzag(c, 1.5), o);
  const auto weak = npend::lyapunov_spectrum(c, zigzag(c, 0.1), o);
  // Linear growth of ln‖Z‖ for the strong excitation; the weak one's grows like ln t.
  const double ln_growth_strong = strong.exponents[0] * strong.averaging_time;
  const double ln_growth_weak = weak.exponents[0] * weak.averaging_time;
  CHECK(strong.exponents[0] > 0.2);
  CHECK(ln_growth_strong > 10 * ln_growth_weak);
  // The largest exponent has settled: its spread over the last quarter is a fraction of it.
  CHECK(strong.spread[0] < 0.25 * strong.exponents[0]);
  // Two exponents vanish (the flow direction and the energy): the middle pair is zero within
  // its own convergence estimate and far below the largest.
  for (std::size_t i : {std::size_t{2}, std::size_t{3}}) {
    CHECK(std::fabs(strong.exponents[i]) <= 2 * strong.spread[i]);
    CHECK(std::fabs(strong.exponents[i]) < 0.2 * strong.exponents[0]);
  }
}

TEST_CASE("maximal_lyapunov_exponent: the spectrum's largest, from one tangent vector") {
  const chain c(chain_parameters::uniform(3));
  const auto x0 = zigzag(c, 1.5);
  const auto o = short_run(100);
  const auto spectrum = npend::lyapunov_spectrum(c, x0, o);
  const auto maximal = npend::maximal_lyapunov_exponent(c, x0, o);
  REQUIRE(maximal.exponents.size() == 1);
  // Different start vectors: the same limit, reached up to O(1/t).
  CHECK(maximal.exponents[0] == doctest::Approx(spectrum.exponents[0]).epsilon(0.05));
}

TEST_CASE("lyapunov_spectrum: the running values, the convergence estimate and the observer") {
  const chain c(chain_parameters::uniform(2));
  const std::vector<double> x0{2.0, -1.0, 0.0, 0.0};
  auto o = short_run(20);
  o.transient = 5;
  o.max_history = 50;
  o.convergence_fraction = 0.5;
  std::size_t calls = 0, during_transient = 0;
  const auto r = npend::lyapunov_spectrum(c, x0, o, [&](double t, std::span<const double> running) {
    ++calls;
    if (t <= 5 + 1e-12) {
      CHECK(running.empty());
      ++during_transient;
    } else {
      CHECK(running.size() == 4);
    }
    return npend::observer_action::proceed;
  });
  CHECK(calls == 200);
  CHECK(during_transient == 50);
  CHECK(r.transient == doctest::Approx(5));
  CHECK(r.averaging_time == doctest::Approx(15));
  CHECK(r.renormalisations == 150);
  CHECK(r.history_t.size() <= 51);
  CHECK(r.history_t.back() == doctest::Approx(20));
  CHECK(r.history.back() == r.exponents);
  // The spread is max − min of each running value over the last half (t ≥ 12.5 s).
  for (std::size_t i = 0; i < 4; ++i) {
    double low = INFINITY, high = -INFINITY;
    for (std::size_t j = 0; j < r.history_t.size(); ++j)
      if (r.history_t[j] >= 12.5 - 1e-9) {
        low = std::min(low, r.history[j][i]);
        high = std::max(high, r.history[j][i]);
      }
    CHECK(r.spread[i] == high - low);
  }

  // An observer that stops the run.
  const auto stopped = npend::lyapunov_spectrum(c, x0, o, [](double t, std::span<const double>) {
    return t >= 10 - 1e-12 ? npend::observer_action::stop : npend::observer_action::proceed;
  });
  CHECK(stopped.stopped);
  CHECK(stopped.t == doctest::Approx(10));
  CHECK(stopped.averaging_time == doctest::Approx(5));
  CHECK(std::isfinite(stopped.exponents[0]));
}

TEST_CASE("lyapunov_spectrum: bad arguments are refused with the reason") {
  using doctest::Contains;
  using npend::lyapunov_spectrum;
  const chain c(chain_parameters::uniform(2));
  const std::vector<double> x0{0.5, 0.2, 0, 0}, short_state{0.5, 0.2, 0}, nan{0.5, NAN, 0, 0};
  CHECK_THROWS_WITH_AS(lyapunov_spectrum(c, short_state, short_run(10)),
                       Contains("x0 has 3 entries"), std::invalid_argument);
  CHECK_THROWS_WITH_AS(lyapunov_spectrum(c, nan, short_run(10)), Contains("entry 2 is not finite"),
                       std::invalid_argument);
  CHECK_THROWS_WITH_AS(lyapunov_spectrum(c, x0, short_run(10, stepper_kind::rosenbrock4)),
                       Contains("rosenbrock4"), std::invalid_argument);
  auto o = short_run(10);
  o.transient = 10;
  CHECK_THROWS_WITH_AS(lyapunov_spectrum(c, x0, o), Contains("leaves no time to average"),
                       std::invalid_argument);
  o = short_run(10);
  o.renormalisation_interval = 0;
  CHECK_THROWS_WITH_AS(lyapunov_spectrum(c, x0, o), Contains("renormalisation_interval"),
                       std::invalid_argument);
  o = short_run(10);
  o.convergence_fraction = 0;
  CHECK_THROWS_WITH_AS(lyapunov_spectrum(c, x0, o), Contains("convergence_fraction"),
                       std::invalid_argument);
  o = short_run(10);
  o.integration.t_start = 10;
  o.integration.t_end = 0;
  o.integration.dt = -0.01;
  CHECK_THROWS_WITH_AS(lyapunov_spectrum(c, x0, o), Contains("forwards in time"),
                       std::invalid_argument);
}

TEST_CASE("lyapunov_spectrum: the blocks split the averaging time, their standard error") {
  const chain c(chain_parameters::uniform(3));
  auto o = short_run(100);
  o.blocks = 8;
  const auto r = npend::lyapunov_spectrum(c, zigzag(c, 1.5), o);
  REQUIRE(r.block_exponents.size() == 8);
  REQUIRE(r.block_edges.size() == 9);
  CHECK(r.block_edges.front() == doctest::Approx(0));
  CHECK(r.block_edges.back() == doctest::Approx(100));
  // The exponents are the length-weighted means of the blocks' (Σ ln R_ii telescopes).
  for (std::size_t i = 0; i < 6; ++i) {
    double mean = 0;
    for (std::size_t b = 0; b < 8; ++b)
      mean += r.block_exponents[b][i] * (r.block_edges[b + 1] - r.block_edges[b]);
    CHECK(mean / 100 == doctest::Approx(r.exponents[i]).epsilon(1e-9));
    CHECK(r.block_standard_error[i] > 0);
  }
  // Chaos: the blocks' λ_1 scatter, by more than round-off.
  CHECK(r.block_standard_error[0] > 1e-3);
  o.blocks = 1;
  CHECK_THROWS_WITH_AS(npend::lyapunov_spectrum(c, zigzag(c, 1.5), o), doctest::Contains("blocks"),
                       std::invalid_argument);
}

TEST_CASE("energy_surface_neighbours: x0 first, the others nearby at exactly its energy") {
  std::mt19937_64 rng(47);
  const chain c(npend::test::random_parameters(3, rng));
  for (const auto& x0 :
       {zigzag(chain(chain_parameters::uniform(3)), 1.5), npend::test::random_state(3, rng, 1.0)}) {
    const chain& model = x0[3] == 0 ? chain(chain_parameters::uniform(3)) : c;
    const auto starts = npend::energy_surface_neighbours(model, x0, 5, 1e-4, 7);
    REQUIRE(starts.size() == 5);
    CHECK(starts[0] == x0);
    const double h0 = model.hamiltonian(x0);
    for (std::size_t k = 1; k < 5; ++k) {
      CHECK(std::fabs(model.hamiltonian(starts[k]) - h0) <= 1e-14 * std::max(1.0, std::fabs(h0)));
      double distance = 0;
      for (std::size_t i = 0; i < 6; ++i) distance += std::pow(starts[k][i] - x0[i], 2);
      CHECK(std::sqrt(distance) > 1e-5);
      CHECK(std::sqrt(distance) < 1e-3);
      CHECK(starts[k] != starts[k - 1]);
    }
  }
  const std::vector<double> hanging(6, 0.0);
  CHECK_THROWS_WITH_AS(
      npend::energy_surface_neighbours(chain(chain_parameters::uniform(3)), hanging, 3, 1e-6),
      doctest::Contains("equilibrium"), std::invalid_argument);
}

TEST_CASE("lyapunov_ensemble: its standard error covers the exponents of runs at two dt") {
  // The demo's strong start: at dt = 0.01 and 0.005 the trajectories part after some tens of
  // seconds, and so do their finite-time exponents. Each ensemble's mean comes with a
  // standard error; the two means must agree within it (3 sigma of the difference).
  const chain c(chain_parameters::uniform(3));
  const auto x0 = zigzag(c, 1.5);
  npend::lyapunov_ensemble_options e;
  e.members = 6;
  e.maximal = true;
  const auto coarse =
      npend::lyapunov_ensemble(c, x0, short_run(200, stepper_kind::gauss6, 0.01), e);
  const auto fine = npend::lyapunov_ensemble(c, x0, short_run(200, stepper_kind::gauss6, 0.005), e);
  REQUIRE(coarse.runs.size() == 6);
  REQUIRE(fine.mean.size() == 1);
  CHECK(coarse.starts == fine.starts);
  CAPTURE(coarse.mean[0]);
  CAPTURE(fine.mean[0]);
  CAPTURE(coarse.standard_error[0]);
  CAPTURE(fine.standard_error[0]);
  CHECK(coarse.mean[0] > 0.2);
  CHECK(std::fabs(coarse.mean[0] - fine.mean[0]) <=
        3 * std::hypot(coarse.standard_error[0], fine.standard_error[0]));
  // The members scatter (the finite-time values are not one number), and the standard error
  // is the standard deviation / sqrt(K).
  CHECK(coarse.standard_deviation[0] > 0.005);
  CHECK(coarse.standard_error[0] == doctest::Approx(coarse.standard_deviation[0] / std::sqrt(6.0)));
  e.members = 1;
  CHECK_THROWS_WITH_AS(npend::lyapunov_ensemble(c, x0, short_run(10), e),
                       doctest::Contains("members"), std::invalid_argument);
}
