// The physical chain at run time — rigid links, joint springs and damping, a moving pivot —
// against a hand-written implementation, closed forms of small chains and energy balances.
#include <doctest/doctest.h>

#include <algorithm>
#include <boost/numeric/odeint/integrate/integrate_const.hpp>
#include <boost/numeric/odeint/stepper/generation.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta_dopri5.hpp>
#include <cmath>
#include <complex>
#include <numbers>

#include "npend/chain.hpp"
#include "npend/chain_system.hpp"
#include "npend/integrators/integrate.hpp"
#include "npend/integrators/stepper_kind.hpp"
#include "reference/dense_chain.hpp"
#include "support/test_support.hpp"

using npend::chain;
using npend::chain_parameters;
using npend::pivot_motion;

namespace {

// Random physical parameters: every feature switched on, values of order one.
chain_parameters random_physical(int n, std::mt19937_64& rng) {
  chain_parameters p = npend::test::random_parameters(n, rng);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int i = 0; i < n; ++i) {
    p.com.push_back((0.2 + unit(rng)) * p.lengths[static_cast<std::size_t>(i)]);
    p.inertia.push_back(0.3 * unit(rng));
    p.stiffness.push_back(5 * unit(rng));
    p.rest_angles.push_back(unit(rng) - 0.5);
    p.damping.push_back(0.5 * unit(rng));
  }
  return p;
}

npend::reference::dense_chain reference_of(const chain_parameters& p) {
  return npend::reference::dense_chain::physical(p.masses, p.lengths, p.g, p.com, p.inertia,
                                                 p.stiffness, p.rest_angles, p.damping);
}

// The eigenvalues of the Jacobian at the state x (the linearisation there).
std::vector<std::complex<double>> linear_spectrum(const chain& c, const std::vector<double>& x) {
  const int d = c.state_size();
  const Eigen::MatrixXd J = npend::test::to_eigen(c.jacobian(x), d, d);
  const Eigen::VectorXcd ev = J.eigenvalues();
  std::vector<std::complex<double>> out(ev.data(), ev.data() + d);
  std::sort(out.begin(), out.end(), [](auto a, auto b) {
    return std::abs(a.imag()) != std::abs(b.imag()) ? std::abs(a.imag()) < std::abs(b.imag())
                                                    : a.imag() < b.imag();
  });
  return out;
}

// The angular frequencies |Im λ| of the linearisation at rest, ascending, one per mode.
std::vector<double> mode_frequencies(const chain& c) {
  const auto spectrum =
      linear_spectrum(c, std::vector<double>(static_cast<std::size_t>(c.state_size()), 0.0));
  std::vector<double> w;
  for (const auto& l : spectrum)
    if (l.imag() > 0) w.push_back(l.imag());
  return w;
}

}  // namespace

TEST_CASE(
    "physical chain: rhs, Jacobian, H and the mass matrix equal the hand-written rigid chain") {
  std::mt19937_64 rng(1301);
  for (int n = 1; n <= 6; ++n) {
    for (int trial = 0; trial < 3; ++trial) {
      const chain_parameters p = random_physical(n, rng);
      const chain c(p);
      REQUIRE(c.is_physical());
      const auto ref = reference_of(p);
      const auto x = npend::test::random_state(n, rng);
      const Eigen::VectorXd xe = npend::test::to_eigen(x);
      const Eigen::VectorXd fr = ref.rhs(xe);
      CHECK(npend::test::relative_error(c.rhs(x),
                                        std::vector<double>(fr.data(), fr.data() + 2 * n)) < 1e-12);
      CHECK(npend::test::relative_error(npend::test::to_eigen(c.jacobian(x), 2 * n, 2 * n),
                                        ref.jacobian(xe)) < 1e-12);
      CHECK(std::fabs(c.hamiltonian(x) - ref.hamiltonian(xe)) <
            1e-12 * std::max(1.0, std::fabs(ref.hamiltonian(xe))));
      std::vector<double> A(static_cast<std::size_t>(n * n));
      c.mass_matrix(std::span<const double>(x).first(static_cast<std::size_t>(n)), A);
      CHECK(npend::test::relative_error(npend::test::to_eigen(A, n, n),
                                        ref.mass_matrix(xe.head(n))) < 1e-13);
    }
  }
}

