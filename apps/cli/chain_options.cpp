#include "chain_options.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>

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

std::vector<double> per_link_values(std::vector<double> values, std::string_view option, int links,
                                    std::string_view symbol) {
  if (values.size() == 1) return std::vector<double>(static_cast<std::size_t>(links), values[0]);
  if (values.size() != static_cast<std::size_t>(links))
    throw input_error(
        fmt::format("{}: expected {} values ({}_1..{}_{}) or one for all links, "
                    "got {}",
                    option, links, symbol, symbol, links, values.size()));
  return values;
}

namespace {

std::vector<double> per_link(const std::string& text, std::string_view option, int links,
                             std::string_view symbol) {
  return per_link_values(parse_number_list(text, option), option, links, symbol);
}

}  // namespace

pivot_motion parse_pivot(const std::string& text) {
  const std::vector<std::string_view> parts = split_list(text, ':');
  if (parts.size() != 3 || (parts[0] != "vertical" && parts[0] != "horizontal"))
    throw input_error(
        fmt::format("--pivot: expected vertical:A:OMEGA or horizontal:A:OMEGA, got '{}'", text));
  const double a = parse_number(parts[1], "--pivot (amplitude)");
  const double w = parse_number(parts[2], "--pivot (angular frequency)");
  return parts[0] == "vertical" ? pivot_motion::vertical(a, w) : pivot_motion::horizontal(a, w);
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

// The keys of --chain FILE.json that hold per-link values (a number for every link, or a list
// of one per link), with their options and symbols.
struct list_key {
  const char* key;
  std::string chain_options::*member;
  const char* symbol;
};
constexpr const char* known_keys =
    "links, masses, lengths, g, com, inertia, rods, stiffness, rest_angles, damping, pivot";

const std::vector<list_key>& list_keys() {
  static const std::vector<list_key> keys{{"masses", &chain_options::masses, "m"},
                                          {"lengths", &chain_options::lengths, "l"},
                                          {"com", &chain_options::com, "c"},
                                          {"inertia", &chain_options::inertia, "J"},
                                          {"stiffness", &chain_options::stiffness, "k"},
                                          {"rest_angles", &chain_options::rest_angles, "theta"},
                                          {"damping", &chain_options::damping, "b"}};
  return keys;
}

const list_key* find_list_key(const std::string& key) {
  for (const auto& k : list_keys())
    if (key == k.key) return &k;
  return nullptr;
}

// What a key's value must be, for the message that refuses another.
std::string expected_value(const std::string& key) {
  if (key == "links") return "must be a whole number";
  if (key == "rods") return "must be true or false";
  if (key == "pivot") return "must be a string such as \"vertical:0.01:100\"";
  if (key == "g") return "must be a number";
  return "must be a number or a list of numbers";
}

// The file's JSON object, read with its checks made while parsing: a key given twice, an
// unknown key, a list nested in a list and a list longer than the link count are refused as
// soon as they are read (a long list costs no more than its first n + 1 items).
nlohmann::json parse_chain_json(std::istream& in, const std::string& file, int links) {
  std::set<std::string> seen;
  std::string key;     // the top-level key being read
  std::size_t items = 0;  // items read of its list
  const auto error = [&](const std::string& what) {
    return input_error(fmt::format("--chain {}: {}", file, what));
  };
  using event = nlohmann::json::parse_event_t;
  const nlohmann::json::parser_callback_t check = [&](int depth, event e, nlohmann::json& parsed) {
    if (depth == 0 && e != event::object_start && e != event::object_end)
      throw error("the file must hold one JSON object");
    if (depth == 1 && e == event::key) {
      key = parsed.get<std::string>();
      if (key != "links" && key != "rods" && key != "pivot" && key != "g" &&
          find_list_key(key) == nullptr)
        throw error(fmt::format("unknown key \"{}\" (known: {})", key, known_keys));
      if (!seen.insert(key).second) throw error(fmt::format("\"{}\" is given twice", key));
      items = 0;
    } else if (depth == 1 && e == event::object_start) {
      throw error(fmt::format("\"{}\" {}", key, expected_value(key)));
    } else if (depth == 1 && e == event::array_start && find_list_key(key) == nullptr) {
      throw error(fmt::format("\"{}\" {}", key, expected_value(key)));
    } else if (depth >= 2 && (e == event::object_start || e == event::array_start)) {
      throw error(fmt::format("\"{}\" {}", key, expected_value(key)));
    } else if (depth == 2 && e == event::value && ++items > static_cast<std::size_t>(links)) {
      const list_key* k = find_list_key(key);
      throw error(fmt::format(
          "\"{}\": expected {} values ({}_1..{}_{}) or one number for all links, got a longer list",
          key, links, k->symbol, k->symbol, links));
    }
    return true;
  };
  try {
    return nlohmann::json::parse(in, check);
  } catch (const nlohmann::json::exception& e) {
    throw error(fmt::format("not valid JSON ({})", e.what()));
  }
}

// A JSON number, or a list of n numbers, as the text the command-line option would carry.
std::string option_text(const nlohmann::json& value, const list_key& k, int links,
                        const std::string& file) {
  const auto number = [&](const nlohmann::json& v) {
    if (!v.is_number())
      throw input_error(fmt::format("--chain {}: \"{}\" must be a number or a list of numbers",
                                    file, k.key));
    return fmt::format("{}", v.get<double>());
  };
  if (!value.is_array()) return number(value);
  // A list has one value per link; one number (not a list of one) stands for all links.
  if (value.size() != static_cast<std::size_t>(links))
    throw input_error(fmt::format(
        "--chain {}: \"{}\": expected {} values ({}_1..{}_{}) or one number for all links, got a "
        "list of {}",
        file, k.key, links, k.symbol, k.symbol, links, value.size()));
  std::string out;
  for (const auto& v : value) out += (out.empty() ? "" : ",") + number(v);
  return out;
}

}  // namespace

