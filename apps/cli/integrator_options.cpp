#include "integrator_options.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

#include "input_parsing.hpp"

namespace npend::cli {

void integrator_options::add_to(CLI::App& command) {
  command.add_option("--t-end", t_end, "Integrate from t = 0 to this time in s")->required();
  command.add_option("--dt", dt,
                     "Output step in s: the step of the fixed-step steppers, the output grid "
                     "of the adaptive ones (default: 0.001)");
  add_stepper_options(command);
}

void integrator_options::add_stepper_options(CLI::App& command, std::string_view note) {
  command.add_option(
      "--stepper", stepper,
      fmt::format("{}Integrator: one of {} (default: gauss6)", note, stepper_names()));
  add_tolerance_options(
      command, abs_tol, rel_tol, tol,
      fmt::format("{}Absolute error tolerance of the adaptive steppers (default: 1e-10)", note),
      fmt::format("{}Relative error tolerance of the adaptive steppers (default: 1e-10)", note),
      fmt::format("{}Both tolerances of the adaptive steppers at once: --abs-tol and --rel-tol "
                  "TOL (taylor: its order from TOL too)",
                  note));
  command.add_option("--order", order,
                     fmt::format("{}Order of the taylor stepper, 2..{} (default: from the "
                                 "tolerances, ceil(1 - ln(tol)/2))",
                                 note, taylor_max_order));
}

void add_monodromy_options(CLI::App& command, std::string& stepper, std::string& tol,
                           std::string_view what, std::string_view gauss6_steps, double default_tol,
                           std::string_view tol_note) {
  command.add_option("--stepper", stepper,
                     fmt::format("{} crosses the period: {} (default gauss6, {}; taylor: adaptive "
                                 "steps on the Taylor series of the variational equations, at "
                                 "--tol)",
                                 what, stepper_names(stepper_use::monodromy), gauss6_steps));
  command.add_option("--tol", tol,
                     fmt::format("With --stepper taylor: its absolute and relative tolerance "
                                 "(default {:g}; at most 1e-6){}",
                                 default_tol, tol_note));
}

stepper_kind parse_monodromy_integrator(const std::string& stepper_text, bool steps_given,
                                        const std::string& tol_text, std::string_view what,
                                        double& tolerance) {
  stepper_kind stepper = stepper_kind::gauss6;
  if (!stepper_text.empty()) {
    try {
      stepper = parse_stepper_kind(stepper_text);
    } catch (const std::invalid_argument& e) {
      throw input_error(fmt::format("--stepper: {}", e.what()));
    }
    if (!serves(stepper, stepper_use::monodromy))
      throw input_error(fmt::format("--stepper: {} integrates with {}, not {}", what,
                                    stepper_names(stepper_use::monodromy), stepper_text));
  }
  if (stepper != stepper_kind::taylor) {
    if (!tol_text.empty())
      throw input_error(fmt::format("--tol: only with --stepper taylor ({} takes --steps)",
                                    stepper_name(stepper)));
    return stepper;
  }
  if (steps_given)
    throw input_error("--steps: taylor chooses its own steps; set its accuracy with --tol");
  if (tol_text.empty()) return stepper;
  tolerance = parse_number(tol_text, "--tol");
  if (!(tolerance > 0 && tolerance <= 1e-6))
    throw input_error(fmt::format("--tol: must lie in (0, 1e-6], got {}", tol_text));
  return stepper;
}

void parse_taylor_order(const std::string& text, stepper_kind stepper, int& order) {
  if (text.empty()) return;
  if (stepper != stepper_kind::taylor)
    throw input_error(fmt::format("--order: only the taylor stepper takes an order, not {}",
                                  stepper_name(stepper)));
  const double value = parse_number(text, "--order");
  if (!(value >= 2 && value <= taylor_max_order) || value != std::floor(value))
    throw input_error(
        fmt::format("--order: must be an integer in 2..{}, got {}", taylor_max_order, text));
  order = static_cast<int>(value);
}

void check_step_count(double t_end, double dt, std::string_view options, std::string_view advice) {
  if (t_end / dt > integrator_options::max_steps)
    throw input_error(fmt::format("{}: {:.3g} steps is more than the limit of {:.0e}; {}", options,
                                  t_end / dt, integrator_options::max_steps, advice));
}

void add_tolerance_options(CLI::App& command, std::string& abs_text, std::string& rel_text,
                           std::string& tol_text, const std::string& abs_help,
                           const std::string& rel_help, const std::string& tol_help) {
  CLI::Option* abs_option = command.add_option("--abs-tol", abs_text, abs_help);
  CLI::Option* rel_option = command.add_option("--rel-tol", rel_text, rel_help);
  command.add_option("--tol", tol_text, tol_help)->excludes(abs_option)->excludes(rel_option);
}

void parse_tolerances(const std::string& abs_text, const std::string& rel_text,
                      const std::string& tol_text, std::string_view refusal, double& abs_tol,
                      double& rel_tol) {
  const auto tolerance = [&](const std::string& text, const char* option, double& value) {
    if (text.empty()) return;
    if (!refusal.empty()) throw input_error(fmt::format("{}: {}", option, refusal));
    value = parse_number(text, option);
    if (value < 0)
      throw input_error(fmt::format("{}: must not be negative, got {}", option, value));
  };
  if (!tol_text.empty()) {
    tolerance(tol_text, "--tol", abs_tol);
    if (abs_tol == 0) throw input_error("--tol: must be positive, got 0");
    rel_tol = abs_tol;
    return;
  }
  tolerance(abs_text, "--abs-tol", abs_tol);
  tolerance(rel_text, "--rel-tol", rel_tol);
  if (abs_tol == 0 && rel_tol == 0)
    throw input_error("--abs-tol/--rel-tol: both are 0; at least one must be positive");
}

integration_options integrator_options::make() const {
  integration_options o;
  o.t_start = 0;
  o.t_end = parse_number(t_end, "--t-end");
  if (o.t_end <= 0) throw input_error(fmt::format("--t-end: must be positive, got {}", o.t_end));
  if (!dt.empty()) o.dt = parse_number(dt, "--dt");
  if (o.dt <= 0) throw input_error(fmt::format("--dt: must be positive, got {}", o.dt));
  if (o.dt > o.t_end)
    throw input_error(fmt::format("--dt: {} is longer than --t-end {}", o.dt, o.t_end));
  check_step_count(o.t_end, o.dt, "--t-end/--dt");
  if (!stepper.empty()) {
    try {
      o.stepper = parse_stepper_kind(stepper);
    } catch (const std::invalid_argument& e) {
      throw input_error(fmt::format("--stepper: {}", e.what()));
    }
  }
  parse_tolerances(abs_tol, rel_tol, tol,
                   is_adaptive(o.stepper)
                       ? ""
                       : fmt::format("only the adaptive steppers ({}) take tolerances, not {}",
                                     stepper_names(stepper_use::adaptive), stepper_name(o.stepper)),
                   o.abs_tol, o.rel_tol);
  parse_taylor_order(order, o.stepper, o.taylor_order);
  return o;
}

integration_options integrator_options::make_for(const chain& c) const {
  const integration_options o = make();
  try {
    check_stepper_fits(c, o.stepper);
  } catch (const std::invalid_argument& e) {
    throw input_error(fmt::format("--stepper: {}", e.what()));
  }
  return o;
}

}  // namespace npend::cli