TEST_CASE("physical chain: a pivot's acceleration and joint torques enter as the reference says") {
  std::mt19937_64 rng(1302);
  for (int n = 1; n <= 4; ++n) {
    chain_parameters p = random_physical(n, rng);
    p.pivot = pivot_motion::horizontal(0.1, 7.0);
    const chain c(p);
    auto ref = reference_of(p);
    const double t = 0.37;
    const auto a = p.pivot.acceleration_at(t);
    ref.set_inputs(a[0], a[1], std::vector<double>(static_cast<std::size_t>(n), 0.0));
    const auto x = npend::test::random_state(n, rng);
    std::vector<double> f(static_cast<std::size_t>(2 * n));
    c.rhs(x, f, t);
    const Eigen::VectorXd fr = ref.rhs(npend::test::to_eigen(x));
    CHECK(npend::test::relative_error(f, std::vector<double>(fr.data(), fr.data() + 2 * n)) <
          1e-12);

    // Torques: f(u) − f(0) is the input matrix's torque columns times u (f is affine in u).
    std::vector<double> u(static_cast<std::size_t>(n));
    for (auto& ui : u) ui = std::uniform_real_distribution<double>(-2, 2)(rng);
    ref.set_inputs(a[0], a[1], u);
    const Eigen::VectorXd fu = ref.rhs(npend::test::to_eigen(x));
    const int inputs = npend::chain_layout::input_size(n);
    std::vector<double> dfdw(static_cast<std::size_t>(2 * n * inputs));
    c.input_matrix(std::span<const double>(x).first(static_cast<std::size_t>(n)), dfdw);
    for (int i = 0; i < 2 * n; ++i) {
      double bu = 0;
      for (int j = 0; j < n; ++j)
        bu += dfdw[static_cast<std::size_t>(i * inputs + npend::chain_layout::torque_index(n, j))] *
              u[static_cast<std::size_t>(j)];
      CHECK(f[static_cast<std::size_t>(i)] + bu == doctest::Approx(fu(i)).epsilon(1e-12));
    }
  }
}

TEST_CASE("physical chain: with c = l and nothing else it is the point-mass chain") {
  std::mt19937_64 rng(1303);
  for (int n = 1; n <= 6; ++n) {
    const chain_parameters point = npend::test::random_parameters(n, rng);
    chain_parameters rigid = point;
    rigid.com = rigid.lengths;
    rigid.inertia.assign(static_cast<std::size_t>(n), 0.0);
    const chain a(point), b(rigid);
    REQUIRE_FALSE(a.is_physical());
    REQUIRE(b.is_physical());
    const auto x = npend::test::random_state(n, rng);
    CHECK(npend::test::relative_error(b.rhs(x), a.rhs(x)) < 1e-12);
    CHECK(npend::test::relative_error(b.jacobian(x), a.jacobian(x)) < 1e-12);
    CHECK(b.hamiltonian(x) == doctest::Approx(a.hamiltonian(x)).epsilon(1e-13));
  }
}

TEST_CASE("physical chain: the compound pendulum's frequency sqrt(m g c / (J + m c^2))") {
  for (const auto& [c, J] : {std::pair{0.5, 1.0 / 12}, std::pair{0.3, 0.02}, std::pair{1.2, 0.4}}) {
    chain_parameters p = chain_parameters::uniform(1, 1.7, 1.4);
    p.com = {c};
    p.inertia = {J};
    const double expected = std::sqrt(1.7 * 9.81 * c / (J + 1.7 * c * c));
    const auto w = mode_frequencies(chain{p});
    REQUIRE(w.size() == 1);
    CHECK(w[0] == doctest::Approx(expected).epsilon(1e-12));
  }
}

