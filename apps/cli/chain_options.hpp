// The options every command shares: which chain (--links, --masses, --lengths, --g), the
// physical chain's options (--com, --inertia, --rods, --stiffness, --rest-angles, --damping,
// --pivot) and the cart's (--cart, --cart-damping).
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "npend/chain.hpp"

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
  bool no_rods = false;  ///< --no-rods: overrides "rods": true of a --chain file
  std::string chain_file;  ///< --chain FILE.json: the same parameters, under the JSON keys

  /// Adds --links (required unless `links_required` is false: for commands that can also
  /// read data instead), --masses, --lengths, --g and the physical chain's options to
  /// `command`.
  void add_to(CLI::App& command, bool links_required = true);

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

/// A per-link parameter (symbol m, l, c, J, k, theta, b) given as n values, or as one value
/// for every link (a long chain cannot be typed out link by link). Throws input_error
/// naming `option` for any other count.
std::vector<double> per_link_values(std::vector<double> values, std::string_view option, int links,
                                    std::string_view symbol);

/// "vertical:A:OMEGA" or "horizontal:A:OMEGA" (amplitude in m, angular frequency in rad/s).
pivot_motion parse_pivot(const std::string& text);

/// The state of chain `c` given as "--state phi_1..phi_n,p_1..p_n" (dim 2n), on a cart
/// "--state x_c,phi_1..phi_n,p_x,p_1..p_n" (dim 2(n + 1)).
std::vector<double> parse_state(const std::string& text, const chain& c);

}  // namespace npend::cli
