#include "npend/spec/chain_spec.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>

#include "npend/spec/number_parsing.hpp"

namespace npend::spec {

std::string argument_name(std::string_view key, naming names) {
  if (names == naming::keywords) return std::string(key);
  std::string option = "--" + std::string(key);
  std::replace(option.begin(), option.end(), '_', '-');
  return option;
}

std::span<const per_link_key> per_link_keys() {
  static const std::array<per_link_key, 7> keys{{{"masses", &chain_spec::masses, "m"},
                                                 {"lengths", &chain_spec::lengths, "l"},
                                                 {"com", &chain_spec::com, "c"},
                                                 {"inertia", &chain_spec::inertia, "J"},
                                                 {"stiffness", &chain_spec::stiffness, "k"},
                                                 {"rest_angles", &chain_spec::rest_angles, "theta"},
                                                 {"damping", &chain_spec::damping, "b"}}};
  return keys;
}

const per_link_key* find_per_link_key(std::string_view key) {
  for (const auto& k : per_link_keys())
    if (key == k.key) return &k;
  return nullptr;
}

std::vector<double> per_link_values(std::vector<double> values, std::string_view option, int links,
                                    std::string_view symbol) {
  if (values.size() == 1) return std::vector<double>(static_cast<std::size_t>(links), values[0]);
  if (values.size() != static_cast<std::size_t>(links))
    throw input_error(
        fmt::format("{}: expected {} values ({}_1..{}_{}) or one for all links, got {}", option,
                    links, symbol, symbol, links, values.size()));
  return values;
}

pivot_motion parse_pivot(std::string_view text, std::string_view option) {
  const std::vector<std::string_view> parts = split_list(text, ':');
  if (parts.size() != 3 || (parts[0] != "vertical" && parts[0] != "horizontal"))
    throw input_error(
        fmt::format("{}: expected vertical:A:OMEGA or horizontal:A:OMEGA, got '{}'", option, text));
  const double a = parse_number(parts[1], fmt::format("{} (amplitude)", option));
  const double w = parse_number(parts[2], fmt::format("{} (angular frequency)", option));
  return parts[0] == "vertical" ? pivot_motion::vertical(a, w) : pivot_motion::horizontal(a, w);
}

void check_links(int links, naming names) {
  if (links < 1)
    throw input_error(
        fmt::format("{}: must be at least 1, got {}", argument_name("links", names), links));
}

namespace {

// The cart's mass and damping (a cart replaces the pivot, so it cannot move as a drive).
template <class Name>
void set_cart(const chain_spec& spec, const Name& name, chain_parameters& params) {
  if (spec.cart_damping && !spec.cart)
    throw input_error(fmt::format("{}: the cart's damping needs a cart: give {} MASS",
                                  name("cart_damping"), name("cart")));
  if (!spec.cart) return;
  if (!spec.pivot.empty())
    throw input_error(fmt::format("{} and {} exclude each other: the chain hangs from the cart",
                                  name("cart"), name("pivot")));
  if (!(*spec.cart > 0) || !std::isfinite(*spec.cart))
    throw input_error(
        fmt::format("{}: the cart's mass must be a positive finite number (kg), got {}",
                    name("cart"), *spec.cart));
  params.cart_mass = *spec.cart;
  if (!spec.cart_damping) return;
  if (!(*spec.cart_damping >= 0) || !std::isfinite(*spec.cart_damping))
    throw input_error(
        fmt::format("{}: the cart's damping must be a finite number >= 0 (N s/m), got {}",
                    name("cart_damping"), *spec.cart_damping));
  params.cart_damping = *spec.cart_damping;
}

}  // namespace

chain_parameters make_parameters(const chain_spec& spec, naming names) {
  check_links(spec.links, names);
  const int n = spec.links;
  const auto name = [&](std::string_view key) { return argument_name(key, names); };
  const auto per_link = [&](const std::vector<double>& values, std::string_view key,
                            std::string_view symbol) {
    return per_link_values(values, name(key), n, symbol);
  };
  chain_parameters params = chain_parameters::uniform(n);
  if (!spec.masses.empty()) params.masses = per_link(spec.masses, "masses", "m");
  if (!spec.lengths.empty()) params.lengths = per_link(spec.lengths, "lengths", "l");
  if (spec.g) params.g = *spec.g;
  if (spec.rods && (!spec.com.empty() || !spec.inertia.empty()))
    throw input_error(fmt::format("{} sets the centres of mass and inertias: leave out {} and {}",
                                  name("rods"), name("com"), name("inertia")));
  if (spec.rods) params.make_uniform_rods();
  if (!spec.com.empty()) params.com = per_link(spec.com, "com", "c");
  if (!spec.inertia.empty()) params.inertia = per_link(spec.inertia, "inertia", "J");
  if (!spec.stiffness.empty()) params.stiffness = per_link(spec.stiffness, "stiffness", "k");
  if (!spec.rest_angles.empty())
    params.rest_angles = per_link(spec.rest_angles, "rest_angles", "theta");
  if (!spec.damping.empty()) params.damping = per_link(spec.damping, "damping", "b");
  // A rest angle only shifts a spring's zero: without any spring it would be ignored.
  if (!spec.rest_angles.empty() && std::none_of(params.stiffness.begin(), params.stiffness.end(),
                                                [](double k) { return k > 0; }))
    throw input_error(fmt::format(
        "{}: the rest angles of the joint springs need springs: give {} (without it they change "
        "nothing)",
        name("rest_angles"), name("stiffness")));
  if (!spec.pivot.empty()) params.pivot = parse_pivot(spec.pivot, name("pivot"));
  set_cart(spec, name, params);
  return params;
}

chain make_chain(const chain_spec& spec, naming names) {
  chain_parameters params = make_parameters(spec, names);
  try {
    return chain(std::move(params));
  } catch (const input_error&) {
    throw;
  } catch (const std::invalid_argument& e) {
    throw input_error(e.what());
  }
}

std::string format_values(const std::vector<double>& values) {
  std::string out;
  for (const double v : values) out += fmt::format("{}{}", out.empty() ? "" : ",", v);
  return out;
}

}  // namespace npend::spec
