// The contract between the generated batch kernels and the runtime: the table entry every
// generated batch_<n>.cpp fills (point-mass chains only), like chain_kernels for the scalar
// kernels.
#pragma once

#include <cstddef>

#include "npend/batch_math.hpp"

namespace npend {

/// The batch kernels of one link count of the point-mass chain. Arrays are
/// structure-of-arrays over `width` lanes: coordinate i of lane l at [i*width + l]. A caller
/// compiled for another target than the kernels has another batch_width: size the arrays by
/// `width`.
struct batch_kernels {
  int links;
  int width;  ///< lanes, batch_width of the translation unit that emitted the entry
  // Each kernel runs on `blocks` blocks of `width` states, block b of every array at
  // b*stride doubles from its start: one call for all the blocks, so that what depends on
  // the parameters alone is computed once and the blocks' independent work can overlap.

  /// Hamilton's equations: x_soa and dxdt_soa dim 2n*width per block, params the point-mass
  /// layout (dim 2n+1, the same for all lanes).
  void (*rhs_batch)(const double* x_soa, const double* params, double* dxdt_soa, int blocks,
                    std::size_t stride) noexcept;
  /// Hamilton's equations and their tangent: dxdt_soa = f(x) as rhs_batch, dwdt_soa =
  /// J(x) w for the tangent vectors w_soa (dim 2n*width per block, the same layout).
  void (*tangent_batch)(const double* x_soa, const double* w_soa, const double* params,
                        double* dxdt_soa, double* dwdt_soa, int blocks,
                        std::size_t stride) noexcept;
  /// tangent_batch for `count` tangent vectors: ws_soa and dws_soa hold them one after
  /// another (vector j at [j*2n*width] in a block); f(x) and what the vectors share is
  /// computed once, and each dws is bit for bit tangent_batch's dwdt for that vector.
  void (*tangents_batch)(const double* x_soa, const double* ws_soa, int count, const double* params,
                         double* dxdt_soa, double* dws_soa, int blocks,
                         std::size_t stride) noexcept;
};

}  // namespace npend
