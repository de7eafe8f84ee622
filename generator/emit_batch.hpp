// The batch kernels of the point-mass chain: Hamilton's equations on W states at once, in
// structure-of-arrays layout, printed from the same expression graph as the scalar rhs so that
// each lane computes what the scalar kernel computes (with SLEEF's sines and cosines).
#pragma once

#include <string>
#include <vector>

#include "chain_functions.hpp"
#include "emit_cpp.hpp"

namespace npend::gen {

/// batch_<n>.hpp / batch_<n>.cpp from the chain's scalar `rhs` (an emitted_function of
/// build_chain_functions, layout state): rhs_batch and the table entry npend::batch_kernels.
/// Throws std::logic_error if the graph takes a sine or cosine of anything but an angle.
chain_sources emit_batch(int links, const emitted_function& rhs);

/// batch_index.hpp / batch_index.cpp: the table of batch kernels by link count.
chain_sources emit_batch_index(const std::vector<int>& links);

/// File name stem of the batch sources for n links (batch_<n>).
std::string batch_stem(int links);
inline constexpr const char* batch_index_stem = "batch_index";

}  // namespace npend::gen
