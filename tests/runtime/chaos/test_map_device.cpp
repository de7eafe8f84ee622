// The GPU maps' kernels (runtime/src/gpu/map_kernels.cuh) compiled for the CPU and run cell
// by cell against the library's maps (map_cell: the batch lanes for point masses, odeint
// cell by cell for physical chains): the same steps, so the same values up to round-off —
// what runs on a GPU, checked on machines without one. The device choice and the refusals
// of check_cuda_map are checked here too; the GPU itself in test_map_device_gpu.cpp.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "npend/analysis/chaos/chaos_map.hpp"
#include "npend/analysis/chaos/map_device.hpp"
#include "runtime/src/gpu/map_launch.hpp"

// The generated device functions, included once in this file (they are not headers with
// guards: NVRTC takes them as text).
#include "gpu_chain_2.cuh"
#include "gpu_chain_loop.cuh"
#include "gpu_physical_2.cuh"

namespace npend::gpu {
NPEND_GPU_POINT_MODEL(test_chain_2, chain_2)
NPEND_GPU_PHYSICAL_MODEL(test_physical_2, physical_2)
NPEND_GPU_LOOP_MODEL(test_loop_8, chain_loop, 8)
}  // namespace npend::gpu

namespace map_device_test {

using npend::chain;
using npend::map_cell_options;
using npend::map_quantity;

// The host-compiled kernel's value of the cell x0, as the GPU computes it (the energy's
// verdict on a flip taken first, on the CPU, as cuda_cells does); the chaos indicators with
// `Vectors` deviation vectors.
template <class Model, int Vectors = 0>
double kernel_cell(const chain& c, const std::vector<double>& x0, const map_cell_options& o) {
  if (o.quantity == map_quantity::flip && npend::energy_forbids_flip(c, x0, o.flip_link))
    return std::numeric_limits<double>::quiet_NaN();
  std::vector<double> params;
  npend::gpu::append_parameters(c, params);
  const npend::gpu::map_job job = npend::gpu::make_map_job(c, o);
  if constexpr (Vectors > 0)
    return npend::gpu::cell_value_of<Model, npend::gpu::job_indicators, npend::gpu::job_rk4,
                                     Vectors>(x0.data(), params.data(), job);
  else
    return npend::gpu::cell_value<Model>(x0.data(), params.data(), job);
}

struct agreement {
  int cells = 0, same_kind = 0, close = 0;
  double worst = 0;  // largest difference among the cells within tolerance
};

// Both sides over a grid of starts (φ1, φ2) at rest: how many cells agree in kind (NaN,
// +inf, finite) and how many finite ones agree within `tolerance` (relative to max(1, |v|)).
template <class Model, int Vectors = 0>
agreement compare_on_grid(const chain& c, const map_cell_options& o, double tolerance,
                          int side = 9) {
  agreement a;
  for (int i = 0; i < side; ++i)
    for (int j = 0; j < side; ++j) {
      const double phi1 = -3.0 + 6.0 * i / (side - 1), phi2 = -3.0 + 6.0 * j / (side - 1);
      const std::vector<double> x0{phi1, phi2, 0.0, 0.0};
      const double library = npend::map_cell(c, x0, o);
      const double kernel = kernel_cell<Model, Vectors>(c, x0, o);
      ++a.cells;
      const bool kind =
          std::isnan(library) == std::isnan(kernel) && std::isinf(library) == std::isinf(kernel);
      if (!kind) continue;
      ++a.same_kind;
      if (!std::isfinite(library)) {
        ++a.close;
        continue;
      }
      const double d = std::fabs(library - kernel) / std::max(1.0, std::fabs(library));
      if (d <= tolerance) {
        ++a.close;
        a.worst = std::max(a.worst, d);
      }
    }
  return a;
}

map_cell_options options(map_quantity q, npend::stepper_kind stepper, double t_end) {
  map_cell_options o;
  o.quantity = q;
  o.stepping.stepper = stepper;
  o.t_end = t_end;
  o.dt = 0.01;
  return o;
}

}  // namespace map_device_test

using namespace map_device_test;  // NOLINT: the test cases below only

TEST_CASE("gpu map kernels: flip times of the double pendulum as the CPU's lanes, rk4 and dopri5") {
  const chain c(npend::chain_parameters::uniform(2));
  for (const auto stepper : {npend::stepper_kind::rk4, npend::stepper_kind::dopri5}) {
    CAPTURE(npend::stepper_name(stepper));
    // Up to t = 10: the chaotic cells have not yet blown the last bit of a sine up to a
    // different flip (the lanes' SLEEF and the kernels' std::sin agree within 1 ulp).
    const agreement a = compare_on_grid<npend::gpu::test_chain_2>(
        c, options(map_quantity::flip, stepper, 10.0), 1e-9);
    CHECK(a.same_kind == a.cells);
    CHECK(a.close == a.cells);
  }
}

