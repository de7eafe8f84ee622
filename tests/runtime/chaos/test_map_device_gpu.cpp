// The GPU maps on a GPU (where find_cuda finds one; elsewhere each case says it is skipped)
// against the CPU's maps of the same grids: identical cells ruled out by their energy,
// identical non-flipping regular cells, and on the regular cells values within the stepper's
// own accuracy. A cell is regular where the CPU's map does not change by more than that
// accuracy when the step is halved, nor when it is halved again (dopri5: the tolerances
// divided by ten, then by a hundred); there a last-bit difference between the GPU's and the
// CPU's sines cannot have grown to more. (One refinement alone lets the odd chaotic cell
// through, whose two values happen to fall close.)
#include <doctest/doctest.h>

#include <cmath>
#include <vector>

#include "npend/analysis/chaos/map_device.hpp"
#include "npend/analysis/chaos/map_grid.hpp"
#include "npend/analysis/chaos/map_run.hpp"

namespace map_device_gpu_test {

using npend::map_cell_options;
using npend::map_grid;
using npend::map_quantity;

bool gpu_present() {
  const npend::cuda_status s = npend::find_cuda();
  if (!s.usable) MESSAGE("skipped, no usable GPU: " << s.problem);
  return s.usable;
}

map_grid angle_grid(npend::chain_parameters p, int side) {
  map_grid g;
  const int n = p.links();
  g.parameters = std::move(p);
  g.angles.assign(static_cast<std::size_t>(n), 0.0);
  g.momenta.assign(static_cast<std::size_t>(n), 0.0);
  g.x = npend::make_map_axis("phi1", -3.0, 3.0, side, n);
  g.y = npend::make_map_axis(n > 1 ? "phi2" : "p1", -3.0, 3.0, side, n);
  return g;
}

// Whether a and b agree within `accuracy`, +inf with +inf.
bool agree(double a, double b, double accuracy) {
  return (std::isinf(a) && std::isinf(b) && (a > 0) == (b > 0)) || std::fabs(a - b) <= accuracy;
}

// The GPU's map against the CPU's (every core), with `finer` and `finest` the CPU's options
// one and two steps of accuracy finer; `accuracy` the stepper's (an absolute difference).
void check_against_cpu(const map_grid& g, const map_cell_options& o, const map_cell_options& finer,
                       const map_cell_options& finest, double accuracy) {
  const std::vector<double> cpu = npend::map_values(g, o);
  const std::vector<double> cpu_finer = npend::map_values(g, finer);
  const std::vector<double> cpu_finest = npend::map_values(g, finest);
  const std::vector<double> gpu = npend::map_values(g, o, 0, nullptr, npend::map_device::cuda);
  REQUIRE(gpu.size() == cpu.size());
  int nan_mismatch = 0, regular = 0, regular_off = 0, close = 0, finite = 0;
  double worst = 0;
  for (std::size_t k = 0; k < cpu.size(); ++k) {
    if (std::isnan(cpu[k]) != std::isnan(gpu[k])) ++nan_mismatch;
    if (std::isfinite(cpu[k]) && std::isfinite(gpu[k])) {
      ++finite;
      if (std::fabs(cpu[k] - gpu[k]) <= 1e-9 * std::max(1.0, std::fabs(cpu[k]))) ++close;
    }
    const bool steady =
        agree(cpu[k], cpu_finer[k], accuracy) && agree(cpu_finer[k], cpu_finest[k], accuracy);
    if (!steady || std::isnan(cpu[k])) continue;
    ++regular;
    if (!agree(cpu[k], gpu[k], accuracy)) ++regular_off;
    if (std::isfinite(cpu[k]) && std::isfinite(gpu[k]))
      worst = std::max(worst, std::fabs(cpu[k] - gpu[k]));
  }
  MESSAGE(npend::map_quantity_name(o.quantity)
          << " (" << npend::stepper_name(o.stepping.stepper) << "): " << cpu.size() << " cells, "
          << regular << " regular, " << regular_off << " of them off; " << close << " of " << finite
          << " finite values equal to 1e-9; worst regular difference " << worst);
  CHECK(nan_mismatch == 0);
  CHECK(regular > static_cast<int>(cpu.size()) / 4);
  CHECK(regular_off == 0);
}

map_cell_options cell(map_quantity q, double t_end, double dt) {
  map_cell_options o;
  o.quantity = q;
  o.t_end = t_end;
  o.dt = dt;
  return o;
}

map_cell_options halved(map_cell_options o, double times = 1) {
  o.dt /= std::pow(2.0, times);
  return o;
}

map_cell_options tightened(map_cell_options o, double factor) {
  o.stepping.abs_tol /= factor;
  o.stepping.rel_tol /= factor;
  return o;
}

}  // namespace map_device_gpu_test

