// The GPU maps' device functions (generated/gpu_<stem>_<n>.cuh) compiled as host C++: they
// are the statements of the chain's C++ kernels with unqualified sin and cos, so on the host
// they compute the same doubles, bit for bit, as npend::generated::<stem>_<n>. The loop
// kernels' (gpu_chain_loop.cuh) agree with npend::generated::chain_loop to rounding: the
// host's sines and cosines come from SLEEF's batch sincos, theirs from sin and cos.
#include <doctest/doctest.h>

#include <array>
#include <chain_2.hpp>
#include <chain_3.hpp>
#include <chain_loop.hpp>
#include <cmath>
#include <cstring>
#include <physical_2.hpp>
#include <random>
#include <utility>
#include <vector>

#include "support/test_support.hpp"

// The includer's part of the .cuh contract: NPEND_GPU_FUNCTION, and sin and cos visible
// (here <cmath>'s, brought into this file's own namespace; the .cuh namespaces land inside
// it, so the library's kernels are named from the global namespace below).
namespace npend_gpu_sources_test {
using std::cos;
using std::sin;
#define NPEND_GPU_FUNCTION inline
#include <gpu_chain_2.cuh>
#include <gpu_chain_3.cuh>
#include <gpu_chain_loop.cuh>
#include <gpu_physical_2.cuh>
#undef NPEND_GPU_FUNCTION
}  // namespace npend_gpu_sources_test

namespace npend_gpu_sources_test {

namespace {

// The number of entries whose bits differ (0.0 and -0.0 differ too: same statements, same
// order, so not even the sign of a zero may change).
int differing_bits(const std::vector<double>& a, const std::vector<double>& b) {
  int count = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (std::memcmp(&a[i], &b[i], sizeof(double)) != 0) ++count;
  return count;
}

std::vector<double> draw(std::mt19937_64& rng, int count, double low, double high) {
  std::uniform_real_distribution<double> dist(low, high);
  std::vector<double> v;
  for (int i = 0; i < count; ++i) v.push_back(dist(rng));
  return v;
}

// A random state of n links: angles anywhere on the circle and beyond, momenta of either sign.
std::vector<double> random_state(std::mt19937_64& rng, int n) {
  std::vector<double> x = draw(rng, n, -7, 7);
  const std::vector<double> p = draw(rng, n, -5, 5);
  x.insert(x.end(), p.begin(), p.end());
  return x;
}

// The point-mass chain's device functions F against its kernels G, at random states and
// parameters [m, l, g].
template <int n, class Rhs, class Ham, class Jac, class GRhs, class GHam, class GJac>
void check_point_chain(Rhs rhs, Ham hamiltonian, Jac jacobian, GRhs g_rhs, GHam g_hamiltonian,
                       GJac g_jacobian) {
  std::mt19937_64 rng(8100 + n);
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<double> params = draw(rng, 2 * n, 0.3, 3);
    params.push_back(9.81);
    const std::vector<double> x = random_state(rng, n);
    std::vector<double> f(2 * n), g(2 * n), jf(4 * n * n), jg(4 * n * n);
    rhs(x.data(), params.data(), f.data());
    g_rhs(x.data(), params.data(), g.data());
    jacobian(x.data(), params.data(), jf.data());
    g_jacobian(x.data(), params.data(), jg.data());
    INFO("n = ", n, ", trial ", trial);
    CHECK(differing_bits(f, g) == 0);
    CHECK(differing_bits(jf, jg) == 0);
    CHECK(differing_bits({hamiltonian(x.data(), params.data())},
                         {g_hamiltonian(x.data(), params.data())}) == 0);
  }
}

}  // namespace

TEST_CASE("gpu sources: gpu_chain_<n>.cuh computes chain_<n>'s rhs, hamiltonian, jacobian") {
  namespace gen2 = ::npend::generated::chain_2;
  namespace gen3 = ::npend::generated::chain_3;
  check_point_chain<2>(npend::gpu::chain_2::rhs, npend::gpu::chain_2::hamiltonian,
                       npend::gpu::chain_2::jacobian, gen2::rhs, gen2::hamiltonian, gen2::jacobian);
  check_point_chain<3>(npend::gpu::chain_3::rhs, npend::gpu::chain_3::hamiltonian,
                       npend::gpu::chain_3::jacobian, gen3::rhs, gen3::hamiltonian, gen3::jacobian);
}