TEST_CASE("gpu map kernels: final states and Lyapunov exponents as the CPU's") {
  const chain c(npend::chain_parameters::uniform(2));
  auto o = options(map_quantity::state, npend::stepper_kind::rk4, 3.005);  // a last short step
  o.component = 3;
  agreement a = compare_on_grid<npend::gpu::test_chain_2>(c, o, 1e-9);
  CHECK(a.close == a.cells);
  o.stepping.stepper = npend::stepper_kind::dopri5;
  o.component = 0;
  a = compare_on_grid<npend::gpu::test_chain_2>(c, o, 1e-9);
  CHECK(a.close == a.cells);
  a = compare_on_grid<npend::gpu::test_chain_2>(
      c, options(map_quantity::lyapunov, npend::stepper_kind::rk4, 2.0), 1e-9, 5);
  CHECK(a.close == a.cells);
  a = compare_on_grid<npend::gpu::test_chain_2>(
      c, options(map_quantity::lyapunov, npend::stepper_kind::dopri5, 2.0), 1e-9, 5);
  CHECK(a.close == a.cells);
}

TEST_CASE("gpu map kernels: FLI, MEGNO, SALI and GALI as the CPU's chaos indicators") {
  const chain c(npend::chain_parameters::uniform(2));
  for (const auto q : {map_quantity::fli, map_quantity::megno, map_quantity::sali}) {
    CAPTURE(npend::map_quantity_name(q));
    const agreement a = compare_on_grid<npend::gpu::test_chain_2, 2>(
        c, options(q, npend::stepper_kind::rk4, 3.0), 1e-9, 5);
    CHECK(a.close == a.cells);
  }
  // GALI_3 (n + 1) and GALI_4: a QR's volume against the library's singular values.
  auto o = options(map_quantity::gali, npend::stepper_kind::rk4, 3.0);
  agreement a = compare_on_grid<npend::gpu::test_chain_2, 3>(c, o, 1e-9, 5);
  CHECK(a.close == a.cells);
  o.gali_order = 4;
  a = compare_on_grid<npend::gpu::test_chain_2, 4>(c, o, 1e-9, 5);
  CHECK(a.close == a.cells);
}

TEST_CASE("gpu map kernels: an 8-link chain on the loop kernels as the CPU's") {
  // The CPU runs it cell by cell on the loop kernels (their sines from SLEEF, the kernels'
  // from std::sin: within an ulp), over a short time.
  const chain c(npend::chain_parameters::uniform(8));
  REQUIRE(c.runs_on_loops());
  const auto start = [](double a, double b) {
    std::vector<double> x(16, 0.0);
    x[0] = a;
    x[7] = b;
    return x;
  };
  for (const auto q : {map_quantity::flip, map_quantity::lyapunov, map_quantity::megno}) {
    CAPTURE(npend::map_quantity_name(q));
    const auto o = options(q, npend::stepper_kind::rk4, 2.0);
    for (const double a : {-2.5, 0.5, 3.0})
      for (const double b : {-3.0, 1.0}) {
        const std::vector<double> x0 = start(a, b);
        const double library = npend::map_cell(c, x0, o);
        const double kernel = q == map_quantity::megno
                                  ? kernel_cell<npend::gpu::test_loop_8, 2>(c, x0, o)
                                  : kernel_cell<npend::gpu::test_loop_8>(c, x0, o);
        CAPTURE(a);
        CAPTURE(b);
        CHECK(std::isinf(library) == std::isinf(kernel));
        if (std::isfinite(library))
          CHECK(std::fabs(library - kernel) <= 1e-9 * std::max(1.0, std::fabs(library)));
      }
  }
}

TEST_CASE("gpu map kernels: a driven physical pendulum and a damped one as the CPU's odeint") {
  auto p = npend::chain_parameters::uniform(2);
  p.make_uniform_rods();
  p.pivot = npend::pivot_motion::vertical(0.1, 30.0);
  const chain driven(p);
  for (const auto q : {map_quantity::flip, map_quantity::state}) {
    CAPTURE(npend::map_quantity_name(q));
    const agreement a = compare_on_grid<npend::gpu::test_physical_2>(
        driven, options(q, npend::stepper_kind::rk4, 4.0), 1e-9, 5);
    CHECK(a.close == a.cells);
  }
  p.pivot = {};
  p.damping = {0.05, 0.02};
  p.stiffness = {0.5, 0.0};
  const chain damped(p);
  const agreement a = compare_on_grid<npend::gpu::test_physical_2>(
      damped, options(map_quantity::flip, npend::stepper_kind::dopri5, 6.0), 1e-9, 5);
  CHECK(a.close == a.cells);
}

