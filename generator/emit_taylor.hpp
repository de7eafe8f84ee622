// The Taylor integrators' kernels: the recurrences of automatic differentiation over the
// expression graph of a chain's Hamilton's equations, which give the Taylor coefficients
// x^[1..p] of the solution through a state for any order p chosen at run time.
#pragma once

#include <string>

#include "chain_functions.hpp"
#include "emit_cpp.hpp"

namespace npend::gen {

/// taylor_<stem>_<n>.hpp / .cpp from the chain's `rhs` (an emitted_function of
/// build_chain_functions, layout state, for `kind`): `coefficients` in double and long
/// double, and the table entry npend::taylor_kernels. Every node of the graph becomes one
/// recurrence, computed once per order: sums and differences term by term, products,
/// quotients and sine/cosine pairs by <npend/integrators/taylor_recurrences.hpp>; nodes
/// that read only the parameters are computed once, before the orders. The time-dependent
/// inputs w of a physical chain or a cart are series the caller gives. `options` as for
/// emit_chain.
chain_sources emit_taylor(int links, const emitted_function& rhs, const std::string& options,
                          link_kind kind);

/// File name stem of the Taylor kernels for n links of `kind`: taylor_<chain_stem>.
std::string taylor_stem(int links, link_kind kind);

}  // namespace npend::gen