TEST_CASE("gpu sources: gpu_chain_loop.cuh computes chain_loop's functions to rounding") {
  namespace gpu = npend::gpu::chain_loop;
  namespace gen = ::npend::generated::chain_loop;
  using ::npend::test::relative_error;
  for (const int n : {3, 8, 20}) {
    std::mt19937_64 rng(8300 + n);
    // Exactly the sizes each file promises, so that the sanitized build catches a function
    // that reads or writes past them.
    std::vector<double> gpu_work(static_cast<std::size_t>(gpu::workspace_size(n)));
    std::vector<double> gen_work(static_cast<std::size_t>(gen::workspace_size(n)));
    for (int trial = 0; trial < 10; ++trial) {
      std::vector<double> params = draw(rng, 2 * n, 0.3, 3);
      params.push_back(9.81);
      const std::vector<double> x = random_state(rng, n);
      const std::vector<double> u = draw(rng, 2 * n, -1, 1);
      std::vector<double> f(2 * n), g(2 * n), jf(2 * n), jg(2 * n);
      gpu::rhs(n, x.data(), params.data(), f.data(), gpu_work.data());
      gen::rhs(n, x.data(), params.data(), g.data(), gen_work.data());
      gpu::jacobian_vector(n, x.data(), params.data(), u.data(), jf.data(), gpu_work.data());
      gen::jacobian_vector(n, x.data(), params.data(), u.data(), jg.data(), gen_work.data());
      const double h_gpu = gpu::hamiltonian(n, x.data(), params.data(), gpu_work.data());
      const double h_gen = gen::hamiltonian(n, x.data(), params.data(), gen_work.data());
      INFO("n = ", n, ", trial ", trial);
      // 1 ulp in a sine or cosine, through the elimination's divisions: far below 1e-13.
      CHECK(relative_error(f, g) < 1e-13);
      CHECK(relative_error(jf, jg) < 1e-13);
      CHECK(std::fabs(h_gpu - h_gen) < 1e-13 * std::fabs(h_gen));
    }
  }
}

TEST_CASE("gpu sources: the sizes are the kernels' sizes") {
  CHECK(npend::gpu::chain_2::links == ::npend::generated::chain_2::links);
  CHECK(npend::gpu::chain_2::state_size == ::npend::generated::chain_2::state_size);
  CHECK(npend::gpu::chain_2::param_size == ::npend::generated::chain_2::param_size);
  CHECK(npend::gpu::chain_3::links == ::npend::generated::chain_3::links);
  CHECK(npend::gpu::chain_3::state_size == ::npend::generated::chain_3::state_size);
  CHECK(npend::gpu::chain_3::param_size == ::npend::generated::chain_3::param_size);
  CHECK(npend::gpu::physical_2::links == ::npend::generated::physical_2::links);
  CHECK(npend::gpu::physical_2::state_size == ::npend::generated::physical_2::state_size);
  CHECK(npend::gpu::physical_2::param_size == ::npend::generated::physical_2::param_size);
  CHECK(npend::gpu::physical_2::input_size == ::npend::generated::physical_2::input_size);
}

TEST_CASE("gpu sources: gpu_physical_2.cuh computes physical_2's functions, driven and damped") {
  namespace gpu = npend::gpu::physical_2;
  namespace gen = ::npend::generated::physical_2;
  constexpr int n = 2;
  std::mt19937_64 rng(8202);
  for (int trial = 0; trial < 20; ++trial) {
    // [m, l, g, c, J, k, theta0, b]: every spring, rest angle and damper nonzero.
    std::vector<double> params = draw(rng, 2 * n, 0.3, 3);
    params.push_back(9.81);
    const std::array<std::pair<double, double>, 5> ranges{
        {{0.1, 1.0}, {0.01, 0.5}, {0.5, 4.0}, {-1.0, 1.0}, {0.05, 0.8}}};
    for (const auto& [low, high] : ranges) {
      const std::vector<double> more = draw(rng, n, low, high);
      params.insert(params.end(), more.begin(), more.end());
    }
    // [a_x, a_y, u_1, u_2]: the pivot accelerates and both joints are driven.
    const std::vector<double> inputs = draw(rng, gen::input_size, 0.5, 3);
    const std::vector<double> x = random_state(rng, n);
    REQUIRE(params.size() == static_cast<std::size_t>(gen::param_size));
    std::vector<double> f(2 * n), g(2 * n), jf(4 * n * n), jg(4 * n * n);
    gpu::rhs(x.data(), params.data(), inputs.data(), f.data());
    gen::rhs(x.data(), params.data(), inputs.data(), g.data());
    gpu::jacobian(x.data(), params.data(), inputs.data(), jf.data());
    gen::jacobian(x.data(), params.data(), inputs.data(), jg.data());
    INFO("trial ", trial);
    CHECK(differing_bits(f, g) == 0);
    CHECK(differing_bits(jf, jg) == 0);
    CHECK(differing_bits({gpu::hamiltonian(x.data(), params.data(), inputs.data())},
                         {gen::hamiltonian(x.data(), params.data(), inputs.data())}) == 0);
  }
}

}  // namespace npend_gpu_sources_test
