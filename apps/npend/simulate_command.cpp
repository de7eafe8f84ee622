// npend simulate: integrate a chain from a start state and write the trajectory as CSV.
#include <fmt/format.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <iostream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <optional>

#include "chain_options.hpp"
#include "command.hpp"
#include "control_options.hpp"
#include "input_parsing.hpp"
#include "integrator_options.hpp"
#include "npend/analysis/motion/energy_drift.hpp"
#include "npend/analysis/motion/rod_tensions.hpp"
#include "npend/integrators/integrate.hpp"
#include "output_file.hpp"
#include "series_output.hpp"
#include "start_options.hpp"
#include "terminal_run.hpp"
#include "trajectory_csv.hpp"

namespace npend::app {

namespace {

struct simulate_options {
  cli::chain_options chain;
  cli::start_options start;
  cli::integrator_options integrator;
  cli::control_options control;
  std::string out, every;
  bool json = false, tensions = false;
};

int run_simulate(const simulate_options& o) {
  const chain c = o.chain.make_chain(cli::model_support::any, "npend simulate", true);
  if (o.tensions && c.has_cart())
    throw cli::input_error(
        "--tensions: rod tensions are those of a chain on a fixed pivot; drop "
        "--cart");
  if (o.tensions && c.is_physical())
    throw cli::input_error(
        "--tensions: rod tensions are those of point masses on massless rods; drop --com, "
        "--inertia, --rods, --stiffness, --rest-angles, --damping and --pivot");
  const std::vector<double> x0 = o.start.make_state(c);
  integration_options options = o.integrator.make_for(c);
  const std::size_t every = parse_every(o.every);
  // --controller lqr: the chain under u = −K(x − x*) of the design at --at.
  const std::optional<lqr_design> design = o.control.controller_design(c, options.stepper);
  if (o.tensions && design)
    throw cli::input_error(
        "--tensions: a controlled chain's joint torques load the rods with more than a tension");

  // From here on Ctrl-C only stops the run at its next output step, so the temporary file
  // created below is always removed again.
  cli::terminal_run control;
  options.control = &control;
  std::optional<cli::atomic_output_file> file;
  if (!o.out.empty()) {
    cli::claim_output(o.out, "--out");
    try {
      file.emplace(o.out);
    } catch (const std::runtime_error& e) {
      throw cli::input_error(fmt::format("--out: {}", e.what()));
    }
  }
  // CSV to the file, or to stdout unless only the --json summary was asked for.
  std::optional<trajectory_csv> csv;
  if (file)
    csv.emplace(c, file->stream(), fmt::format("'{}'", o.out), o.tensions);
  else if (!o.json)
    csv.emplace(c, stdout, "stdout", o.tensions);
  if (csv) csv->header();

  // Damping, a moving pivot and a controller's torques all change H.
  const bool conserved = c.parameters().is_conservative() && !design;
  if (!conserved && is_gauss_legendre(options.stepper))
    fmt::print(stderr,
               "npend simulate: note: the chain is {}, so {} is not symplectic here (it stays "
               "an implicit method of order {}) and H is not conserved\n",
               design                       ? "controlled"
               : c.parameters().is_damped() ? "damped"
                                            : "driven",
               stepper_name(options.stepper), options.stepper == stepper_kind::gauss4 ? 4 : 6);
  energy_drift energy(c, c.hamiltonian(x0, 0.0));
  std::size_t index = 0, rows = 0;
  const auto observe = [&](double t, std::span<const double> x) {
    energy.add(x, t);
    if (csv && index % every == 0) {
      csv->row(t, x, energy.last());
      ++rows;
    }
    ++index;
    return observer_action::proceed;
  };
  const integration_result result = design
                                        ? integrate_under_feedback(c, *design, x0, options, observe)
                                        : integrate(c, x0, options, observe);
  control.finish();

  if (result.stopped) {
    file.reset();  // removes the temporary file
    fmt::print(stderr, "npend simulate: interrupted at t = {} s{}\n", result.t,
               o.out.empty() ? "" : fmt::format("; nothing written to {}", o.out));
    return control.exit_code();
  }
  if (csv) csv->flush();
  if (file) file->commit();
  // Above 1 % the trajectory is not a solution of the chain any more (an angle so large that
  // its rounding is a sizeable fraction of a turn, a step far too long): say so, whatever
  // the output.
  constexpr double energy_warning = 1e-2;
  if (conserved && energy.max_relative_error() > energy_warning)
    fmt::print(stderr,
               "npend simulate: warning: the energy drifted by up to {:.3g} of its start value "
               "(more than {:g}): the trajectory is not to be trusted; try a smaller dt or "
               "tighter tolerances, and angles of moderate size\n",
               energy.max_relative_error(), energy_warning);

  if (o.json) {
    nlohmann::json j = describe_chain(c);
    j["stepper"] = std::string(stepper_name(options.stepper));
    j["dt"] = options.dt;
    j["t_end"] = result.t;
    j["steps"] = result.steps;
    j["outputs"] = result.outputs;
    j["rows"] = rows;
    j["energy_initial"] = energy.initial();
    j["energy_final"] = energy.last();
    // On a damped or driven chain H changes by physics: its drift measures nothing.
    j["energy_conserved"] = conserved;
    j["max_rel_energy_error"] =
        conserved ? nlohmann::json(energy.max_relative_error()) : nlohmann::json(nullptr);
    j["initial_state"] = x0;
    if (design) {
      double deviation = 0;
      for (std::size_t i = 0; i < result.state.size(); ++i)
        deviation = std::max(deviation, std::fabs(result.state[i] - design->equilibrium[i]));
      j["controller"] = "lqr";
      j["equilibrium"] = design->equilibrium;
      j["final_deviation"] = deviation;
    }
    j["final_state"] = result.state;
    j["out"] = o.out.empty() ? nlohmann::json(nullptr) : nlohmann::json(o.out);
    std::cout << j.dump(2) << "\n";
  }
  return 0;
}

}  // namespace

void add_simulate_command(CLI::App& app, command_list& commands) {
  auto opts = std::make_shared<simulate_options>();
  CLI::App* cmd = app.add_subcommand(
      "simulate", "Integrate the chain from a start state; write the trajectory as CSV");
  opts->chain.add_to(*cmd);
  opts->start.add_to(*cmd);
  opts->integrator.add_to(*cmd);
  cmd->add_option("--out", opts->out,
                  "Write the CSV here (default: stdout; with --json and no --out, no CSV). "
                  "Columns: t, phi_i, p_i, H, x_i, y_i (and tau_i with --tensions)");
  cmd->add_flag("--tensions", opts->tensions,
                "Add the rod tensions tau_1..tau_N (N, positive when a rod pulls) as columns: "
                "Lagrange's equations of the first kind; point-mass chains only");
  cmd->add_option("--every", opts->every, "Write every K-th output step only (default: 1)");
  cmd->add_flag("--json", opts->json,
                "Print a JSON summary (steps, energies, max_rel_energy_error, ...) to stdout");
  opts->control.add_controller_to(*cmd);
  commands.push_back({cmd, [opts] { return run_simulate(*opts); }});
}

}  // namespace npend::app
