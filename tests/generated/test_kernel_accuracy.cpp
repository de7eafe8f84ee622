// Componentwise accuracy of the generated kernels at extreme mass and length ratios, against
// a binary128 evaluation of the dense formulas
// (tests/reference/include/reference/precise_chain.hpp).
//
// Every output y must satisfy |ŷ − y| ≤ c u Σ_j |∂y/∂x_j| |x_j| (u = 2⁻⁵³), the bound that
// relative errors of u in each datum x = (sin φ, cos φ, p, m, l, g) would cause to first
// order: the componentwise condition number of y times its size, times u. The factor c leaves
// room for the roundings of the O(n) recursion and of its derivative: over 28,000 random
// chains (n = 2…6, mass and length ratios 1e2…1e8, these patterns) the kernels reached
// c = 1.5 in f and φ̇, 5.4 in H, 0.8 in det A and 24 in the Jacobian (its ∂ṗ/∂φ block, a
// derivative along an angle through the whole elimination), so c = 8 for the values and 32
// for the Jacobian. The inverse-mass formulation they replaced missed this by factors of up
// to 1e7 (5e10 at the mass ratio 1e12 of the second example).
#include <doctest/doctest.h>

#include <algorithm>
#include <chain_index.hpp>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "reference/precise_chain.hpp"

