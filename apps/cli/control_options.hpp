// The options of an LQR design (npend control, npend simulate --controller lqr): the
// equilibrium, the motorised joints and the weights.
#pragma once

#include <CLI/CLI.hpp>
#include <npend/analysis/lqr.hpp>
#include <string>

namespace npend::cli {

struct control_options {
  std::string at, actuated, weights;

  /// Adds --at (required unless `at_required` is false), --actuated and --weights.
  void add_to(CLI::App& command, bool at_required = true);

  /// Whether a design was asked for (--at given).
  bool given() const { return !at.empty(); }

  /// The LQR design for the chain; throws input_error naming the option at fault.
  lqr_design design(const chain& c) const;
};

}  // namespace npend::cli
