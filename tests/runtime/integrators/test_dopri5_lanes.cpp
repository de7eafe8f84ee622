// Maps integrated by dopri5 (analysis/chaos_map.hpp, map_stepping): each batch lane under its
// own step control, against npend::integrate's dopri5 on the scalar kernel; the flip time
// located by the dense output against the single pendulum's quadrature; a lane's value
// independent of its neighbours' accepted and rejected steps.
#include <doctest/doctest.h>

#include <algorithm>
#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <span>
#include <stdexcept>
#include <vector>

#include "npend/analysis/chaos/chaos_map.hpp"
#include "npend/analysis/chaos/lyapunov.hpp"
#include "npend/integrators/integrate.hpp"

namespace {

bool same_bits(double a, double b) { return a == b || (std::isnan(a) && std::isnan(b)); }

npend::map_stepping dopri5_at(double tol) { return {npend::stepper_kind::dopri5, tol, tol}; }

// Random starts of the n-link chain: angles in ±3 rad (a third of them small), momenta ±2.
std::vector<double> random_chain_starts(int n, int count, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> angle(-3, 3), momentum(-2, 2);
  std::vector<double> x;
  for (int k = 0; k < count; ++k) {
    for (int i = 0; i < n; ++i) x.push_back(angle(rng) * (k % 3 == 0 ? 0.1 : 1.0));
    for (int i = 0; i < n; ++i) x.push_back(momentum(rng));
  }
  return x;
}

// The state at t_end by npend::integrate's dopri5 (first trial step dt), read from its dense
// output in the step that reaches t_end: written here from the public API, independently of
// the map's code.
std::vector<double> integrate_dopri5_to(const npend::chain& c, std::span<const double> x0,
                                        double t_end, double dt, double tol) {
  npend::integration_options io;
  io.stepper = npend::stepper_kind::dopri5;
  io.dt = dt;
  io.t_end = 2 * t_end;
  io.abs_tol = tol;
  io.rel_tol = tol;
  std::vector<double> x(x0.size(), std::numeric_limits<double>::quiet_NaN());
  npend::integrate(c, x0, io, {}, [&](const npend::integration_step& step) {
    if (step.t_end() < t_end) return npend::observer_action::proceed;
    step.state_at(t_end, x);
    return npend::observer_action::stop;
  });
  return x;
}

}  // namespace

TEST_CASE("dopri5 flip times: the single pendulum's time to the top, by quadrature") {
  // Energy conservation gives φ̇(φ)² = φ̇0² + 2 (g/l)(cos φ − cos φ0), so the time from φ0 to
  // the top is ∫ dφ / φ̇ from φ0 to π (Gauss–Kronrod; the integrand is smooth as long as the
  // pendulum goes over the top). dopri5's flip time is located inside its step by the dense
  // output, so it matches to the tolerance; rk4's inside its step of dt by the step's Hermite
  // interpolant, so it matches to rk4's own error at dt.
  const double g = 9.81, l = 1.0, m = 1.0;
  const npend::chain c(npend::chain_parameters::uniform(1, m, l, g));
  std::vector<double> starts, exact;
  for (int k = 0; k < 3 * npend::batch_lanes(c) + 5; ++k) {
    const double phi0 = -2.5 + 0.05 * k;
    const double over = 1.05 + 0.02 * k;  // φ̇0² as a multiple of what reaches the top
    const double rate0 = std::sqrt(over * 2 * (g / l) * (1 + std::cos(phi0)));
    starts.push_back(phi0);
    starts.push_back(m * l * l * rate0);
    const auto rate = [&](double phi) {
      return std::sqrt(rate0 * rate0 + 2 * (g / l) * (std::cos(phi) - std::cos(phi0)));
    };
    exact.push_back(boost::math::quadrature::gauss_kronrod<double, 61>::integrate(
        [&](double phi) { return 1 / rate(phi); }, phi0, std::numbers::pi, 15, 1e-14));
  }
  npend::flip_options o{10.0, 0.01, 0, dopri5_at(1e-12)};
  const std::vector<double> lanes = npend::flip_times(c, starts, o);
  npend::flip_options rk4 = o;
  rk4.stepping = {};
  const std::vector<double> stepped = npend::flip_times(c, starts, rk4);
  double worst = 0;
  for (std::size_t k = 0; k < exact.size(); ++k) {
    CAPTURE(k);
    worst = std::max(worst, std::fabs(lanes[k] - exact[k]));
    // rk4 locates the passage of the top inside the step, as accurately as its trajectory.
    CHECK(std::fabs(stepped[k] - exact[k]) <= 1e-5);
    // One start alone on the scalar path (flip_time), as the lanes locate it.
    if (k % 5 == 0) {
      const double scalar = npend::flip_time(c, std::span(starts).subspan(2 * k, 2), o);
      CHECK(std::fabs(scalar - lanes[k]) <= 1e-12 * exact[k]);
    }
  }
  MESSAGE("dopri5 at 1e-12: worst difference from the quadrature " << worst << " s");
  CHECK(worst <= 1e-9);
}

