// Start states of a requested energy: the paper's analysis parameter (section 6.6).
#pragma once

#include <span>
#include <string_view>
#include <vector>

#include "npend/chain.hpp"

namespace npend {

/// The two ways the paper gives the chain its energy: deflecting the arms from rest, or a
/// kick (an impulse) to the chain hanging at rest.
enum class excitation { deflection, kick };

/// "deflection" or "kick".
std::string_view excitation_name(excitation style);
/// The style called `name`; throws std::invalid_argument naming the valid names.
excitation parse_excitation(std::string_view name);

/// E = ε m g l (J) for a chain of equal masses m and equal lengths l: the paper's
/// dimensionless energy ε = E/(m g l). Throws std::invalid_argument if the masses or the
/// lengths are not all equal, or ε is not finite.
double energy_from_epsilon(const chain& c, double epsilon);
/// ε = E/(m g l), the inverse of energy_from_epsilon (same requirements).
double epsilon_from_energy(const chain& c, double energy);

/// The largest energy (J) a deflection along `direction` (dim n; empty: all ones) reaches:
/// V(s_max·u) with s_max = π / max_i |u_i|, where the arm with the largest |u_i| points
/// straight up. Throws std::invalid_argument for a direction of the wrong size, non-finite
/// or all zero.
double max_deflection_energy(const chain& c, std::span<const double> direction = {});

/// The chain at rest deflected along `direction` u (dim n; empty: all ones, i.e. every arm
/// by the same angle): the state [s·u, 0] (dim 2n) with the s ≥ 0 for which H = V(s·u) =
/// energy (J). V(s·u) grows monotonically for 0 ≤ s ≤ s_max (see max_deflection_energy),
/// and s is found by bisection to the last bit. Throws std::invalid_argument for an energy
/// that is not finite, below the minimum 0 J of the potential (the chain hanging at rest),
/// or above max_deflection_energy, and for a bad direction.
std::vector<double> deflected_state(const chain& c, double energy,
                                    std::span<const double> direction = {});

/// The hanging chain (φ = 0) given momenta along `direction` d (dim n): the state [0, s·d]
/// (dim 2n) with s = √(E / H(0, d)) ≥ 0, so that H = ½ s² dᵀA(0)⁻¹d = energy (J). The
/// default d_i = l_i is a horizontal impulse on the lowest bob: p_i = (∂x_n/∂φ_i)·J at φ = 0.
/// Every energy ≥ 0 is reachable (large ones make the arms flip over). Throws
/// std::invalid_argument for an energy that is not finite or below 0 J, and a bad direction.
std::vector<double> kicked_state(const chain& c, double energy,
                                 std::span<const double> direction = {});

/// deflected_state or kicked_state with the default direction.
std::vector<double> excited_state(const chain& c, double energy, excitation style);

}  // namespace npend
