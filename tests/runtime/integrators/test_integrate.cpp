// npend::integrate with every stepper: against an independent tight-tolerance reference,
// against the linear normal-mode solution for small oscillations, its output grid, the
// observer, its guards, and integrate_system on a system that is not a chain.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <map>

#include "npend/integrators/detail/rejecting_range_algebra.hpp"
#include "npend/integrators/integrate.hpp"
#include "npend/integrators/integrate_system.hpp"
#include "npend/integrators/integration_error.hpp"
#include "reference/reference_trajectory.hpp"
#include "support/test_support.hpp"

using npend::chain;
using npend::integration_options;
using npend::stepper_kind;

namespace {

// Grid points k·dt at which the observer records the state.
struct recorder {
  std::map<long, std::vector<double>> states;
  double dt;
  void operator()(double t, std::span<const double> x) {
    states[std::lround(t / dt)] = std::vector<double>(x.begin(), x.end());
  }
};

// What each stepper should reach on a 2 s run of a moderately excited chain (measured
// worst cases over n = 2, 3 in parentheses): fixed-step ones at dt = 1e-3 — rk4 and gauss4
// have global errors ~ (ω dt)⁴ ω t (2e-9, 6e-10), gauss6 ~ (ω dt)⁶ ω t (9e-13); adaptive ones
// at abs = rel = 1e-12 (dopri5 1e-11, rkf78 2e-13, bs 3e-13, rosenbrock4 1e-12, taylor ?).
double expected_accuracy(stepper_kind k) {
  switch (k) {
    case stepper_kind::rk4:
      return 1e-8;
    case stepper_kind::gauss4:
      return 5e-9;
    case stepper_kind::gauss6:
      return 1e-11;
    case stepper_kind::dopri5:
      return 1e-10;
    case stepper_kind::rkf78:
      return 5e-12;
    case stepper_kind::bulirsch_stoer:
      return 5e-12;
    case stepper_kind::rosenbrock4:
      return 1e-11;
    case stepper_kind::taylor:
      return 5e-12;
  }
  return 0;
}

}  // namespace

TEST_CASE("integrate: every stepper agrees with a tight-tolerance reference, n = 2 and 3") {
  std::mt19937_64 rng(11);
  for (int n : {2, 3}) {
    const npend::chain_parameters params = npend::test::random_parameters(n, rng);
    const chain c(params);
    std::vector<double> x0;
    for (int i = 0; i < n; ++i) x0.push_back(0.9 * (i % 2 == 0 ? 1 : -1) / (i + 1));
    for (int i = 0; i < n; ++i) x0.push_back(0.5 * (i + 1));
    const std::vector<double> times{0.5, 1.0, 1.5, 2.0};
    const auto reference =
        npend::reference::reference_trajectory(npend::reference::dense_chain_of(params), x0, times);

    for (stepper_kind k : npend::all_stepper_kinds()) {
      integration_options o;
      o.stepper = k;
      o.t_end = 2.0;
      o.dt = 1e-3;
      o.abs_tol = o.rel_tol = 1e-12;
      recorder rec{{}, o.dt};
      const auto result = npend::integrate(c, x0, o, rec);
      double worst = 0;
      for (std::size_t i = 0; i < times.size(); ++i)
        worst = std::max(worst, npend::test::relative_error(
                                    rec.states.at(std::lround(times[i] / o.dt)), reference[i]));
      INFO("n = ", n, ", ", npend::stepper_name(k), ": worst relative error ", worst);
      CHECK(worst < expected_accuracy(k));
      CHECK(npend::test::relative_error(result.state, reference.back()) < expected_accuracy(k));
    }
  }
}

