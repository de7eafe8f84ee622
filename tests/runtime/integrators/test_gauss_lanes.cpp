// Maps integrated by Gauss–Legendre (map_stepping gauss4, gauss6): the lanes solve their stage
// equations by fixed-point iteration, the library (npend::gauss_legendre) by simplified
// Newton; both to round-off, so the steps agree to round-off. Against the library's stepper,
// the energy a symplectic method keeps, and the library's answer for cells the lanes give up.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <span>
#include <vector>

#include "npend/analysis/chaos/chaos_map.hpp"
#include "npend/chain_system.hpp"
#include "npend/integrators/gauss_legendre.hpp"
#include "runtime/src/integrators/batch_lanes.hpp"

namespace {

bool same_value(double a, double b) { return a == b || (std::isnan(a) && std::isnan(b)); }

npend::map_stepping gauss_stepping(int stages) {
  return {stages == 2 ? npend::stepper_kind::gauss4 : npend::stepper_kind::gauss6, 1e-10, 1e-10};
}

// The state at t_end by the library's stepper: steps of dt, a last shorter one onto t_end.
template <class Stepper>
std::vector<double> library_state(const npend::chain& c, std::span<const double> x0, double t_end,
                                  double dt) {
  Stepper stepper;
  const auto system = npend::make_implicit_system(c);
  std::vector<double> x(x0.begin(), x0.end());
  const auto steps = static_cast<long long>(std::floor(t_end / dt + 1e-9));
  for (long long k = 0; k < steps; ++k) stepper.do_step(system, x, static_cast<double>(k) * dt, dt);
  const double rest = t_end - static_cast<double>(steps) * dt;
  if (rest > 1e-9 * dt) stepper.do_step(system, x, static_cast<double>(steps) * dt, rest);
  return x;
}

// Every coordinate of each start's state at t_end through map_cells.
std::vector<std::vector<double>> final_states(const npend::chain& c,
                                              const std::vector<double>& starts,
                                              npend::map_cell_options mo) {
  const auto d = static_cast<std::size_t>(c.state_size());
  std::vector<std::vector<double>> out(starts.size() / d, std::vector<double>(d));
  mo.quantity = npend::map_quantity::state;
  for (std::size_t i = 0; i < d; ++i) {
    mo.component = static_cast<int>(i);
    const auto values = npend::map_cells(c, starts, mo);
    for (std::size_t k = 0; k < values.size(); ++k) out[k][i] = values[k];
  }
  return out;
}

std::vector<double> random_triple_starts(int count, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> angle(-2.5, 2.5), momentum(-1.5, 1.5);
  std::vector<double> x;
  for (int k = 0; k < count; ++k) {
    for (int i = 0; i < 3; ++i) x.push_back(angle(rng) * (k % 3 == 0 ? 0.1 : 1.0));
    for (int i = 0; i < 3; ++i) x.push_back(momentum(rng));
  }
  return x;
}

}  // namespace

TEST_CASE("Gauss-Legendre maps: final states on the lanes agree with the library's stepper") {
  const npend::chain c(npend::chain_parameters::uniform(3));
  const int count = npend::batch_lanes(c) + 5;
  const std::vector<double> starts = random_triple_starts(count, 3);
  for (const int stages : {2, 3}) {
    CAPTURE(stages);
    npend::map_cell_options mo;
    mo.t_end = 2.005;  // 200 steps and one of 0.005 s
    mo.dt = 0.01;
    mo.stepping = gauss_stepping(stages);
    const auto lanes = final_states(c, starts, mo);
    double worst = 0;
    for (int k = 0; k < count; ++k) {
      const std::span<const double> x0(starts.data() + 6 * k, 6);
      const auto want = stages == 2 ? library_state<npend::gauss_legendre4>(c, x0, mo.t_end, mo.dt)
                                    : library_state<npend::gauss_legendre6>(c, x0, mo.t_end, mo.dt);
      for (std::size_t i = 0; i < 6; ++i)
        worst = std::max(worst, std::fabs(lanes[static_cast<std::size_t>(k)][i] - want[i]));
    }
    MESSAGE("gauss" << 2 * stages << ": worst difference from the library " << worst);
    CHECK(worst <= 1e-10);
  }
}

TEST_CASE("Gauss-Legendre maps: the energy stays bounded where rk4's drifts") {
  // A symplectic method keeps H within a bound of order h^(2s) for all time; rk4 lets it
  // drift. The triple pendulum from moderate starts over 200 s at dt = 0.02 (measured:
  // gauss6 2.6e-8, rk4 2.7e-3, the worst of the starts).
  const npend::chain c(npend::chain_parameters::uniform(3));
  std::vector<double> starts = random_triple_starts(npend::batch_lanes(c), 7);
  for (double& v : starts) v *= 0.4;  // moderate energies
  npend::map_cell_options mo;
  mo.t_end = 200;
  mo.dt = 0.02;
  const auto drift = [&](npend::map_stepping stepping) {
    mo.stepping = stepping;
    const auto ends = final_states(c, starts, mo);
    double worst = 0;
    for (std::size_t k = 0; k < ends.size(); ++k) {
      const double h0 = c.hamiltonian(std::span(starts).subspan(6 * k, 6));
      worst =
          std::max(worst, std::fabs(c.hamiltonian(ends[k]) - h0) / std::max(1.0, std::fabs(h0)));
    }
    return worst;
  };
  const double gauss6 = drift(gauss_stepping(3)), rk4 = drift({});
  MESSAGE("relative energy error after 200 s: gauss6 " << gauss6 << ", rk4 " << rk4);
  CHECK(gauss6 <= 1e-6);
  CHECK(rk4 > 1000 * gauss6);
}

