// The Toda–Brumer criterion (paper §6.5.2): where the potential's curvature turns negative.
#pragma once

#include <span>
#include <vector>

#include "npend/chain.hpp"

namespace npend {

/// Eigenvalues Λ of −∂²V/∂φ_i∂φ_j at φ (dim n), ascending. For the chain the Hessian is
/// diagonal: Λ_k = −g μ_k l_k cos φ_k (eq. 6.20). Some Λ_k > 0 marks a locally unstable
/// region. Throws std::invalid_argument for phi of another size. A chain without joint
/// springs on a fixed pivot (V a sum over the links) costs O(n) time and memory here and in
/// toda_brumer_links; any other chain forms the n × n Hessian.
std::vector<double> toda_brumer_eigenvalues(const chain& c, std::span<const double> phi);

/// Per link k: the curvature scale g μ_k l_k (J) and the critical energy of entering the
/// region Λ_k > 0 (π/2 < φ_k < 3π/2) from rest with every other link hanging: V at φ_k = π/2.
struct toda_brumer_link {
  int link = 0;                ///< 1-based
  double curvature = 0;        ///< g μ_k l_k
  double critical_energy = 0;  ///< V(φ_k = π/2, others 0)
};
std::vector<toda_brumer_link> toda_brumer_links(const chain& c);

/// The critical energy of a configuration family with p = 0 and the links in `fixed`
/// (1-based) held at φ = 0: the least energy at which some free link reaches Λ_k > 0, i.e.
/// the minimum of critical_energy over the free links. The paper's example: fixed {1, 2} of
/// the triple pendulum gives E_c = m₃ g l₃. Throws std::invalid_argument for an index out of
/// range or when no link is free.
double toda_brumer_critical_energy(const chain& c, std::span<const int> fixed);

}  // namespace npend
