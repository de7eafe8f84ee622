#include "cuda_driver.hpp"

#include <dlfcn.h>
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <map>
#include <mutex>
#include <optional>
#include <stdexcept>

namespace npend::gpu {

namespace {

// The few entry points of the CUDA driver API and NVRTC that npend uses, declared as their
// stable C ABI (cuda.h and nvrtc.h are not needed to build npend). The _v2 names are the
// ones cuda.h maps the unversioned names to since CUDA 4.
using CUresult = int;
using CUdevice = int;
using CUdeviceptr = unsigned long long;
using CUcontext = void*;
using CUmodule = void*;
using CUfunction = void*;
using nvrtcResult = int;
using nvrtcProgram = void*;

constexpr int attribute_multiprocessors = 16;  // CU_DEVICE_ATTRIBUTE_MULTIPROCESSOR_COUNT
constexpr int attribute_major = 75;            // CU_DEVICE_ATTRIBUTE_COMPUTE_CAPABILITY_MAJOR
constexpr int attribute_minor = 76;            // CU_DEVICE_ATTRIBUTE_COMPUTE_CAPABILITY_MINOR

struct driver_api {
  CUresult (*cuInit)(unsigned);
  CUresult (*cuDriverGetVersion)(int*);
  CUresult (*cuDeviceGetCount)(int*);
  CUresult (*cuDeviceGet)(CUdevice*, int);
  CUresult (*cuDeviceGetName)(char*, int, CUdevice);
  CUresult (*cuDeviceGetAttribute)(int*, int, CUdevice);
  CUresult (*cuDevicePrimaryCtxRetain)(CUcontext*, CUdevice);
  CUresult (*cuCtxSetCurrent)(CUcontext);
  CUresult (*cuModuleLoadDataEx)(CUmodule*, const void*, unsigned, int*, void**);
  CUresult (*cuModuleUnload)(CUmodule);
  CUresult (*cuModuleGetFunction)(CUfunction*, CUmodule, const char*);
  CUresult (*cuMemAlloc)(CUdeviceptr*, std::size_t);
  CUresult (*cuMemFree)(CUdeviceptr);
  CUresult (*cuMemcpyHtoD)(CUdeviceptr, const void*, std::size_t);
  CUresult (*cuMemcpyDtoH)(void*, CUdeviceptr, std::size_t);
  CUresult (*cuMemsetD8)(CUdeviceptr, unsigned char, std::size_t);
  CUresult (*cuLaunchKernel)(CUfunction, unsigned, unsigned, unsigned, unsigned, unsigned, unsigned,
                             unsigned, void*, void**, void**);
  CUresult (*cuCtxSynchronize)();
  CUresult (*cuOccupancyMaxActiveBlocksPerMultiprocessor)(int*, CUfunction, int, std::size_t);
  CUresult (*cuGetErrorString)(CUresult, const char**);
};

struct nvrtc_api {
  nvrtcResult (*nvrtcVersion)(int*, int*);
  nvrtcResult (*nvrtcCreateProgram)(nvrtcProgram*, const char*, const char*, int,
                                    const char* const*, const char* const*);
  nvrtcResult (*nvrtcCompileProgram)(nvrtcProgram, int, const char* const*);
  nvrtcResult (*nvrtcGetPTXSize)(nvrtcProgram, std::size_t*);
  nvrtcResult (*nvrtcGetPTX)(nvrtcProgram, char*);
  nvrtcResult (*nvrtcGetProgramLogSize)(nvrtcProgram, std::size_t*);
  nvrtcResult (*nvrtcGetProgramLog)(nvrtcProgram, char*);
  nvrtcResult (*nvrtcDestroyProgram)(nvrtcProgram*);
  const char* (*nvrtcGetErrorString)(nvrtcResult);
  nvrtcResult (*nvrtcGetNumSupportedArchs)(int*);
  nvrtcResult (*nvrtcGetSupportedArchs)(int*);
};

// The first library of `names` that loads (dlopen's search: LD_LIBRARY_PATH, the cache).
void* open_first(const std::vector<std::string>& names, std::string& tried) {
  for (const auto& name : names) {
    if (void* handle = dlopen(name.c_str(), RTLD_NOW | RTLD_LOCAL)) return handle;
    tried += (tried.empty() ? "" : ", ") + name;
  }
  return nullptr;
}

template <class F>
bool bind(void* library, const char* symbol, F& function) {
  function = reinterpret_cast<F>(dlsym(library, symbol));
  return function != nullptr;
}

// Where NVRTC may be: $NPEND_NVRTC, the loader's path, then the CUDA toolkit's usual homes.
std::vector<std::string> nvrtc_candidates() {
  std::vector<std::string> names;
  if (const char* own = std::getenv("NPEND_NVRTC")) names.emplace_back(own);
  const char* versions[] = {"libnvrtc.so", "libnvrtc.so.13", "libnvrtc.so.12", "libnvrtc.so.11.2"};
  for (const char* v : versions) names.emplace_back(v);
  std::vector<std::string> homes;
  for (const char* variable : {"CUDA_HOME", "CUDA_PATH"})
    if (const char* home = std::getenv(variable)) homes.emplace_back(home);
  homes.emplace_back("/usr/local/cuda");
  for (const auto& home : homes)
    for (const char* lib : {"/lib64/", "/lib/"})
      for (const char* v : versions) names.push_back(home + lib + v);
  return names;
}

struct cuda_state {
  cuda_probe found;
  driver_api cu{};
  nvrtc_api rtc{};
  CUdevice device = 0;
  int multiprocessors = 0;
  int arch = 0;  // the compute architecture NVRTC compiles for, e.g. 90
  double kernel_seconds = 0;
  bool nvrtc_loaded = false;
  std::mutex lock;
  std::map<std::string, std::unique_ptr<cuda_module>> modules;
};

std::string cuda_message(const driver_api& cu, CUresult r) {
  const char* text = nullptr;
  if (cu.cuGetErrorString != nullptr) cu.cuGetErrorString(r, &text);
  return text != nullptr ? fmt::format("{} (CUDA error {})", text, r)
                         : fmt::format("CUDA error {}", r);
}

// The GPU this process uses: one per MPI rank on a node (the launcher's local rank), else
// the first; $NPEND_CUDA_DEVICE picks one.
int chosen_ordinal(int count) {
  for (const char* variable :
       {"NPEND_CUDA_DEVICE", "OMPI_COMM_WORLD_LOCAL_RANK", "MPI_LOCALRANKID", "SLURM_LOCALID"})
    if (const char* value = std::getenv(variable)) {
      char* end = nullptr;
      const long k = std::strtol(value, &end, 10);
      if (end != value && k >= 0) return static_cast<int>(k % count);
    }
  return 0;
}

bool load_driver(cuda_state& s) {
  std::string tried;
  void* library = open_first({"libcuda.so.1", "libcuda.so"}, tried);
  if (library == nullptr) {
    s.found.problem = fmt::format("no CUDA driver: none of {} loads ({})", tried, dlerror());
    return false;
  }
  driver_api& cu = s.cu;
  const bool bound = bind(library, "cuInit", cu.cuInit) &&
                     bind(library, "cuDriverGetVersion", cu.cuDriverGetVersion) &&
                     bind(library, "cuDeviceGetCount", cu.cuDeviceGetCount) &&
                     bind(library, "cuDeviceGet", cu.cuDeviceGet) &&
                     bind(library, "cuDeviceGetName", cu.cuDeviceGetName) &&
                     bind(library, "cuDeviceGetAttribute", cu.cuDeviceGetAttribute) &&
                     bind(library, "cuDevicePrimaryCtxRetain", cu.cuDevicePrimaryCtxRetain) &&
                     bind(library, "cuCtxSetCurrent", cu.cuCtxSetCurrent) &&
                     bind(library, "cuModuleLoadDataEx", cu.cuModuleLoadDataEx) &&
                     bind(library, "cuModuleUnload", cu.cuModuleUnload) &&
                     bind(library, "cuModuleGetFunction", cu.cuModuleGetFunction) &&
                     bind(library, "cuMemAlloc_v2", cu.cuMemAlloc) &&
                     bind(library, "cuMemFree_v2", cu.cuMemFree) &&
                     bind(library, "cuMemcpyHtoD_v2", cu.cuMemcpyHtoD) &&
                     bind(library, "cuMemcpyDtoH_v2", cu.cuMemcpyDtoH) &&
                     bind(library, "cuMemsetD8_v2", cu.cuMemsetD8) &&
                     bind(library, "cuLaunchKernel", cu.cuLaunchKernel) &&
                     bind(library, "cuCtxSynchronize", cu.cuCtxSynchronize) &&
                     bind(library, "cuOccupancyMaxActiveBlocksPerMultiprocessor",
                          cu.cuOccupancyMaxActiveBlocksPerMultiprocessor) &&
                     bind(library, "cuGetErrorString", cu.cuGetErrorString);
  if (!bound) {
    s.found.problem = "the CUDA driver (libcuda.so.1) lacks functions npend needs: too old";
    return false;
  }
  if (const CUresult r = cu.cuInit(0); r != 0) {
    s.found.problem = fmt::format("the CUDA driver does not start: {}", cuda_message(cu, r));
    return false;
  }
  int version = 0, count = 0;
  cu.cuDriverGetVersion(&version);
  s.found.driver = fmt::format("{}.{}", version / 1000, version % 1000 / 10);
  if (const CUresult r = cu.cuDeviceGetCount(&count); r != 0 || count < 1) {
    s.found.problem = "the CUDA driver finds no GPU";
    return false;
  }
  s.found.ordinal = chosen_ordinal(count);
  cu.cuDeviceGet(&s.device, s.found.ordinal);
  char name[256] = {};
  cu.cuDeviceGetName(name, sizeof name, s.device);
  int major = 0, minor = 0;
  cu.cuDeviceGetAttribute(&major, attribute_major, s.device);
  cu.cuDeviceGetAttribute(&minor, attribute_minor, s.device);
  cu.cuDeviceGetAttribute(&s.multiprocessors, attribute_multiprocessors, s.device);
  s.arch = 10 * major + minor;
  s.found.device = fmt::format("{} (compute capability {}.{}, {} multiprocessors)", name, major,
                               minor, s.multiprocessors);
  CUcontext context = nullptr;
  if (const CUresult r = cu.cuDevicePrimaryCtxRetain(&context, s.device); r != 0) {
    s.found.problem = fmt::format("no CUDA context on {}: {}", name, cuda_message(cu, r));
    return false;
  }
  cu.cuCtxSetCurrent(context);
  return true;
}

bool load_nvrtc(cuda_state& s) {
  std::string tried;
  void* library = open_first(nvrtc_candidates(), tried);
  if (library == nullptr) {
    s.found.problem = fmt::format(
        "no NVRTC (CUDA's run-time compiler, part of the CUDA toolkit): none of {} loads; "
        "set NPEND_NVRTC to the path of libnvrtc.so",
        tried);
    return false;
  }
  nvrtc_api& rtc = s.rtc;
  const bool bound = bind(library, "nvrtcVersion", rtc.nvrtcVersion) &&
                     bind(library, "nvrtcCreateProgram", rtc.nvrtcCreateProgram) &&
                     bind(library, "nvrtcCompileProgram", rtc.nvrtcCompileProgram) &&
                     bind(library, "nvrtcGetPTXSize", rtc.nvrtcGetPTXSize) &&
                     bind(library, "nvrtcGetPTX", rtc.nvrtcGetPTX) &&
                     bind(library, "nvrtcGetProgramLogSize", rtc.nvrtcGetProgramLogSize) &&
                     bind(library, "nvrtcGetProgramLog", rtc.nvrtcGetProgramLog) &&
                     bind(library, "nvrtcDestroyProgram", rtc.nvrtcDestroyProgram);
  if (!bound) {
    s.found.problem = "NVRTC (libnvrtc) lacks functions npend needs";
    return false;
  }
  bind(library, "nvrtcGetErrorString", rtc.nvrtcGetErrorString);
  int major = 0, minor = 0;
  rtc.nvrtcVersion(&major, &minor);
  s.found.nvrtc = fmt::format("{}.{}", major, minor);
  s.nvrtc_loaded = true;
  // A GPU newer than NVRTC knows gets the newest architecture NVRTC has, as PTX that the
  // driver compiles on.
  if (bind(library, "nvrtcGetNumSupportedArchs", rtc.nvrtcGetNumSupportedArchs) &&
      bind(library, "nvrtcGetSupportedArchs", rtc.nvrtcGetSupportedArchs)) {
    int count = 0;
    rtc.nvrtcGetNumSupportedArchs(&count);
    std::vector<int> archs(static_cast<std::size_t>(count));
    if (count > 0) rtc.nvrtcGetSupportedArchs(archs.data());
    if (s.arch == 0) {  // no GPU: the compile check (compile_ptx) takes the oldest
      if (!archs.empty()) s.arch = archs.front();
      return true;
    }
    int best = 0;
    for (const int a : archs)
      if (a <= s.arch && a > best) best = a;
    if (best == 0 && !archs.empty()) {
      s.found.problem = fmt::format("NVRTC {} cannot compile for compute capability {}.{}",
                                    s.found.nvrtc, s.arch / 10, s.arch % 10);
      return false;
    }
    if (best != 0) s.arch = best;
  }
  return true;
}

cuda_state& state() {
  static cuda_state s;
  static std::once_flag once;
  std::call_once(once, [] {
    // NVRTC is loaded also without a driver: compile_ptx checks the kernels compile.
    const bool driver = load_driver(s);
    const std::string driver_problem = s.found.problem;
    const bool rtc = load_nvrtc(s);
    s.found.usable = driver && rtc;
    if (!driver) s.found.problem = driver_problem;
  });
  return s;
}

cuda_state& usable_state() {
  cuda_state& s = state();
  if (!s.found.usable) throw std::runtime_error("CUDA is not usable here: " + s.found.problem);
  return s;
}

void check(CUresult r, const char* what) {
  if (r != 0) throw std::runtime_error(fmt::format("{}: {}", what, cuda_message(state().cu, r)));
}

std::string nvrtc_message(const nvrtc_api& rtc, nvrtcResult r) {
  if (rtc.nvrtcGetErrorString == nullptr) return fmt::format("NVRTC error {}", r);
  return rtc.nvrtcGetErrorString(r);
}

// PTX for `source`, compiled for the chosen architecture.
std::string ptx_of(cuda_state& s, const std::string& name, const std::string& source) {
  const nvrtc_api& rtc = s.rtc;
  nvrtcProgram program = nullptr;
  if (const nvrtcResult r =
          rtc.nvrtcCreateProgram(&program, source.c_str(), name.c_str(), 0, nullptr, nullptr);
      r != 0)
    throw std::runtime_error(
        fmt::format("NVRTC could not take {}: {}", name, nvrtc_message(rtc, r)));
  const std::string arch = fmt::format("--gpu-architecture=compute_{}", s.arch);
  // CUDA's default contraction of a·b + c into one fused multiply-add: rounding each
  // operation as the CPU does would cost time and bring the GPU's maps hardly closer to the
  // CPU's, whose sines and cosines differ anyway (docs/benchmarks-gpu.md measures both).
  const char* options[] = {arch.c_str(), "--std=c++17", "-default-device", "--fmad=true"};
  const nvrtcResult compiled = rtc.nvrtcCompileProgram(program, 4, options);
  std::size_t log_size = 0;
  rtc.nvrtcGetProgramLogSize(program, &log_size);
  std::string log(log_size, '\0');
  if (log_size > 0) rtc.nvrtcGetProgramLog(program, log.data());
  if (compiled != 0) {
    rtc.nvrtcDestroyProgram(&program);
    throw std::runtime_error(fmt::format("NVRTC could not compile {} ({}):\n{}", name,
                                         nvrtc_message(rtc, compiled), log));
  }
  std::size_t size = 0;
  rtc.nvrtcGetPTXSize(program, &size);
  std::string ptx(size, '\0');
  rtc.nvrtcGetPTX(program, ptx.data());
  rtc.nvrtcDestroyProgram(&program);
  return ptx;
}

}  // namespace

const cuda_probe& probe() noexcept { return state().found; }

std::optional<std::string> compile_ptx(const std::string& name, const std::string& source) {
  cuda_state& s = state();
  if (!s.nvrtc_loaded) return std::nullopt;
  return ptx_of(s, name, source);
}

const cuda_module& cuda_module::compiled(const std::string& name, const std::string& source) {
  cuda_state& s = usable_state();
  const std::lock_guard guard(s.lock);
  auto& slot = s.modules[source];
  if (slot) return *slot;
  const std::string ptx = ptx_of(s, name, source);
  std::unique_ptr<cuda_module> module(new cuda_module);
  check(s.cu.cuModuleLoadDataEx(&module->m_module, ptx.c_str(), 0, nullptr, nullptr),
        "loading the compiled map kernels onto the GPU");
  slot = std::move(module);
  return *slot;
}

void cuda_module::launch_resident(const char* function, void** args) const {
  cuda_state& s = usable_state();
  const std::lock_guard guard(s.lock);
  CUfunction kernel = nullptr;
  check(s.cu.cuModuleGetFunction(&kernel, m_module, function), function);
  constexpr int threads = 128;
  int per_multiprocessor = 0;
  check(s.cu.cuOccupancyMaxActiveBlocksPerMultiprocessor(&per_multiprocessor, kernel, threads, 0),
        "the GPU's occupancy");
  const auto blocks =
      static_cast<unsigned>(std::max(1, per_multiprocessor) * std::max(1, s.multiprocessors));
  const auto started = std::chrono::steady_clock::now();
  check(s.cu.cuLaunchKernel(kernel, blocks, 1, 1, threads, 1, 1, 0, nullptr, args, nullptr),
        "launching the map kernel");
  check(s.cu.cuCtxSynchronize(), "running the map kernel");
  s.kernel_seconds +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
}

double seconds_in_kernels() noexcept {
  cuda_state& s = state();
  const std::lock_guard guard(s.lock);
  return s.kernel_seconds;
}

cuda_module::~cuda_module() {
  if (m_module != nullptr) state().cu.cuModuleUnload(m_module);
}

device_buffer::device_buffer(std::size_t bytes) : m_bytes(bytes) {
  cuda_state& s = usable_state();
  check(s.cu.cuMemAlloc(&m_address, bytes == 0 ? 1 : bytes),
        fmt::format("allocating {} MB on the GPU", bytes >> 20).c_str());
}

device_buffer::~device_buffer() {
  if (m_address != 0) state().cu.cuMemFree(m_address);
}

void device_buffer::upload(const void* data, std::size_t bytes) {
  if (bytes > 0) check(state().cu.cuMemcpyHtoD(m_address, data, bytes), "copying to the GPU");
}

void device_buffer::download(void* data, std::size_t bytes) const {
  if (bytes > 0) check(state().cu.cuMemcpyDtoH(data, m_address, bytes), "copying from the GPU");
}

void device_buffer::zero() { check(state().cu.cuMemsetD8(m_address, 0, m_bytes), "clearing"); }

}  // namespace npend::gpu
