#include "chain_options.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <fstream>

#include "input_file.hpp"
#include "input_parsing.hpp"

namespace npend::cli {

void chain_options::add_to(CLI::App& command, bool links_required) {
  command.add_option("--links,-n", links, "Number of links n")->required(links_required);
  command.add_option("--masses", masses,
                     "Masses m_1,...,m_n in kg, or one value for all links (default: all 1)");
  command.add_option("--lengths", lengths,
                     "Rod lengths l_1,...,l_n in m, or one value for all links (default: all 1)");
  command.add_option("--g", g, "Gravitational acceleration in m/s^2 (default: 9.81)");
  // The physical chain (docs/model.md): one value per link, or one for all links.
  command.add_option("--com", com,
                     "Physical chain: centre of mass of each link, c_i in m down the link from "
                     "its upper joint (default: c = l, the mass at the link's end)");
  command.add_option("--inertia", inertia,
                     "Physical chain: moment of inertia J_i of each link about its centre of "
                     "mass in kg m^2 (default: 0)");
  command.add_flag("--rods", rods,
                   "Physical chain: uniform rods, c = l/2 and J = m l^2/12 (instead of --com and "
                   "--inertia)");
  command.add_flag("--no-rods", no_rods,
                   "Physical chain: not uniform rods, whatever --chain FILE says (the command "
                   "line overrides the file)");
  command.add_option("--stiffness", stiffness,
                     "Physical chain: torsion spring k_j at joint j in N m/rad on the joint angle "
                     "phi_j - phi_(j-1) (default: 0)");
  command.add_option("--rest-angles", rest_angles,
                     "Physical chain: rest angles of the joint springs in rad (default: 0)");
  command.add_option("--damping", damping,
                     "Physical chain: viscous damping b_j at joint j in N m s/rad (default: 0)");
  command.add_option("--chain", chain_file,
                     "A JSON file with the chain's parameters (keys links, masses, lengths, g, "
                     "com, inertia, rods, stiffness, rest_angles, damping, pivot; docs/model.md); "
                     "options given on the command line override it");
  command.add_option("--pivot", pivot,
                     "Physical chain: the pivot moves, vertical:A:OMEGA (its height A cos(OMEGA "
                     "t)) or horizontal:A:OMEGA; A in m, OMEGA in rad/s");
  command.add_option("--cart", cart,
                     "Pendulum on a cart: the chain hangs from a cart of mass M in kg that rolls "
                     "along x; the state is x_c,phi_1..phi_n,p_x,p_1..p_n");
  command.add_option("--cart-damping", cart_damping,
                     "Pendulum on a cart: the cart's viscous damping b_x in N s/m (default: 0)");
}

namespace {

// The physical options given, by name, for a message.
std::vector<std::string> features_outside(const chain_parameters& p, model_support support) {
  std::vector<std::string> out;
  if (support == model_support::any) return out;
  if (std::any_of(p.damping.begin(), p.damping.end(), [](double b) { return b != 0; }))
    out.push_back("--damping");
  if (p.cart_damping != 0) out.push_back("--cart-damping");
  if (p.pivot.moves()) out.push_back("--pivot");
  if (support == model_support::rigid_links || support == model_support::canonical) {
    if (std::any_of(p.stiffness.begin(), p.stiffness.end(), [](double k) { return k != 0; }))
      out.push_back("--stiffness");
    if (std::any_of(p.rest_angles.begin(), p.rest_angles.end(), [](double a) { return a != 0; }))
      out.push_back("--rest-angles");
  }
  return out;
}

// Why a command of this support refuses the features features_outside lists.
const char* refusal_reason(model_support support) {
  switch (support) {
    case model_support::conservative:
      return "it relies on a conserved energy (no damping, a fixed pivot)";
    case model_support::canonical:
      return "the canonical ensemble needs a conserved energy periodic in the angles (no joint "
             "springs, damping or moving pivot)";
    default:
      return "its equilibria are those of gravity at 0 and pi, without joint springs, damping "
             "or a moving pivot (npend simulate and eval take every chain)";
  }
}

// The text member of each per-link list of chain_spec, by its key.
std::string chain_options::*text_of(std::string_view key) {
  static const std::pair<std::string_view, std::string chain_options::*> members[] = {
      {"masses", &chain_options::masses},
      {"lengths", &chain_options::lengths},
      {"com", &chain_options::com},
      {"inertia", &chain_options::inertia},
      {"stiffness", &chain_options::stiffness},
      {"rest_angles", &chain_options::rest_angles},
      {"damping", &chain_options::damping}};
  for (const auto& [k, member] : members)
    if (k == key) return member;
  throw std::logic_error(fmt::format("chain_options: no option for the list \"{}\"", key));
}

}  // namespace

chain_options chain_options::with_file() const {
  if (chain_file.empty()) return *this;
  std::ifstream in = open_input_file(chain_file, "--chain");
  const spec::chain_spec file = spec::read_chain_file(in, "--chain " + chain_file, links);
  const auto error = [&](const std::string& what) {
    return input_error(fmt::format("--chain {}: {}", chain_file, what));
  };
  chain_options merged = *this;
  // Each key fills its option unless the command line gave that option.
  for (const spec::per_link_key& k : spec::per_link_keys()) {
    std::string& text = merged.*text_of(k.key);
    if (text.empty()) text = spec::format_values(file.*(k.member));
  }
  if (merged.g.empty() && file.g) merged.g = fmt::format("{}", *file.g);
  if (merged.pivot.empty()) merged.pivot = file.pivot;
  if (merged.cart.empty() && file.cart) merged.cart = fmt::format("{}", *file.cart);
  if (merged.cart_damping.empty() && file.cart_damping)
    merged.cart_damping = fmt::format("{}", *file.cart_damping);
  // "rods" stands for com and inertia: the command line's --rods overrides all three keys,
  // its --no-rods the file's "rods", and its --com or --inertia cannot be mixed with the
  // file's rods.
  if (rods && no_rods) throw input_error("--rods and --no-rods exclude each other");
  if (rods) {
    merged.com = com;
    merged.inertia = inertia;
  } else if (file.rods && !no_rods) {
    if (!file.com.empty() || !file.inertia.empty())
      throw error(
          "\"rods\": true sets the centres of mass and inertias: leave out \"com\" and "
          "\"inertia\"");
    if (!com.empty() || !inertia.empty())
      throw input_error(fmt::format(
          "{}: the chain file {} has \"rods\": true, which sets the centres of mass and "
          "inertias; add --no-rods to give them on the command line",
          com.empty() ? "--inertia" : "--com", chain_file));
    merged.rods = true;
  }
  merged.chain_file.clear();
  return merged;
}

spec::chain_spec chain_options::to_spec() const {
  if (rods && no_rods) throw input_error("--rods and --no-rods exclude each other");
  spec::chain_spec s;
  s.links = links;
  for (const spec::per_link_key& k : spec::per_link_keys()) {
    const std::string& text = this->*text_of(k.key);
    if (!text.empty())
      s.*(k.member) = parse_number_list(text, spec::argument_name(k.key, spec::naming::options));
  }
  if (!g.empty()) s.g = parse_number(g, "--g");
  s.rods = rods;
  s.pivot = pivot;
  if (!cart.empty()) s.cart = parse_number(cart, "--cart");
  if (!cart_damping.empty()) s.cart_damping = parse_number(cart_damping, "--cart-damping");
  return s;
}

chain chain_options::make_chain(model_support support, std::string_view name,
                                bool takes_cart) const {
  // Before the file, whose lists are checked against the link count.
  spec::check_links(links, spec::naming::options);
  const chain_options merged = with_file();
  if (!merged.cart.empty() && !takes_cart)
    throw input_error(fmt::format(
        "{} does not take --cart: it works on the angles of a chain on a fixed pivot (npend "
        "simulate, eval, control and lyapunov take a cart)",
        name));
  const chain_parameters params = spec::make_parameters(merged.to_spec(), spec::naming::options);
  const std::vector<std::string> refused = features_outside(params, support);
  if (!refused.empty())
    throw input_error(fmt::format("{} does not take {}: {}", name, fmt::join(refused, ", "),
                                  refusal_reason(support)));
  try {
    return chain(params);
  } catch (const std::invalid_argument& e) {
    throw input_error(e.what());
  }
}

}  // namespace npend::cli
