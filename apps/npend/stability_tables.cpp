#include "stability_tables.hpp"

#include <fmt/format.h>

#include <cstdint>

namespace npend::app {

namespace {

std::string angle_text(double a) { return a == 0.0 ? "0" : "pi"; }

// The eigenvalues come in ± pairs: show each pair once, real pairs first.
std::string eigenvalue_pairs(const std::vector<std::complex<double>>& values) {
  std::string out;
  for (const auto& z : values) {
    if (z.real() > 0)
      out += fmt::format("±{:.6g}  ", z.real());
    else if (z.real() == 0.0 && z.imag() > 0)
      out += fmt::format("±{:.6g}i  ", z.imag());
  }
  return out;
}

}  // namespace

void print_equilibria_table(const chain& c, const std::vector<equilibrium>& eqs) {
  const bool all = c.links() <= max_equilibria_links &&
                   eqs.size() == (std::size_t{1} << static_cast<unsigned>(c.links()));
  if (all)
    fmt::print("The {} equilibria of the {}-link chain (p = 0, each angle 0 or pi):\n\n",
               eqs.size(), c.links());
  else
    fmt::print("{} of the 2^{} equilibria of the {}-link chain (p = 0, each angle 0 or pi):\n\n",
               eqs.size(), c.links(), c.links());
  fmt::print("{:>4}  {:<{}}  {:>14}  {:<8}  {:>8}  {}\n", "#", "angles", 3 * c.links(),
             "energy (J)", "stable", "unstable", "Jacobian eigenvalues (1/s)");
  for (std::size_t k = 0; k < eqs.size(); ++k) {
    const auto& e = eqs[k];
    std::string angles;
    for (double a : e.angles) angles += fmt::format("{:<3}", angle_text(a));
    const std::string values = eigenvalue_pairs(e.eigenvalues);
    fmt::print("{:>4}  {:<{}}  {:>14.6g}  {:<8}  {:>8}  {}\n", k + 1, angles, 3 * c.links(),
               e.energy, e.stable ? "yes" : "no", e.unstable_directions, values);
  }
  fmt::print(
      "\nstable = elliptic (all eigenvalues imaginary); unstable = eigenvalues with "
      "positive real part.\n");
}

void print_modes_table(const linearisation& lin) {
  const auto n = lin.angles.size();
  std::string where;
  for (double a : lin.angles) where += (where.empty() ? "" : ", ") + fmt::format("{:.6g}", a);
  fmt::print("Linearisation M y'' + K y = 0 of the {}-link chain at phi = ({}):\n\n", n, where);
  fmt::print("{:>4}  {:>14}  {:>16}  {}\n", "mode", "omega^2 (1/s^2)", "frequency",
             "shape (M-normalised)");
  for (std::size_t k = 0; k < lin.modes.size(); ++k) {
    const auto& m = lin.modes[k];
    const std::string f = m.omega_squared > 0 ? fmt::format("{:.6g} rad/s", m.frequency)
                                              : fmt::format("unstable, {:.4g}/s", m.growth_rate);
    std::string shape;
    for (double v : m.shape) shape += fmt::format("{:>10.4f}", v);
    fmt::print("{:>4}  {:>14.6g}  {:>16}  {}\n", k + 1, m.omega_squared, f, shape);
  }
}

}  // namespace npend::app
