// flip_times on the batch kernels' lanes (analysis/chaos_map.hpp) against the scalar
// flip_time (odeint's rk4 on the scalar kernel with std::sin), and the independence of a
// cell's value from its lane and from the other cells; Lyapunov, chaos-indicator and
// final-state cells on the lanes against the library.
#include <doctest/doctest.h>

#include <algorithm>
#include <boost/numeric/odeint/stepper/runge_kutta4.hpp>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "npend/analysis/chaos/chaos_map.hpp"
#include "npend/batch_math.hpp"
#include "npend/chain_system.hpp"
#include "support/test_support.hpp"

namespace {

constexpr double inf = std::numeric_limits<double>::infinity();
constexpr double nan_value = std::numeric_limits<double>::quiet_NaN();

bool same(double a, double b) { return a == b || (std::isnan(a) && std::isnan(b)); }

// Starts of the equal double pendulum from rest on a grid over (φ1, φ2).
std::vector<double> grid_starts(int count, double from, double to) {
  std::vector<double> x;
  for (int j = 0; j < count; ++j)
    for (int i = 0; i < count; ++i) {
      x.push_back(npend::grid_value(from, to, count, i));
      x.push_back(npend::grid_value(from, to, count, j));
      x.push_back(0);
      x.push_back(0);
    }
  return x;
}

// A reference rk4 written out here: odeint's runge_kutta4 step sum for sum on the scalar
// kernel (std::sin), which also records whether SLEEF's sines and cosines equalled std::sin's
// at every evaluation along the way. Its time is the end of the step at whose end an arm is
// upright: the step inside which flip_time locates the flip.
struct reference_flip {
  double time = inf;
  bool sines_agreed = true;
};

reference_flip reference_flip_time(const npend::chain& c, std::vector<double> x, double t_end,
                                   double dt) {
  const auto& k = c.kernels();
  const double* params = c.packed_parameters().data();
  const std::size_t m = x.size(), n = m / 2;
  reference_flip r;
  const auto rhs = [&](const std::vector<double>& y, std::vector<double>& f) {
    for (std::size_t i = 0; i < n; ++i) {
      double a[npend::batch_width], s[npend::batch_width], co[npend::batch_width];
      std::fill(a, a + npend::batch_width, y[i]);
      npend::batch_sincos(a, s, co);
      if (s[0] != std::sin(y[i]) || co[0] != std::cos(y[i])) r.sines_agreed = false;
    }
    k.rhs(y.data(), params, f.data());
  };
  const auto flipped = [&] {
    for (std::size_t i = 0; i < n; ++i)
      if (std::fabs(x[i]) >= std::numbers::pi) return true;
    return false;
  };
  if (npend::energy_forbids_flip(c, x)) return r;
  if (flipped()) return {0, true};
  std::vector<double> k1(m), k2(m), k3(m), k4(m), tmp(m);
  const double half = 0.5 * dt, zero = 0.0 * dt, full = 1.0 * dt, sixth = (1.0 / 6.0) * dt,
               third = (1.0 / 3.0) * dt;
  const auto steps = static_cast<long long>(std::floor(t_end / dt + 1e-9));
  for (long long s = 1; s <= steps; ++s) {
    rhs(x, k1);
    for (std::size_t i = 0; i < m; ++i) tmp[i] = x[i] + half * k1[i];
    rhs(tmp, k2);
    for (std::size_t i = 0; i < m; ++i) tmp[i] = x[i] + zero * k1[i] + half * k2[i];
    rhs(tmp, k3);
    for (std::size_t i = 0; i < m; ++i) tmp[i] = x[i] + zero * k1[i] + zero * k2[i] + full * k3[i];
    rhs(tmp, k4);
    for (std::size_t i = 0; i < m; ++i)
      x[i] = x[i] + sixth * k1[i] + third * k2[i] + third * k3[i] + sixth * k4[i];
    if (flipped()) {
      rhs(x, k1);  // the rate at the step's end, which the flip's interpolant takes too
      r.time = static_cast<double>(s) * dt;
      return r;
    }
  }
  return r;
}

}  // namespace

