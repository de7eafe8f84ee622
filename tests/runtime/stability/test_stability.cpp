// Equilibria, normal modes and the Toda–Brumer criterion against the paper's closed forms
// (docs/paper.md §6.4, §6.5, with error 3 corrected) and against Eigen's eigenvalues of the
// generated Jacobian.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "npend/analysis/chaos/toda_brumer.hpp"
#include "npend/analysis/stability/equilibria.hpp"
#include "npend/analysis/stability/normal_modes.hpp"
#include "support/test_support.hpp"

using npend::chain;
using npend::chain_parameters;

namespace {

constexpr double pi = std::numbers::pi;

// The squared Jacobian eigenvalues λ² of an equilibrium, ascending.
std::vector<double> squared_eigenvalues(const npend::equilibrium& e) {
  std::vector<double> out;
  for (const auto& z : e.eigenvalues) out.push_back((z * z).real());
  std::sort(out.begin(), out.end());
  return out;
}

// κ² = g/(2√(l₁l₂)) [ML ± √(M²L² + s·4M)], M = 1 + m₂/m₁ (paper §6.5.1; s = −1 for the
// standing/hanging form, s = +1 for the bent equilibria, where the paper prints −4M).
std::vector<double> paper_kappa_squared(double m1, double m2, double l1, double l2, double g,
                                        double L, double s) {
  const double M = 1 + m2 / m1, pre = g / (2 * std::sqrt(l1 * l2));
  const double root = std::sqrt(M * M * L * L + s * 4 * M);
  std::vector<double> k{pre * (M * L - root), pre * (M * L + root)};
  std::sort(k.begin(), k.end());
  return k;
}

}  // namespace

TEST_CASE("normal_modes: double pendulum frequencies match the paper's omega^2_1,2") {
  std::mt19937_64 rng(11);
  for (int s = 0; s < 100; ++s) {
    const auto p = npend::test::random_parameters(2, rng);
    const double m1 = p.masses[0], m2 = p.masses[1], l1 = p.lengths[0], l2 = p.lengths[1];
    const double mu1 = m1 + m2, g = p.g;
    const double root = std::sqrt(mu1 * (mu1 * (l1 + l2) * (l1 + l2) - 4 * m1 * l1 * l2));
    const double w1 = g / (2 * m1 * l1 * l2) * (mu1 * (l1 + l2) - root);
    const double w2 = g / (2 * m1 * l1 * l2) * (mu1 * (l1 + l2) + root);
    const auto lin = npend::normal_modes(chain(p), std::vector<double>{0, 0});
    CHECK(lin.modes[0].omega_squared == doctest::Approx(w1).epsilon(1e-12));
    CHECK(lin.modes[1].omega_squared == doctest::Approx(w2).epsilon(1e-12));
    CHECK(lin.modes[0].frequency == doctest::Approx(std::sqrt(w1)).epsilon(1e-12));
  }
}

