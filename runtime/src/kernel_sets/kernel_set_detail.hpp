// What the kernel sets share: their constructors, the parts of the physical chain's inputs
// and the potential that keeps its precision near rest.
#pragma once

#include <array>
#include <memory>
#include <stdexcept>

#include "npend/kernel_set.hpp"

namespace npend::detail {

/// The inputs of one evaluation, on the stack: no allocation inside an integrator's step
/// (the cart's n + 1 inputs fit too).
using input_buffer = std::array<double, chain_layout::input_size(chain_layout::max_links)>;
/// All inputs zero.
inline constexpr input_buffer no_inputs{};

/// V of the links on a fixed support: gravity g Σ_k a_k (1 − cos φ_k) with
/// a_k = m_k c_k + l_k Σ_{j>k} m_j (c_k = l_k for a point mass) and the joint springs
/// ½ k_j (φ_j − φ_{j−1} − θ⁰_j)² (φ_0 = 0), the kernels' V term for term, but with 1 − cos φ
/// written 2 sin²(φ/2): near the rest position 1 − cos φ cancels to one rounding unit of 1 (an
/// energy of 1e-12 J came out with a relative error of 1e-3), its half-angle form keeps the
/// relative precision of φ². phi: dim n.
double fixed_support_potential(const chain_parameters& p, const double* phi);

/// The refusal of a computation that needs input kernels on a chain running on the loops.
std::invalid_argument no_physical_kernels(int n, const char* what);

/// Throws std::logic_error where a generated table's sizes are not those the runtime packs.
void check_generated_sizes(int links, int state, int param, int inputs, int want_state,
                           int want_param, int want_inputs);

std::shared_ptr<const kernel_set> make_point_mass_kernel_set(const chain_parameters& params,
                                                             const chain_kernels& point,
                                                             const physical_kernels& physical);
std::shared_ptr<const kernel_set> make_physical_kernel_set(const chain_parameters& params,
                                                           const physical_kernels& physical);
std::shared_ptr<const kernel_set> make_loop_kernel_set(const chain_parameters& params);
std::shared_ptr<const kernel_set> make_cart_kernel_set(const chain_parameters& params,
                                                       const physical_kernels& cart);

}  // namespace npend::detail
