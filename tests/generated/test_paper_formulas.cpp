// Generated equations against the paper's own formulas (docs/paper.md §6.3.2), typed in
// by hand, with the paper's typos corrected where docs/paper.md lists them.
#include <doctest/doctest.h>

#include <cmath>

#include "npend/chain.hpp"
#include "support/test_support.hpp"

using npend::chain;
using npend::chain_parameters;

namespace {

constexpr int paper_samples = 300;
constexpr double paper_tolerance = 1e-12;  // relative: a few ulps of accumulated rounding

struct double_pendulum_paper {
  double m1, m2, l1, l2, g;

  double N(double phi1, double phi2) const {
    const double s = std::sin(phi1 - phi2);
    return m1 + m2 * s * s;
  }
  // (6.18); the paper prints "q" for g in the potential terms.
  double H(const std::vector<double>& x) const {
    const double phi1 = x[0], phi2 = x[1], p1 = x[2], p2 = x[3];
    const double mu1 = m1 + m2, mu2 = m2, n = N(phi1, phi2);
    const double a = p1 / l1, b = p2 / l2;
    return (a * a - 2 * std::cos(phi1 - phi2) * p1 * p2 / (l1 * l2) + mu1 / mu2 * b * b) / (2 * n) +
           mu1 * g * l1 * (1 - std::cos(phi1)) + mu2 * g * l2 * (1 - std::cos(phi2));
  }
  std::vector<double> f(const std::vector<double>& x) const {
    const double phi1 = x[0], phi2 = x[1], p1 = x[2], p2 = x[3];
    const double mu1 = m1 + m2, mu2 = m2, n = N(phi1, phi2), d = phi1 - phi2;
    const double a = p1 / l1, b = p2 / l2, c = std::cos(d);
    const double dphi1 = (a - b * c) / (l1 * n);
    const double dphi2 = (mu1 / mu2 * b - a * c) / (l2 * n);
    const double common = mu2 * a * a + mu1 * b * b;
    const double cross = (mu1 + mu2 * c * c) * p1 * p2 / (l1 * l2);
    const double dp1 = std::sin(2 * d) / (2 * n * n) * common - std::sin(d) / (n * n) * cross -
                       mu1 * g * l1 * std::sin(phi1);
    const double dp2 = std::sin(-2 * d) / (2 * n * n) * common - std::sin(-d) / (n * n) * cross -
                       mu2 * g * l2 * std::sin(phi2);
    return {dphi1, dphi2, dp1, dp2};
  }
};

struct triple_pendulum_paper {
  double m1, m2, m3, l1, l2, l3, g;

  double N(const std::vector<double>& x) const {
    const double s23 = std::sin(x[1] - x[2]), s12 = std::sin(x[0] - x[1]);
    return m1 * m2 + m1 * m3 * s23 * s23 + m2 * (m2 + m3) * s12 * s12;
  }
  // The brackets of H; H = Σ bracket·p_i p_j/(l_i l_j)/(2N) + V.
  struct brackets {
    double b11, b22, b33, b12, b13, b23;
  };
  brackets coefficients(const std::vector<double>& x) const {
    const double f1 = x[0], f2 = x[1], f3 = x[2];
    const double mu1 = m1 + m2 + m3, mu2 = m2 + m3, mu3 = m3;
    const auto cos2 = [](double a) { return std::cos(a) * std::cos(a); };
    brackets b{};
    b.b11 = mu2 - mu3 * cos2(f2 - f3);
    b.b22 = mu1 - mu3 * cos2(f1 - f3);
    b.b33 = mu2 / mu3 * (mu1 - mu2 * cos2(f1 - f2));
    // Error 1 of the paper: it prints +μ₃cos(φ₁+φ₂−2φ₃) here (and in φ̇₁, φ̇₂); the sign is −.
    b.b12 = -((2 * mu2 - mu3) * std::cos(f1 - f2) - mu3 * std::cos(f1 + f2 - 2 * f3));
    b.b13 = -mu2 * (std::cos(f1 - f3) - std::cos(f1 - 2 * f2 + f3));
    b.b23 = -((2 * mu1 - mu2) * std::cos(f2 - f3) - mu2 * std::cos(2 * f1 - f2 - f3));
    return b;
  }
  double H(const std::vector<double>& x) const {
    const auto b = coefficients(x);
    const double n = N(x), q1 = x[3] / l1, q2 = x[4] / l2, q3 = x[5] / l3;
    const double mu1 = m1 + m2 + m3, mu2 = m2 + m3, mu3 = m3;
    // The paper prints "q" for g in the potential terms.
    return (b.b11 * q1 * q1 + b.b22 * q2 * q2 + b.b33 * q3 * q3 + b.b12 * q1 * q2 +
            b.b13 * q1 * q3 + b.b23 * q2 * q3) /
               (2 * n) +
           mu1 * g * l1 * (1 - std::cos(x[0])) + mu2 * g * l2 * (1 - std::cos(x[1])) +
           mu3 * g * l3 * (1 - std::cos(x[2]));
  }
  // φ̇_i as printed (each a ∂H/∂p_i), with error 1 fixed as above and error 2 (the last
  // denominator of φ̇₃ printed l₂l₂) fixed to l₂l₃.
  std::vector<double> dphi(const std::vector<double>& x) const {
    const auto b = coefficients(x);
    const double n = N(x), p1 = x[3], p2 = x[4], p3 = x[5];
    const double d1 =
        b.b11 * p1 / (l1 * l1) + 0.5 * b.b12 * p2 / (l1 * l2) + 0.5 * b.b13 * p3 / (l1 * l3);
    const double d2 =
        b.b22 * p2 / (l2 * l2) + 0.5 * b.b12 * p1 / (l1 * l2) + 0.5 * b.b23 * p3 / (l2 * l3);
    const double d3 =
        b.b33 * p3 / (l3 * l3) + 0.5 * b.b13 * p1 / (l1 * l3) + 0.5 * b.b23 * p2 / (l2 * l3);
    return {d1 / n, d2 / n, d3 / n};
  }
  // det A = m₃ l₁² l₂² l₃² N (the paper omits m₃).
  double det_A(const std::vector<double>& x) const {
    return m3 * l1 * l1 * l2 * l2 * l3 * l3 * N(x);
  }
};

}  // namespace

