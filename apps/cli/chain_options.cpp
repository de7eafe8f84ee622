#include "chain_options.hpp"

#include <fmt/format.h>

#include "input_parsing.hpp"

namespace npend::cli {

void chain_options::add_to(CLI::App& command, bool links_required) {
  command.add_option("--links,-n", links, "Number of links n")->required(links_required);
  command.add_option("--masses", masses,
                     "Masses m_1,...,m_n in kg, or one value for all links (default: all 1)");
  command.add_option("--lengths", lengths,
                     "Rod lengths l_1,...,l_n in m, or one value for all links (default: all 1)");
  command.add_option("--g", g, "Gravitational acceleration in m/s^2 (default: 9.81)");
}

namespace {

// n values, or one for every link (a long chain cannot be typed out link by link).
std::vector<double> per_link(const std::string& text, std::string_view option, int links,
                             std::string_view symbol) {
  const std::vector<double> values = parse_number_list(text, option);
  if (values.size() == 1) return std::vector<double>(static_cast<std::size_t>(links), values[0]);
  if (values.size() != static_cast<std::size_t>(links))
    throw input_error(
        fmt::format("{}: expected {} values ({}_1..{}_{}) or one for all links, "
                    "got {}",
                    option, links, symbol, symbol, links, values.size()));
  return values;
}

}  // namespace

chain chain_options::make_chain() const {
  if (links < 1) throw input_error(fmt::format("--links: must be at least 1, got {}", links));
  chain_parameters params = chain_parameters::uniform(links);
  if (!masses.empty()) params.masses = per_link(masses, "--masses", links, "m");
  if (!lengths.empty()) params.lengths = per_link(lengths, "--lengths", links, "l");
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
