// The energy balance of a damped chain (energy_drift.hpp): the friction's work against the
// exact dissipation of a linear damped oscillator, the joint rates' power by hand, and the
// balance of H along an integrated damped chain.
#include <doctest/doctest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "npend/analysis/motion/energy_drift.hpp"
#include "npend/chain_system.hpp"
#include "npend/integrators/integrate_system.hpp"

using npend::chain;
using npend::chain_parameters;

TEST_CASE("energy_balance: the friction's work is a linear damped oscillator's exact loss") {
  // One link, m l² φ̈ + b φ̇ + m g l φ = 0 solved in closed form: φ = A e^{−γt} cos(ω_d t).
  // Its energy E = ½ m l² φ̇² + ½ m g l φ² loses exactly ∫ b φ̇² dt, and the friction's work
  // depends on the state only through φ̇ = p / (m l²): fed the exact states, the balance's
  // work is −(E(0) − E(T)) to the trapezoid rule's error.
  const double m = 0.8, l = 1.3, g = 9.81, b = 0.4, A = 0.1;
  chain_parameters params{{m}, {l}, g};
  params.damping = {b};
  const chain c(params);
  const double inertia = m * l * l, gamma = b / (2 * inertia);
  const double omega_d = std::sqrt(g / l - gamma * gamma);
  const auto phi = [&](double t) { return A * std::exp(-gamma * t) * std::cos(omega_d * t); };
  const auto rate = [&](double t) {
    return -A * std::exp(-gamma * t) *
           (gamma * std::cos(omega_d * t) + omega_d * std::sin(omega_d * t));
  };
  const auto linear_energy = [&](double t) {
    return 0.5 * inertia * rate(t) * rate(t) + 0.5 * m * g * l * phi(t) * phi(t);
  };
  npend::energy_balance books(c);
  const double dt = 1e-3, t_end = 5;
  const int steps = static_cast<int>(std::lround(t_end / dt));
  for (int k = 0; k <= steps; ++k) {
    const double t = k * dt;
    books.add(t, std::vector<double>{phi(t), inertia * rate(t)});
  }
  const double lost = linear_energy(0) - linear_energy(t_end);
  CHECK(lost > 0.5 * linear_energy(0));  // most of it: the check means something
  CHECK(books.work() == doctest::Approx(-lost).epsilon(1e-6));
  const double h0 = m * g * l * (1 - std::cos(A)) + 0.5 * inertia * rate(0) * rate(0);
  CHECK(books.initial() == doctest::Approx(h0).epsilon(1e-13));
}

TEST_CASE("friction_power: minus the damping times the squared joint rates") {
  chain_parameters params = chain_parameters::uniform(2, 1.0, 1.0);
  params.damping = {0.3, 0.7};
  const chain c(params);
  const std::vector<double> phi{0.4, -0.2}, dphi{1.1, -0.5};
  const std::vector<double> x = c.state_from_velocities(phi, dphi);
  // Joint 1 turns at φ̇₁, joint 2 at φ̇₂ − φ̇₁.
  const double expected = -0.3 * 1.1 * 1.1 - 0.7 * (-0.5 - 1.1) * (-0.5 - 1.1);
  CHECK(npend::friction_power(c, x) == doctest::Approx(expected).epsilon(1e-12));
  CHECK(npend::friction_power(chain(chain_parameters::uniform(2)), x) == 0.0);
  CHECK_THROWS_AS(npend::friction_power(c, std::vector<double>{0.1, 0.2}), std::invalid_argument);
}

TEST_CASE("energy_balance: H minus the friction's work stays H(0) along a damped run") {
  chain_parameters params = chain_parameters::uniform(3, 1.0, 1.0);
  params.make_uniform_rods();
  params.damping = {0.05, 0.05, 0.05};
  const chain c(params);
  const std::vector<double> angles{1.2, 1.2, 1.2}, rest(3, 0.0);
  npend::integration_options o;
  o.stepper = npend::stepper_kind::gauss6;
  o.dt = 1e-3;
  o.t_end = 20;
  npend::energy_balance books(c);
  npend::integrate_system(npend::make_implicit_system(c), c.state_from_velocities(angles, rest), o,
                          [&](double t, std::span<const double> x) {
                            books.add(t, x);
                            return npend::observer_action::proceed;
                          });
  // The friction took a good part of the energy; the balance holds to the trapezoid rule's
  // error, O(dt²) of it.
  CHECK(books.energy() < 0.8 * books.initial());
  CHECK(books.balance() == doctest::Approx(books.initial()).epsilon(1e-7));
  CHECK(books.max_imbalance() < 1e-6 * books.initial());
  chain_parameters shaken = chain_parameters::uniform(1);
  shaken.pivot = npend::pivot_motion::vertical(0.01, 50.0);
  CHECK_THROWS_AS(npend::energy_balance(chain(shaken)), std::invalid_argument);
}
