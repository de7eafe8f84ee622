// The derived equations as LaTeX, for people to read and to compare with the paper.
#pragma once

#include <iosfwd>

#include "chain_model.hpp"

namespace npend::gen {

/// Prints kinematics, T, V, L, the mass matrix, the momenta, the Hamiltonian (closed form
/// for n ≤ 3), Hamilton's equations and the Euler–Lagrange equations of the n-link chain as
/// a LaTeX fragment (amsmath), in μ_j = m_j + … + m_n.
void print_latex(const chain_symbols& sym, const chain_mechanics& mech, std::ostream& out);

}  // namespace npend::gen