TEST_CASE("physical chain: two uniform rods swing at omega^2 = (3 -+ 6/sqrt 7) g/l") {
  const double l = 0.8, g = 9.81;
  chain_parameters p = chain_parameters::uniform(2, 1.3, l, g);
  p.make_uniform_rods();
  const auto w = mode_frequencies(chain{p});
  REQUIRE(w.size() == 2);
  CHECK(w[0] * w[0] == doctest::Approx((3 - 6 / std::sqrt(7.0)) * g / l).epsilon(1e-12));
  CHECK(w[1] * w[1] == doctest::Approx((3 + 6 / std::sqrt(7.0)) * g / l).epsilon(1e-12));
}

TEST_CASE("physical chain: springs alone (g = 0) give the linear chain's modes") {
  // Point masses on a horizontal table with torsion springs: K = Dᵀ diag(k) D, and A at
  // φ = 0 is μ_max(i,j) l_i l_j — the generalised eigenproblem K v = ω² A v by hand.
  const std::vector<double> m{1.0, 0.7, 1.5}, l{1.0, 0.6, 0.9}, k{3.0, 2.0, 5.0};
  chain_parameters p;
  p.masses = m;
  p.lengths = l;
  p.g = 0;
  p.stiffness = k;
  Eigen::Matrix3d A, K = Eigen::Matrix3d::Zero();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      double mu = 0;
      for (int r = std::max(i, j); r < 3; ++r) mu += m[static_cast<std::size_t>(r)];
      A(i, j) = mu * l[static_cast<std::size_t>(i)] * l[static_cast<std::size_t>(j)];
    }
    K(i, i) = k[static_cast<std::size_t>(i)] + (i < 2 ? k[static_cast<std::size_t>(i + 1)] : 0.0);
    if (i < 2) K(i, i + 1) = K(i + 1, i) = -k[static_cast<std::size_t>(i + 1)];
  }
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::Matrix3d> modes(K, A);
  const auto w = mode_frequencies(chain{p});
  REQUIRE(w.size() == 3);
  for (int i = 0; i < 3; ++i)
    CHECK(w[static_cast<std::size_t>(i)] ==
          doctest::Approx(std::sqrt(modes.eigenvalues()(i))).epsilon(1e-11));
}

TEST_CASE("physical chain: the damped pendulum decays at b/(2I), the linear theory's rate") {
  chain_parameters p = chain_parameters::uniform(1, 2.0, 0.9);
  p.com = {0.45};
  p.inertia = {2.0 * 0.81 / 12};
  p.damping = {0.3};
  const double I = p.inertia[0] + 2.0 * 0.45 * 0.45, w0 = std::sqrt(2.0 * 9.81 * 0.45 / I);
  const double rate = 0.3 / (2 * I);
  const auto spectrum = linear_spectrum(chain{p}, {0.0, 0.0});
  REQUIRE(spectrum.size() == 2);
  for (const auto& l : spectrum) {
    CHECK(l.real() == doctest::Approx(-rate).epsilon(1e-12));
    CHECK(std::abs(l.imag()) == doctest::Approx(std::sqrt(w0 * w0 - rate * rate)).epsilon(1e-12));
  }
}

