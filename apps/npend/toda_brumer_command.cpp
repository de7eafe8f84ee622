// npend toda-brumer: the Toda-Brumer criterion of local instability and the critical energies
// (paper §6.5).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <nlohmann/json.hpp>
#include <numbers>

#include "chain_options.hpp"
#include "command.hpp"
#include "input_parsing.hpp"
#include "npend/analysis/chaos/toda_brumer.hpp"

namespace npend::app {

namespace {

struct toda_options {
  cli::chain_options chain;
  std::string phi, fixed;
  bool json = false;
};

std::vector<int> parse_fixed(const std::string& text, int links) {
  std::vector<int> out;
  if (text.empty()) return out;
  for (const double v : cli::parse_number_list(text, "--fixed")) {
    if (!cli::is_whole_number(v, 1, links))
      throw cli::input_error(fmt::format("--fixed: {} is not a link number 1..{}", v, links));
    out.push_back(static_cast<int>(v));
  }
  return out;
}

int run_toda(const toda_options& o) {
  const chain c = o.chain.make_chain(cli::model_support::rigid_links, "npend toda-brumer");
  const int n = c.links();
  const auto links = toda_brumer_links(c);
  const std::vector<int> fixed = parse_fixed(o.fixed, n);
  if (static_cast<int>(fixed.size()) >= n && !fixed.empty()) {
    std::vector<bool> seen(static_cast<std::size_t>(n), false);
    for (int k : fixed) seen[static_cast<std::size_t>(k - 1)] = true;
    if (std::all_of(seen.begin(), seen.end(), [](bool b) { return b; }))
      throw cli::input_error("--fixed: every link is fixed; leave at least one free");
  }
  const double critical = toda_brumer_critical_energy(c, fixed);
  std::vector<double> lambda;
  bool unstable = false;
  if (!o.phi.empty()) {
    const auto phi = cli::parse_number_list(o.phi, "--phi", static_cast<std::size_t>(n),
                                            fmt::format("phi_1..phi_{}", n));
    lambda = toda_brumer_eigenvalues(c, phi);
    unstable = lambda.back() > 0;
  }
  if (o.json) {
    nlohmann::json list = nlohmann::json::array();
    for (const auto& l : links)
      list.push_back({{"link", l.link},
                      {"curvature", l.curvature},
                      {"unstable_interval", {std::numbers::pi / 2, 3 * std::numbers::pi / 2}},
                      {"critical_energy", l.critical_energy}});
    nlohmann::json j{
        {"links", n}, {"per_link", list}, {"fixed", fixed}, {"critical_energy", critical}};
    if (!lambda.empty()) {
      j["eigenvalues"] = lambda;
      j["unstable"] = unstable;
    }
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  fmt::print(
      "Toda-Brumer: eigenvalues of -d2V/dphi2 are Lambda_k = -g mu_k l_k cos(phi_k); some\n"
      "Lambda_k > 0 (pi/2 < phi_k < 3pi/2 mod 2pi) marks a locally unstable region.\n\n");
  fmt::print("{:>5}  {:>18}  {:>28}\n", "link", "g mu_k l_k (J)", "E_c entering from rest (J)");
  for (const auto& l : links)
    fmt::print("{:>5}  {:>18.6g}  {:>28.6g}\n", l.link, l.curvature, l.critical_energy);
  std::string family = "p = 0";
  for (int k : fixed) family += fmt::format(", phi_{} = 0", k);
  fmt::print("\nCritical energy for the family {}: E_c = {:.6g} J\n", family, critical);
  if (!lambda.empty()) {
    std::string values;
    for (double v : lambda) values += fmt::format(" {:.6g}", v);
    fmt::print("At phi = ({}): Lambda ={}; {}\n", o.phi, values,
               unstable ? "in a locally unstable region" : "locally stable");
  }
  return 0;
}

}  // namespace

void add_toda_brumer_command(CLI::App& app, command_list& commands) {
  auto o = std::make_shared<toda_options>();
  CLI::App* cmd = app.add_subcommand(
      "toda-brumer", "Toda-Brumer criterion: unstable regions and critical energies");
  o->chain.add_to(*cmd);
  cmd->add_option("--phi", o->phi, "Evaluate the eigenvalues Lambda at phi_1,...,phi_n");
  cmd->add_option("--fixed", o->fixed,
                  "Links held at phi = 0 for the critical energy of a family, e.g. 1,2");
  cmd->add_flag("--json", o->json, "Print JSON");
  commands.push_back({cmd, [o] { return run_toda(*o); }});
}

}  // namespace npend::app