TEST_CASE("integrate: small oscillations follow the normal-mode solution, n = 2 and 3") {
  std::mt19937_64 rng(12);
  for (int n : {2, 3}) {
    const npend::chain_parameters params = npend::test::random_parameters(n, rng);
    const chain c(params);
    const auto ref = npend::reference::dense_chain_of(params);
    // M ÿ + K y = 0 at the hanging position: M = A(0), K = diag(g μ_i l_i).
    const Eigen::MatrixXd M = ref.mass_matrix(Eigen::VectorXd::Zero(n));
    Eigen::MatrixXd K = Eigen::MatrixXd::Zero(n, n);
    for (int i = 0; i < n; ++i) K(i, i) = params.g * ref.mu(i) * ref.l(i);
    const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> modes(K, M);
    const Eigen::VectorXd omega = modes.eigenvalues().cwiseSqrt();
    const Eigen::MatrixXd V = modes.eigenvectors();  // Vᵀ M V = I

    // A mixture of all modes with the largest angle `amplitude`, and its linear solution
    // φ(t) = V η(t), p(t) = A(0) φ̇(t) from the modal coordinates η = Vᵀ M φ.
    Eigen::VectorXd mix_phi = Eigen::VectorXd::Zero(n), mix_dphi = Eigen::VectorXd::Zero(n);
    for (int k = 0; k < n; ++k) {
      mix_phi += (1.0 + 0.3 * k) * V.col(k);
      mix_dphi += (0.5 - 0.4 * k) * omega(k) * V.col(k);
    }
    // The largest deviation from the linear solution over 10 s, relative to the amplitude.
    const auto deviation = [&](stepper_kind k, double amplitude) {
      const double scale = amplitude / mix_phi.cwiseAbs().maxCoeff();
      const Eigen::VectorXd phi0 = scale * mix_phi, dphi0 = scale * mix_dphi;
      const Eigen::VectorXd eta0 = V.transpose() * M * phi0, deta0 = V.transpose() * M * dphi0;
      const auto linear = [&](double t) {
        Eigen::VectorXd eta(n), deta(n);
        for (int m = 0; m < n; ++m) {
          const double w = omega(m);
          eta(m) = eta0(m) * std::cos(w * t) + deta0(m) / w * std::sin(w * t);
          deta(m) = -eta0(m) * w * std::sin(w * t) + deta0(m) * std::cos(w * t);
        }
        Eigen::VectorXd x(2 * n);
        x << V * eta, M * (V * deta);
        return x;
      };
      std::vector<double> x0(phi0.data(), phi0.data() + n);
      const Eigen::VectorXd p0 = M * dphi0;
      x0.insert(x0.end(), p0.data(), p0.data() + n);
      integration_options o;
      o.stepper = k;
      o.t_end = 10;
      o.dt = 1e-3;
      o.abs_tol = 1e-12 * amplitude;  // relative control for a state of size ~amplitude
      o.rel_tol = 1e-12;
      double worst = 0, size = 0;
      npend::integrate(c, x0, o, [&](double t, std::span<const double> x) {
        const Eigen::VectorXd expected = linear(t);
        worst = std::max(worst, (npend::test::to_eigen(x) - expected).cwiseAbs().maxCoeff());
        size = std::max(size, expected.cwiseAbs().maxCoeff());
      });
      return worst / size;
    };
    // The deviation comes from the nonlinear terms: it shrinks with the amplitude squared.
    const double at_1e4 = deviation(stepper_kind::gauss6, 1e-4);
    const double at_1e5 = deviation(stepper_kind::gauss6, 1e-5);
    INFO("n = ", n, ": deviation ", at_1e4, " at amplitude 1e-4, ", at_1e5, " at 1e-5");
    CHECK(at_1e4 / at_1e5 == doctest::Approx(100).epsilon(0.05));
    CHECK(at_1e4 < 1e-5);
    // Every stepper follows the normal modes at amplitude 1e-5 (deviation ~1e-8 here; a
    // frequency off by 1e-8 would add ~ω t·1e-8 ≈ 1e-7).
    for (stepper_kind k : npend::all_stepper_kinds()) {
      const double d = deviation(k, 1e-5);
      INFO("n = ", n, ", ", npend::stepper_name(k), ": deviation ", d, " of the amplitude");
      CHECK(d < 3e-8);
    }
  }
}