TEST_CASE("dopri5 flip times: the lanes agree with flip_time on the scalar path") {
  // The equal double pendulum from rest over a grid of angles, to 5 s: the lanes take the
  // same accepted and rejected steps as integrate's dopri5 up to round-off (SLEEF's sines),
  // so the located times agree to round-off amplified by the flow.
  const npend::chain c(npend::chain_parameters::uniform(2));
  std::vector<double> starts;
  for (int j = 0; j < 20; ++j)
    for (int i = 0; i < 20; ++i)
      starts.insert(starts.end(), {npend::grid_value(-3.1, 3.1, 20, i),
                                   npend::grid_value(-3.1, 3.1, 20, j), 0.0, 0.0});
  const npend::flip_options o{5.0, 0.01, 0, dopri5_at(1e-10)};
  const std::vector<double> lanes = npend::flip_times(c, starts, o);
  int finite = 0, close = 0;
  double worst = 0;
  for (std::size_t i = 0; i < lanes.size(); ++i) {
    const double want = npend::flip_time(c, std::span(starts).subspan(4 * i, 4), o);
    if (std::isinf(want) || std::isinf(lanes[i])) {
      close += same_bits(want, lanes[i]) ? 1 : 0;
      continue;
    }
    ++finite;
    const double d = std::fabs(lanes[i] - want) / want;
    worst = std::max(worst, d);
    close += d <= 1e-11 ? 1 : 0;
  }
  MESSAGE(finite << " of " << lanes.size() << " cells flip by 5 s; worst relative difference "
                 << worst << "; " << close << " within 1e-11");
  CHECK(finite > 100);
  // Round-off apart (a step sequence of its own would differ by ~1e-10 here). A cell that
  // just grazes the top may flip on one path and not on the other.
  CHECK(close >= static_cast<int>(lanes.size()) - 2);
}

TEST_CASE("dopri5 maps: a lane's value does not depend on its neighbours' steps") {
  // Each lane accepts, rejects and sizes its own steps: the same start in another slot,
  // among other cells, gives the same bits.
  const npend::chain c(npend::chain_parameters::uniform(3));
  const int count = 2 * npend::batch_lanes(c) + 3;
  const std::vector<double> starts = random_chain_starts(3, count, 21);
  std::vector<double> reversed;
  for (int k = count; k-- > 0;)
    reversed.insert(reversed.end(), starts.begin() + 6 * k, starts.begin() + 6 * k + 6);
  npend::map_cell_options mo;
  mo.quantity = npend::map_quantity::state;
  mo.t_end = 1.5;
  mo.stepping = dopri5_at(1e-9);
  const auto forward = npend::map_cells(c, starts, mo);
  const auto backward = npend::map_cells(c, reversed, mo);
  for (int k = 0; k < count; ++k) {
    CAPTURE(k);
    CHECK(same_bits(forward[static_cast<std::size_t>(k)],
                    backward[static_cast<std::size_t>(count - 1 - k)]));
  }
  CHECK(same_bits(npend::map_cell(c, std::span(starts).subspan(0, 6), mo), forward[0]));
}

TEST_CASE("dopri5 maps: final-state cells agree with integrate's dense output at t_end") {
  const npend::chain c(npend::chain_parameters::uniform(3));
  const int count = npend::batch_lanes(c) + 7;
  const std::vector<double> starts = random_chain_starts(3, count, 13);
  npend::map_cell_options mo;
  mo.quantity = npend::map_quantity::state;
  mo.t_end = 2.005;
  mo.dt = 0.01;
  mo.stepping = dopri5_at(1e-10);
  double worst = 0;
  std::vector<std::vector<double>> want;
  for (int k = 0; k < count; ++k)
    want.push_back(integrate_dopri5_to(
        c, std::span(starts).subspan(6 * static_cast<std::size_t>(k), 6), mo.t_end, mo.dt, 1e-10));
  for (int component = 0; component < 6; ++component) {
    mo.component = component;
    const std::vector<double> lanes = npend::map_cells(c, starts, mo);
    for (int k = 0; k < count; ++k)
      worst = std::max(
          worst, std::fabs(lanes[static_cast<std::size_t>(k)] -
                           want[static_cast<std::size_t>(k)][static_cast<std::size_t>(component)]));
  }
  MESSAGE("worst difference " << worst);
  CHECK(worst <= 1e-10);

  // A physical chain goes cell by cell through the library: the same reference.
  npend::chain_parameters rods = npend::chain_parameters::uniform(2);
  rods.make_uniform_rods();
  const npend::chain rod_chain(rods);
  REQUIRE(npend::batch_lanes(rod_chain) == 0);
  const std::vector<double> x0{1.0, -0.5, 0.2, 0.1};
  mo.component = 1;
  CHECK(npend::map_cell(rod_chain, x0, mo) ==
        doctest::Approx(integrate_dopri5_to(rod_chain, x0, mo.t_end, mo.dt, 1e-10)[1])
            .epsilon(1e-13));

  // A state that leaves the doubles is NaN.
  const std::vector<double> blown{0.5, 0.5, 0.5, 1e200, -1e200, 1e200};
  CHECK(std::isnan(npend::map_cell(c, blown, mo)));
}

