#include "npend/analysis/chaos/map_device.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "analysis/detail/argument_checks.hpp"
#include "analysis/detail/map_cell_steps.hpp"
#include "gpu/cuda_driver.hpp"
#include "gpu/gpu_sources.hpp"
#include "gpu/host_kernels.hpp"
#include "gpu/map_launch.hpp"
#include "npend/integrators/integrate.hpp"

namespace npend {

std::string_view map_device_name(map_device device) {
  return device == map_device::cuda ? "cuda" : "cpu";
}

map_device parse_map_device(std::string_view name) {
  if (name == "cpu") return map_device::cpu;
  if (name == "cuda") return map_device::cuda;
  throw std::invalid_argument(
      fmt::format("'{}' is not a device: cpu (the CPU's cores) or cuda (a GPU)", name));
}

cuda_status find_cuda() {
  const gpu::cuda_probe& p = gpu::probe();
  return {p.usable, p.device, p.driver, p.nvrtc, p.problem};
}

double cuda_kernel_seconds() { return gpu::seconds_in_kernels(); }

void require_cuda() {
  const gpu::cuda_probe& p = gpu::probe();
  if (!p.usable) throw std::runtime_error("CUDA is not usable here: " + p.problem);
}

namespace {

// The generated device functions' file stem of the chain's model: gpu_chain_<n>,
// gpu_physical_<n>, or gpu_chain_loop for a point-mass chain on the loop kernels.
std::string device_functions(const chain& c) {
  if (c.runs_on_loops()) return "gpu_chain_loop";
  return fmt::format("gpu_{}_{}", c.is_physical() ? "physical" : "chain", c.links());
}

// The adapter that makes the chain's device functions a model of map_kernels.cuh.
std::string model_adapter(const chain& c) {
  if (c.runs_on_loops())
    return fmt::format("NPEND_GPU_LOOP_MODEL(model, chain_loop, {})", c.links());
  return fmt::format("{}(model, {})",
                     c.is_physical() ? "NPEND_GPU_PHYSICAL_MODEL" : "NPEND_GPU_POINT_MODEL",
                     device_functions(c).substr(4));
}

// The program NVRTC compiles for the chain's model and the job's quantity and stepper (the
// indicators: and `vectors`): the prelude, the generated device functions, the model adapter,
// the map kernels and the one kernel, npend_map_cells, that runs them.
std::string program_text(const chain& c, const gpu::map_job& job, int vectors) {
  const std::string functions = device_functions(c);
  std::string text =
      "#define NPEND_GPU_FUNCTION __device__ inline\n"
      "#define NPEND_GPU_INF __longlong_as_double(0x7ff0000000000000LL)\n"
      "#define NPEND_GPU_NAN __longlong_as_double(0x7ff8000000000000LL)\n";
  text += gpu::embedded_source(functions);
  text += gpu::embedded_source("map_models");
  text += fmt::format("\nnamespace npend::gpu {{\n{}\n}}\n", model_adapter(c));
  text += gpu::embedded_source("map_kernels");
  text += fmt::format(
      "\nextern \"C\" __global__ void npend_map_cells(const double* starts, const int* chain_of,\n"
      "    const double* params, long long count, npend::gpu::map_job job, double* values,\n"
      "    unsigned long long* next) {{\n"
      "  npend::gpu::run_cells<npend::gpu::model, {}, {}, {}>(starts, chain_of, params, count,\n"
      "                                                       job, values, next);\n"
      "}}\n",
      job.quantity, job.stepper, vectors);
  return text;
}

using gpu::map_job;

}  // namespace

map_job gpu::make_map_job(const chain& c, const map_cell_options& o) {
  map_job job{};
  job.t_end = o.t_end;
  job.dt = o.dt;
  job.abs_tol = o.stepping.abs_tol;
  job.rel_tol = o.stepping.rel_tol;
  job.min_step = integration_options{}.min_step_ratio * o.dt;
  job.energy_tolerance = flip_energy_tolerance;
  job.steps = detail::whole_steps(o.t_end, o.dt);
  job.rest = o.t_end - static_cast<double>(job.steps) * o.dt;
  if (!(job.rest > 1e-9 * o.dt)) job.rest = 0;
  job.stepper = o.stepping.stepper == stepper_kind::dopri5 ? gpu::job_dopri5 : gpu::job_rk4;
  job.flip_link = o.flip_link;
  job.component = o.component;
  job.max_tries = 500;  // odeint's failed_step_checker, as the lanes
  const chain_parameters& p = c.parameters();
  job.energy_check = p.pivot.moves() ? gpu::energy_none
                     : p.is_damped() ? gpu::energy_falls
                                     : gpu::energy_conserved;
  switch (o.quantity) {
    case map_quantity::flip:
      job.quantity = gpu::job_flip;
      break;
    case map_quantity::state:
      job.quantity = gpu::job_state;
      break;
    case map_quantity::fli:
    case map_quantity::megno:
    case map_quantity::sali:
    case map_quantity::gali:
      job.quantity = gpu::job_indicators;
      job.indicator = o.quantity == map_quantity::fli     ? gpu::indicator_fli
                      : o.quantity == map_quantity::megno ? gpu::indicator_megno
                      : o.quantity == map_quantity::sali  ? gpu::indicator_sali
                                                          : gpu::indicator_gali;
      job.rest = 0;
      break;
    case map_quantity::lyapunov: {
      job.quantity = gpu::job_lyapunov;
      // maximal_lyapunov_exponent's steps and renormalisations, as the lanes take them.
      const lyapunov_options lo = detail::map_lyapunov_options(o);
      job.steps = static_cast<long long>(output_steps(lo.integration));
      job.chunk = std::max<long long>(1, std::llround(lo.renormalisation_interval / o.dt));
      job.lyapunov_time = static_cast<double>(job.steps) * o.dt;
      job.rest = 0;
      break;
    }
  }
  return job;
}

void gpu::append_parameters(const chain& c, std::vector<double>& block) {
  const auto& packed = c.packed_parameters();
  block.insert(block.end(), packed.begin(), packed.end());
  if (!c.is_physical()) return;
  const pivot_motion& pivot = c.parameters().pivot;
  const double kind = pivot.type == pivot_motion::kind::vertical     ? 1
                      : pivot.type == pivot_motion::kind::horizontal ? 2
                                                                     : 0;
  block.push_back(kind);
  block.push_back(kind == 0 ? 0.0 : pivot.amplitude);
  block.push_back(kind == 0 ? 0.0 : pivot.frequency);
}

namespace {

// The cells `send` (indices into starts) computed on the GPU into values.
void run_on_gpu(const chain& model_chain, std::span<const chain> chains,
                std::span<const int> chain_of, std::span<const double> starts,
                const std::vector<std::size_t>& send, const map_job& job, int vectors,
                std::vector<double>& values, run_control* control) {
  if (send.empty()) return;
  const auto m = static_cast<std::size_t>(model_chain.state_size());
  std::vector<double> params;
  for (const chain& c : chains) gpu::append_parameters(c, params);
  const gpu::cuda_module& module = gpu::cuda_module::compiled(
      device_functions(model_chain), program_text(model_chain, job, vectors));
  gpu::device_buffer params_on_gpu(params.size() * sizeof(double));
  params_on_gpu.upload(params.data(), params.size() * sizeof(double));
  gpu::device_buffer counter(sizeof(unsigned long long));
  const std::size_t per_launch = std::min(send.size(), cuda_cells_per_launch);
  gpu::device_buffer starts_on_gpu(per_launch * m * sizeof(double));
  gpu::device_buffer chains_on_gpu(per_launch * sizeof(int));
  gpu::device_buffer values_on_gpu(per_launch * sizeof(double));
  std::vector<double> batch_starts;
  std::vector<int> batch_chains;
  std::vector<double> batch_values;
  for (std::size_t first = 0; first < send.size(); first += per_launch) {
    if (stop_requested(control)) return;  // the rest stay NaN
    const std::size_t count = std::min(per_launch, send.size() - first);
    batch_starts.resize(count * m);
    batch_chains.resize(count);
    for (std::size_t k = 0; k < count; ++k) {
      const std::size_t cell = send[first + k];
      std::copy_n(starts.begin() + static_cast<std::ptrdiff_t>(cell * m), m,
                  batch_starts.begin() + static_cast<std::ptrdiff_t>(k * m));
      batch_chains[k] = chain_of.empty() ? 0 : chain_of[cell];
    }
    starts_on_gpu.upload(batch_starts.data(), batch_starts.size() * sizeof(double));
    chains_on_gpu.upload(batch_chains.data(), batch_chains.size() * sizeof(int));
    counter.zero();
    long long cells = static_cast<long long>(count);
    map_job launch_job = job;
    void* args[] = {&starts_on_gpu.address(),
                    &chains_on_gpu.address(),
                    &params_on_gpu.address(),
                    &cells,
                    &launch_job,
                    &values_on_gpu.address(),
                    &counter.address()};
    module.launch_resident("npend_map_cells", args);
    batch_values.resize(count);
    values_on_gpu.download(batch_values.data(), count * sizeof(double));
    for (std::size_t k = 0; k < count; ++k) values[send[first + k]] = batch_values[k];
  }
}

}  // namespace

void check_cuda_map(const chain& c, const map_cell_options& o) {
  o.validate(c);
  const std::string_view name = map_quantity_name(o.quantity);
  const stepper_kind stepper = o.stepping.stepper;
  if (stepper != stepper_kind::rk4 && stepper != stepper_kind::dopri5)
    throw std::invalid_argument(
        fmt::format("{}: the GPU maps integrate with rk4 or dopri5, not {} (--device cpu takes it)",
                    name, stepper_name(stepper)));
  if (c.parameters().pivot.type == pivot_motion::kind::custom)
    throw std::invalid_argument(fmt::format(
        "{}: a pivot on a custom path runs on the CPU only (its path is a function there)", name));
  if (gpu::embedded_source(device_functions(c)).empty())
    throw std::invalid_argument(fmt::format(
        "{}: this build has no GPU functions for the {}-link {} chain (built: the link counts "
        "of NPEND_LINKS)",
        name, c.links(), c.is_physical() ? "physical" : "point-mass"));
}

namespace detail {

std::vector<double> cuda_cells(std::span<const chain> chains, std::span<const int> chain_of,
                               std::span<const double> starts, const map_cell_options& options) {
  if (chains.empty()) throw std::invalid_argument("cuda_cells: no chain");
  const chain& first = chains.front();
  for (const chain& c : chains) {
    check_cuda_map(c, options);
    if (c.links() != first.links() || c.is_physical() != first.is_physical())
      throw std::invalid_argument("cuda_cells: the chains must share their model and link count");
  }
  const auto m = static_cast<std::size_t>(first.state_size());
  if (starts.size() % m != 0)
    throw std::invalid_argument(
        fmt::format("{}: the {}-link chain needs states of {} one after another, got {} numbers",
                    map_quantity_name(options.quantity), first.links(), m, starts.size()));
  const std::size_t count = starts.size() / m;
  if (!chain_of.empty() && chain_of.size() != count)
    throw std::invalid_argument("cuda_cells: one chain index per start");
  for (const int k : chain_of)
    if (k < 0 || static_cast<std::size_t>(k) >= chains.size())
      throw std::invalid_argument("cuda_cells: a chain index out of range");
  std::vector<double> values(count, std::numeric_limits<double>::quiet_NaN());
  const std::string prefix = fmt::format("{}: ", map_quantity_name(options.quantity));
  for (std::size_t i = 0; i < count; ++i)
    detail::require_finite_start(starts.subspan(i * m, m), prefix);
  // A flip the energy rules out is NaN without integrating: the CPU's own check, on every
  // core (for a large map it is a fair share of the GPU's time).
  std::vector<unsigned char> ruled_out(count, 0);
  if (options.quantity == map_quantity::flip) {
    const auto cells = static_cast<long long>(count);
#pragma omp parallel for schedule(static)
    for (long long i = 0; i < cells; ++i) {
      const auto k = static_cast<std::size_t>(i);
      const chain& c = chains[chain_of.empty() ? 0 : static_cast<std::size_t>(chain_of[k])];
      ruled_out[k] = energy_forbids_flip(c, starts.subspan(k * m, m), options.flip_link);
    }
  }
  std::vector<std::size_t> send;
  for (std::size_t i = 0; i < count; ++i)
    if (ruled_out[i] == 0) send.push_back(i);
  require_cuda();
  run_on_gpu(first, chains, chain_of, starts, send, gpu::make_map_job(first, options),
             static_cast<int>(detail::indicator_vectors(first, options)), values, options.control);
  return values;
}

std::string cuda_program_ptx(const chain& c, const map_cell_options& options) {
  check_cuda_map(c, options);
  return gpu::compile_ptx(device_functions(c),
                          program_text(c, gpu::make_map_job(c, options),
                                       static_cast<int>(detail::indicator_vectors(c, options))))
      .value_or(std::string());
}

}  // namespace detail

std::vector<double> cuda_map_cells(const chain& c, std::span<const double> starts,
                                   const map_cell_options& options) {
  return detail::cuda_cells(std::span<const chain>(&c, 1), {}, starts, options);
}

}  // namespace npend