TEST_CASE(
    "integrate: the output grid is t_start + k dt and ends at t_end, forwards and backwards") {
  const npend::chain_parameters params = npend::chain_parameters::uniform(2);
  const chain c(params);
  const std::vector<double> x0{0.3, -0.2, 0.1, 0.0};
  for (stepper_kind k : npend::all_stepper_kinds()) {
    for (double sign : {1.0, -1.0}) {
      integration_options o;
      o.stepper = k;
      o.t_start = 1.0;
      o.t_end = 1.0 + sign * 0.35;
      o.dt = sign * 0.1;  // 3.5 steps: three of dt, then half a step to t_end
      o.abs_tol = o.rel_tol = 1e-12;
      std::vector<double> times;
      const auto r = npend::integrate(
          c, x0, o, [&](double t, std::span<const double>) { times.push_back(t); });
      INFO(npend::stepper_name(k), ", dt = ", o.dt);
      CHECK(npend::output_steps(o) == 3);
      CHECK(npend::output_intervals(o) == 4);
      REQUIRE(times.size() == 5);
      for (std::size_t i = 0; i + 1 < times.size(); ++i)
        CHECK(times[i] == o.t_start + static_cast<double>(i) * o.dt);
      CHECK(times.back() == o.t_end);
      CHECK(r.outputs == 5);
      CHECK(r.t == o.t_end);
      CHECK_FALSE(r.stopped);
      if (!npend::is_adaptive(k)) CHECK(r.steps == 4);
      // The state is the one at t_end: against an independent tight reference, to the
      // stepper's accuracy at this coarse dt (rk4 at 0.1 s is the loosest). Backwards in
      // time is forwards with the momenta reversed (the chain is reversible).
      std::vector<double> start = x0;
      if (sign < 0) start[2] = -start[2], start[3] = -start[3];
      auto reference = npend::reference::reference_trajectory(
                           npend::reference::dense_chain_of(params), start, {0.35})
                           .back();
      if (sign < 0) reference[2] = -reference[2], reference[3] = -reference[3];
      CHECK(npend::test::relative_error(r.state, reference) < 1e-3);
    }
  }
  integration_options o;
  o.t_end = 1.0;
  o.dt = 0.1;  // 1/0.1 is 9.999999999999998 in floating point: still 10 steps, none left
  CHECK(npend::output_steps(o) == 10);
  CHECK(npend::output_intervals(o) == 10);
}

TEST_CASE("integrate: going backwards retraces the forward motion") {
  const chain c(npend::chain_parameters::uniform(3));
  const std::vector<double> x0{0.5, -0.3, 0.8, 0.2, 0.0, -0.1};
  for (stepper_kind k : npend::all_stepper_kinds()) {
    integration_options forward;
    forward.stepper = k;
    forward.t_end = 1.0;
    forward.dt = 1e-3;
    forward.abs_tol = forward.rel_tol = 1e-12;
    const auto there = npend::integrate(c, x0, forward);
    integration_options backward = forward;
    backward.t_start = 1.0;
    backward.t_end = 0.0;
    backward.dt = -1e-3;
    const auto back = npend::integrate(c, there.state, backward);
    INFO(npend::stepper_name(k));
    CHECK(back.t == 0.0);
    CHECK(npend::test::relative_error(back.state, x0) < 1e-8);
  }
}

TEST_CASE("integrate: an observer can stop the run") {
  const chain c(npend::chain_parameters::uniform(2));
  const std::vector<double> x0{0.3, -0.2, 0.1, 0.0};
  for (stepper_kind k : npend::all_stepper_kinds()) {
    integration_options o;
    o.stepper = k;
    o.t_end = 10;
    o.dt = 0.01;
    std::size_t calls = 0;
    std::vector<double> last;
    const auto r = npend::integrate(c, x0, o, [&](double t, std::span<const double> x) {
      ++calls;
      last.assign(x.begin(), x.end());
      return t >= 0.5 - 1e-12 ? npend::observer_action::stop : npend::observer_action::proceed;
    });
    INFO(npend::stepper_name(k));
    CHECK(r.stopped);
    CHECK(calls == 51);
    CHECK(r.outputs == 51);
    CHECK(r.t == doctest::Approx(0.5).epsilon(1e-14));
    CHECK(r.state == last);
  }
}