namespace {

// dH/dt along the flow, written out from the model: the damping's power −Σ b_j θ̇_j² plus
// ∂H/∂t, the inertial potential's rate Σ G-weighted ȧ terms: ∂V/∂a_x = Σ m_k x_k and
// ∂V/∂a_y = −Σ m_k (h_k − y_k) for the mass points r_k (h_k their depth at rest). Point
// masses here (c = l), so the mass points are the link ends of positions().
double energy_rate(const chain& c, std::span<const double> x, double t) {
  const int n = c.links();
  const chain_parameters& p = c.parameters();
  std::vector<double> dphi(static_cast<std::size_t>(n)), xy(static_cast<std::size_t>(2 * n));
  const auto phi = x.first(static_cast<std::size_t>(n));
  c.velocities(phi, x.subspan(static_cast<std::size_t>(n)), dphi);
  double power = 0;
  for (int j = 0; j < n; ++j) {
    const double rate =
        dphi[static_cast<std::size_t>(j)] - (j > 0 ? dphi[static_cast<std::size_t>(j - 1)] : 0.0);
    if (!p.damping.empty()) power -= p.damping[static_cast<std::size_t>(j)] * rate * rate;
  }
  c.positions(phi, xy);
  const auto jerk = p.pivot.jerk_at(t);
  double depth = 0;
  for (int k = 0; k < n; ++k) {
    depth += p.lengths[static_cast<std::size_t>(k)];
    const double m = p.masses[static_cast<std::size_t>(k)];
    power += m * xy[static_cast<std::size_t>(2 * k)] * jerk[0] -
             m * (depth - xy[static_cast<std::size_t>(2 * k + 1)]) * jerk[1];
  }
  return power;
}

// Integrates [x, W] with Ẇ = energy_rate to t_end and returns (H(t_end) − H(0), W(t_end)).
std::pair<double, double> energy_balance(const chain& c, std::vector<double> x0, double t_end) {
  namespace odeint = boost::numeric::odeint;
  const std::size_t d = x0.size();
  std::vector<double> y = x0;
  y.push_back(0.0);
  const double h0 = c.hamiltonian(x0, 0.0);
  auto sys = [&](const std::vector<double>& s, std::vector<double>& dsdt, double t) {
    c.rhs(std::span<const double>(s).first(d), std::span<double>(dsdt).first(d), t);
    dsdt[d] = energy_rate(c, std::span<const double>(s).first(d), t);
  };
  odeint::integrate_const(
      odeint::make_controlled(1e-13, 1e-13, odeint::runge_kutta_dopri5<std::vector<double>>()), sys,
      y, 0.0, t_end, 0.01);
  return {c.hamiltonian(std::span<const double>(y).first(d), t_end) - h0, y[d]};
}

}  // namespace

TEST_CASE("physical chain: a damped chain loses dH/dt = -sum b theta_dot^2, to 1e-9") {
  chain_parameters p = chain_parameters::uniform(3, 1.0, 1.0);
  p.com = p.lengths;
  p.damping = {0.2, 0.1, 0.05};
  const chain c(p);
  const std::vector<double> x0 = c.state_from_velocities(std::vector<double>{1.5, 1.5, 1.5},
                                                         std::vector<double>{0.0, 0.0, 0.0});
  const auto [dh, work] = energy_balance(c, x0, 10.0);
  CHECK(dh < -1.0);  // it did lose energy
  CHECK(std::fabs(dh - work) < 1e-9 * std::fabs(c.hamiltonian(x0)));
}

TEST_CASE("physical chain: on a shaken pivot H(t) - H(0) is the work of the inertial force") {
  chain_parameters p = chain_parameters::uniform(2, 1.0, 1.0);
  p.pivot = pivot_motion::vertical(0.05, 20.0);
  const chain c(p);
  const std::vector<double> x0 =
      c.state_from_velocities(std::vector<double>{0.8, -0.4}, std::vector<double>{0.0, 0.0});
  const auto [dh, work] = energy_balance(c, x0, 5.0);
  CHECK(std::fabs(dh) > 1e-2);  // the drive did change the energy
  CHECK(std::fabs(dh - work) < 1e-9 * std::fabs(c.hamiltonian(x0)));
}

