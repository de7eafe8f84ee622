// The chaos map's cells (analysis/chaos_map.hpp): the energy bound on flips against Heyl's
// closed forms for the double pendulum from rest, the flip time against a gauss6
// integration that looks for the flip on its own and against a fine rk4 written out here,
// and the energy check that keeps a numerical blow-up from counting as a flip.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <span>
#include <stdexcept>
#include <vector>

#include "npend/analysis/chaos/chaos_map.hpp"
#include "npend/integrators/integrate.hpp"
#include "npend/integrators/integration_error.hpp"

namespace {

// The first time an arm of chain c started at x passes the upright (|φ_k| ≥ π) by a classical
// rk4 written out here at h = 1e-5 s on the chain's rhs, the crossing inside the step found
// by bisection on the length of one rk4 step from the step's start (to 1e-13 s): a reference
// that shares nothing with the map's steppers or its interpolant.
double fine_flip_time(const npend::chain& c, std::vector<double> x, double t_end) {
  const std::size_t m = x.size(), n = m / 2;
  const double h = 1e-5;
  std::vector<double> k1(m), k2(m), k3(m), k4(m), tmp(m), y(m);
  const auto step = [&](double dt) {
    c.rhs(x, k1);
    for (std::size_t i = 0; i < m; ++i) tmp[i] = x[i] + dt / 2 * k1[i];
    c.rhs(tmp, k2);
    for (std::size_t i = 0; i < m; ++i) tmp[i] = x[i] + dt / 2 * k2[i];
    c.rhs(tmp, k3);
    for (std::size_t i = 0; i < m; ++i) tmp[i] = x[i] + dt * k3[i];
    c.rhs(tmp, k4);
    for (std::size_t i = 0; i < m; ++i)
      y[i] = x[i] + dt / 6 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
  };
  const auto upright = [&] {
    for (std::size_t k = 0; k < n; ++k)
      if (std::fabs(y[k]) >= std::numbers::pi) return true;
    return false;
  };
  const auto steps = static_cast<long>(t_end / h);
  for (long s = 0; s < steps; ++s) {
    step(h);
    if (upright()) {
      double lo = 0, hi = h;
      while (hi - lo > 1e-13) {
        const double mid = 0.5 * (lo + hi);
        step(mid);
        (upright() ? hi : lo) = mid;
      }
      return static_cast<double>(s) * h + hi;
    }
    x = y;
  }
  return std::numeric_limits<double>::infinity();
}

}  // namespace

TEST_CASE("chaos map: the energy bound on flips is Heyl's for point masses and for rods") {
  // From rest, E = m g l (3 - 2 cos phi1 - cos phi2) for point masses: the second arm can
  // only flip if E >= 2 m g l, i.e. 2 cos phi1 + cos phi2 <= 1. For uniform rods E =
  // m g l (3/2 (1 - cos phi1) + 1/2 (1 - cos phi2)) and the bound is 3 cos phi1 + cos phi2 <= 2.
  const npend::chain points(npend::chain_parameters::uniform(2));
  npend::chain_parameters p = npend::chain_parameters::uniform(2);
  p.make_uniform_rods();
  const npend::chain rods(p);
  for (double a = -3.0; a <= 3.0; a += 0.37)
    for (double b = -3.0; b <= 3.0; b += 0.41) {
      const std::vector<double> x{a, b, 0, 0};
      INFO("phi = (" << a << ", " << b << ")");
      CHECK(npend::energy_forbids_flip(points, x) == (2 * std::cos(a) + std::cos(b) > 1));
      CHECK(npend::energy_forbids_flip(rods, x) == (3 * std::cos(a) + std::cos(b) > 2));
    }
}

TEST_CASE("chaos map: the flip time agrees with a gauss6 run watching the angles") {
  const npend::chain c(npend::chain_parameters::uniform(2));
  for (const auto& start : {std::vector<double>{2.0, 2.5, 0, 0},
                            {-1.5, 2.9, 0, 0},
                            std::vector<double>{2.8, -0.3, 0, 0}}) {
    const double t_flip = npend::flip_time(c, start, {30.0, 0.01, 0});
    REQUIRE(std::isfinite(t_flip));
    // gauss6 at dt = 1e-3, stopped at the first grid point where an arm is past upright.
    npend::integration_options o;
    o.t_end = 30;
    o.dt = 1e-3;
    double seen = std::numeric_limits<double>::infinity();
    npend::integrate(c, start, o, [&](double t, std::span<const double> x) {
      if (std::fabs(x[0]) >= std::numbers::pi || std::fabs(x[1]) >= std::numbers::pi) {
        seen = t;
        return npend::observer_action::stop;
      }
      return npend::observer_action::proceed;
    });
    INFO("start (" << start[0] << ", " << start[1] << "): rk4 " << t_flip << " s, gauss6 " << seen
                   << " s");
    // rk4's flip is the end of the step that crossed: within one step of the true time.
    CHECK(std::fabs(t_flip - seen) <= 0.0101);
  }
  // Ruled out by the energy: +inf without integrating; arm 1 alone flips later or never.
  CHECK(std::isinf(npend::flip_time(c, std::vector<double>{0.5, 0.5, 0, 0}, {30.0, 0.01, 0})));
  CHECK(npend::flip_time(c, std::vector<double>{2.0, 2.5, 0, 0}, {30.0, 0.01, 1}) >=
        npend::flip_time(c, std::vector<double>{2.0, 2.5, 0, 0}, {30.0, 0.01, 0}));
}

