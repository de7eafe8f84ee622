// How the subcommands of `npend` plug into main: each registers its CLI11 subcommand and
// the function that runs it.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <vector>

namespace npend::app {

struct command {
  CLI::App* options;
  std::function<int()> run;
};

using command_list = std::vector<command>;

void add_eval_command(CLI::App& app, command_list& commands);
void add_equations_command(CLI::App& app, command_list& commands);
void add_demo_command(CLI::App& app, command_list& commands);
void add_equilibria_command(CLI::App& app, command_list& commands);
void add_modes_command(CLI::App& app, command_list& commands);
void add_toda_brumer_command(CLI::App& app, command_list& commands);
void add_simulate_command(CLI::App& app, command_list& commands);
void add_animate_command(CLI::App& app, command_list& commands);
void add_spectrum_command(CLI::App& app, command_list& commands);
void add_autocorrelation_command(CLI::App& app, command_list& commands);
void add_recurrence_command(CLI::App& app, command_list& commands);
void add_embed_command(CLI::App& app, command_list& commands);
void add_poincare_command(CLI::App& app, command_list& commands);
void add_analyze_command(CLI::App& app, command_list& commands);
void add_lyapunov_command(CLI::App& app, command_list& commands);
void add_floquet_command(CLI::App& app, command_list& commands);
void add_control_command(CLI::App& app, command_list& commands);
void add_rope_command(CLI::App& app, command_list& commands);
void add_partition_command(CLI::App& app, command_list& commands);
void add_map_command(CLI::App& app, command_list& commands);
void add_backbone_command(CLI::App& app, command_list& commands);
void add_corrections_command(CLI::App& app, command_list& commands);
void add_orbits_command(CLI::App& app, command_list& commands);
void add_orbit_command(CLI::App& app, command_list& commands);
void add_upo_command(CLI::App& app, command_list& commands);
void add_explore_command(CLI::App& app, command_list& commands);

}  // namespace npend::app
