#include "start_options.hpp"

namespace npend::cli {

void start_options::add_to(CLI::App& command) {
  command.add_option("--phi", phi,
                     "Start angles phi_1,...,phi_n in rad (from the downward vertical), or one "
                     "value for all links");
  command.add_option(
      "--p", p,
      "Start momenta p_1,...,p_n in kg m^2/s, or one value for all (default: all 0; with --phi)");
  command.add_option(
      "--dphi", dphi,
      "Start angular velocities dphi_1,...,dphi_n in rad/s, or one value for all (instead of --p)");
  command.add_option("--energy", energy,
                     "Start with this total energy E in J (instead of --phi), see --excitation");
  command.add_option("--excitation", style,
                     "How --energy enters: 'deflection' (default; all arms deflected by the same "
                     "angle, at rest) or 'kick' (the hanging chain, a horizontal impulse on the "
                     "lowest bob)");
}

}  // namespace npend::cli