TEST_CASE("physical chain: df/dt of a moving pivot agrees with a difference in t") {
  std::mt19937_64 rng(1304);
  chain_parameters p = random_physical(3, rng);
  p.pivot = pivot_motion::vertical(0.02, 30.0);
  const chain c(p);
  const auto x = npend::test::random_state(3, rng);
  const double t = 0.123, h = 1e-6;
  std::vector<double> dfdt(6), fp(6), fm(6);
  c.time_derivative(x, dfdt, t);
  c.rhs(x, fp, t + h);
  c.rhs(x, fm, t - h);
  for (std::size_t i = 0; i < 6; ++i)
    CHECK(dfdt[i] == doctest::Approx((fp[i] - fm[i]) / (2 * h)).epsilon(1e-6).scale(1.0));
}

TEST_CASE("physical chain: bad parameters are refused with the reason") {
  chain_parameters p = chain_parameters::uniform(2);
  p.com = {0.5, 0.0};
  CHECK_THROWS_WITH_AS(chain{p}, doctest::Contains("link 2 has its centre of mass at its joint"),
                       std::invalid_argument);
  p.inertia = {0.0, 0.1};
  CHECK_NOTHROW(chain{p});
  p.damping = {0.1, -0.2};
  CHECK_THROWS_WITH_AS(chain{p}, doctest::Contains("damping 2 is -0.2"), std::invalid_argument);
  p.damping = {0.1};
  CHECK_THROWS_WITH_AS(chain{p}, doctest::Contains("1 values for damping"), std::invalid_argument);
  p.damping.clear();
  p.pivot = pivot_motion::vertical(0.1, 0.0);
  CHECK_THROWS_WITH_AS(chain{p}, doctest::Contains("pivot frequency is 0"), std::invalid_argument);
  chain_parameters q = chain_parameters::uniform(1);
  q.g = 0;
  CHECK_THROWS_WITH_AS(chain{q}, doctest::Contains("g is 0"), std::invalid_argument);
}

namespace {

// The smallest det A / Π A_ii (Hadamard's ratio, in [0, 1]) of the hand-written dense mass
// matrix over configurations φ_1 = 0, φ_i = multiples of 2π/steps: A depends only on the
// differences φ_i − φ_j, and the singular configurations (links lined up) lie on the grid.
double smallest_det_ratio(const chain_parameters& p, int steps) {
  const int n = p.links();
  const auto zeros = std::vector<double>(static_cast<std::size_t>(n), 0.0);
  const auto ref = npend::reference::dense_chain::physical(p.masses, p.lengths, p.g, p.com,
                                                           p.inertia, zeros, zeros, zeros);
  double smallest = INFINITY;
  std::vector<int> k(static_cast<std::size_t>(n), 0);
  for (;;) {
    Eigen::VectorXd phi(n);
    for (int i = 0; i < n; ++i)
      phi(i) = 2 * std::numbers::pi * k[static_cast<std::size_t>(i)] / steps;
    const Eigen::MatrixXd A = ref.mass_matrix(phi);
    // A zero on the diagonal of this positive semidefinite A makes it singular.
    const double scale = A.diagonal().prod();
    smallest = std::min(smallest, scale > 0 ? A.determinant() / scale : 0.0);
    int i = 1;  // φ_1 stays 0
    while (i < n && ++k[static_cast<std::size_t>(i)] == steps) k[static_cast<std::size_t>(i++)] = 0;
    if (i == n) break;
  }
  return smallest;
}

}  // namespace