TEST_CASE("flip_times: runs on the batch lanes for point-mass chains, not for physical ones") {
  // Four blocks of the lane ISA's vector of doubles.
  const std::string_view isa = npend::batch_lane_isa();
  const int doubles = npend::test::doubles_per_vector(isa);
  CHECK(npend::batch_lanes(npend::chain(npend::chain_parameters::uniform(2))) == 4 * doubles);
  npend::chain_parameters rods = npend::chain_parameters::uniform(2);
  rods.make_uniform_rods();
  CHECK(npend::batch_lanes(npend::chain(rods)) == 0);
}

// Whether the lanes' time a and the library's b are the same cell's value up to round-off:
// SLEEF's sines against std::sin's, an ulp apart, grown by the flow (e^(λ t) ≲ 1e5 over a
// few seconds), which the flip located inside its step shows (a step-resolved time hid it).
bool close_times(double a, double b) { return same(a, b) || std::fabs(a - b) <= 1e-9; }

TEST_CASE("flip_times: within a step of the scalar flip_time, mostly the same value") {
  const npend::chain c(npend::chain_parameters::uniform(2));
  const std::vector<double> starts = grid_starts(24, -3.1, 3.1);
  const npend::flip_options o{5.0, 0.01, 0};
  const std::vector<double> got = npend::flip_times(c, starts, o);
  REQUIRE(got.size() == starts.size() / 4);
  int equal = 0, near = 0, finite = 0;
  for (std::size_t i = 0; i < got.size(); ++i) {
    const std::vector<double> x(starts.begin() + static_cast<long>(4 * i),
                                starts.begin() + static_cast<long>(4 * i + 4));
    const double want = npend::flip_time(c, x, o);
    INFO("start (" << x[0] << ", " << x[1] << "): lanes " << got[i] << ", scalar " << want);
    // Over 5 s a difference of an ulp in a sine grows by e^(λ t) at most ~1e5: far from
    // moving a flip by a step, so the times agree to a step everywhere.
    if (std::isinf(want))
      CHECK(std::isinf(got[i]));
    else
      CHECK(std::fabs(got[i] - want) <= o.dt * (1 + 1e-9));
    equal += same(got[i], want) ? 1 : 0;
    near += close_times(got[i], want) ? 1 : 0;
    finite += std::isfinite(want) ? 1 : 0;
  }
  MESSAGE(equal << " of " << got.size() << " cells the same value, " << near << " within 1e-9 s ("
                << finite << " flip)");
  CHECK(finite > 50);
  CHECK(near >= static_cast<int>(got.size()) - 2);
}

TEST_CASE("flip_times: the first flip of one chosen link, as the scalar flip_time finds it") {
  // The lanes look at a block only when one of its watched angles has left (-π, π); with one
  // link watched, the others may pass the upright unseen.
  const npend::chain c(npend::chain_parameters::uniform(3));
  std::vector<double> starts;
  for (const double phi : grid_starts(16, -3.1, 3.1)) starts.push_back(phi);
  std::vector<double> three;  // (φ1, φ2, 0.5, 0, 0, 0) from the double pendulum's grid
  for (std::size_t i = 0; i < starts.size(); i += 4)
    three.insert(three.end(), {starts[i], starts[i + 1], 0.5, 0, 0, 0});
  const std::vector<double> any = npend::flip_times(c, three, {3.0, 0.01, 0});
  for (int link = 1; link <= 3; ++link) {
    CAPTURE(link);
    const npend::flip_options o{3.0, 0.01, link};
    const std::vector<double> got = npend::flip_times(c, three, o);
    int equal = 0, near = 0, later_than_any = 0;
    for (std::size_t i = 0; i < got.size(); ++i) {
      const std::vector<double> x(three.begin() + static_cast<long>(6 * i),
                                  three.begin() + static_cast<long>(6 * i + 6));
      const double want = npend::flip_time(c, x, o);
      INFO("start " << i << ": lanes " << got[i] << ", scalar " << want);
      if (std::isinf(want))
        CHECK(std::isinf(got[i]));
      else
        CHECK(std::fabs(got[i] - want) <= o.dt * (1 + 1e-9));
      equal += same(got[i], want) ? 1 : 0;
      near += close_times(got[i], want) ? 1 : 0;
      later_than_any += got[i] > any[i] ? 1 : 0;
    }
    MESSAGE(equal << " of " << got.size() << " cells the same value, " << near << " within 1e-9 s; "
                  << later_than_any << " flip later than the first flip of any link");
    CHECK(near >= static_cast<int>(got.size()) - 2);
    CHECK(later_than_any > 0);
  }
}