using namespace map_device_gpu_test;  // NOLINT: the test cases below only

TEST_CASE("gpu maps: the double pendulum's flip map as the CPU's, rk4 and dopri5") {
  if (!gpu_present()) return;
  const map_grid g = angle_grid(npend::chain_parameters::uniform(2), 96);
  const map_cell_options o = cell(map_quantity::flip, 60, 0.01);
  check_against_cpu(g, o, halved(o), halved(o, 2), 1e-3);
  map_cell_options d = cell(map_quantity::flip, 30, 0.01);
  d.stepping.stepper = npend::stepper_kind::dopri5;
  check_against_cpu(angle_grid(npend::chain_parameters::uniform(2), 48), d, tightened(d, 10),
                    tightened(d, 100), 1e-6);
}

TEST_CASE("gpu maps: a rod triple pendulum's flip map as the CPU's") {
  if (!gpu_present()) return;
  auto p = npend::chain_parameters::uniform(3);
  p.make_uniform_rods();
  const map_cell_options o = cell(map_quantity::flip, 30, 0.01);
  check_against_cpu(angle_grid(p, 48), o, halved(o), halved(o, 2), 1e-3);
}

TEST_CASE("gpu maps: a driven pendulum's flip map as the CPU's") {
  if (!gpu_present()) return;
  auto p = npend::chain_parameters::uniform(1);
  p.make_uniform_rods();
  p.pivot = npend::pivot_motion::vertical(0.05, 40.0);
  const map_cell_options o = cell(map_quantity::flip, 20, 0.005);
  check_against_cpu(angle_grid(p, 64), o, halved(o), halved(o, 2), 1e-3);
}

TEST_CASE("gpu maps: a Lyapunov map and a final-state map as the CPU's") {
  if (!gpu_present()) return;
  const map_grid g = angle_grid(npend::chain_parameters::uniform(2), 32);
  const map_cell_options o = cell(map_quantity::lyapunov, 20, 0.01);
  check_against_cpu(g, o, halved(o), halved(o, 2), 1e-3);
  // rk4's own error in φ₂ at dt = 0.01 over 5 s: within 1e-5 where the map is regular.
  map_cell_options s = cell(map_quantity::state, 5, 0.01);
  s.component = 1;
  check_against_cpu(g, s, halved(s), halved(s, 2), 1e-5);
}

TEST_CASE("gpu maps: chaos indicator maps and a dopri5 Lyapunov map as the CPU's") {
  if (!gpu_present()) return;
  const map_grid g = angle_grid(npend::chain_parameters::uniform(2), 32);
  for (const auto q : {map_quantity::fli, map_quantity::megno, map_quantity::gali}) {
    const map_cell_options o = cell(q, 20, 0.01);
    check_against_cpu(g, o, halved(o), halved(o, 2), 1e-3);
  }
  map_cell_options d = cell(map_quantity::lyapunov, 20, 0.01);
  d.stepping.stepper = npend::stepper_kind::dopri5;
  check_against_cpu(g, d, tightened(d, 10), tightened(d, 100), 1e-3);
}

TEST_CASE("gpu maps: a 10-link chain on the loop kernels as the CPU's") {
  if (!gpu_present()) return;
  const map_grid g = angle_grid(npend::chain_parameters::uniform(10), 24);
  const map_cell_options o = cell(map_quantity::flip, 10, 0.005);
  check_against_cpu(g, o, halved(o), halved(o, 2), 1e-3);
}
