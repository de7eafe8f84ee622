// npend: the command-line front end (see docs/commands.md for every command).
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cstdio>
#include <exception>
#include <iostream>
#include <stdexcept>
#include <string>

#include "command.hpp"
#include "input_parsing.hpp"
#include "npend/analysis/chaos/chaos_map.hpp"
#include "npend/analysis/chaos/map_device.hpp"
#include "signal_cleanup.hpp"
#include "terminal_run.hpp"

namespace {

// CLI11's own messages do not say which command they are about, and for an unknown command
// it only says that one is required: name the command, and list the commands there are.
void report_parse_error(const CLI::App& app, int argc, char** argv, const CLI::ParseError& e) {
  const auto parsed = app.get_subcommands();
  if (!parsed.empty()) {
    const std::string name = "npend " + parsed.front()->get_name();
    fmt::print(stderr, "{}: error: {} (see {} --help)\n", name, e.what(), name);
    return;
  }
  if (argc > 1 && argv[1][0] != '-') {
    std::string names;
    for (const auto* sub : app.get_subcommands([](const CLI::App*) { return true; }))
      names += (names.empty() ? "" : ", ") + sub->get_name();
    fmt::print(stderr, "npend: error: unknown command '{}': choose one of {} (see npend --help)\n",
               argv[1], names);
    return;
  }
  fmt::print(stderr, "npend: error: {} (see npend --help)\n", e.what());
}

// CLI11 takes `--stepper ''` as a given option with an empty value, and most commands then
// fall back to their default as if the option were absent: refuse it instead, naming the
// option, for every option that takes a value.
void refuse_empty_values(const CLI::App& command) {
  for (const CLI::Option* option : command.get_options()) {
    if (option->get_type_size() == 0 || option->count() == 0) continue;
    for (const std::string& value : option->results())
      if (value.find_first_not_of(" \t") == std::string::npos)
        throw npend::cli::input_error(fmt::format(
            "{}: empty value (give a value or leave the option out)", option->get_name()));
  }
}

// npend's version and what this build and machine run the maps on: the batch lanes'
// instruction set (and those it could take), and the GPU the maps' --device cuda would use
// (or why there is none).
std::string version_text() {
  const npend::cuda_status gpu = npend::find_cuda();
  std::string lanes;
  try {
    lanes = std::string(npend::batch_lane_isa());
  } catch (const std::invalid_argument& e) {  // a bad NPEND_LANE_ISA
    lanes = e.what();
  }
  return fmt::format(
      "npend 0.1\nbatch lanes: {} (this machine: {}; NPEND_LANE_ISA picks one)\n"
      "GPU maps (--device cuda): {}",
      lanes, fmt::join(npend::batch_lane_isas(), ", "),
      gpu.usable ? fmt::format("{}; CUDA driver {}, NVRTC {}", gpu.device, gpu.driver, gpu.nvrtc)
                 : "not available: " + gpu.problem);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "npend: exact equations of planar n-link pendulums, generated code, and the analysis of\n"
      "their motion. Run `npend <command> --help` for a command's options."};
  app.set_version_flag("--version", version_text);
  app.require_subcommand(1);
  npend::app::command_list commands;
  npend::app::add_eval_command(app, commands);
  npend::app::add_equations_command(app, commands);
  npend::app::add_equilibria_command(app, commands);
  npend::app::add_modes_command(app, commands);
  npend::app::add_toda_brumer_command(app, commands);
  npend::app::add_lyapunov_command(app, commands);
  npend::app::add_floquet_command(app, commands);
  npend::app::add_control_command(app, commands);
  npend::app::add_rope_command(app, commands);
  npend::app::add_partition_command(app, commands);
  npend::app::add_map_command(app, commands);
  npend::app::add_backbone_command(app, commands);
  npend::app::add_orbits_command(app, commands);
  npend::app::add_orbit_command(app, commands);
  npend::app::add_upo_command(app, commands);
  npend::app::add_corrections_command(app, commands);
  npend::app::add_simulate_command(app, commands);
  npend::app::add_animate_command(app, commands);
  npend::app::add_spectrum_command(app, commands);
  npend::app::add_autocorrelation_command(app, commands);
  npend::app::add_recurrence_command(app, commands);
  npend::app::add_embed_command(app, commands);
  npend::app::add_poincare_command(app, commands);
  npend::app::add_analyze_command(app, commands);
  npend::app::add_demo_command(app, commands);
  npend::app::add_explore_command(app, commands);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    report_parse_error(app, argc, argv, e);
    return 2;
  }
  npend::cli::remove_temporaries_on_signal();
  for (const auto& c : commands) {
    if (!c.options->parsed()) continue;
    const std::string name = "npend " + c.options->get_name();
    try {
      refuse_empty_values(*c.options);
      return c.run();
    } catch (const npend::cli::input_error& e) {
      fmt::print(stderr, "{}: error: {}\n", name, e.what());
      return 2;
    } catch (const npend::cli::interrupted& e) {
      fmt::print(stderr, "{}: {}\n", name, e.what());
      return e.exit_code();
    } catch (const std::exception& e) {
      fmt::print(stderr, "{}: error: {}\n", name, e.what());
      return 1;
    }
  }
  return 2;
}
