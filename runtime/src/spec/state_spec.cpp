#include "npend/spec/state_spec.hpp"

#include <fmt/format.h>

#include "npend/excitation.hpp"
#include "npend/spec/chain_spec.hpp"
#include "npend/spec/number_parsing.hpp"

namespace npend::spec {

std::vector<double> parse_state(std::string_view text, const chain& c, std::string_view option) {
  const int n = c.links();
  return parse_number_list(text, option, static_cast<std::size_t>(c.state_size()),
                           c.has_cart() ? fmt::format("x_c, phi_1..phi_{0}, p_x, p_1..p_{0}", n)
                                        : fmt::format("phi_1..phi_{0}, p_1..p_{0}", n));
}

std::vector<double> start_spec::make_state(const chain& c) const {
  const int n = c.links();
  if (!energy.empty()) {
    if (!phi.empty() || !p.empty() || !dphi.empty())
      throw input_error("--energy: give either --energy or --phi (with --p or --dphi), not both");
    if (c.has_cart())
      throw input_error(
          "--energy: the excitations are those of a chain on a fixed pivot; on a "
          "cart give --phi (with --p or --dphi)");
    const double e = parse_number(energy, "--energy");
    excitation how = excitation::deflection;
    if (!style.empty()) {
      try {
        how = parse_excitation(style);
      } catch (const std::invalid_argument& err) {
        throw input_error(fmt::format("--excitation: {}", err.what()));
      }
    }
    try {
      return excited_state(c, e, how);
    } catch (const std::invalid_argument& err) {
      throw input_error(fmt::format("--energy: {}", err.what()));
    }
  }
  if (!style.empty()) throw input_error("--excitation: only applies with --energy");
  if (phi.empty())
    throw input_error(
        "no start state: give --phi (with --p or --dphi), or --energy E (see --help)");
  if (!p.empty() && !dphi.empty())
    throw input_error("--p and --dphi exclude each other: give momenta or angular velocities");
  // One value for all links, as for the masses: a 1000-link rope cannot be typed out.
  std::vector<double> angles = per_link_values(parse_number_list(phi, "--phi"), "--phi", n, "phi");
  // On a cart the angles follow its position x_c = 0, and the momenta its p_x = 0 (with
  // --dphi: the cart at rest).
  if (c.has_cart()) angles.insert(angles.begin(), 0.0);
  if (!dphi.empty()) {
    std::vector<double> rates =
        per_link_values(parse_number_list(dphi, "--dphi"), "--dphi", n, "dphi");
    if (c.has_cart()) rates.insert(rates.begin(), 0.0);
    return c.state_from_velocities(angles, rates);
  }
  std::vector<double> x = angles;
  if (p.empty())
    x.resize(static_cast<std::size_t>(c.state_size()), 0.0);
  else {
    const std::vector<double> momenta = per_link_values(parse_number_list(p, "--p"), "--p", n, "p");
    if (c.has_cart()) x.push_back(0.0);
    x.insert(x.end(), momenta.begin(), momenta.end());
  }
  return x;
}

}  // namespace npend::spec
