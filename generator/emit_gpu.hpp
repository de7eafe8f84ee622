// The device functions of npend's GPU maps: a chain's rhs, hamiltonian and jacobian printed
// from the same emitted functions as its C++ kernels, as a text that NVRTC compiles (no
// includes, unqualified sin and cos) and host C++ compiles too.
#pragma once

#include <string>
#include <vector>

#include "chain_functions.hpp"

namespace npend::gen {

/// Whether npend-gen writes device functions for `kind`: the point-mass and the physical
/// chain (the models of the GPU maps), not the cart.
bool has_gpu_functions(link_kind kind);

/// gpu_<stem>_<n>.cuh: rhs, hamiltonian and jacobian of `functions` (build_chain_functions's,
/// the same that emit_chain writes) for `links` links, in namespace npend::gpu::<stem>_<n>.
/// `options` as for emit_chain. Throws std::invalid_argument for a kind without device
/// functions, std::logic_error if one of the three functions is missing.
std::string emit_gpu(int links, const std::vector<emitted_function>& functions,
                     const std::string& options, link_kind kind);

/// File name of the device functions for n links: gpu_<stem>_<n>.cuh.
std::string gpu_file_name(int links, link_kind kind);

}  // namespace npend::gen