TEST_CASE("find_equilibria: double pendulum eigenvalues at all four equilibria (paper 6.5.1)") {
  std::mt19937_64 rng(12);
  for (int s = 0; s < 100; ++s) {
    const auto p = npend::test::random_parameters(2, rng);
    const double m1 = p.masses[0], m2 = p.masses[1], l1 = p.lengths[0], l2 = p.lengths[1];
    const double r = std::sqrt(l1 * l2);
    const auto eq = npend::find_equilibria(chain(p));
    REQUIRE(eq.size() == 4);  // (0,0), (0,π), (π,0), (π,π)

    const auto standing = paper_kappa_squared(m1, m2, l1, l2, p.g, (l1 + l2) / r, -1);
    // Hanging: κ = i·(standing values), so λ² = −κ²_standing; stable.
    const auto hanging = squared_eigenvalues(eq[0]);
    CHECK(hanging[0] == doctest::Approx(-standing[1]).epsilon(1e-11));
    CHECK(hanging[2] == doctest::Approx(-standing[0]).epsilon(1e-11));
    CHECK(eq[0].stable);
    CHECK(eq[0].unstable_directions == 0);
    // Standing: four real eigenvalues ±κ.
    const auto top = squared_eigenvalues(eq[3]);
    CHECK(top[0] == doctest::Approx(standing[0]).epsilon(1e-11));
    CHECK(top[3] == doctest::Approx(standing[1]).epsilon(1e-11));
    CHECK(eq[3].unstable_directions == 2);
    // Bent (0, π) and (π, 0): error 3 of the paper — the root has +4M; L = ±(l₁ − l₂)/√(l₁l₂).
    for (const auto& [index, L] : {std::pair{1, (l1 - l2) / r}, std::pair{2, (l2 - l1) / r}}) {
      const auto want = paper_kappa_squared(m1, m2, l1, l2, p.g, L, +1);
      const auto got = squared_eigenvalues(eq[static_cast<std::size_t>(index)]);
      CHECK(got[0] == doctest::Approx(want[0]).epsilon(1e-11));
      CHECK(got[3] == doctest::Approx(want[1]).epsilon(1e-11));
      CHECK(eq[static_cast<std::size_t>(index)].unstable_directions == 1);
      CHECK_FALSE(eq[static_cast<std::size_t>(index)].stable);
    }
    CHECK(eq[3].energy == doctest::Approx(2 * p.g * ((m1 + m2) * l1 + m2 * l2)).epsilon(1e-14));
  }
}

TEST_CASE("find_equilibria: eigenvalues are Eigen's eigenvalues of the generated Jacobian") {
  std::mt19937_64 rng(13);
  for (int n = 1; n <= 5; ++n) {
    const chain c(npend::test::random_parameters(n, rng));
    for (const auto& e : npend::find_equilibria(c)) {
      std::vector<double> x = e.angles;
      x.resize(static_cast<std::size_t>(2 * n), 0.0);
      const Eigen::MatrixXd J = npend::test::to_eigen(c.jacobian(x), 2 * n, 2 * n);
      Eigen::VectorXcd direct = Eigen::EigenSolver<Eigen::MatrixXd>(J).eigenvalues();
      std::vector<std::complex<double>> got(direct.data(), direct.data() + 2 * n);
      const auto by_value = [](auto a, auto b) {
        return a.real() != b.real() ? a.real() > b.real() : a.imag() > b.imag();
      };
      // Round away the ±1e-16 real parts of imaginary pairs before sorting.
      for (auto& z : got) z = {std::fabs(z.real()) < 1e-9 * std::abs(z) ? 0.0 : z.real(), z.imag()};
      std::sort(got.begin(), got.end(), by_value);
      for (std::size_t k = 0; k < got.size(); ++k)
        CHECK(std::abs(got[k] - e.eigenvalues[k]) <= 1e-9 * (1 + std::abs(e.eigenvalues[k])));
      int positive = 0;
      for (const auto& z : got) positive += z.real() > 1e-9 * std::abs(z);
      CHECK(positive == e.unstable_directions);
    }
  }
}