TEST_CASE("flip_times: the value of the reference rk4 wherever the sines agree") {
  // Short runs from near upright, so that many trajectories see only sines that SLEEF and
  // std::sin round the same way; those must give exactly flip_time's time (the same steps,
  // the same rates at the flip step's ends, the same interpolant), and flip_time's lies in
  // the reference's (odeint's sums written out) flip step.
  const npend::chain c(npend::chain_parameters::uniform(2));
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> angle(2.6, 3.1), sign(-1, 1), momentum(-3, 3);
  std::vector<double> starts;
  for (int k = 0; k < 400; ++k) {
    starts.push_back(angle(rng) * (sign(rng) < 0 ? -1 : 1));
    starts.push_back(angle(rng) * (sign(rng) < 0 ? -1 : 1));
    starts.push_back(momentum(rng));
    starts.push_back(momentum(rng));
  }
  const npend::flip_options o{1.0, 0.01, 0};
  // On the lanes of the build's own ISA, whose sines the reference checks (batch_sincos of
  // this unit's ISA) and whose arithmetic fuses no multiply-adds, as the scalar kernels'.
  const std::string isa(npend::batch_lane_isa());
  npend::use_batch_lane_isa(npend::batch_lane_isas().front());
  const std::vector<double> got = npend::flip_times(c, starts, o);
  npend::use_batch_lane_isa(isa);
  int agreed = 0, flipped = 0;
  for (std::size_t i = 0; i < got.size(); ++i) {
    const std::vector<double> x(starts.begin() + static_cast<long>(4 * i),
                                starts.begin() + static_cast<long>(4 * i + 4));
    const reference_flip want = reference_flip_time(c, x, o.t_end, o.dt);
    INFO("start " << i << ": lanes " << got[i] << ", reference " << want.time);
    const double library = npend::flip_time(c, x, o);
    if (std::isfinite(want.time) && want.time > 0)
      CHECK((library > want.time - o.dt && library <= want.time));
    else
      CHECK(same(want.time, library));
    if (want.sines_agreed) {
      ++agreed;
      CHECK(same(got[i], library));
    } else if (std::isfinite(want.time)) {
      CHECK(std::fabs(got[i] - want.time) <= o.dt * (1 + 1e-9));
    }
    flipped += std::isfinite(want.time) && want.time > 0 ? 1 : 0;
  }
  MESSAGE(agreed << " of " << got.size() << " trajectories with all sines equal; " << flipped
                 << " flip after the start");
  CHECK(agreed >= 20);
  CHECK(flipped >= 20);
}