TEST_CASE("dopri5 maps: Lyapunov cells agree with maximal_lyapunov_exponent's dopri5") {
  // The library restarts dopri5 at every renormalisation (every 10 steps of dt here) and
  // reads the state at the interval's end from the dense output; the lanes do the same.
  const npend::chain c(npend::chain_parameters::uniform(3));
  const int count = 2 * npend::batch_lanes(c) + 5;
  const std::vector<double> starts = random_chain_starts(3, count, 5);
  npend::map_cell_options mo;
  mo.quantity = npend::map_quantity::lyapunov;
  mo.t_end = 2.005;
  mo.dt = 0.01;
  mo.stepping = dopri5_at(1e-10);
  const std::vector<double> lanes = npend::map_cells(c, starts, mo);
  npend::lyapunov_options lo;
  lo.integration.stepper = npend::stepper_kind::dopri5;
  lo.integration.t_end = mo.t_end;
  lo.integration.dt = mo.dt;
  lo.integration.abs_tol = lo.integration.rel_tol = 1e-10;
  double worst = 0, largest = 0;
  for (int k = 0; k < count; ++k) {
    const double want = npend::maximal_lyapunov_exponent(
                            c, std::span(starts).subspan(6 * static_cast<std::size_t>(k), 6), lo)
                            .exponents.front();
    CAPTURE(k);
    CHECK(std::isfinite(lanes[static_cast<std::size_t>(k)]));
    worst = std::max(worst, std::fabs(lanes[static_cast<std::size_t>(k)] - want));
    largest = std::max(largest, std::fabs(want));
  }
  MESSAGE("largest |λ| " << largest << " 1/s, worst difference " << worst);
  CHECK(largest > 0.5);
  // Round-off apart; a step sequence of its own would differ by ~1e-9 (tried: the step
  // increase's exponent -1/4 for odeint's -1/5 gave 6e-9).
  CHECK(worst <= 1e-10);
  const std::vector<double> blown{0.5, 0.5, 0.5, 1e200, -1e200, 1e200};
  CHECK(std::isnan(npend::map_cell(c, blown, mo)));
}

TEST_CASE("dopri5 maps: what a map refuses") {
  const npend::chain c(npend::chain_parameters::uniform(2));
  const std::vector<double> x0{1.0, 1.0, 0.0, 0.0};
  npend::map_cell_options mo;
  mo.t_end = 1;
  mo.stepping.stepper = npend::stepper_kind::rosenbrock4;
  CHECK_THROWS_WITH_AS(
      npend::map_cell(c, x0, mo),
      "flip: maps integrate with one of rk4, dopri5, gauss4, gauss6, taylor, not rosenbrock4",
      std::invalid_argument);
  mo.stepping = dopri5_at(0);
  CHECK_THROWS_WITH_AS(npend::map_cell(c, x0, mo),
                       "flip: abs_tol and rel_tol are both 0; at least one must be positive",
                       std::invalid_argument);
  mo.stepping = {npend::stepper_kind::dopri5, -1, 1e-9};
  CHECK_THROWS_AS(npend::map_cell(c, x0, mo), std::invalid_argument);
  mo.stepping = dopri5_at(1e-9);
  mo.quantity = npend::map_quantity::megno;
  CHECK_THROWS_WITH_AS(npend::map_cell(c, x0, mo),
                       "megno: the chaos indicators integrate with one of rk4, taylor, not dopri5",
                       std::invalid_argument);
  // A blown-up start gives NaN, not an exception or a hang.
  mo.quantity = npend::map_quantity::flip;
  const std::vector<double> blown{0.5, 0.5, 1e200, -1e200};
  CHECK(std::isnan(npend::map_cell(c, blown, mo)));
}