TEST_CASE("physical chain: refused exactly when the dense mass matrix is singular somewhere") {
  // Every chain of 2..4 links whose links each have c in {0, l/2, l, -l/2} (3 links: also
  // -l/2) and J in {0, 0.2}: refused by the chain's rule exactly when det A reaches 0 on a
  // grid of configurations, and otherwise bounded away from 0 there.
  const std::vector<double> masses{1.0, 0.7, 1.4, 0.9}, lengths{1.0, 1.3, 0.8, 1.1};
  int refused = 0, accepted = 0;
  double largest_refused = 0, smallest_accepted = INFINITY;
  for (int n = 2; n <= 4; ++n) {
    const std::vector<double> fractions =
        n <= 3 ? std::vector<double>{0.0, 0.5, 1.0, -0.5} : std::vector<double>{0.0, 0.5, 1.0};
    const int kinds = 2 * static_cast<int>(fractions.size()), steps = n <= 3 ? 16 : 8;
    int chains = 1;
    for (int i = 0; i < n; ++i) chains *= kinds;
    for (int code = 0; code < chains; ++code) {
      chain_parameters p;
      p.masses.assign(masses.begin(), masses.begin() + n);
      p.lengths.assign(lengths.begin(), lengths.begin() + n);
      for (int i = 0, rest = code; i < n; ++i, rest /= kinds) {
        const int kind = rest % kinds;
        p.com.push_back(fractions[static_cast<std::size_t>(kind / 2)] *
                        lengths[static_cast<std::size_t>(i)]);
        p.inertia.push_back(kind % 2 == 0 ? 0.0 : 0.2);
      }
      bool throws = false;
      try {
        p.validate();
      } catch (const std::invalid_argument&) {
        throws = true;
      }
      const double ratio = smallest_det_ratio(p, steps);
      if (throws) {
        ++refused;
        largest_refused = std::max(largest_refused, ratio);
      } else {
        ++accepted;
        smallest_accepted = std::min(smallest_accepted, ratio);
      }
      INFO("n = ", n, ", c = ", p.com[0], ",", p.com[1], ",", p.com.back(), ", J = ", p.inertia[0],
           ",", p.inertia[1], ",", p.inertia.back(), ", min ratio = ", ratio);
      CHECK((throws ? ratio < 1e-13 : ratio > 1e-4));
    }
  }
  MESSAGE("refused ", refused, " chains (largest ratio ", largest_refused, "), accepted ", accepted,
          " (smallest ratio ", smallest_accepted, ")");
  CHECK(refused > 100);
  CHECK(accepted > 100);
}

TEST_CASE("physical chain: a singular chain's refusal names its links") {
  // det A = m_2² c_2² l_1² sin²(φ_1 − φ_2) for c_1 = J_1 = J_2 = 0 (n = 2): zero where the links
  // line up.
  chain_parameters p = chain_parameters::uniform(2);
  p.com = {0.0, 1.0};
  p.inertia = {0.0, 0.0};
  CHECK_THROWS_WITH_AS(chain{p}, doctest::Contains("links 1..2 make the mass matrix singular"),
                       std::invalid_argument);
  p.com = {0.0, 0.5};  // the same with c_2 != l_2: the motion runs out of the chain
  CHECK_THROWS_WITH_AS(chain{p}, doctest::Contains("links 1..2 make the mass matrix singular"),
                       std::invalid_argument);
  p.inertia = {0.0, 0.01};
  CHECK_NOTHROW(chain{p});
  chain_parameters q = chain_parameters::uniform(3);
  q.com = {1.0, 0.0, 1.0};
  q.inertia = {0.0, 0.0, 0.0};
  CHECK_THROWS_WITH_AS(chain{q}, doctest::Contains("links 2..3 make the mass matrix singular"),
                       std::invalid_argument);
  q.com = {0.0, 1.0, 0.0};  // links 1..2 close at rest; link 3 alone is singular too
  CHECK_THROWS_WITH_AS(chain{q}, doctest::Contains("links 1..2"), std::invalid_argument);
}

