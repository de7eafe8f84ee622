// A Poincare section of the double pendulum: the crossings of phi_1 = 0 (upwards), located
// on the integrator's steps to rounding, projected onto (phi_2, p_2).
//
//   poincare_section [t_end] > section.csv
//
// writes t, phi_2, p_2 of each crossing as CSV; exits 1 unless every crossing lies on the
// section (|phi_1| below 1e-12 after wrapping) and keeps the start's energy to 1e-9.
#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <exception>
#include <npend/analysis/chaos/poincare_section.hpp>
#include <npend/chain.hpp>
#include <numbers>
#include <string>
#include <vector>

int main(int argc, char** argv) try {
  const npend::chain c(npend::chain_parameters::uniform(2));
  const std::vector<double> x0{0.0, 1.0, 2.0, 0.5};  // [phi_1, phi_2, p_1, p_2]

  npend::integration_options o;
  o.t_end = argc > 1 ? std::stod(argv[1]) : 200.0;
  o.dt = 0.01;
  const auto section = npend::section_plane::coordinate(2, 0, 0.0);  // phi_1 = 0
  const npend::poincare_result r = npend::poincare_section(c, x0, section, o);

  const double h0 = c.hamiltonian(x0);
  bool good = !r.crossings.empty();
  fmt::print("t,phi_2,p_2\n");
  for (const auto& x : r.crossings) {
    fmt::print("{},{},{}\n", x.t, x.state[1], x.state[3]);
    const double phi1 = std::remainder(x.state[0], 2 * std::numbers::pi);
    good = good && std::fabs(phi1) < 1e-12 &&
           std::fabs(c.hamiltonian(x.state) - h0) <= 1e-9 * std::fabs(h0);
  }
  fmt::print(stderr, "{} crossings in {} s\n", r.crossings.size(), o.t_end);
  return good ? 0 : 1;
} catch (const std::exception& e) {
  fmt::print(stderr, "poincare_section: {}\n", e.what());
  return 2;
}
