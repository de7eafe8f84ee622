// The hash of a map run's tile files (map_tiles.cpp), shared with map_run.cpp, which tags
// the tiles with the hash of the run's identity.
#pragma once

#include <cstdint>
#include <string_view>

namespace npend::detail {

/// FNV-1a (64 bit) of `bytes`: of the run's identity, the tag at the head of every tile file,
/// which ties the tile to its run.json without repeating the identity in each tile; and of
/// each tile's data, its checksum.
std::uint64_t fnv1a(std::string_view bytes);

}  // namespace npend::detail