TEST_CASE(
    "normal_modes: triple pendulum frequencies are the roots of the paper's harmonic equations") {
  // Paper §6.4.2: M₀ = [[μ₁l₁², μ₂l₁l₂, m₃l₁l₃], [μ₂l₁l₂, μ₂l₂², m₃l₂l₃], [l₁l₃, l₂l₃, l₃²]]
  // (third equation divided by m₃), K₀ = diag(μ₁gl₁, μ₂gl₂, gl₃). det(K₀ − λM₀) is a cubic
  // in λ = ω², expanded here by Sarrus' rule and solved in closed form (three real roots).
  std::mt19937_64 rng(14);
  for (int s = 0; s < 50; ++s) {
    const auto p = npend::test::random_parameters(3, rng);
    const double m3 = p.masses[2], l1 = p.lengths[0], l2 = p.lengths[1], l3 = p.lengths[2];
    const double mu1 = p.masses[0] + p.masses[1] + m3, mu2 = p.masses[1] + m3, g = p.g;
    const double M[3][3] = {{mu1 * l1 * l1, mu2 * l1 * l2, m3 * l1 * l3},
                            {mu2 * l1 * l2, mu2 * l2 * l2, m3 * l2 * l3},
                            {l1 * l3, l2 * l3, l3 * l3}};
    const double K[3] = {mu1 * g * l1, mu2 * g * l2, g * l3};
    // Entries K_ij − λ M_ij as polynomials a + bλ; products as coefficient vectors.
    using poly = std::vector<double>;
    auto entry = [&](int i, int j) { return poly{i == j ? K[i] : 0.0, -M[i][j]}; };
    auto mul = [](const poly& a, const poly& b) {
      poly c(a.size() + b.size() - 1, 0.0);
      for (std::size_t i = 0; i < a.size(); ++i)
        for (std::size_t j = 0; j < b.size(); ++j) c[i + j] += a[i] * b[j];
      return c;
    };
    poly det(4, 0.0);
    const int perms[6][3] = {{0, 1, 2}, {1, 2, 0}, {2, 0, 1}, {0, 2, 1}, {1, 0, 2}, {2, 1, 0}};
    for (int k = 0; k < 6; ++k) {
      const poly term =
          mul(mul(entry(0, perms[k][0]), entry(1, perms[k][1])), entry(2, perms[k][2]));
      for (std::size_t i = 0; i < 4; ++i) det[i] += (k < 3 ? 1 : -1) * term[i];
    }
    // Roots of det[3] λ³ + det[2] λ² + det[1] λ + det[0] by the trigonometric method.
    const double a = det[2] / det[3], b = det[1] / det[3], c0 = det[0] / det[3];
    const double q = (3 * b - a * a) / 9, r = (9 * a * b - 27 * c0 - 2 * a * a * a) / 54;
    const double theta = std::acos(r / std::sqrt(-q * q * q));
    std::vector<double> roots;
    for (int k = 0; k < 3; ++k)
      roots.push_back(2 * std::sqrt(-q) * std::cos((theta + 2 * pi * k) / 3) - a / 3);
    std::sort(roots.begin(), roots.end());

    const auto lin = npend::normal_modes(chain(p), std::vector<double>{0, 0, 0});
    for (int k = 0; k < 3; ++k)
      CHECK(lin.modes[static_cast<std::size_t>(k)].omega_squared ==
            doctest::Approx(roots[static_cast<std::size_t>(k)]).epsilon(1e-10));
  }
}

TEST_CASE("normal_modes: shapes are M-orthonormal and solve K v = omega^2 M v") {
  std::mt19937_64 rng(15);
  for (int n = 1; n <= 6; ++n) {
    const chain c(npend::test::random_parameters(n, rng));
    const auto lin = npend::normal_modes(c, std::vector<double>(static_cast<std::size_t>(n), 0.0));
    const Eigen::MatrixXd M = npend::test::to_eigen(lin.mass_matrix, n, n);
    const Eigen::MatrixXd K = npend::test::to_eigen(lin.stiffness_matrix, n, n);
    for (std::size_t a = 0; a < lin.modes.size(); ++a) {
      const Eigen::VectorXd va = npend::test::to_eigen(lin.modes[a].shape);
      CHECK((K * va - lin.modes[a].omega_squared * M * va).norm() <= 1e-10 * K.norm());
      for (std::size_t b = 0; b < lin.modes.size(); ++b) {
        const Eigen::VectorXd vb = npend::test::to_eigen(lin.modes[b].shape);
        CHECK(va.dot(M * vb) == doctest::Approx(a == b ? 1.0 : 0.0).scale(1).epsilon(1e-10));
      }
    }
  }
}

TEST_CASE("normal_modes: refuses a state that is not an equilibrium") {
  const chain c(chain_parameters::uniform(2));
  CHECK_THROWS_WITH_AS(npend::normal_modes(c, std::vector<double>{0.1, 0.0}),
                       doctest::Contains("not an equilibrium: dV/dphi_1"), std::invalid_argument);
  CHECK_NOTHROW(npend::normal_modes(c, std::vector<double>{3.14159265358979, 0.0}));
}