TEST_CASE("flip_times: a cell's value depends on its own start only") {
  const npend::chain c(npend::chain_parameters::uniform(3));
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> angle(-3, 3), momentum(-2, 2);
  const int count = 5 * npend::batch_lanes(c) + 3;
  std::vector<double> starts;
  for (int k = 0; k < count; ++k) {
    for (int i = 0; i < 3; ++i) starts.push_back(angle(rng));
    for (int i = 0; i < 3; ++i) starts.push_back(k % 4 == 0 ? 0.0 : momentum(rng));
  }
  const npend::flip_options o{20.0, 0.01, 0};
  const std::vector<double> all = npend::flip_times(c, starts, o);
  // Reversed: every cell in another lane, beside other cells, refilled at other times.
  std::vector<double> reversed;
  for (int k = count - 1; k >= 0; --k)
    reversed.insert(reversed.end(), starts.begin() + 6 * k, starts.begin() + 6 * k + 6);
  const std::vector<double> back = npend::flip_times(c, reversed, o);
  int finite = 0, never = 0;
  for (int k = 0; k < count; ++k) {
    const auto ku = static_cast<std::size_t>(k);
    CAPTURE(k);
    CHECK(same(all[ku], back[static_cast<std::size_t>(count - 1 - k)]));
    // Alone (the other lanes copies of it), and through map_cell.
    const std::vector<double> x(starts.begin() + 6 * k, starts.begin() + 6 * k + 6);
    CHECK(same(all[ku], npend::flip_times(c, x, o).front()));
    // map_cell marks the cells the energy rules out as NaN (a map shows them apart).
    npend::map_cell_options mo;
    mo.t_end = o.t_end;
    const double in_map = npend::energy_forbids_flip(c, x) ? nan_value : all[ku];
    CHECK(same(in_map, npend::map_cell(c, x, mo)));
    finite += std::isfinite(all[ku]) ? 1 : 0;
    never += std::isinf(all[ku]) ? 1 : 0;
  }
  // Both kinds of cell, so that lanes finished at different steps were refilled.
  CHECK(finite > 5);
  CHECK(never > 0);
  npend::map_cell_options mo;
  mo.t_end = o.t_end;
  const std::vector<double> cells = npend::map_cells(c, starts, mo);
  for (std::size_t k = 0; k < cells.size(); ++k) {
    const std::span<const double> x(starts.data() + 6 * k, 6);
    CHECK(same(cells[k], npend::energy_forbids_flip(c, x) ? nan_value : all[k]));
  }
}

TEST_CASE("flip_times: flip_time's special cells and argument checks") {
  const npend::chain c(npend::chain_parameters::uniform(2));
  const npend::flip_options o{10.0, 0.01, 0};
  const double nan = std::numeric_limits<double>::quiet_NaN();
  // Forbidden by the energy, past upright at the start, a non-finite state, one that flips.
  const std::vector<double> starts{0.5, 0.5, 0, 0, 3.5, 0, 0, 0, nan, 0, 0, 0, 2.0, 2.5, 0, 0};
  const std::vector<double> t = npend::flip_times(c, starts, o);
  REQUIRE(t.size() == 4);
  CHECK(std::isinf(t[0]));
  CHECK(t[1] == 0);
  CHECK(std::isnan(t[2]));
  CHECK(t[3] > 0);
  CHECK(std::isfinite(t[3]));
  CHECK(std::fabs(t[3] - npend::flip_time(c, std::vector<double>{2.0, 2.5, 0, 0}, o)) <=
        o.dt * (1 + 1e-9));
  // Not a flip within a short t_end.
  CHECK(std::isinf(
      npend::flip_times(c, std::vector<double>{2.0, 2.5, 0, 0}, {0.05, 0.01, 0}).front()));
  CHECK(npend::flip_times(c, std::vector<double>{}, o).empty());
  CHECK_THROWS_AS(npend::flip_times(c, std::vector<double>{1, 2, 3}, o), std::invalid_argument);
  CHECK_THROWS_AS(npend::flip_times(c, starts, {1.0, 0.0, 0}), std::invalid_argument);
  CHECK_THROWS_AS(npend::flip_times(c, starts, {1.0, 0.01, 3}), std::invalid_argument);
  // A damped chain goes cell by cell too: flip_time's values, NaN where it would throw.
  npend::chain_parameters damped = npend::chain_parameters::uniform(2);
  damped.damping = {0.1, 0.1};
  const npend::chain damped_chain(damped);
  const auto damped_times = npend::flip_times(damped_chain, starts, o);
  REQUIRE(damped_times.size() == 4);
  for (const std::size_t k : {0u, 1u, 3u})
    CHECK(same(damped_times[k],
               npend::flip_time(damped_chain, std::span(starts).subspan(4 * k, 4), o)));
  CHECK(std::isnan(damped_times[2]));
  // A physical chain goes cell by cell through flip_time, with NaN for its integration_error.
  npend::chain_parameters rods = npend::chain_parameters::uniform(2);
  rods.make_uniform_rods();
  const npend::chain rod_chain(rods);
  const std::vector<double> rod_times = npend::flip_times(rod_chain, starts, o);
  CHECK(std::isinf(rod_times[0]));
  CHECK(std::isnan(rod_times[2]));
  CHECK(rod_times[3] == npend::flip_time(rod_chain, std::vector<double>{2.0, 2.5, 0, 0}, o));
}

