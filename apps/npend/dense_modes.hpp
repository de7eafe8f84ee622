// The cost check of the dense normal-mode eigenproblem, shared by `npend equilibria` and
// `npend modes`.
#pragma once

#include <string_view>

#include "npend/chain.hpp"

namespace npend::app {

/// Refuses (cli::input_error, through cli::require_feasible) `count` linearisations of the
/// chain c when the dense n x n eigenproblem each of them is would not fit the machine;
/// `what` names them in the message.
void require_dense_modes(const chain& c, double count, std::string_view what);

}  // namespace npend::app
