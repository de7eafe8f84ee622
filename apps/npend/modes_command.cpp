// npend modes: the normal modes of the linearisation around an equilibrium (paper §6.4).
#include <fmt/format.h>

#include <iostream>
#include <nlohmann/json.hpp>

#include "chain_options.hpp"
#include "command.hpp"
#include "dense_modes.hpp"
#include "input_parsing.hpp"
#include "npend/analysis/stability/normal_modes.hpp"
#include "stability_tables.hpp"

namespace npend::app {

namespace {

struct modes_options {
  cli::chain_options chain;
  std::string at;
  bool json = false;
};

int run_modes(const modes_options& o) {
  const chain c = o.chain.make_chain(cli::model_support::rigid_links, "npend modes");
  require_dense_modes(c, 1, "the normal modes");
  const int n = c.links();
  std::vector<double> at(static_cast<std::size_t>(n), 0.0);
  if (!o.at.empty()) at = cli::parse_angle_list(o.at, "--at", n);
  linearisation lin;
  try {
    lin = normal_modes(c, at);
  } catch (const std::invalid_argument& e) {
    throw cli::input_error(fmt::format("--at: {}", e.what()));
  }
  if (o.json) {
    nlohmann::json shapes = nlohmann::json::array(), omega2 = nlohmann::json::array(),
                   freq = nlohmann::json::array(), growth = nlohmann::json::array();
    for (const auto& m : lin.modes) {
      shapes.push_back(m.shape);
      omega2.push_back(m.omega_squared);
      if (m.omega_squared > 0)
        freq.push_back(m.frequency);
      else
        growth.push_back(m.growth_rate);
    }
    nlohmann::json j{{"links", n},
                     {"at", lin.angles},
                     {"omega_squared", omega2},
                     {"frequencies", freq},
                     {"growth_rates", growth},
                     {"shapes", shapes},
                     {"mass_matrix", lin.mass_matrix},
                     {"stiffness_matrix", lin.stiffness_matrix}};
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  print_modes_table(lin);
  return 0;
}

}  // namespace

void add_modes_command(CLI::App& app, command_list& commands) {
  auto o = std::make_shared<modes_options>();
  CLI::App* cmd = app.add_subcommand(
      "modes", "Normal modes of the linearisation M y'' + K y = 0 around an equilibrium");
  o->chain.add_to(*cmd);
  cmd->add_option("--at", o->at,
                  "The equilibrium phi_1,...,phi_n, each 0 or pi (one value for all links; "
                  "default: hanging)");
  cmd->add_flag("--json", o->json, "Print JSON");
  commands.push_back({cmd, [o] { return run_modes(*o); }});
}

}  // namespace npend::app