TEST_CASE("map_cells: Lyapunov cells on the lanes agree with maximal_lyapunov_exponent") {
  // Over 2 s the lanes' and the scalar library's trajectories stay within round-off (SLEEF's
  // sines against std::sin's, growing by e^(λ t) ≲ e^20), so the two exponents agree closely
  // on regular and chaotic starts alike; renormalisation every 10 steps and at the end.
  const npend::chain c(npend::chain_parameters::uniform(3));
  REQUIRE(npend::batch_lanes(c) > 0);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> angle(-3, 3), momentum(-2, 2);
  const int count = 3 * npend::batch_lanes(c) + 5;
  std::vector<double> starts;
  for (int k = 0; k < count; ++k) {
    for (int i = 0; i < 3; ++i) starts.push_back(angle(rng) * (k % 3 == 0 ? 0.1 : 1.0));
    for (int i = 0; i < 3; ++i) starts.push_back(momentum(rng));
  }
  npend::map_cell_options mo;
  mo.quantity = npend::map_quantity::lyapunov;
  mo.t_end = 2.005;  // not a whole number of renormalisation intervals: a short last one
  mo.dt = 0.01;
  const std::vector<double> lanes = npend::map_cells(c, starts, mo);
  npend::lyapunov_options lo;
  lo.integration.stepper = npend::stepper_kind::rk4;
  lo.integration.t_end = mo.t_end;
  lo.integration.dt = mo.dt;
  double worst = 0, largest = 0;
  for (int k = 0; k < count; ++k) {
    const std::span<const double> x(starts.data() + 6 * k, 6);
    const double want = npend::maximal_lyapunov_exponent(c, x, lo).exponents.front();
    CAPTURE(k);
    CHECK(std::isfinite(lanes[static_cast<std::size_t>(k)]));
    worst = std::max(worst, std::fabs(lanes[static_cast<std::size_t>(k)] - want));
    largest = std::max(largest, std::fabs(want));
    // One cell alone, through map_cell: the same value (a lane does not see its neighbours).
    if (k % 7 == 0) CHECK(same(npend::map_cell(c, x, mo), lanes[static_cast<std::size_t>(k)]));
  }
  MESSAGE("largest |λ| " << largest << " 1/s, worst difference " << worst);
  CHECK(largest > 0.5);
  CHECK(worst <= 1e-8);
}

TEST_CASE("map_cells: Lyapunov cells on the lanes, a failed start is NaN, a bad one refused") {
  const npend::chain c(npend::chain_parameters::uniform(2));
  npend::map_cell_options mo;
  mo.quantity = npend::map_quantity::lyapunov;
  mo.t_end = 1;
  // A huge momentum: the state leaves the doubles within the first steps.
  const std::vector<double> blown{0.5, 0.5, 1e200, -1e200};
  CHECK(std::isnan(npend::map_cell(c, blown, mo)));
  const std::vector<double> bad{0.5, std::numeric_limits<double>::infinity(), 0, 0};
  CHECK_THROWS_AS(npend::map_cells(c, bad, mo), std::invalid_argument);
}

