#include "chain_options.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>

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
  if (p.is_damped()) out.push_back("--damping");
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

// A JSON number or list of numbers as the text the command-line option would carry.
std::string option_text(const nlohmann::json& value, const std::string& key) {
  const auto number = [&](const nlohmann::json& v) {
    if (!v.is_number())
      throw input_error(fmt::format("--chain: \"{}\" must be a number or a list of numbers", key));
    return fmt::format("{}", v.get<double>());
  };
  if (!value.is_array()) return number(value);
  std::string out;
  for (const auto& v : value) out += (out.empty() ? "" : ",") + number(v);
  if (out.empty()) throw input_error(fmt::format("--chain: \"{}\" is an empty list", key));
  return out;
}

}  // namespace

chain_options chain_options::with_file() const {
  if (chain_file.empty()) return *this;
  std::ifstream in = open_input_file(chain_file, "--chain");
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw input_error(fmt::format("--chain: '{}' is not valid JSON ({})", chain_file, e.what()));
  }
  if (!j.is_object())
    throw input_error(fmt::format("--chain: '{}' must hold one JSON object", chain_file));
  chain_options merged = *this;
  // Each key fills its option unless the command line gave that option.
  const std::pair<const char*, std::string chain_options::*> lists[] = {
      {"masses", &chain_options::masses},
      {"lengths", &chain_options::lengths},
      {"g", &chain_options::g},
      {"com", &chain_options::com},
      {"inertia", &chain_options::inertia},
      {"stiffness", &chain_options::stiffness},
      {"rest_angles", &chain_options::rest_angles},
      {"damping", &chain_options::damping}};
  for (const auto& [key, value] : j.items()) {
    bool known = false;
    for (const auto& [name, member] : lists)
      if (key == name) {
        known = true;
        if ((merged.*member).empty()) merged.*member = option_text(value, key);
      }
    if (key == "links") {
      known = true;
      if (!value.is_number_integer())
        throw input_error("--chain: \"links\" must be a whole number");
      if (value.get<int>() != links)
        throw input_error(
            fmt::format("--chain: the file describes {} links, the command line asks for {}",
                        value.get<int>(), links));
    } else if (key == "rods") {
      known = true;
      if (!value.is_boolean()) throw input_error("--chain: \"rods\" must be true or false");
      merged.rods = merged.rods || value.get<bool>();
    } else if (key == "pivot") {
      known = true;
      if (!value.is_string())
        throw input_error("--chain: \"pivot\" must be a string such as \"vertical:0.01:100\"");
      if (merged.pivot.empty()) merged.pivot = value.get<std::string>();
    }
    if (!known)
      throw input_error(fmt::format(
          "--chain: unknown key \"{}\" (known: links, masses, lengths, g, com, inertia, rods, "
          "stiffness, rest_angles, damping, pivot)",
          key));
  }
  merged.chain_file.clear();
  return merged;
}

chain chain_options::make_chain(model_support support, std::string_view name) const {
  if (!chain_file.empty()) return with_file().make_chain(support, name);
  if (links < 1) throw input_error(fmt::format("--links: must be at least 1, got {}", links));
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
  if (!pivot.empty()) params.pivot = parse_pivot(pivot);
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

std::vector<double> parse_state(const std::string& text, int links) {
  return parse_number_list(text, "--state", static_cast<std::size_t>(2 * links),
                           fmt::format("phi_1..phi_{0}, p_1..p_{0}", links));
}

}  // namespace npend::cli
