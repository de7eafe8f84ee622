// The options that say how to integrate: --t-end, --dt, --stepper, --abs-tol, --rel-tol,
// --order.
// Shared by every command that integrates.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <string_view>

#include "npend/integrators/integrate.hpp"

namespace npend::cli {

/// Raw text of the integration options, parsed strictly after CLI11 has collected them.
struct integrator_options {
  std::string t_end, dt, stepper, abs_tol, rel_tol, tol, order;

  /// Adds --t-end (required), --dt, --stepper, --abs-tol, --rel-tol, --tol and --order to
  /// `command`.
  void add_to(CLI::App& command);

  /// Adds only --stepper, --abs-tol, --rel-tol, --tol and --order, their help texts starting with
  /// `note` (for commands whose time grid comes from other options).
  void add_stepper_options(CLI::App& command, std::string_view note = "");

  /// The integration options they describe, from t = 0: dt default 0.001 s, stepper
  /// default gauss6, tolerances default 1e-10 (adaptive steppers only). Throws input_error
  /// naming the option: non-numbers, t-end or dt not positive, dt longer than t-end, more
  /// than max_steps steps, an unknown stepper, negative tolerances (or both zero),
  /// tolerances given for a fixed-step stepper, and an --order that is not
  /// 2..taylor_max_order or is given for a stepper other than taylor.
  integration_options make() const;
  /// make(), and the stepper checked against chain c (check_stepper_fits) as input.
  integration_options make_for(const chain& c) const;

  /// The most output steps (t-end / dt) a command accepts.
  static constexpr double max_steps = 1e9;
};

/// Refuses a run of more than integrator_options::max_steps steps of dt up to t_end: throws
/// input_error "<options>: N steps is more than the limit of 1e+09; <advice>". Every
/// command whose runs step at a fixed dt checks its longest run with it, before it starts.
void check_step_count(double t_end, double dt, std::string_view options,
                      std::string_view advice = "use a larger --dt");

/// --order as typed (empty: `order` keeps 0, from the tolerances) for `stepper`. Throws
/// input_error naming --order: not an integer in 2..taylor_max_order, or given for a
/// stepper other than taylor.
void parse_taylor_order(const std::string& text, stepper_kind stepper, int& order);

/// --stepper and --tol of a command that carries a monodromy matrix over a period: `what`
/// crosses the period ("How the shooting"), gauss6 stepping as `gauss6_steps` says ("--steps
/// per period"), taylor at --tol (default `default_tol`; `tol_note` adds what else it does).
void add_monodromy_options(CLI::App& command, std::string& stepper, std::string& tol,
                           std::string_view what, std::string_view gauss6_steps, double default_tol,
                           std::string_view tol_note = "");

/// The integrator of a command that carries a monodromy matrix over a period (npend floquet,
/// npend orbit, orbits and upo): --stepper as typed (empty: gauss6), one of
/// stepper_use::monodromy, for `what` ("Floquet analysis"); whether --steps was given (it sets
/// gauss6's steps); --tol as typed (taylor's tolerance; empty: `tolerance` keeps its default).
/// Throws input_error naming the option: an unknown stepper or one without a monodromy, --tol
/// without taylor, --steps with taylor, and a --tol that is not a number in (0, 1e-6].
stepper_kind parse_monodromy_integrator(const std::string& stepper_text, bool steps_given,
                                        const std::string& tol_text, std::string_view what,
                                        double& tolerance);

/// Adds --abs-tol, --rel-tol and --tol, which sets both at once and excludes them, to
/// `command` with the help texts given, collecting the texts into `abs_text`, `rel_text` and
/// `tol_text`.
void add_tolerance_options(CLI::App& command, std::string& abs_text, std::string& rel_text,
                           std::string& tol_text, const std::string& abs_help,
                           const std::string& rel_help, const std::string& tol_help);

/// --abs-tol, --rel-tol and --tol as typed (`abs_text`, `rel_text`, `tol_text`: both
/// tolerances; empty: `abs_tol` and `rel_tol` keep their defaults). `refusal`: empty where the
/// stepper takes tolerances, else why it does not, said after "<option>: " for a tolerance
/// given anyway. Throws input_error naming the option: a tolerance refused, not a number or
/// negative, or both tolerances 0.
void parse_tolerances(const std::string& abs_text, const std::string& rel_text,
                      const std::string& tol_text, std::string_view refusal, double& abs_tol,
                      double& rel_tol);

}  // namespace npend::cli
