// The loop kernels: the point-mass chain's functions for any link count n, chosen at run
// time, as loops over the links instead of unrolled straight-line code.
//
// Why: the unrolled kernels grow like n² in source (the Jacobian) and their derivation like
// n^3.5 in time, which stops being practical near n = 20; a rope of hundreds of links needs
// code whose size does not depend on n. The articulated-body elimination (articulated_form.hpp)
// has the same shape at every link, so each of its passes is one loop whose body is a small
// graph over the link's own values and its neighbour's: the same step functions
// (eliminate_link, pivot_link, rod_turn) the unrolled kernels are built from, printed once
// instead of n times. The Jacobian–vector product is the forward-mode derivative of each step
// (forward_diff.hpp), so J·v costs O(n) and the Jacobian, 2n of them, O(n²).
//
// The other functions (momenta, energies, mass matrix, positions, ∂V and ∂²V) follow from the
// chain's kinematics as loops too: μ_k = Σ_{j≥k} m_j, V = g Σ μ_k l_k (1 − cos φ_k), bob
// velocities summed from the pivot and p_k = l_k n_k·P_k with P_k summed from the tip.
#pragma once

#include "emit_cpp.hpp"

namespace npend::gen {

/// chain_loop.hpp / chain_loop.cpp: the loop kernels and their table entry
/// (npend::loop_kernels of <npend/chain_kernels.hpp>).
chain_sources emit_loop_kernels();

/// gpu_chain_loop.cuh: the loop kernels' rhs, jacobian_vector and hamiltonian as device
/// functions of the GPU maps (namespace npend::gpu::chain_loop), printed from the same steps
/// as chain_loop.cpp's, with no includes and unqualified sin and cos, as emit_gpu's files.
/// Throws std::logic_error if one of the three functions is missing.
std::string emit_gpu_loop_kernels();

inline constexpr const char* loop_stem = "chain_loop";
inline constexpr const char* gpu_loop_file_name = "gpu_chain_loop.cuh";

}  // namespace npend::gen
