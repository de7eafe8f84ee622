// A chain as users describe it — the command line's --links, --masses, ..., --chain FILE.json
// and Python's npend.Chain(links, masses=..., ...) — and the checks that turn it into
// chain_parameters. Both front ends fill one chain_spec, so a new parameter is one member
// here, one key in chain_spec.cpp and one option or keyword in each front end.
#pragma once

#include <iosfwd>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "npend/chain.hpp"
#include "npend/parameters.hpp"
#include "npend/spec/input_error.hpp"

namespace npend::spec {

/// How messages name a chain's parameters: as the command line's options ("--rest-angles")
/// or as Python's keywords, which are also the keys of a chain file ("rest_angles").
enum class naming { options, keywords };

/// The parameter `key` (a chain file's key: "rest_angles") as `names` spells it:
/// "--rest-angles" or "rest_angles".
std::string argument_name(std::string_view key, naming names);

/// What the user gave for a chain; everything left out takes its default. Each per-link list
/// is empty (left out), one value for every link (a long chain cannot be typed out link by
/// link) or one value per link.
struct chain_spec {
  int links = 0;                       ///< n ≥ 1
  std::vector<double> masses;          ///< m_i in kg (default 1)
  std::vector<double> lengths;         ///< l_i in m (default 1)
  std::optional<double> g;             ///< m/s² (default standard_gravity)
  std::vector<double> com;             ///< c_i in m down link i (default l_i)
  std::vector<double> inertia;         ///< J_i in kg m² about the centre of mass (default 0)
  bool rods = false;                   ///< uniform rods: c = l/2, J = m l²/12
  std::vector<double> stiffness;       ///< k_j in N m/rad at joint j (default 0)
  std::vector<double> rest_angles;     ///< θ_j⁰ in rad of the joint springs (default 0)
  std::vector<double> damping;         ///< b_j in N m s/rad at joint j (default 0)
  std::string pivot;                   ///< "" (fixed), vertical:A:OMEGA or horizontal:A:OMEGA
  std::optional<double> cart;          ///< M in kg: the chain hangs from a cart on the x axis
  std::optional<double> cart_damping;  ///< b_x in N s/m, the cart's viscous damping (default 0)
};

/// A per-link list of chain_spec: its key (a chain file's key, Python's keyword) and the
/// symbol of its values in messages (m for m_1..m_n).
struct per_link_key {
  const char* key;
  std::vector<double> chain_spec::*member;
  const char* symbol;
};

/// The per-link lists in the order they are checked: masses, lengths, com, inertia,
/// stiffness, rest_angles, damping.
std::span<const per_link_key> per_link_keys();

/// The per_link_key of `key`, or nullptr.
const per_link_key* find_per_link_key(std::string_view key);

/// A per-link parameter (symbol m, l, c, J, k, theta, b) given as n values, or as one value
/// for every link: the n values. Throws input_error naming `option` for any other count.
std::vector<double> per_link_values(std::vector<double> values, std::string_view option, int links,
                                    std::string_view symbol);

/// "vertical:A:OMEGA" or "horizontal:A:OMEGA" (amplitude A in m, angular frequency OMEGA in
/// rad/s); `option` names it in messages. Throws input_error otherwise.
pivot_motion parse_pivot(std::string_view text, std::string_view option = "--pivot");

/// Refuses a link count below 1: throws input_error naming `links` as `names` spells it.
void check_links(int links, naming names);

/// The parameters `spec` describes: masses 1 kg, lengths 1 m, g = 9.81 m/s², point masses on
/// a fixed pivot unless given. Throws input_error naming the parameter as `names` spells it:
/// a link count below 1, a list of another count, rods with centres of mass or inertias,
/// rest angles without any spring, a pivot that is not a drive, a cart's mass that is not
/// positive and finite, its damping below 0 or without a cart, a cart with a moving pivot. The
/// values themselves are checked by chain_parameters::validate (in the chain's constructor).
chain_parameters make_parameters(const chain_spec& spec, naming names);

/// chain(make_parameters(spec, names)), the chain's refusal of its parameters (a link count
/// not built, a singular mass matrix, ...) as input_error with the same message.
chain make_chain(const chain_spec& spec, naming names);

/// The keys a chain file may hold, for messages: "links, masses, lengths, g, ...".
std::string_view chain_file_keys();

/// The chain of a chain file: one JSON object with the keys of chain_file_keys() — links a
/// whole number (it must equal `links`), g a number, rods true or false, pivot a string, and
/// each per-link key one number for every link or a list of one per link. Checked while
/// parsing, so a long list costs no more than its first n + 1 items. Throws input_error,
/// its message starting with `source` (e.g. "--chain FILE"), for text that is not one JSON
/// object, a key given twice, an unknown key, a value of the wrong type, a list whose length
/// is not `links`, or another link count.
chain_spec read_chain_file(std::istream& in, std::string_view source, int links);

/// `values` as a list option carries them: "1,0.5,2" (each number as the shortest text that
/// reads back as the same double).
std::string format_values(const std::vector<double>& values);

}  // namespace npend::spec