TEST_CASE("toda_brumer_eigenvalues: Lambda_k = -g l_k mu_k cos phi_k (eq. 6.20)") {
  std::mt19937_64 rng(16);
  for (int n = 1; n <= 6; ++n) {
    const auto p = npend::test::random_parameters(n, rng);
    const chain c(p);
    const auto x = npend::test::random_state(n, rng);
    const std::span<const double> phi(x.data(), static_cast<std::size_t>(n));
    std::vector<double> want;
    double mu = 0;
    for (int k = n - 1; k >= 0; --k) {
      mu += p.masses[static_cast<std::size_t>(k)];
      want.push_back(-p.g * p.lengths[static_cast<std::size_t>(k)] * mu *
                     std::cos(phi[static_cast<std::size_t>(k)]));
    }
    std::sort(want.begin(), want.end());
    const auto got = npend::toda_brumer_eigenvalues(c, phi);
    for (std::size_t k = 0; k < want.size(); ++k)
      CHECK(got[k] == doctest::Approx(want[k]).epsilon(1e-12).scale(1));
  }
}

TEST_CASE("toda_brumer_critical_energy: the paper's example E_c = m3 g l3, and min_k mu_k g l_k") {
  const chain_parameters p{{1.2, 0.7, 0.9}, {0.8, 1.1, 1.3}, 9.81};
  const chain c(p);
  const std::vector<int> fixed12{1, 2};
  CHECK(npend::toda_brumer_critical_energy(c, fixed12) ==
        doctest::Approx(0.9 * 9.81 * 1.3).epsilon(1e-14));
  const double mu[3] = {2.8, 1.6, 0.9};
  double threshold = 1e300;
  for (int k = 0; k < 3; ++k)
    threshold = std::min(threshold, mu[k] * 9.81 * p.lengths[static_cast<std::size_t>(k)]);
  CHECK(npend::toda_brumer_critical_energy(c, std::vector<int>{}) ==
        doctest::Approx(threshold).epsilon(1e-14));
  CHECK_THROWS_AS(npend::toda_brumer_critical_energy(c, std::vector<int>{1, 2, 3}),
                  std::invalid_argument);
  CHECK_THROWS_AS(npend::toda_brumer_critical_energy(c, std::vector<int>{4}),
                  std::invalid_argument);
}

TEST_CASE("toda_brumer_links: O(n) for a long chain, g mu_k l_k per link") {
  // 100000 links: the n x n Hessian would take 80 GB; the diagonal it has comes in O(n).
  const int n = 100000;
  chain_parameters p = chain_parameters::uniform(n, 1.0, 0.01);
  for (int k = 0; k < n; ++k) p.masses[static_cast<std::size_t>(k)] = 1.0 + 0.5 * std::sin(k);
  const chain c(p);
  const auto links = npend::toda_brumer_links(c);
  REQUIRE(links.size() == static_cast<std::size_t>(n));
  double mu = 0, smallest = 1e300, worst = 0;
  bool numbered = true;
  for (int k = n - 1; k >= 0; --k) {
    mu += p.masses[static_cast<std::size_t>(k)];
    const double want = p.g * mu * 0.01;
    const auto& link = links[static_cast<std::size_t>(k)];
    numbered = numbered && link.link == k + 1;
    worst = std::max({worst, std::fabs(link.curvature - want) / want,
                      std::fabs(link.critical_energy - want) / want});
    smallest = std::min(smallest, want);
  }
  CHECK(numbered);
  CHECK(worst < 1e-10);  // sums of 1e5 masses in another order: rounding, n eps
  CHECK(npend::toda_brumer_critical_energy(c, std::vector<int>{}) ==
        doctest::Approx(smallest).epsilon(1e-10));
  std::vector<double> phi(static_cast<std::size_t>(n), std::numbers::pi);
  const auto lambda = npend::toda_brumer_eigenvalues(c, phi);  // cos π = −1: Λ_k = g μ_k l_k
  CHECK(lambda.front() == doctest::Approx(smallest).epsilon(1e-10));
}