TEST_CASE("integrate: a non-finite state stops the run with integration_error at its time") {
  const chain c(npend::chain_parameters::uniform(2));
  // p² overflows: ṗ is infinite at the start.
  const std::vector<double> x0{0.1, 0.2, 1e200, 0.0};
  for (stepper_kind k : npend::all_stepper_kinds()) {
    integration_options o;
    o.stepper = k;
    o.t_end = 1;
    o.dt = 0.01;
    INFO(npend::stepper_name(k));
    try {
      npend::integrate(c, x0, o);
      FAIL("no integration_error");
    } catch (const npend::integration_error& e) {
      const std::string what = e.what();
      INFO(what);
      // rk4 and the adaptive steppers see a non-finite state; gauss4/6 non-finite stages; an
      // adaptive controller may also shrink the step until it collapses.
      CHECK((what.find("non-finite") != std::string::npos ||
             what.find("collapsed") != std::string::npos));
      CHECK(what.find("t = 0") != std::string::npos);
      CHECK(e.time() < 1e-300);  // the start: the first step fails
    }
  }
}

TEST_CASE("integrate: a collapsing adaptive step size stops the run with a message") {
  const chain c(npend::chain_parameters::uniform(2));
  const std::vector<double> x0{1.0, 0.5, 0.0, 0.0};
  for (stepper_kind k : npend::all_stepper_kinds()) {
    if (!npend::is_adaptive(k)) continue;
    integration_options o;
    o.stepper = k;
    o.t_end = 1;
    o.dt = 0.01;
    o.abs_tol = 0;
    o.rel_tol = 1e-300;  // unreachable: every step is rejected
    INFO(npend::stepper_name(k));
    try {
      npend::integrate(c, x0, o);
      FAIL("no integration_error");
    } catch (const npend::integration_error& e) {
      const std::string what = e.what();
      INFO(what);
      CHECK(what.find("step size of " + std::string(npend::stepper_name(k)) +
                      " collapsed at t = ") != std::string::npos);
      CHECK(e.time() < 1e-300);  // no step of a useful size was taken
      CHECK(what.find("loosen") != std::string::npos);
    }
  }
}

TEST_CASE("integration_options: bad values are refused, naming the field") {
  const chain c(npend::chain_parameters::uniform(2));
  const std::vector<double> x0{0.1, 0.2, 0.0, 0.0};
  const auto refused = [&](integration_options o, const std::string& message) {
    try {
      npend::integrate(c, x0, o);
      return false;
    } catch (const std::invalid_argument& e) {
      INFO(e.what());
      CHECK(std::string(e.what()).find(message) != std::string::npos);
      return true;
    }
  };
  integration_options good;
  good.t_end = 1;
  good.dt = 0.1;
  auto o = good;
  o.dt = 0;
  CHECK(refused(o, "dt must not be 0"));
  o = good;
  o.dt = -0.1;
  CHECK(refused(o, "holds no step of dt = -0.1"));
  o = good;
  o.t_end = 0.05;
  CHECK(refused(o, "holds no step"));
  o = good;
  o.t_end = std::nan("");
  CHECK(refused(o, "t_end is nan"));
  o = good;
  o.rel_tol = -1;
  CHECK(refused(o, "both must be >= 0"));
  o = good;
  o.abs_tol = o.rel_tol = 0;
  CHECK(refused(o, "one > 0"));
  o = good;
  o.min_step_ratio = 0;
  CHECK(refused(o, "min_step_ratio"));
  const std::vector<double> short_state{0.1, 0.2, 0.0};
  CHECK_THROWS_WITH_AS(npend::integrate(c, short_state, good),
                       "start state x0 has 3 entries; the 2-link chain needs 4",
                       std::invalid_argument);
  const std::vector<double> nan_state{0.1, std::nan(""), 0.0, 0.0};
  CHECK_THROWS_WITH_AS(npend::integrate(c, nan_state, good), "start state entry 2 is not finite",
                       std::invalid_argument);
}