chain_options chain_options::with_file() const {
  if (chain_file.empty()) return *this;
  std::ifstream in = open_input_file(chain_file, "--chain");
  const nlohmann::json j = parse_chain_json(in, chain_file, links);
  const auto error = [&](const std::string& what) {
    return input_error(fmt::format("--chain {}: {}", chain_file, what));
  };
  chain_options merged = *this;
  // Each key fills its option unless the command line gave that option.
  for (const auto& [key, value] : j.items()) {
    if (const list_key* k = find_list_key(key)) {
      const std::string text = option_text(value, *k, links, chain_file);
      if ((merged.*(k->member)).empty()) merged.*(k->member) = text;
    } else if (key == "links") {
      if (!value.is_number_integer()) throw error("\"links\" must be a whole number");
      if (value.get<long long>() != links)
        throw error(fmt::format("the file describes {} links, the command line asks for {}",
                                value.dump(), links));
    } else if (key == "g") {
      if (!value.is_number()) throw error("\"g\" must be a number");
      if (merged.g.empty()) merged.g = fmt::format("{}", value.get<double>());
    } else if (key == "rods") {
      if (!value.is_boolean()) throw error("\"rods\" must be true or false");
    } else if (key == "pivot") {
      if (!value.is_string())
        throw error("\"pivot\" must be a string such as \"vertical:0.01:100\"");
      if (merged.pivot.empty()) merged.pivot = value.get<std::string>();
    }
  }
  // "rods" stands for com and inertia: the command line's --rods overrides all three keys,
  // its --no-rods the file's "rods", and its --com or --inertia cannot be mixed with the
  // file's rods.
  const bool file_rods = j.contains("rods") && j["rods"].get<bool>();
  if (rods && no_rods) throw input_error("--rods and --no-rods exclude each other");
  if (rods) {
    merged.com = com;
    merged.inertia = inertia;
  } else if (file_rods && !no_rods) {
    if (j.contains("com") || j.contains("inertia"))
      throw error("\"rods\": true sets the centres of mass and inertias: leave out \"com\" and "
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

chain chain_options::make_chain(model_support support, std::string_view name,
                                bool takes_cart) const {
  if (links < 1) throw input_error(fmt::format("--links: must be at least 1, got {}", links));
  if (!chain_file.empty()) return with_file().make_chain(support, name, takes_cart);
  if (rods && no_rods) throw input_error("--rods and --no-rods exclude each other");
  chain_parameters params = chain_parameters::uniform(links);
  if (!masses.empty()) params.masses = per_link(masses, "--masses", links, "m");
  if (!lengths.empty()) params.lengths = per_link(lengths, "--lengths", links, "l");
  if (!g.empty()) params.g = parse_number(g, "--g");
  if (rods && (!com.empty() || !inertia.empty()))
    throw input_error(
        "--rods sets the centres of mass and inertias: leave out --com and --inertia");
  if (rods) params.make_uniform_rods();
  if (!com.empty()) params.com = per_link(com, "--com", links, "c");
  if (!inertia.empty()) params.inertia = per_link(inertia, "--inertia", links, "J");
  if (!stiffness.empty()) params.stiffness = per_link(stiffness, "--stiffness", links, "k");
  if (!rest_angles.empty())
    params.rest_angles = per_link(rest_angles, "--rest-angles", links, "theta");
  if (!damping.empty()) params.damping = per_link(damping, "--damping", links, "b");
  // A rest angle only shifts a spring's zero: without any spring it would be ignored.
  if (!rest_angles.empty() &&
      std::none_of(params.stiffness.begin(), params.stiffness.end(), [](double k) { return k > 0; }))
    throw input_error(
        "--rest-angles: the rest angles of the joint springs need springs: give --stiffness "
        "(without it they change nothing)");
  if (!pivot.empty()) params.pivot = parse_pivot(pivot);
  if (!cart_damping.empty() && cart.empty())
    throw input_error("--cart-damping: the cart's damping needs a cart: give --cart MASS");
  if (!cart.empty()) {
    if (!takes_cart)
      throw input_error(fmt::format(
          "{} does not take --cart: it works on the angles of a chain on a fixed pivot (npend "
          "simulate, eval and control take a cart)",
          name));
    if (!pivot.empty())
      throw input_error("--cart and --pivot exclude each other: the chain hangs from the cart");
    params.cart_mass = parse_number(cart, "--cart");
    if (!(*params.cart_mass > 0) || !std::isfinite(*params.cart_mass))
      throw input_error(fmt::format("--cart: the cart's mass must be a positive finite number "
                                    "(kg), got {}",
                                    cart));
  }
  if (!cart_damping.empty()) {
    params.cart_damping = parse_number(cart_damping, "--cart-damping");
    if (!(params.cart_damping >= 0) || !std::isfinite(params.cart_damping))
      throw input_error(fmt::format(
          "--cart-damping: the cart's damping must be a finite number >= 0 (N s/m), got {}",
          cart_damping));
  }
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

std::vector<double> parse_state(const std::string& text, const chain& c) {
  const int n = c.links();
  return parse_number_list(text, "--state", static_cast<std::size_t>(c.state_size()),
                           c.has_cart() ? fmt::format("x_c, phi_1..phi_{0}, p_x, p_1..p_{0}", n)
                                        : fmt::format("phi_1..phi_{0}, p_1..p_{0}", n));
}

}  // namespace npend::cli