TEST_CASE("gpu maps: the device names, and what the GPU maps refuse by name") {
  CHECK(npend::parse_map_device("cuda") == npend::map_device::cuda);
  CHECK(npend::map_device_name(npend::map_device::cpu) == "cpu");
  CHECK_THROWS_WITH_AS(npend::parse_map_device("gpu"),
                       doctest::Contains("cpu (the CPU's cores) or cuda"), std::invalid_argument);
  const chain c(npend::chain_parameters::uniform(2));
  CHECK_THROWS_WITH_AS(
      npend::check_cuda_map(c, options(map_quantity::flip, npend::stepper_kind::gauss6, 10)),
      doctest::Contains("rk4 or dopri5, not gauss6"), std::invalid_argument);
  CHECK_THROWS_WITH_AS(
      npend::check_cuda_map(c, options(map_quantity::megno, npend::stepper_kind::dopri5, 10)),
      doctest::Contains("integrate with one of rk4, taylor, not dopri5"), std::invalid_argument);
  auto custom = npend::chain_parameters::uniform(2);
  custom.make_uniform_rods();
  custom.pivot.type = npend::pivot_motion::kind::custom;
  custom.pivot.position = custom.pivot.velocity = custom.pivot.acceleration = [](double) {
    return npend::pivot_motion::vec2{0.0, 0.0};
  };
  CHECK_THROWS_WITH_AS(
      npend::check_cuda_map(chain(custom),
                            options(map_quantity::flip, npend::stepper_kind::rk4, 10)),
      doctest::Contains("custom path runs on the CPU only"), std::invalid_argument);
  npend::check_cuda_map(c, options(map_quantity::flip, npend::stepper_kind::dopri5, 10));
  npend::check_cuda_map(c, options(map_quantity::gali, npend::stepper_kind::rk4, 10));
}

TEST_CASE("gpu maps: without a usable GPU, a clear error and no values") {
  const npend::cuda_status s = npend::find_cuda();
  if (s.usable) return;  // a machine with a GPU: test_map_device_gpu.cpp checks it
  CHECK(!s.problem.empty());
  const chain c(npend::chain_parameters::uniform(2));
  const std::vector<double> x0{2.0, 2.0, 0.0, 0.0};
  CHECK_THROWS_WITH_AS(
      npend::cuda_map_cells(c, x0, options(map_quantity::flip, npend::stepper_kind::rk4, 10)),
      doctest::Contains("CUDA is not usable here"), std::runtime_error);
}

TEST_CASE("gpu maps: the GPU programs compile with NVRTC where it is installed") {
  // Where the CUDA toolkit's NVRTC is found (also without a GPU): each model's program for
  // each kind of kernel, the longest generated functions among them.
  auto rods = npend::chain_parameters::uniform(3);
  rods.make_uniform_rods();
  auto driven = npend::chain_parameters::uniform(1);
  driven.make_uniform_rods();
  driven.pivot = npend::pivot_motion::horizontal(0.1, 20.0);
  auto o = options(map_quantity::flip, npend::stepper_kind::rk4, 10);
  const std::string flip =
      npend::detail::cuda_program_ptx(chain(npend::chain_parameters::uniform(2)), o);
  if (flip.empty()) {
    MESSAGE("skipped: NVRTC is not installed (" << npend::find_cuda().problem << ")");
    return;
  }
  CHECK(flip.find(".entry npend_map_cells") != std::string::npos);
  o.stepping.stepper = npend::stepper_kind::dopri5;
  CHECK(!npend::detail::cuda_program_ptx(chain(rods), o).empty());
  o.quantity = map_quantity::state;
  CHECK(!npend::detail::cuda_program_ptx(chain(driven), o).empty());
  o = options(map_quantity::lyapunov, npend::stepper_kind::dopri5, 10);
  CHECK(!npend::detail::cuda_program_ptx(chain(npend::chain_parameters::uniform(3)), o).empty());
  o = options(map_quantity::gali, npend::stepper_kind::rk4, 10);  // GALI_7: 7 vectors of 12
  CHECK(!npend::detail::cuda_program_ptx(chain(npend::chain_parameters::uniform(6)), o).empty());
  o = options(map_quantity::lyapunov, npend::stepper_kind::rk4, 10);  // the loop kernels
  CHECK(!npend::detail::cuda_program_ptx(chain(npend::chain_parameters::uniform(12)), o).empty());
}
