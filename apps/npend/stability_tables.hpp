// The readable tables of the linear stability analysis, shared by `npend equilibria`,
// `npend modes` and `npend demo`.
#pragma once

#include <vector>

#include "npend/analysis/stability/equilibria.hpp"
#include "npend/analysis/stability/normal_modes.hpp"

namespace npend::app {

/// The equilibria with their energy, stability and Jacobian eigenvalue pairs, and a legend.
void print_equilibria_table(const chain& c, const std::vector<equilibrium>& eqs);

/// The normal modes of a linearisation: ω², frequency (or growth rate), mode shape.
void print_modes_table(const linearisation& lin);

}  // namespace npend::app