TEST_CASE("chaos map: bad options and chains are refused") {
  const npend::chain c(npend::chain_parameters::uniform(2));
  const std::vector<double> x{2.0, 2.5, 0, 0};
  CHECK_THROWS_AS(npend::flip_time(c, x, {1.0, 0.0, 0}), std::invalid_argument);
  CHECK_THROWS_AS(npend::flip_time(c, x, {1.0, 0.01, 3}), std::invalid_argument);
  CHECK_THROWS_AS(npend::flip_time(c, std::vector<double>{1.0, 0}, {1.0, 0.01, 0}),
                  std::invalid_argument);
}

TEST_CASE("chaos map: the energy bound holds with springs and damping, and not under a drive") {
  // Point masses m = l = 1 from rest with springs k_1, k_2 (rest angles 0) on the joint angles
  // θ_1 = φ_1, θ_2 = φ_2 − φ_1: H = g (3 − 2 cos φ1 − cos φ2) + ½ k_1 φ1² + ½ k_2 (φ2 − φ1)²,
  // and arm 2 upright needs at least V = 2 g (arm 1: 4 g). Springs only add energy that is
  // never negative, and damping only takes energy out, so H < 2 g still rules a flip out.
  npend::chain_parameters p = npend::chain_parameters::uniform(2);
  p.stiffness = {3.0, 1.5};
  p.rest_angles = {0.0, 0.0};
  npend::chain_parameters damped = p;
  damped.damping = {0.4, 0.2};
  const npend::chain springs(p), both(damped);
  npend::chain_parameters driven = npend::chain_parameters::uniform(2);
  driven.pivot = npend::pivot_motion::vertical(0.05, 30);
  const npend::chain drive(driven);
  const double g = p.g;
  long ruled_out = 0;
  for (double a = -3.0; a <= 3.0; a += 0.37)
    for (double b = -3.0; b <= 3.0; b += 0.41) {
      const std::vector<double> x{a, b, 0, 0};
      const double h = g * (3 - 2 * std::cos(a) - std::cos(b)) + 0.5 * 3.0 * a * a +
                       0.5 * 1.5 * (b - a) * (b - a);
      INFO("phi = (" << a << ", " << b << "), H = " << h);
      CHECK(springs.hamiltonian(x) == doctest::Approx(h).epsilon(1e-12));
      CHECK(npend::energy_forbids_flip(springs, x) == (h < 2 * g));
      CHECK(npend::energy_forbids_flip(both, x) == (h < 2 * g));
      CHECK_FALSE(npend::energy_forbids_flip(drive, x));
      ruled_out += h < 2 * g ? 1 : 0;
    }
  CHECK(ruled_out > 0);
  // A drive of zero amplitude leaves the fixed-pivot chain (on the other kernels: the same
  // flip to within a step).
  const std::vector<double> x{2.0, 2.5, 0, 0};
  const npend::flip_options o{30.0, 0.01, 0};
  const double free_flip =
      npend::flip_time(npend::chain(npend::chain_parameters::uniform(2)), x, o);
  REQUIRE(std::isfinite(free_flip));
  npend::chain_parameters still = npend::chain_parameters::uniform(2);
  still.pivot = npend::pivot_motion::vertical(0.0, 30);
  CHECK(std::fabs(npend::flip_time(npend::chain(still), x, o) - free_flip) <= o.dt);
}

