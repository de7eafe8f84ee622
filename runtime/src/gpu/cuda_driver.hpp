// The CUDA driver and NVRTC, loaded at run time (dlopen) rather than linked: one npend
// binary runs on machines with and without a GPU, and builds on machines without the CUDA
// toolkit. The GPU maps compile their kernels with NVRTC for the GPU they find, from the
// generated device functions and runtime/src/gpu/map_kernels.cuh.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace npend::gpu {

/// What the process found of CUDA: the driver, NVRTC and the GPU it uses.
struct cuda_probe {
  bool usable = false;
  std::string problem;  ///< why not usable
  std::string device;   ///< "NVIDIA H200 (compute capability 9.0, 132 multiprocessors)"
  std::string driver;   ///< the driver's CUDA version, "13.0"
  std::string nvrtc;    ///< NVRTC's version, "13.0"
  int ordinal = 0;      ///< the GPU's index among the machine's
};

/// Loads the driver and NVRTC and picks the GPU (once per process; later calls return the
/// first answer). Never throws.
const cuda_probe& probe() noexcept;

/// PTX for `source` from NVRTC for the GPU of probe() (without one, for the oldest
/// architecture NVRTC knows), or nullopt where NVRTC is not found: the check that the
/// kernels compile on a machine with the CUDA toolkit but no GPU. Throws std::runtime_error
/// with NVRTC's log where the source does not compile.
std::optional<std::string> compile_ptx(const std::string& name, const std::string& source);

/// The seconds spent in launch_resident so far (every module, every thread).
double seconds_in_kernels() noexcept;

/// A compiled kernel program on the GPU of probe(); one per source text, kept for the
/// process's lifetime.
class cuda_module {
 public:
  /// Compiles `source` (named `name` in NVRTC's messages) for the GPU and loads it. Throws
  /// std::runtime_error with NVRTC's log where it does not compile, and where CUDA is not
  /// usable (probe().problem).
  static const cuda_module& compiled(const std::string& name, const std::string& source);

  /// Runs kernel `function` on a grid that fills the GPU (blocks × threads that stay resident
  /// together, the kernel looping over its work itself) with the kernel arguments `args`
  /// (pointers to each argument's value, as cuLaunchKernel takes them), and waits for it.
  /// Throws std::runtime_error naming the CUDA error.
  void launch_resident(const char* function, void** args) const;

  cuda_module(const cuda_module&) = delete;
  cuda_module& operator=(const cuda_module&) = delete;
  ~cuda_module();

 private:
  cuda_module() = default;
  void* m_module = nullptr;
};

/// Memory on the GPU, freed with the object.
class device_buffer {
 public:
  /// Throws std::runtime_error where the GPU has not `bytes` free.
  explicit device_buffer(std::size_t bytes);
  ~device_buffer();
  device_buffer(const device_buffer&) = delete;
  device_buffer& operator=(const device_buffer&) = delete;

  void upload(const void* data, std::size_t bytes);
  void download(void* data, std::size_t bytes) const;
  void zero();
  /// The address on the GPU (a CUdeviceptr), for a kernel's arguments.
  unsigned long long& address() { return m_address; }

 private:
  unsigned long long m_address = 0;
  std::size_t m_bytes = 0;
};

}  // namespace npend::gpu
