// npend equilibria: all 2^n equilibria of the chain with their energy, Jacobian eigenvalues and
// stability (paper §6.4), or those asked for.
#include <fmt/format.h>

#include <iostream>
#include <nlohmann/json.hpp>
#include <numbers>

#include "chain_options.hpp"
#include "command.hpp"
#include "dense_modes.hpp"
#include "input_parsing.hpp"
#include "npend/analysis/stability/equilibria.hpp"
#include "series_output.hpp"
#include "stability_tables.hpp"

namespace npend::app {

namespace {

struct equilibria_options {
  cli::chain_options chain;
  std::vector<std::string> at;
  bool json = false;
};

// The equilibria asked for with --at; without it all 2^n, or for a chain too long to list
// them the hanging and the standing one.
std::vector<equilibrium> chosen_equilibria(const chain& c, const std::vector<std::string>& at) {
  const int n = c.links();
  std::vector<std::vector<double>> chosen;
  for (const auto& text : at) chosen.push_back(cli::parse_angle_list(text, "--at", n));
  if (chosen.empty()) {
    if (n <= max_equilibria_links) return find_equilibria(c);
    chosen = {std::vector<double>(static_cast<std::size_t>(n), 0.0),
              std::vector<double>(static_cast<std::size_t>(n), std::numbers::pi)};
  }
  std::vector<equilibrium> out;
  for (auto& angles : chosen) {
    try {
      out.push_back(classify_equilibrium(c, std::move(angles)));
    } catch (const std::invalid_argument& e) {
      throw cli::input_error(fmt::format("--at: {}", e.what()));
    }
  }
  return out;
}

int run_equilibria(const equilibria_options& o) {
  const chain c = o.chain.make_chain(cli::model_support::rigid_links, "npend equilibria");
  if (c.links() > max_equilibria_links)
    require_dense_modes(c, o.at.empty() ? 2.0 : static_cast<double>(o.at.size()),
                        "the linear stability");
  const auto eqs = chosen_equilibria(c, o.at);
  if (o.json) {
    nlohmann::json list = nlohmann::json::array();
    for (const auto& e : eqs) {
      list.push_back({{"angles", e.angles},
                      {"energy", e.energy},
                      {"eigenvalues", json_complex_list(e.eigenvalues)},
                      {"stable", e.stable},
                      {"unstable_directions", e.unstable_directions}});
    }
    std::cout << nlohmann::json{{"links", c.links()}, {"equilibria", list}}.dump(2) << "\n";
    return 0;
  }
  print_equilibria_table(c, eqs);
  return 0;
}

}  // namespace

void add_equilibria_command(CLI::App& app, command_list& commands) {
  auto o = std::make_shared<equilibria_options>();
  CLI::App* cmd = app.add_subcommand(
      "equilibria", "All 2^n equilibria with their energy, Jacobian eigenvalues and stability");
  o->chain.add_to(*cmd);
  cmd->add_option("--at", o->at,
                  "Only this equilibrium, phi_1,...,phi_n each 0 or pi (one value for all "
                  "links); repeat for several (default: all 2^n up to 16 links, the hanging "
                  "and the standing chain beyond)");
  cmd->add_flag("--json", o->json, "Print JSON");
  commands.push_back({cmd, [o] { return run_equilibria(*o); }});
}

}  // namespace npend::app
