#include "emit_gpu.hpp"

#include <fmt/format.h>

#include <npend/chain_kernels.hpp>
#include <sstream>
#include <stdexcept>

#include "emit_cpp.hpp"

namespace npend::gen {

namespace {

// The functions a GPU map integrates with: the equations, the energy it checks and the
// Jacobian of the tangent dynamics.
constexpr const char* device_functions[] = {"rhs", "hamiltonian", "jacobian"};

// `text` as `// ` comment lines of at most `width` characters, broken between words.
std::string comment(const std::string& text, std::size_t width = 92) {
  std::istringstream words(text);
  std::string out, line, word;
  while (words >> word) {
    if (!line.empty() && line.size() + 1 + word.size() > width) {
      out += line + "\n";
      line.clear();
    }
    line += (line.empty() ? "// " : " ") + word;
  }
  if (!line.empty()) out += line + "\n";
  return out;
}

std::string model_description(int n, link_kind kind) {
  if (kind == link_kind::physical)
    return fmt::format(
        "the physical planar {}-link pendulum (rigid links, joint springs, damping and "
        "torques, a moving pivot)",
        n);
  return fmt::format("the planar {}-link pendulum (point masses on massless rods)", n);
}

}  // namespace

bool has_gpu_functions(link_kind kind) {
  return kind == link_kind::point_mass || kind == link_kind::physical;
}

std::string gpu_file_name(int links, link_kind kind) {
  return fmt::format("gpu_{}.cuh", chain_stem(links, kind));
}

std::string emit_gpu(int n, const std::vector<emitted_function>& functions,
                     const std::string& options, link_kind kind) {
  if (!has_gpu_functions(kind))
    throw std::invalid_argument(
        fmt::format("npend-gen writes no device functions for the {} model", link_kind_name(kind)));
  const std::string stem = chain_stem(n, kind);
  std::string out = generated_banner(chain_command(n, options, kind));
  out += comment(fmt::format(
      "The device functions of {} for npend's GPU maps: rhs, hamiltonian and jacobian of "
      "{}.hpp, the same statements, as plain functions of doubles that CUDA device code and "
      "host C++ both compile. The includer defines NPEND_GPU_FUNCTION (`__device__ inline` for "
      "CUDA, `inline` on the host) and makes sin and cos visible (CUDA's device maths; <cmath> "
      "on the host). Layouts as {}.hpp.",
      model_description(n, kind), stem, stem));
  out += fmt::format("\nnamespace npend::gpu::{} {{\n\n", stem);
  // `inline`, as in the .hpp: NVRTC warns of every unused constant with internal linkage.
  out += fmt::format("inline constexpr int links = {};\n", n);
  out += fmt::format("inline constexpr int state_size = {};\n", chain_layout::state_size(n));
  if (kind == link_kind::physical) {
    out += fmt::format("inline constexpr int param_size = {};\n",
                       chain_layout::physical_param_size(n));
    out += fmt::format("inline constexpr int input_size = {};\n", chain_layout::input_size(n));
  } else {
    out += fmt::format("inline constexpr int param_size = {};\n", chain_layout::param_size(n));
  }
  for (const char* name : device_functions) {
    const emitted_function* found = nullptr;
    for (const auto& f : functions)
      if (f.name == name) found = &f;
    if (found == nullptr) throw std::logic_error(fmt::format("emit_gpu: no function {}", name));
    // Unqualified sin and cos: CUDA's device maths, or <cmath>'s on the host.
    out += "\nNPEND_GPU_FUNCTION " + function_definition(n, *found, kind, "");
  }
  out += fmt::format("\n}}  // namespace npend::gpu::{}\n", stem);
  return out;
}

}  // namespace npend::gen
