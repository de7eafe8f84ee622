// The options of an LQR design (npend control, npend simulate --controller lqr): the
// equilibrium, the motorised joints and the weights.
#pragma once

#include <CLI/CLI.hpp>
#include <npend/analysis/stability/lqr.hpp>
#include <npend/integrators/stepper_kind.hpp>
#include <optional>
#include <string>

namespace npend::cli {

struct control_options {
  std::string at, actuated, weights;
  std::string controller;  ///< --controller, for commands that run a chain under control

  /// Adds --at (required unless `at_required` is false), --actuated and --weights.
  void add_to(CLI::App& command, bool at_required = true);

  /// Adds --controller and, optional, the design's --at, --actuated and --weights (npend
  /// simulate, npend animate: running the chain under the feedback).
  void add_controller_to(CLI::App& command);

  /// The design to run the chain under: none without --controller, the LQR design with
  /// --controller lqr, run by `stepper`. Throws input_error for another controller, lqr
  /// without --at, --at, --actuated or --weights without --controller, and a stepper that
  /// runs only the chain's own equations (taylor), not the feedback system.
  std::optional<lqr_design> controller_design(const chain& c, stepper_kind stepper) const;

  /// Whether a design was asked for (--at given).
  bool given() const { return !at.empty(); }

  /// The LQR design for the chain; throws input_error naming the option at fault.
  lqr_design design(const chain& c) const;
};

}  // namespace npend::cli