TEST_CASE("integrate_system: integrates any implicit system, here a harmonic oscillator") {
  // x'' = −ω² x as [x, v]: exact solution x = cos ωt, v = −ω sin ωt.
  const double w = 2.0;
  const auto rhs = [w](const std::vector<double>& x, std::vector<double>& dxdt, double) {
    dxdt[0] = x[1];
    dxdt[1] = -w * w * x[0];
  };
  const auto jacobian = [w](const std::vector<double>&, auto& J, double,
                            std::vector<double>& dfdt) {
    J(0, 0) = 0;
    J(0, 1) = 1;
    J(1, 0) = -w * w;
    J(1, 1) = 0;
    dfdt[0] = dfdt[1] = 0;
  };
  const auto system = std::make_pair(rhs, jacobian);
  for (stepper_kind k : npend::all_stepper_kinds()) {
    if (!npend::serves(k, npend::stepper_use::system)) {
      // taylor runs a chain's generated kernels only, and says so.
      integration_options o;
      o.stepper = k;
      o.t_end = 1;
      CHECK_THROWS_AS(npend::integrate_system(system, std::vector<double>{1.0, 0.0}, o),
                      std::invalid_argument);
      continue;
    }
    integration_options o;
    o.stepper = k;
    o.t_end = 5;
    o.dt = 1e-3;
    o.abs_tol = o.rel_tol = 1e-12;
    double worst = 0;
    const std::vector<double> x0{1.0, 0.0};
    npend::integrate_system(system, x0, o, [&](double t, std::span<const double> x) {
      worst = std::max(
          {worst, std::fabs(x[0] - std::cos(w * t)), std::fabs(x[1] + w * std::sin(w * t))});
      return npend::observer_action::proceed;
    });
    INFO(npend::stepper_name(k), ": worst error ", worst);
    CHECK(worst < expected_accuracy(k));
  }
}

TEST_CASE("integrate: an adaptive trial step that overflows is rejected and shrunk") {
  // Three links from 1.5 rad each with a first trial step of the whole 10 s: the trial
  // overflows (its error estimate is NaN), which odeint's error norm (a fold with std::max)
  // dropped, accepting a non-finite state. Rejected and shrunk, every adaptive stepper gets
  // through, and keeps H as well as its tolerances promise.
  const chain c(npend::chain_parameters::uniform(3));
  const std::vector<double> x0{1.5, 1.5, 1.5, 0.0, 0.0, 0.0};
  const double h0 = c.hamiltonian(x0);
  for (stepper_kind k : npend::all_stepper_kinds()) {
    if (!npend::is_adaptive(k)) continue;
    INFO(npend::stepper_name(k));
    integration_options o;
    o.stepper = k;
    o.t_end = 10;
    o.dt = 10;
    o.abs_tol = o.rel_tol = 1e-10;
    const auto r = npend::integrate(c, x0, o);
    CHECK(r.t == 10);
    CHECK(r.steps > 100);
    // The energy error of a run at tolerance 1e-10 over ~20 swings: well under 1e-6.
    CHECK(std::fabs(c.hamiltonian(r.state) - h0) < 1e-6 * std::fabs(h0));
  }
}

TEST_CASE("rejecting_range_algebra: the norm of a vector with a non-finite entry is +inf") {
  using algebra = npend::detail::rejecting_range_algebra;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  CHECK(algebra::norm_inf(std::vector<double>{1.0, -3.0, 2.0}) == 3.0);
  CHECK(algebra::norm_inf(std::vector<double>{1.0, nan, 2.0}) == inf);
  CHECK(algebra::norm_inf(std::vector<double>{nan, nan}) == inf);
  CHECK(algebra::norm_inf(std::vector<double>{-inf, 0.0}) == inf);
  // range_algebra's own norm drops NaN: what let overflowing steps through.
  CHECK(boost::numeric::odeint::range_algebra::norm_inf(std::vector<double>{nan, nan}) == 0.0);
}

