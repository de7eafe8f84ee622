// Where a map's cells are computed: on the CPU's cores (the batch lanes, chaos_map.hpp) or on
// a GPU through CUDA. The GPU path compiles, at its first use in a process, the generated
// device functions of the chain's model and link count (generated/gpu_<model>_<n>.cuh) with
// the map kernels into a program for the GPU it finds (NVRTC, CUDA's run-time compiler), and
// runs one thread a cell, each thread taking the next cell as soon as its last is done. It
// takes the same steps as the CPU (odeint's rk4 and dopri5, the flip located alike), so
// that the values agree with the CPU's to round-off (the GPU's sine and cosine may differ
// from the CPU's in the last bit, which a chaotic cell amplifies). npend needs neither the
// CUDA toolkit to build nor a GPU to run; the driver (libcuda) and NVRTC (libnvrtc) are
// loaded when a GPU map is asked for.
#pragma once

#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "npend/analysis/chaos/chaos_map.hpp"
#include "npend/chain.hpp"

namespace npend {

enum class map_device { cpu, cuda };

/// "cpu" or "cuda".
std::string_view map_device_name(map_device device);
/// The device called `name`; throws std::invalid_argument naming the valid names.
map_device parse_map_device(std::string_view name);

/// What this process finds of CUDA.
struct cuda_status {
  bool usable = false;
  std::string device;   ///< the GPU: "NVIDIA H200 (compute capability 9.0, 132 multiprocessors)"
  std::string driver;   ///< the driver's CUDA version
  std::string nvrtc;    ///< NVRTC's version
  std::string problem;  ///< why CUDA is not usable (empty when it is)
};

/// Looks for the CUDA driver, NVRTC and a GPU (once per process: the GPU of the MPI rank's
/// local rank, or $NPEND_CUDA_DEVICE, among several). Never throws.
cuda_status find_cuda();

/// The seconds this process has spent in GPU map launches (from the launch to the kernel's
/// end, copies excluded): what the GPU itself took, for the maps' summaries and benchmarks.
double cuda_kernel_seconds();

/// Throws std::runtime_error "CUDA is not usable here: <why>" where find_cuda finds none.
void require_cuda();

/// Throws std::invalid_argument naming what the GPU maps do not take for chain `c`: the
/// Gauss–Legendre steppers, a pivot on a custom path, a model without generated device
/// functions in this build; and what no map takes, as map_cell_options::validate (a cart, the
/// chaos indicators with dopri5, ...). Point-mass chains of link counts without unrolled
/// kernels run on the loop kernels' device functions.
void check_cuda_map(const chain& c, const map_cell_options& options);

/// map_cells on the GPU: the value of each of count = starts.size() / 2n start states, the
/// same quantities as map_cells computes (NaN where the energy rules a flip out — checked
/// on the CPU, without integrating — or the integration fails). Runs in launches of at most
/// cuda_cells_per_launch cells, polling options.control between them (once it asks to
/// stop, the cells not computed are NaN). Throws std::invalid_argument as check_cuda_map
/// and for a size that is not a multiple of 2n, std::runtime_error where CUDA is not usable
/// or the GPU fails.
std::vector<double> cuda_map_cells(const chain& c, std::span<const double> starts,
                                   const map_cell_options& options);

/// The most cells one GPU launch computes: enough to fill a large GPU many times over,
/// few enough that the GPU's memory holds them (a few hundred bytes a cell) and that a stop
/// request is heard within a fraction of a large map.
inline constexpr std::size_t cuda_cells_per_launch = std::size_t{1} << 20;

namespace detail {

/// The GPU's values of cells on several chains (the maps' parameter axes): cell k starts at
/// starts[k·2n …] on chains[chain_of[k]]; every chain has the same model and link count.
/// As cuda_map_cells otherwise.
std::vector<double> cuda_cells(std::span<const chain> chains, std::span<const int> chain_of,
                               std::span<const double> starts, const map_cell_options& options);

/// The PTX NVRTC makes of the GPU program of a map of `options` on chain `c`, or an empty
/// string where NVRTC is not found: the check that the kernels compile, also on machines
/// without a GPU. Throws std::runtime_error with NVRTC's log where they do not compile.
std::string cuda_program_ptx(const chain& c, const map_cell_options& options);

}  // namespace detail

}  // namespace npend
