// The texts the GPU maps compile at run time, embedded into the library when it is built
// (cmake/embed_gpu_sources.cmake): runtime/src/gpu/map_models.cuh and map_kernels.cuh, and
// the generated device functions of every built model and link count.
#pragma once

#include <string_view>

namespace npend::gpu {

/// The text called `name` — "map_kernels", "map_models", or the generated file's stem
/// ("gpu_chain_3", "gpu_physical_2") — or an empty view where there is none.
std::string_view embedded_source(std::string_view name);

}  // namespace npend::gpu
