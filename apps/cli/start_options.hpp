// The options that choose a start state: angles and momenta, angles and angular
// velocities, or an energy with an excitation style. Shared by every command that
// integrates (simulate, and the analyses built on it).
#pragma once

#include "npend/chain.hpp"

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

namespace npend::cli {

/// Raw text of --phi, --p, --dphi, --energy and --excitation (style).
struct start_options {
  std::string phi, p, dphi, energy, style;

  /// Adds the five options to `command`.
  void add_to(CLI::App& command);

  /// The start state [φ, p] (dim 2n) for chain c: from --phi (rad) and --p (kg m²/s,
  /// default 0), from --phi and --dphi (rad/s, converted by p = A(φ) φ̇), or from
  /// --energy E (J) with --excitation deflection (default: all arms deflected equally from
  /// rest) or kick (a horizontal impulse on the lowest bob of the hanging chain). Throws
  /// input_error for a missing or contradictory choice, a wrong number of values, non-finite
  /// values, or an energy below the minimum or out of reach.
  std::vector<double> make_state(const chain& c) const;
};

}  // namespace npend::cli