TEST_CASE("Gauss-Legendre maps: flip times on the lanes are flip_time's") {
  // The flip is located inside its step, as with rk4; over 5 s the lanes' and the library's
  // trajectories stay within round-off, so the times agree to round-off grown by the flow
  // (1e-9 s) but for a grazing cell.
  const npend::chain c(npend::chain_parameters::uniform(2));
  std::vector<double> starts;
  for (int j = 0; j < 16; ++j)
    for (int i = 0; i < 16; ++i)
      starts.insert(starts.end(), {npend::grid_value(-3.1, 3.1, 16, i),
                                   npend::grid_value(-3.1, 3.1, 16, j), 0.0, 0.0});
  npend::flip_options o{5.0, 0.01, 0, gauss_stepping(3)};
  const auto lanes = npend::flip_times(c, starts, o);
  int equal = 0, finite = 0;
  for (std::size_t i = 0; i < lanes.size(); ++i) {
    const double want = npend::flip_time(c, std::span(starts).subspan(4 * i, 4), o);
    equal += same_value(lanes[i], want) || std::fabs(lanes[i] - want) <= 1e-9 ? 1 : 0;
    finite += std::isfinite(want) ? 1 : 0;
  }
  MESSAGE(equal << " of " << lanes.size() << " cells the same time within 1e-9 s (" << finite
                << " flip)");
  CHECK(finite > 50);
  CHECK(equal >= static_cast<int>(lanes.size()) - 2);
  // The same start in any slot: the same bits.
  std::vector<double> reversed;
  for (std::size_t k = lanes.size(); k-- > 0;)
    reversed.insert(reversed.end(), starts.begin() + static_cast<long>(4 * k),
                    starts.begin() + static_cast<long>(4 * k + 4));
  const auto backward = npend::flip_times(c, reversed, o);
  for (std::size_t k = 0; k < lanes.size(); ++k)
    CHECK(same_value(lanes[k], backward[lanes.size() - 1 - k]));
}

// Which of the starts a Gauss–Legendre lane gives up within t_end at step dt (the lanes'
// own stepper, driven directly: white-box).
std::vector<bool> lanes_give_up(const npend::chain& c, const std::vector<double>& starts, double dt,
                                double t_end) {
  const npend::batch_kernels& k = *npend::detail::lane_kernels(c);
  const auto m = static_cast<std::size_t>(c.state_size());
  std::vector<bool> out;
  for (std::size_t cell = 0; cell < starts.size() / m; ++cell) {
    npend::detail::lane_gauss<3> rk(
        npend::detail::lane_system(k, c.packed_parameters().data(), c.links(), 0, false), dt);
    for (std::size_t l = 0; l < static_cast<std::size_t>(rk.lanes); ++l) {
      for (std::size_t i = 0; i < m; ++i) rk.state()[rk.at(i, l)] = starts[cell * m + i];
      rk.restart(l);
    }
    for (double t = 0; t < t_end - 1e-9 && !rk.failed(0); t += dt)
      rk.step(npend::detail::lane_blocks);
    out.push_back(rk.failed(0));
  }
  return out;
}

TEST_CASE("Gauss-Legendre maps: long steps the fixed point cannot take go to the library") {
  // At long steps a fast cell's fixed-point iteration contracts too slowly or not at all
  // (h‖J‖ ~ 1); the lane gives up and the cell is the library's (its Newton iteration, or
  // NaN where that fails too), bit for bit. At dt = 0.01 no lane gives up.
  const npend::chain c(npend::chain_parameters::uniform(2));
  std::vector<double> starts;
  for (int i = 0; i < 40; ++i)
    starts.insert(starts.end(), {0.1 * i - 2, 0.07 * i - 1.4, 0.2 * i - 4, 3 - 0.15 * i});
  const auto library = [&](std::size_t i, double t_end, double dt) {
    try {
      return library_state<npend::gauss_legendre6>(c, std::span(starts).subspan(4 * i, 4), t_end,
                                                   dt)[0];
    } catch (const npend::integration_error&) {
      return std::numeric_limits<double>::quiet_NaN();
    }
  };
  npend::map_cell_options mo;
  mo.quantity = npend::map_quantity::state;
  mo.stepping = gauss_stepping(3);
  mo.t_end = 6;
  mo.dt = 0.2;
  const auto given_up = lanes_give_up(c, starts, mo.dt, mo.t_end);
  const auto got = npend::map_cells(c, starts, mo);
  int handed = 0;
  for (std::size_t i = 0; i < got.size(); ++i) {
    const double want = library(i, mo.t_end, mo.dt);
    CAPTURE(i);
    if (given_up[i]) {
      ++handed;
      CHECK(same_value(got[i], want));
    } else if (!std::isnan(want)) {
      // Solved on the lane: the library's value to round-off grown over 30 long steps.
      CHECK(std::fabs(got[i] - want) <= 1e-9);
    }
    // (A lane may solve a step whose Newton iteration fails in the library: then the lane's
    // converged value stands where the library gives NaN.)
  }
  MESSAGE(handed << " of " << got.size() << " cells handed to the library at dt = " << mo.dt);
  CHECK(handed > 0);
  const auto at_small_steps = lanes_give_up(c, starts, 0.01, 1.0);
  CHECK(std::none_of(at_small_steps.begin(), at_small_steps.end(), [](bool b) { return b; }));
}