namespace {

using npend::reference::quad;

constexpr double unit_roundoff = 0x1p-53;
constexpr double allowed = 8;            // c in |ŷ − y| ≤ c u Σ_j |∂y/∂x_j| |x_j|
constexpr double allowed_jacobian = 32;  // the same for the Jacobian

struct chain_case {
  std::vector<double> phi, p, masses, lengths;
  double g = 9.81;
  int links() const { return static_cast<int>(masses.size()); }
  std::string describe() const {
    auto list = [](const std::vector<double>& v) {
      std::string s;
      for (const double x : v) s += (s.empty() ? "" : ",") + std::to_string(x);
      return s;
    };
    return "masses " + list(masses) + " lengths " + list(lengths) + " phi " + list(phi) + " p " +
           list(p);
  }
};

/// The worst |ŷ − y| / (u Σ_j |∂y/∂x_j| |x_j|) of each kernel at one case.
struct accuracy {
  double velocities = 0, rhs = 0, jacobian = 0, hamiltonian = 0, det = 0;
};

double ratio(double got, quad want, quad sensitivity) {
  const quad diff = static_cast<quad>(got) - want;
  const double err = static_cast<double>(diff < 0 ? -diff : diff);
  const double bound = unit_roundoff * static_cast<double>(sensitivity);
  if (bound == 0) return err == 0 ? 0 : HUGE_VAL;
  return err / bound;
}

double worst_ratio(const std::vector<double>& got, const std::vector<quad>& want,
                   const std::vector<quad>& sensitivity) {
  double worst = 0;
  for (std::size_t i = 0; i < got.size(); ++i)
    worst = std::max(worst, ratio(got[i], want[i], sensitivity[i]));
  return worst;
}

accuracy measure(const chain_case& c) {
  const int n = c.links();
  const auto nn = static_cast<std::size_t>(n);
  const auto* kernels = npend::generated::find_chain(n);
  REQUIRE(kernels != nullptr);
  std::vector<double> x = c.phi, params = c.masses;
  x.insert(x.end(), c.p.begin(), c.p.end());
  params.insert(params.end(), c.lengths.begin(), c.lengths.end());
  params.push_back(c.g);

  std::vector<double> dphi(nn), f(2 * nn), jac(4 * nn * nn);
  kernels->velocities(c.phi.data(), c.p.data(), params.data(), dphi.data());
  kernels->rhs(x.data(), params.data(), f.data());
  kernels->jacobian(x.data(), params.data(), jac.data());
  const double h = kernels->hamiltonian(x.data(), params.data());
  const double det = kernels->det_mass_matrix(c.phi.data(), params.data());

  const auto ref = npend::reference::precise_reference(c.phi, c.p, c.masses, c.lengths, c.g);
  accuracy a;
  a.velocities = worst_ratio(dphi, ref.value.dphi, ref.sensitivity.dphi);
  a.rhs = worst_ratio(f, ref.value.f, ref.sensitivity.f);
  a.jacobian = worst_ratio(jac, ref.value.jac, ref.sensitivity.jac);
  a.hamiltonian = ratio(h, ref.value.hamiltonian, ref.sensitivity.hamiltonian);
  a.det = ratio(det, ref.value.det, ref.sensitivity.det);
  return a;
}

/// Random chains whose masses or lengths (or both) span a ratio up to `spread`: growing
/// towards the tip, shrinking towards it, or scattered log-uniformly; angles anywhere, nearly
/// aligned, or near the hanging position; momenta over two decades.
std::vector<chain_case> extreme_cases(int n, double spread, std::mt19937_64& rng, int count) {
  std::uniform_real_distribution<double> unit(-1, 1);
  const double decades = std::log10(spread);
  std::vector<chain_case> out;
  for (int s = 0; s < count; ++s) {
    chain_case c;
    const int pattern = s % 6;
    for (int i = 0; i < n; ++i) {
      const double along = n > 1 ? static_cast<double>(i) / (n - 1) : 0.0;
      const double near_one = 1 + 0.3 * unit(rng);
      double m = near_one, l = 1 + 0.3 * unit(rng);
      switch (pattern) {
        case 0:
          m = std::pow(10.0, decades * along);
          break;  // heavy tip
        case 1:
          m = std::pow(10.0, -decades * along);
          break;  // heavy pivot link
        case 2:
          l = std::pow(10.0, decades * along);
          break;  // long tip
        case 3:
          l = std::pow(10.0, -decades * along);
          break;  // long pivot link
        case 4:   // both scattered
          m = std::pow(10.0, decades / 2 * unit(rng));
          l = std::pow(10.0, decades / 2 * unit(rng));
          break;
        default:
          m = unit(rng) > 0 ? spread : 1.0;
          break;  // two mass levels
      }
      c.masses.push_back(m * near_one);
      c.lengths.push_back(l);
      c.phi.push_back(3.1 * unit(rng));
      c.p.push_back(3 * unit(rng) * std::pow(10.0, unit(rng)));
    }
    if (s % 4 == 1)
      for (int i = 1; i < n; ++i) c.phi[static_cast<std::size_t>(i)] = c.phi[0] + 1e-3 * unit(rng);
    if (s % 4 == 3)
      for (auto& a : c.phi) a = 1e-3 * unit(rng);
    out.push_back(std::move(c));
  }
  return out;
}

/// One measured case of the sweep.
struct sweep_point {
  int links;
  double spread;
  chain_case chain;
  accuracy result;
};

/// `extreme_cases` for n = 2…6 and ratios 1e4 and 1e8, measured once for all test cases.
const std::vector<sweep_point>& sweep() {
  static const std::vector<sweep_point> points = [] {
    std::vector<sweep_point> out;
    for (int n = 2; n <= 6; ++n) {
      std::mt19937_64 rng(500 + static_cast<unsigned>(n));
      for (const double spread : {1e4, 1e8})
        for (auto& c : extreme_cases(n, spread, rng, 24)) {
          const accuracy a = measure(c);
          out.push_back({n, spread, std::move(c), a});
        }
    }
    return out;
  }();
  return points;
}

/// Checks one kernel's worst ratio (chosen by `pick`) per link count and ratio against `limit`.
template <class Pick>
void check_extremes(const char* what, Pick pick, double limit = allowed) {
  for (int n = 2; n <= 6; ++n)
    for (const double spread : {1e4, 1e8}) {
      double worst = 0;
      std::string where;
      for (const auto& point : sweep()) {
        if (point.links != n || point.spread != spread) continue;
        const double r = pick(point.result);
        if (r > worst) {
          worst = r;
          where = point.chain.describe();
        }
      }
      INFO(std::string(what), ", n = ", n, ", ratio ", spread, ": worst error ", worst,
           " x u x condition, at ", where);
      CHECK(worst <= limit);
    }
}

quad magnitude(quad x) { return x < 0 ? -x : x; }

}  // namespace

