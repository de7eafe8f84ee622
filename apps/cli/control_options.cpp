#include "control_options.hpp"

#include <fmt/format.h>

#include <cmath>

#include "input_parsing.hpp"

namespace npend::cli {

void control_options::add_to(CLI::App& command, bool at_required) {
  command
      .add_option("--at", at,
                  "The equilibrium to hold, phi_1,..,phi_n (numbers or pi; one value for all "
                  "links), e.g. pi,pi,pi for the standing chain")
      ->required(at_required);
  command.add_option("--actuated", actuated,
                     "The joints with a motor, 1-based (default: all, and the cart's force), e.g. "
                     "1 for a single motor at the pivot; with --cart, cart is the force on the "
                     "cart (cart alone: only the cart is pushed)");
  command.add_option("--weights", weights,
                     "LQR weights QPHI:QP:R: Q = diag(QPHI on the angles, QP on the momenta), "
                     "R = R on the torques (default 10:1:1)");
}

void control_options::add_controller_to(CLI::App& command) {
  command.add_option("--controller", controller,
                     "lqr: run the chain under the LQR feedback u = -K (x - x*) that holds it at "
                     "--at (with --actuated, --weights as for npend control)");
  add_to(command, false);
}

std::optional<lqr_design> control_options::controller_design(const chain& c,
                                                             stepper_kind stepper) const {
  if (controller.empty()) {
    if (given() || !actuated.empty() || !weights.empty())
      throw input_error("--at, --actuated and --weights go with --controller lqr");
    return std::nullopt;
  }
  if (controller != "lqr")
    throw input_error(fmt::format("--controller: the one controller is lqr, got '{}'", controller));
  if (!given()) throw input_error("--controller lqr needs the equilibrium to hold: --at phi_1,..");
  if (!serves(stepper, stepper_use::system))
    throw input_error(fmt::format(
        "--stepper: {} integrates the chain's own equations, not the chain under feedback; "
        "with --controller take one of {}",
        stepper_name(stepper), stepper_names(stepper_use::system)));
  return design(c);
}

lqr_design control_options::design(const chain& c) const {
  const int n = c.links();
  // On a cart the equilibrium holds the cart at x_c = 0 and its actuator 0 is the cart's force.
  std::vector<double> angles = parse_angle_list(at, "--at", n);
  if (c.has_cart()) angles.insert(angles.begin(), 0.0);
  std::vector<int> joints;
  const auto add_joint = [&](double v) {
    if (!is_whole_number(v, 1, n))
      throw input_error(fmt::format("--actuated: {} is not a joint 1..{}{}", v, n,
                                    c.has_cart() ? " or cart" : ""));
    // Joint j's torque is actuator j − 1, after the cart's force where there is one.
    joints.push_back(c.actuators() - n + static_cast<int>(v) - 1);
  };
  if (!actuated.empty() && c.has_cart()) {
    for (const std::string_view item : split_list(actuated, ','))
      if (item == "cart")
        joints.push_back(0);
      else
        add_joint(parse_number(item, "--actuated"));
  } else if (!actuated.empty()) {
    for (const double v : parse_number_list(actuated, "--actuated")) add_joint(v);
  }
  lqr_weights w;
  if (!weights.empty()) {
    const auto parts = split_list(weights, ':');
    if (parts.size() != 3)
      throw input_error(fmt::format("--weights: expected QPHI:QP:R, got '{}'", weights));
    w.angle = parse_number(parts[0], "--weights");
    w.momentum = parse_number(parts[1], "--weights");
    w.torque = parse_number(parts[2], "--weights");
  }
  try {
    return lqr(c, angles, joints, w);
  } catch (const std::invalid_argument& e) {
    throw input_error(e.what());
  }
}

}  // namespace npend::cli
