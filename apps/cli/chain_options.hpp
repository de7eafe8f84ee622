// The options every command shares: which chain (--links, --masses, --lengths, --g).
#pragma once

#include "npend/chain.hpp"

#include <CLI/CLI.hpp>

#include <string>

namespace npend::cli {

/// Raw text of the chain options, parsed strictly after CLI11 has collected them.
struct chain_options {
  int links = 0;
  std::string masses, lengths, g;

  /// Adds --links (required unless `links_required` is false: for commands that can also
  /// read data instead), --masses, --lengths and --g to `command`.
  void add_to(CLI::App& command, bool links_required = true);

  /// The chain they describe: defaults are masses 1 kg, lengths 1 m, g = 9.81 m/s².
  /// Throws input_error naming the bad value, including a link count that is not built.
  chain make_chain() const;
};

/// The state given as "--state phi_1..phi_n,p_1..p_n" (dim 2n).
std::vector<double> parse_state(const std::string& text, int links);

}  // namespace npend::cli