TEST_CASE("map_cells: chaos indicator cells on the lanes agree with chaos_indicators") {
  // FLI, MEGNO, SALI (2 vectors) and GALI_4 (4 vectors) of the triple pendulum over 2 s:
  // the lanes' and the library's trajectories stay within round-off, so the values agree
  // closely (relative to the value, for SALI and GALI, which fall towards 0).
  const npend::chain c(npend::chain_parameters::uniform(3));
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> angle(-3, 3), momentum(-2, 2);
  const int count = npend::batch_lanes(c) + 3;
  std::vector<double> starts;
  for (int k = 0; k < count; ++k) {
    for (int i = 0; i < 3; ++i) starts.push_back(angle(rng) * (k % 3 == 0 ? 0.1 : 1.0));
    for (int i = 0; i < 3; ++i) starts.push_back(momentum(rng));
  }
  for (const auto quantity : {npend::map_quantity::fli, npend::map_quantity::megno,
                              npend::map_quantity::sali, npend::map_quantity::gali}) {
    CAPTURE(npend::map_quantity_name(quantity));
    npend::map_cell_options mo;
    mo.quantity = quantity;
    mo.t_end = 2;
    mo.dt = 0.01;
    const std::vector<double> lanes = npend::map_cells(c, starts, mo);
    npend::chaos_indicator_options io;
    io.t_end = mo.t_end;
    io.dt = mo.dt;
    io.vectors = quantity == npend::map_quantity::gali ? 4 : 2;
    double worst = 0;
    for (int k = 0; k < count; ++k) {
      const std::span<const double> x(starts.data() + 6 * k, 6);
      const auto last = npend::chaos_indicators(c, x, io).last;
      const double want = quantity == npend::map_quantity::fli     ? last.fli
                          : quantity == npend::map_quantity::megno ? last.mean_megno
                          : quantity == npend::map_quantity::sali  ? last.sali
                                                                   : last.gali.back();
      const double got = lanes[static_cast<std::size_t>(k)];
      CAPTURE(k);
      REQUIRE(std::isfinite(got));
      worst = std::max(worst, std::fabs(got - want) / std::max(1e-3, std::fabs(want)));
      if (k % 9 == 0) CHECK(same(npend::map_cell(c, x, mo), got));
    }
    MESSAGE(npend::map_quantity_name(quantity) << ": worst relative difference " << worst);
    CHECK(worst <= 1e-9);
  }
}

TEST_CASE("map_cells: final-state cells on the lanes agree with odeint's rk4 on the library") {
  // rk4 steps of dt and a last shorter one to land on t_end (2.005 s: 200 steps and one of
  // 0.005 s), against odeint's runge_kutta4 on the scalar chain_system, every component.
  const npend::chain c(npend::chain_parameters::uniform(3));
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> angle(-3, 3), momentum(-2, 2);
  const int count = npend::batch_lanes(c) + 7;
  std::vector<double> starts;
  for (int k = 0; k < count; ++k) {
    for (int i = 0; i < 3; ++i) starts.push_back(angle(rng));
    for (int i = 0; i < 3; ++i) starts.push_back(momentum(rng));
  }
  npend::map_cell_options mo;
  mo.quantity = npend::map_quantity::state;
  mo.t_end = 2.005;
  mo.dt = 0.01;
  double worst = 0;
  for (int component = 0; component < 6; ++component) {
    mo.component = component;
    const std::vector<double> lanes = npend::map_cells(c, starts, mo);
    for (int k = 0; k < count; ++k) {
      std::vector<double> x(starts.begin() + 6 * k, starts.begin() + 6 * k + 6);
      boost::numeric::odeint::runge_kutta4<std::vector<double>> stepper;
      const npend::chain_system system(c);
      for (int step = 0; step < 200; ++step) stepper.do_step(system, x, step * 0.01, 0.01);
      stepper.do_step(system, x, 2.0, 2.005 - 200 * 0.01);
      const double got = lanes[static_cast<std::size_t>(k)];
      worst = std::max(worst, std::fabs(got - x[static_cast<std::size_t>(component)]));
      if (k % 11 == 0) {
        const std::span<const double> start(starts.data() + 6 * k, 6);
        CHECK(same(npend::map_cell(c, start, mo), got));
      }
    }
  }
  MESSAGE("worst difference " << worst);
  CHECK(worst <= 1e-10);
  // A state that leaves the doubles is NaN.
  const std::vector<double> blown{0.5, 0.5, 0.5, 1e200, -1e200, 1e200};
  CHECK(std::isnan(npend::map_cell(c, blown, mo)));
}