TEST_CASE("flip_time: located inside the step, within 1e-5 s of a fine integration") {
  // The equal double pendulum from rest: the first flips of a few starts, by rk4 and gauss6
  // at the default dt = 0.01, in the library (flip_time) and on the batch lanes
  // (flip_times), against fine_flip_time. The end of the step (what a step-resolved time
  // reports) is off by up to dt; the step's Hermite interpolant is as good as the trajectory.
  // The flips come within 2 s; later ones carry rk4's growing trajectory error (measured:
  // (2, 2.5) flips at 4.015 s, rk4 2.4e-4 s late, gauss6 2e-8 s early), not the
  // interpolant's, so (2, 2.5) is a cell that does not flip by t_end here.
  const npend::chain c(npend::chain_parameters::uniform(2));
  const std::vector<std::vector<double>> starts{{2.0, 2.5, 0, 0},   {3.0, 3.0, 0, 0},
                                                {-2.8, 1.0, 0, 0},  {1.5, -3.0, 0, 0},
                                                {-2.5, -2.9, 0, 0}, {2.6, 0.7, 0, 0}};
  const double t_end = 2.5;
  std::vector<double> flat;
  for (const auto& x : starts) flat.insert(flat.end(), x.begin(), x.end());
  double late = 0;  // the most a step's end lies after the crossing
  double worst = 0;
  int flips = 0;
  for (const auto stepper : {npend::stepper_kind::rk4, npend::stepper_kind::gauss6}) {
    CAPTURE(npend::stepper_name(stepper));
    npend::flip_options o{t_end, 0.01, 0};
    o.stepping.stepper = stepper;
    const std::vector<double> lanes = npend::flip_times(c, flat, o);
    for (std::size_t i = 0; i < starts.size(); ++i) {
      const double want = fine_flip_time(c, starts[i], t_end);
      const double library = npend::flip_time(c, starts[i], o);
      INFO("start (" << starts[i][0] << ", " << starts[i][1] << "): fine " << want << " s, library "
                     << library << " s, lanes " << lanes[i] << " s");
      if (!std::isfinite(want)) {
        CHECK(std::isinf(library));
        continue;
      }
      ++flips;
      late = std::max(late, std::ceil(want / o.dt) * o.dt - want);
      worst = std::max({worst, std::fabs(library - want), std::fabs(lanes[i] - want)});
      CHECK(std::fabs(library - want) <= 1e-5);
      CHECK(std::fabs(lanes[i] - want) <= 1e-5);
    }
  }
  MESSAGE("located within " << worst << " s of the fine integration; a step's end lies up to "
                            << late << " s after the crossing");
  CHECK(flips == 10);
  CHECK(late > 1e-3);  // so a time resolved to a step would fail the checks above
}

TEST_CASE("flip_time: a numerical blow-up is a failed cell, not a flip") {
  // A nearly massless first bob (1e-12 kg) makes the chain stiff: its fast mode has a period
  // far below any practical step, and rk4 blows up within a step or two. Started with both
  // arms at 2 rad, the massless joint keeps the two rods in line, a pendulum of length 2 l
  // swinging to 2 rad and back: no arm ever reaches the upright. The energy at the "flip"
  // is off by orders of magnitude, so the cell fails (NaN, drawn red), where it used to read
  // as a flip at 0.01 s.
  npend::chain_parameters p = npend::chain_parameters::uniform(2);
  p.masses = {1e-12, 1};
  const npend::chain c(p);
  const std::vector<double> x{2, 2, 0, 0};
  REQUIRE_FALSE(npend::energy_forbids_flip(c, x));
  for (const double dt : {0.01, 1e-4}) {
    CAPTURE(dt);
    const npend::flip_options o{5.0, dt, 0};
    CHECK_THROWS_AS(npend::flip_time(c, x, o), npend::integration_error);
    CHECK(std::isnan(npend::flip_times(c, x, o).front()));
    npend::map_cell_options mo;
    mo.t_end = 5;
    mo.dt = dt;
    CHECK(std::isnan(npend::map_cell(c, x, mo)));
  }
  // The same on the cell-by-cell path (a chain without batch lanes: a little damping, whose
  // energy may only fall), and with gauss6.
  npend::chain_parameters damped = p;
  damped.damping = {1e-6, 1e-6};
  const npend::chain damped_chain(damped);
  REQUIRE(npend::batch_lanes(damped_chain) == 0);
  CHECK(std::isnan(npend::flip_times(damped_chain, x, {5.0, 0.01, 0}).front()));
  npend::flip_options gauss{5.0, 0.01, 0};
  gauss.stepping.stepper = npend::stepper_kind::gauss6;
  CHECK(std::isnan(npend::flip_times(c, x, gauss).front()));
}

TEST_CASE("flip_time: the energy check leaves a regular map alone") {
  // Every cell of a 32 x 32 map of the equal double pendulum over 20 s at the default step
  // that can flip gets a time or +inf, never NaN: the energy error of rk4 at dt = 0.01 at
  // the flips of this map stays far below flip_energy_tolerance.
  const npend::chain c(npend::chain_parameters::uniform(2));
  std::vector<double> starts;
  for (int j = 0; j < 32; ++j)
    for (int i = 0; i < 32; ++i)
      starts.insert(starts.end(), {npend::grid_value(-3.1, 3.1, 32, i),
                                   npend::grid_value(-3.1, 3.1, 32, j), 0.0, 0.0});
  for (const auto stepper : {npend::stepper_kind::rk4, npend::stepper_kind::gauss6}) {
    CAPTURE(npend::stepper_name(stepper));
    npend::flip_options o{20.0, 0.01, 0};
    o.stepping.stepper = stepper;
    const std::vector<double> t = npend::flip_times(c, starts, o);
    CHECK(std::count_if(t.begin(), t.end(), [](double v) { return std::isnan(v); }) == 0);
    CHECK(std::count_if(t.begin(), t.end(), [](double v) { return std::isfinite(v); }) > 300);
  }
}
