// The options that choose a start state: angles and momenta, angles and angular
// velocities, or an energy with an excitation style. Shared by every command that
// integrates (simulate, and the analyses built on it).
#pragma once

#include <CLI/CLI.hpp>

#include "npend/spec/state_spec.hpp"

namespace npend::cli {

/// Raw text of --phi, --p, --dphi, --energy and --excitation (style); make_state (the
/// specification library's) turns it into the start state.
struct start_options : spec::start_spec {
  /// Adds the five options to `command`.
  void add_to(CLI::App& command);
};

}  // namespace npend::cli
