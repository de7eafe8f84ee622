// The GPU maps' device functions: rhs, hamiltonian and jacobian exactly as the chain's C++
// source defines them, with unqualified sin and cos, in a text NVRTC compiles (no includes,
// no pragmas), for the point-mass and the physical chain only.
#include <doctest/doctest.h>

#include <memory>
#include <stdexcept>
#include <string>

#include "emit_cpp.hpp"
#include "emit_gpu.hpp"
#include "loop_kernels.hpp"

namespace emit_gpu_test {

using namespace npend::gen;

namespace {

// A function `name` of the state: [sin φ_1 · m_1 + cos φ_2, p_1 / 3] (or their sum as a
// scalar), plus the first torque where `inputs` is set.
emitted_function sample(const std::string& name, bool scalar, bool inputs = false) {
  emitted_function f;
  f.name = name;
  f.layout = argument_layout::state;
  f.returns_scalar = scalar;
  f.output_name = "out";
  f.takes_inputs = inputs;
  f.graph = std::make_unique<expr_graph>();
  expr_graph& g = *f.graph;
  sx a = sin(g.input(input_kind::phi, 0)) * g.input(input_kind::mass, 0) +
         cos(g.input(input_kind::phi, 1));
  if (inputs) a = a + g.input(input_kind::torque, 0);
  const sx b = g.input(input_kind::p, 0) / g.constant(3);
  f.outputs = scalar ? std::vector<sx>{a + b} : std::vector<sx>{a, b};
  return f;
}

std::vector<emitted_function> samples(bool inputs = false) {
  std::vector<emitted_function> functions;
  functions.push_back(sample("rhs", false, inputs));
  functions.push_back(sample("velocities", false));  // not a device function
  functions.push_back(sample("jacobian", false, inputs));
  functions.push_back(sample("hamiltonian", true, inputs));
  return functions;
}

// The definition of `name` in a C++ source: from its signature's return type to its `}`.
std::string definition(const std::string& source, const std::string& name) {
  const std::size_t open = source.find(" " + name + "(");
  REQUIRE(open != std::string::npos);
  const std::size_t start = source.rfind('\n', open) + 1;
  const std::size_t end = source.find("\n}\n", open);
  REQUIRE(end != std::string::npos);
  return source.substr(start, end + 3 - start);
}

std::string without_std(std::string text) {
  for (auto at = text.find("std::"); at != std::string::npos; at = text.find("std::"))
    text.erase(at, 5);
  return text;
}

}  // namespace

TEST_CASE("emit_gpu: the source's rhs, hamiltonian and jacobian, with unqualified sin and cos") {
  const std::vector<emitted_function> functions = samples();
  const chain_sources cpp = emit_chain(2, functions, "x");
  const std::string gpu = emit_gpu(2, functions, "", link_kind::point_mass);
  CHECK(gpu.substr(0, gpu.find('\n')) == cpp.source.substr(0, cpp.source.find('\n')));
  for (const char* name : {"rhs", "hamiltonian", "jacobian"}) {
    INFO(name);
    const std::string expected = without_std(definition(cpp.source, name));
    CHECK(expected.find("sin(x[0])") != std::string::npos);
    CHECK(gpu.find("\nNPEND_GPU_FUNCTION " + expected) != std::string::npos);
  }
  // In the order rhs, hamiltonian, jacobian, and nothing else from the source.
  CHECK(gpu.find(" rhs(") < gpu.find(" hamiltonian("));
  CHECK(gpu.find(" hamiltonian(") < gpu.find(" jacobian("));
  CHECK(gpu.find("velocities") == std::string::npos);
  // NVRTC has no standard headers, and the text is one of several concatenated ones.
  CHECK(gpu.find("std::") == std::string::npos);
  CHECK(gpu.find("#include") == std::string::npos);
  CHECK(gpu.find("#pragma") == std::string::npos);
  CHECK(gpu.find("namespace npend::gpu::chain_2 {\n") != std::string::npos);
  CHECK(gpu.find("inline constexpr int state_size = 4;\ninline constexpr int param_size = 5;\n") !=
        std::string::npos);
  CHECK(gpu.find("input_size") == std::string::npos);
  CHECK(gpu_file_name(2, link_kind::point_mass) == "gpu_chain_2.cuh");
}

TEST_CASE("emit_gpu: the physical chain's functions take its inputs after params") {
  const std::vector<emitted_function> functions = samples(true);
  const std::string gpu = emit_gpu(3, functions, "--solver ldlt", link_kind::physical);
  CHECK(gpu.find("`npend-gen --links 3 --model physical --solver ldlt`") != std::string::npos);
  CHECK(gpu.find("NPEND_GPU_FUNCTION void rhs(const double* x, const double* params, const "
                 "double* inputs, double* out) noexcept {\n") != std::string::npos);
  CHECK(gpu.find("inputs[2]") != std::string::npos);  // u_1, after the pivot's a_x, a_y
  // [m, l, g, c, J, k, theta0, b] of 3 links; inputs [a_x, a_y, u_1..u_3].
  CHECK(gpu.find("inline constexpr int param_size = 22;\ninline constexpr int input_size = 5;\n") !=
        std::string::npos);
  CHECK(gpu_file_name(3, link_kind::physical) == "gpu_physical_3.cuh");
}

TEST_CASE("emit_gpu: refuses the cart and a missing function, the same bytes every time") {
  CHECK_FALSE(has_gpu_functions(link_kind::cart));
  CHECK_THROWS_AS(emit_gpu(2, samples(true), "", link_kind::cart), std::invalid_argument);
  std::vector<emitted_function> functions = samples();
  functions.pop_back();  // no hamiltonian
  CHECK_THROWS_AS(emit_gpu(2, functions, "", link_kind::point_mass), std::logic_error);
  CHECK(emit_gpu(2, samples(), "", link_kind::point_mass) ==
        emit_gpu(2, samples(), "", link_kind::point_mass));
}

TEST_CASE("emit_gpu_loop_kernels: chain_loop.cpp's passes and functions, NVRTC-ready text") {
  const std::string gpu = emit_gpu_loop_kernels();
  const std::string cpp = emit_loop_kernels().source;
  CHECK(gpu.substr(0, gpu.find('\n')) == cpp.substr(0, cpp.find('\n')));
  // The passes and the three functions are the host's definitions, statement for statement.
  for (const char* name :
       {"eliminate_from_tip", "evaluate", "tangent", "rhs", "jacobian_vector", "hamiltonian"}) {
    INFO(name);
    CHECK(gpu.find("\nNPEND_GPU_FUNCTION " + definition(cpp, name)) != std::string::npos);
  }
  CHECK(gpu.find(" rhs(") < gpu.find(" jacobian_vector("));
  CHECK(gpu.find(" jacobian_vector(") < gpu.find(" hamiltonian("));
  CHECK(gpu.find(" jacobian(") == std::string::npos);
  CHECK(gpu.find("velocities") == std::string::npos);
  // One sin and one cos per link, in place of the host's batch sincos.
  CHECK(gpu.find("    v.s[k] = sin(phi[k]);\n    v.c[k] = cos(phi[k]);\n") != std::string::npos);
  CHECK(gpu.find("batch_") == std::string::npos);
  // NVRTC has no standard headers, and the text is one of several concatenated ones.
  CHECK(gpu.find("std::") == std::string::npos);
  CHECK(gpu.find("#include") == std::string::npos);
  CHECK(gpu.find("#pragma") == std::string::npos);
  CHECK(gpu.find("namespace npend::gpu::chain_loop {\n") != std::string::npos);
  // The workspace is the arrays the cut takes, n doubles each.
  int arrays = 0;
  for (auto at = gpu.find("work + n * i++;"); at != std::string::npos;
       at = gpu.find("work + n * i++;", at + 1))
    ++arrays;
  CHECK(arrays > 0);
  CHECK(gpu.find("constexpr int workspace_size(int n) noexcept { return " + std::to_string(arrays) +
                 " * n; }") != std::string::npos);
  CHECK(emit_gpu_loop_kernels() == gpu);
  CHECK(std::string(gpu_loop_file_name) == "gpu_chain_loop.cuh");
}

}  // namespace emit_gpu_test