TEST_CASE("velocities: accurate to the condition number at mass ratios up to 1e8 (n = 2)") {
  // The first example: dphi_1/dt was off by 4e-8 relative at m = 1, 1e8 (2e-14 at
  // 1e2, 1.6e-12 at 1e4, 2e-10 at 1e6), though its condition number is ≈ 9.
  for (const double heavy : {1e2, 1e4, 1e6, 1e8}) {
    for (const bool reversed : {false, true}) {
      chain_case c{{0.4, -1.2}, {1, -3}, {1, heavy}, {1, 1}};
      if (reversed) std::swap(c.masses[0], c.masses[1]);
      const accuracy a = measure(c);
      INFO(c.describe());
      CHECK(a.velocities <= allowed);
      CHECK(a.rhs <= allowed);
      CHECK(a.jacobian <= allowed_jacobian);
      CHECK(a.hamiltonian <= allowed);
    }
  }
  // The value the issue quotes (to 14 digits) from an independent 30-digit derivation.
  const chain_case c{{0.4, -1.2}, {1, -3}, {1, 1e8}, {1, 1}};
  std::vector<double> dphi(2), params{1, 1e8, 1, 1, 9.81};
  npend::generated::find_chain(2)->velocities(c.phi.data(), c.p.data(), params.data(), dphi.data());
  CHECK(std::fabs(dphi[0] - 9.1318001229469e-09) <= 1e-14 * 9.1318001229469e-09);
}

TEST_CASE("jacobian: accurate to the condition number at masses 1e-6, 1e6, 1 (n = 3)") {
  // The second example: dphi_1/dt and dphi_2/dt off by 4e-5 relative, the Jacobian
  // by 3e-5, and A dphi = p held only to 4e-11.
  const chain_case c{{0.4, -1.2, 2.5}, {1, -3, 0.5}, {1e-6, 1e6, 1}, {1, 1.5, 0.7}};
  const accuracy a = measure(c);
  CHECK(a.velocities <= allowed);
  CHECK(a.rhs <= allowed);
  CHECK(a.jacobian <= allowed_jacobian);
  CHECK(a.hamiltonian <= allowed);
  CHECK(a.det <= allowed);

  // The Legendre transform back: A(phi) dphi reproduces p to the rounding of the product,
  // |A dphi − p|_i ≤ c u (|A| |dphi|)_i.
  const auto* k = npend::generated::find_chain(3);
  std::vector<double> params = c.masses;
  params.insert(params.end(), c.lengths.begin(), c.lengths.end());
  params.push_back(c.g);
  std::vector<double> dphi(3), A(9);
  k->velocities(c.phi.data(), c.p.data(), params.data(), dphi.data());
  k->mass_matrix(c.phi.data(), params.data(), A.data());
  for (std::size_t i = 0; i < 3; ++i) {
    quad residual = -static_cast<quad>(c.p[i]), scale = 0;
    for (std::size_t j = 0; j < 3; ++j) {
      residual += static_cast<quad>(A[i * 3 + j]) * dphi[j];
      scale += magnitude(static_cast<quad>(A[i * 3 + j]) * dphi[j]);
    }
    INFO("row ", i + 1, ": |A dphi - p| = ", static_cast<double>(magnitude(residual)));
    CHECK(static_cast<double>(magnitude(residual)) <=
          allowed * unit_roundoff * static_cast<double>(scale));
  }
}

TEST_CASE("velocities: componentwise accurate for mass and length ratios up to 1e8, n = 2..6") {
  check_extremes("velocities", [](const accuracy& a) { return a.velocities; });
}

TEST_CASE("rhs: componentwise accurate for mass and length ratios up to 1e8, n = 2..6") {
  check_extremes("rhs", [](const accuracy& a) { return a.rhs; });
}

TEST_CASE("jacobian: componentwise accurate for mass and length ratios up to 1e8, n = 2..6") {
  check_extremes(
      "jacobian", [](const accuracy& a) { return a.jacobian; }, allowed_jacobian);
}

TEST_CASE("hamiltonian: componentwise accurate for mass and length ratios up to 1e8, n = 2..6") {
  check_extremes("hamiltonian", [](const accuracy& a) { return a.hamiltonian; });
}

TEST_CASE("det_mass_matrix: accurate for mass and length ratios up to 1e8, n = 2..6") {
  check_extremes("det A", [](const accuracy& a) { return a.det; });
}