TEST_CASE("rhs: double pendulum matches the paper's Hamilton equations (6.18)") {
  std::mt19937_64 rng(1);
  double worst_h = 0, worst_f = 0;
  for (int s = 0; s < paper_samples; ++s) {
    const chain_parameters params = npend::test::random_parameters(2, rng);
    const chain c(params);
    const double_pendulum_paper paper{params.masses[0], params.masses[1], params.lengths[0],
                                      params.lengths[1], params.g};
    const auto x = npend::test::random_state(2, rng);
    const double h = c.hamiltonian(x), h_paper = paper.H(x);
    worst_h = std::max(worst_h, std::fabs(h - h_paper) / std::fabs(h_paper));
    worst_f = std::max(worst_f, npend::test::relative_error(c.rhs(x), paper.f(x)));
    // The closed form emitted for n ≤ 3 agrees too.
    worst_h =
        std::max(worst_h, std::fabs(c.hamiltonian_closed_form(x) - h_paper) / std::fabs(h_paper));
  }
  INFO("worst relative error: H ", worst_h, ", f ", worst_f);
  CHECK(worst_h < paper_tolerance);
  CHECK(worst_f < paper_tolerance);
}

TEST_CASE("hamiltonian: triple pendulum matches the paper's H with its typos corrected") {
  std::mt19937_64 rng(2);
  double worst_h = 0, worst_dphi = 0, worst_det = 0;
  for (int s = 0; s < paper_samples; ++s) {
    const chain_parameters params = npend::test::random_parameters(3, rng);
    const chain c(params);
    const triple_pendulum_paper paper{params.masses[0],  params.masses[1],  params.masses[2],
                                      params.lengths[0], params.lengths[1], params.lengths[2],
                                      params.g};
    const auto x = npend::test::random_state(3, rng);
    const double h_paper = paper.H(x);
    worst_h = std::max(worst_h, std::fabs(c.hamiltonian(x) - h_paper) / std::fabs(h_paper));
    worst_h =
        std::max(worst_h, std::fabs(c.hamiltonian_closed_form(x) - h_paper) / std::fabs(h_paper));
    const auto f = c.rhs(x);
    worst_dphi = std::max(worst_dphi, npend::test::relative_error(
                                          std::span<const double>(f.data(), 3), paper.dphi(x)));
    const double det = c.det_mass_matrix(std::span<const double>(x.data(), 3));
    worst_det = std::max(worst_det, std::fabs(det - paper.det_A(x)) / paper.det_A(x));
  }
  INFO("worst relative error: H ", worst_h, ", dphi ", worst_dphi, ", det A ", worst_det);
  CHECK(worst_h < paper_tolerance);
  CHECK(worst_dphi < paper_tolerance);
  CHECK(worst_det < paper_tolerance);
}

TEST_CASE("hamiltonian: the paper's uncorrected p1 p2 sign (error 1) is really wrong") {
  // Guards the correction itself: with the printed + sign the paper's H must disagree.
  const chain c(chain_parameters::uniform(3));
  const std::vector<double> x{0.3, -0.4, 0.9, 0.7, -0.2, 0.5};
  triple_pendulum_paper paper{1, 1, 1, 1, 1, 1, 9.81};
  auto b = paper.coefficients(x);
  const double mu3 = 1, f1 = x[0], f2 = x[1], f3 = x[2];
  const double printed_b12 =
      -((2 * 2 - mu3) * std::cos(f1 - f2) + mu3 * std::cos(f1 + f2 - 2 * f3));
  const double delta = (printed_b12 - b.b12) * x[3] * x[4] / (2 * paper.N(x));
  CHECK(std::fabs(delta) > 1e-3);
  CHECK(c.hamiltonian(x) == doctest::Approx(paper.H(x)).epsilon(1e-13));
}
