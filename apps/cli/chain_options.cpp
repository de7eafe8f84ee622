#include "chain_options.hpp"

#include "input_parsing.hpp"

#include <fmt/format.h>

namespace npend::cli {

void chain_options::add_to(CLI::App& command, bool links_required) {
  command.add_option("--links,-n", links, "Number of links n")->required(links_required);
  command.add_option("--masses", masses, "Masses m_1,...,m_n in kg (default: all 1)");
  command.add_option("--lengths", lengths, "Rod lengths l_1,...,l_n in m (default: all 1)");
  command.add_option("--g", g, "Gravitational acceleration in m/s^2 (default: 9.81)");
}

chain chain_options::make_chain() const {
  if (links < 1) throw input_error(fmt::format("--links: must be at least 1, got {}", links));
  chain_parameters params = chain_parameters::uniform(links);
  const auto n = static_cast<std::size_t>(links);
  if (!masses.empty())
    params.masses = parse_number_list(masses, "--masses", n, fmt::format("m_1..m_{}", links));
  if (!lengths.empty())
    params.lengths = parse_number_list(lengths, "--lengths", n, fmt::format("l_1..l_{}", links));
  if (!g.empty()) params.g = parse_number(g, "--g");
  try {
    return chain(params);
  } catch (const std::invalid_argument& e) {
    throw input_error(e.what());
  }
}

std::vector<double> parse_state(const std::string& text, int links) {
  return parse_number_list(text, "--state", static_cast<std::size_t>(2 * links),
                           fmt::format("phi_1..phi_{0}, p_1..p_{0}", links));
}

}  // namespace npend::cli