namespace {

// A controlled stepper that lets a step too long through with a non-finite state (as odeint's
// controllers did when the error estimate was NaN), and takes explicit Euler steps otherwise.
struct overflowing_euler {
  using stepper_category = boost::numeric::odeint::controlled_stepper_tag;
  template <class System>
  boost::numeric::odeint::controlled_step_result try_step(System system, std::vector<double>& x,
                                                          double& t, double& dt) {
    if (std::fabs(dt) > 0.05) {
      x.assign(x.size(), std::numeric_limits<double>::quiet_NaN());
    } else {
      std::vector<double> f(x.size());
      system(x, f, t);
      for (std::size_t i = 0; i < x.size(); ++i) x[i] += dt * f[i];
    }
    t += dt;
    return boost::numeric::odeint::success;
  }
};

}  // namespace

TEST_CASE("integrate_with: a supplied controlled stepper's non-finite step is shrunk") {
  // x' = -x from 1 over [0, 1], first trial step 1: the trials of 1 and 1/5 come back NaN
  // and are rejected (each cut to a fifth), 1/25 is taken 25 times: x(1) = (1 - 1/25)^25.
  const auto decay = [](const std::vector<double>& x, std::vector<double>& dxdt, double) {
    dxdt[0] = -x[0];
  };
  overflowing_euler stepper;
  integration_options o;
  o.t_end = 1;
  o.dt = 1;
  const auto r = npend::integrate_with(stepper, decay, std::vector<double>{1.0}, o);
  CHECK(r.t == 1);
  CHECK(r.steps == 25);
  CHECK(r.state[0] == doctest::Approx(std::pow(1 - 0.04, 25)).epsilon(1e-12));
}

TEST_CASE("integrate: counts the evaluations of the right-hand side and the Jacobian") {
  const chain c(npend::chain_parameters::uniform(3));
  const std::vector<double> x0{0.3, -0.2, 0.1, 0.0, 0.1, 0.0};
  integration_options o;
  o.t_end = 1;
  o.dt = 0.01;
  // rk4: four stages a step, nothing else; N = 100 steps.
  o.stepper = stepper_kind::rk4;
  auto r = npend::integrate(c, x0, o);
  CHECK(r.steps == 100);
  CHECK(r.evaluations == 400);
  CHECK(r.jacobian_evaluations == 0);
  // A step observer that reads the Hermite dense output costs f at both ends of each step.
  r = npend::integrate(c, x0, o, {}, [](const npend::integration_step& step) {
    std::vector<double> x(step.x_end().size());
    step.state_at(0.5 * (step.t_begin() + step.t_end()), x);
    step.state_at(step.t_end(), x);
    return npend::observer_action::proceed;
  });
  CHECK(r.evaluations == 600);
  // dopri5 (first same as last): f once at the start, then six new stages per attempted step,
  // of which at least the accepted ones.
  o.stepper = stepper_kind::dopri5;
  r = npend::integrate(c, x0, o);
  CHECK((r.evaluations - 1) % 6 == 0);
  CHECK((r.evaluations - 1) / 6 >= r.steps);
  CHECK(r.jacobian_evaluations == 0);
  // gauss6: the Newton iterations of the implicit stages take at least 3 f per step (one per
  // stage), and the exact Jacobian is evaluated at least at the start.
  o.stepper = stepper_kind::gauss6;
  r = npend::integrate(c, x0, o);
  CHECK(r.evaluations >= 3 * r.steps);
  CHECK(r.jacobian_evaluations >= 1);
  // rosenbrock4: one Jacobian per attempted step, so at least one per accepted step.
  o.stepper = stepper_kind::rosenbrock4;
  r = npend::integrate(c, x0, o);
  CHECK(r.jacobian_evaluations >= r.steps);
  // taylor: no f at all, the Taylor kernels expand the solution.
  o.stepper = stepper_kind::taylor;
  r = npend::integrate(c, x0, o);
  CHECK(r.evaluations == 0);
}
