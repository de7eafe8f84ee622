// Integrate a triple pendulum (the paper's model: point masses on massless rods) with the
// symplectic Gauss-Legendre stepper and watch its energy: the simplest use of the library.
//
//   integrate_chain [t_end] [dt] > trajectory.csv
//
// writes t, phi_1..3, H as CSV to stdout (plot it with e.g. gnuplot:
// `plot 'trajectory.csv' using 1:4 with lines`), and on stderr the largest relative energy
// error. Exits 1 if that error exceeds 1e-9: a symplectic method at this step keeps the
// energy to round-off plus a bounded O(dt^6) oscillation.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <npend/chain.hpp>
#include <npend/integrators/integrate.hpp>
#include <string>
#include <vector>

int main(int argc, char** argv) try {
  const npend::chain c(npend::chain_parameters::uniform(3));    // m = 1 kg, l = 1 m, g = 9.81
  const std::vector<double> x0{1.2, -0.6, 0.9, 0.0, 0.0, 0.0};  // [phi_1..3, p_1..3]

  npend::integration_options o;  // gauss6
  o.t_end = argc > 1 ? std::stod(argv[1]) : 20.0;
  o.dt = argc > 2 ? std::stod(argv[2]) : 1e-3;

  const double h0 = c.hamiltonian(x0);
  double worst = 0;
  fmt::print("t,phi_1,phi_2,phi_3,H\n");
  npend::integrate(c, x0, o, [&](double t, std::span<const double> x) {
    const double h = c.hamiltonian(x);
    worst = std::max(worst, std::fabs(h - h0) / std::fabs(h0));
    fmt::print("{},{},{},{},{}\n", t, x[0], x[1], x[2], h);
  });
  fmt::print(stderr, "H(0) = {:.12g} J, largest relative energy error {:.2e}\n", h0, worst);
  return worst <= 1e-9 ? 0 : 1;
} catch (const std::exception& e) {
  fmt::print(stderr, "integrate_chain: {}\n", e.what());
  return 2;
}
