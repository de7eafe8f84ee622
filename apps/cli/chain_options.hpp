// The options every command shares: which chain (--links, --masses, --lengths, --g) and the
// physical chain's options (--com, --inertia, --rods, --stiffness, --rest-angles, --damping,
// --pivot), the cart's (--cart, --cart-damping), and which chains a command takes. The parsing and
// checks are the specification library's (npend/spec/chain_spec.hpp), which Python's npend.Chain
// shares.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "npend/chain.hpp"
#include "npend/spec/chain_spec.hpp"
#include "npend/spec/state_spec.hpp"

namespace npend::cli {

/// Which chains a command can take: its premise, checked once where the chain is made.
enum class model_support {
  any,           ///< every chain (simulate, eval)
  conservative,  ///< H must be conserved: no damping, a fixed pivot
  rigid_links,   ///< the paper's analyses at 0/π equilibria: rigid links at most
  canonical,     ///< the canonical ensemble: a conserved energy periodic in the angles
};

/// Raw text of the chain options, parsed strictly after CLI11 has collected them.
struct chain_options {
  int links = 0;
  std::string masses, lengths, g;
  std::string com, inertia, stiffness, rest_angles, damping, pivot;
  std::string cart, cart_damping;  ///< --cart MASS, --cart-damping B
  bool rods = false;
  bool no_rods = false;    ///< --no-rods: overrides "rods": true of a --chain file
  std::string chain_file;  ///< --chain FILE.json: the same parameters, under the JSON keys

  /// Adds --links (required unless `links_required` is false: for commands that can also
  /// read data instead), --masses, --lengths, --g and the physical chain's options to
  /// `command`.
  void add_to(CLI::App& command, bool links_required = true);

  /// The chain_spec of these options (without --chain FILE: see with_file). Throws
  /// input_error naming the option for text that is no list of numbers, and for --rods with
  /// --no-rods.
  spec::chain_spec to_spec() const;

  /// The chain they describe: defaults are masses 1 kg, lengths 1 m, g = 9.81 m/s², point
  /// masses on a fixed pivot. Throws input_error naming the bad value, including a link
  /// count that is not built, or a physical feature the command (`name`) cannot take —
  /// among them a cart, unless `takes_cart` (the command works on the state
  /// [x_c, phi, p_x, p] of a pendulum on a cart).
  chain make_chain(model_support support = model_support::rigid_links,
                   std::string_view name = "this command", bool takes_cart = false) const;

  /// These options with those of --chain FILE.json filled in where the command line left
  /// them empty (itself without a file); --rods or --no-rods override the file's "rods",
  /// "com" and "inertia". Throws input_error naming the file and the key for an unreadable
  /// file, bad JSON, a key given twice, an unknown key, a value of the wrong type, a list
  /// whose length is not the link count (refused while parsing once it is longer), or a
  /// link count other than --links.
  chain_options with_file() const;
};

using spec::parse_pivot;
using spec::parse_state;
using spec::per_link_values;

}  // namespace npend::cli
