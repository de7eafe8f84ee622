// What a GPU map hands its kernel besides the starts: the job every cell computes and each
// chain's parameters, as map_kernels.cuh reads them (the tests run the kernels' cell
// functions on the CPU with the same numbers).
#pragma once

#include <vector>

#include "host_kernels.hpp"
#include "npend/analysis/chaos/chaos_map.hpp"
#include "npend/chain.hpp"

namespace npend::gpu {

/// The job of a map of `options` on chain `c`'s model (its steps as the library counts them).
map_job make_map_job(const chain& c, const map_cell_options& options);

/// Appends chain `c`'s parameters as the model adapter (map_models.cuh) reads them: the
/// kernels' own, and for the physical chain the pivot's built-in drive [kind, a, Ω].
void append_parameters(const chain& c, std::vector<double>& block);

}  // namespace npend::gpu