TEST_CASE("physical chain: every stepper follows a damped chain on a shaken pivot alike") {
  // The non-autonomous, dissipative system: the Gauss–Legendre steppers evaluate f at their
  // stage times, rosenbrock4 gets df/dt; all must land on the same state.
  chain_parameters p = chain_parameters::uniform(2, 1.0, 0.5);
  p.make_uniform_rods();
  p.damping = {0.02, 0.01};
  p.pivot = pivot_motion::vertical(0.03, 25.0);
  const chain c(p);
  const std::vector<double> x0 =
      c.state_from_velocities(std::vector<double>{2.5, 2.9}, std::vector<double>{0.0, 0.0});
  npend::integration_options o;
  o.t_end = 3.0;
  o.dt = 1e-3;
  o.abs_tol = o.rel_tol = 1e-12;
  o.stepper = npend::stepper_kind::dopri5;
  const std::vector<double> reference = npend::integrate(c, x0, o).state;
  for (const auto kind : {npend::stepper_kind::gauss6, npend::stepper_kind::gauss4,
                          npend::stepper_kind::rk4, npend::stepper_kind::rosenbrock4}) {
    CAPTURE(npend::stepper_name(kind));
    o.stepper = kind;
    o.dt = kind == npend::stepper_kind::gauss6 ? 1e-3 : 2e-4;
    const auto r = npend::integrate(c, x0, o);
    CHECK(npend::test::relative_error(r.state, reference) < 2e-9);
  }
}

TEST_CASE("chain: hamiltonian keeps its relative precision at small energies") {
  // φ = 1e-6 rad: V = a (1 − cos φ) = a φ²/2 (1 − φ²/12 + …), summed by hand from the series;
  // 1 − cos φ computed as such cancels to one rounding unit of 1 (relative error ~2e-4
  // here). Point masses (a = m g l per link below) and uniform rods (a_1 = g (m c + l m_2)).
  const double phi = 1e-6, series = phi * phi / 2 * (1 - phi * phi / 12);
  const npend::chain point(npend::chain_parameters::uniform(1, 1.0, 1.0));
  CHECK(point.hamiltonian(std::vector<double>{phi, 0.0}) ==
        doctest::Approx(9.81 * series).epsilon(1e-14));
  CHECK(point.potential_energy(std::vector<double>{phi}) ==
        doctest::Approx(9.81 * series).epsilon(1e-14));
  npend::chain_parameters p = npend::chain_parameters::uniform(2, 1.0, 1.0);
  p.make_uniform_rods();
  const npend::chain rods(p);
  const double a1 = 9.81 * (0.5 + 1.0), a2 = 9.81 * 0.5;
  CHECK(rods.hamiltonian(std::vector<double>{phi, -phi, 0.0, 0.0}) ==
        doctest::Approx((a1 + a2) * series).epsilon(1e-14));
  // With momentum: T = p²/(2 m l²) for one point mass.
  CHECK(point.hamiltonian(std::vector<double>{phi, 2e-6}) ==
        doctest::Approx(9.81 * series + 2e-12).epsilon(1e-14));
  // And the loop kernels' chains (a link count without unrolled kernels) alike.
  const npend::chain long_chain(npend::chain_parameters::uniform(9, 1.0, 1.0));
  std::vector<double> x(18, 0.0);
  x[8] = phi;  // the last link: a = m g l
  CHECK(long_chain.hamiltonian(x) == doctest::Approx(9.81 * series).epsilon(1e-14));
}

TEST_CASE("chain: the energy drift of a tiny oscillation is measured to rounding") {
  // E ~ 1e-11 J: gauss6 keeps H to ~1e-15 relative; the measured drift used to be ~1e-4,
  // all of it the cancellation in 1 − cos φ.
  const npend::chain c(npend::chain_parameters::uniform(2, 1.0, 1.0));
  const std::vector<double> x0{1e-6, 0.0, 0.0, 0.0};
  npend::integration_options o;
  o.t_end = 10;
  o.dt = 1e-2;
  const double h0 = c.hamiltonian(x0);
  double worst = 0;
  npend::integrate(c, x0, o, [&](double, std::span<const double> x) {
    worst = std::max(worst, std::fabs(c.hamiltonian(x) - h0) / h0);
  });
  CHECK(worst < 1e-12);
}
