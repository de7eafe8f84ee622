#include "start_options.hpp"

#include "input_parsing.hpp"
#include "npend/excitation.hpp"

#include <fmt/format.h>

namespace npend::cli {

void start_options::add_to(CLI::App& command) {
  command.add_option("--phi", phi,
                     "Start angles phi_1,...,phi_n in rad (from the downward vertical)");
  command.add_option("--p", p,
                     "Start momenta p_1,...,p_n in kg m^2/s (default: all 0; with --phi)");
  command.add_option("--dphi", dphi,
                     "Start angular velocities dphi_1,...,dphi_n in rad/s (instead of --p)");
  command.add_option("--energy", energy,
                     "Start with this total energy E in J (instead of --phi), see --excitation");
  command.add_option("--excitation", style,
                     "How --energy enters: 'deflection' (default; all arms deflected by the same "
                     "angle, at rest) or 'kick' (the hanging chain, a horizontal impulse on the "
                     "lowest bob)");
}

std::vector<double> start_options::make_state(const chain& c) const {
  const int n = c.links();
  const auto count = static_cast<std::size_t>(n);
  if (!energy.empty()) {
    if (!phi.empty() || !p.empty() || !dphi.empty())
      throw input_error("--energy: give either --energy or --phi (with --p or --dphi), not both");
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
  const std::vector<double> angles =
      parse_number_list(phi, "--phi", count, fmt::format("phi_1..phi_{}", n));
  if (!dphi.empty()) {
    const std::vector<double> rates =
        parse_number_list(dphi, "--dphi", count, fmt::format("dphi_1..dphi_{}", n));
    return c.state_from_velocities(angles, rates);
  }
  std::vector<double> x = angles;
  if (p.empty())
    x.resize(2 * count, 0.0);
  else {
    const std::vector<double> momenta =
        parse_number_list(p, "--p", count, fmt::format("p_1..p_{}", n));
    x.insert(x.end(), momenta.begin(), momenta.end());
  }
  return x;
}

}  // namespace npend::cli
