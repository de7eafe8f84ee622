// A chain's state as users type it: the whole state "phi_1..phi_n,p_1..p_n", or a start
// chosen by angles and momenta, angles and angular velocities, or an energy with an
// excitation style (the command line's --phi, --p, --dphi, --energy, --excitation).
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "npend/chain.hpp"
#include "npend/spec/input_error.hpp"

namespace npend::spec {

/// The state "phi_1,...,phi_n,p_1,...,p_n" of chain `c` (dim 2n), on a cart
/// "x_c,phi_1,...,phi_n,p_x,p_1,...,p_n" (dim 2(n + 1)). Throws input_error naming `option`
/// for text that is not that many numbers.
std::vector<double> parse_state(std::string_view text, const chain& c,
                                std::string_view option = "--state");

/// The text of a start state's options, each empty when not given: --phi (rad), --p
/// (kg m²/s), --dphi (rad/s), each n values or one for every link; --energy E (J) and
/// --excitation (its style).
struct start_spec {
  std::string phi, p, dphi, energy, style;

  /// The start state [φ, p] (dim 2n) for chain c: from --phi and --p (default 0), from --phi
  /// and --dphi (converted by p = A(φ) φ̇), or from --energy E with --excitation deflection
  /// (default: all arms deflected equally from rest) or kick (a horizontal impulse on the
  /// lowest bob of the hanging chain). Throws input_error naming the option for a missing or
  /// contradictory choice, a wrong number of values, non-finite values, or an energy below
  /// the minimum or out of reach. On a cart the state is [x_c, φ, p_x, p] with the cart at
  /// x_c = 0 and p_x = 0 (with --dphi: the cart at rest); --energy is refused there.
  std::vector<double> make_state(const chain& c) const;
};

}  // namespace npend::spec
