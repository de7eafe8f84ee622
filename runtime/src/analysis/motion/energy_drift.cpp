#include "npend/analysis/motion/energy_drift.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace npend {

double relative_energy_error(double h, double h0) {
  const double error = std::fabs(h - h0);
  return h0 != 0 ? error / std::fabs(h0) : error;
}

double energy_drift::add(std::span<const double> x, double t) {
  m_last = m_chain->hamiltonian(x, t);
  m_max = std::max(m_max, relative_energy_error(m_last, m_initial));
  return m_last;
}

namespace {

// P at x, with the joint rates computed into dphi (dim n).
double power_at(const chain& c, std::span<const double> x, std::vector<double>& dphi) {
  const auto n = static_cast<std::size_t>(c.links());
  if (x.size() != 2 * n)
    throw std::invalid_argument(
        fmt::format("friction_power: the state has {} entries; the {}-link chain needs {}",
                    x.size(), n, 2 * n));
  dphi.resize(n);
  c.velocities(x.first(n), x.subspan(n), dphi);
  const std::vector<double>& b = c.parameters().damping;
  double power = 0;
  for (std::size_t j = 0; j < b.size(); ++j) {
    const double rate = dphi[j] - (j > 0 ? dphi[j - 1] : 0.0);
    power -= b[j] * rate * rate;
  }
  return power;
}

}  // namespace

double friction_power(const chain& c, std::span<const double> x) {
  std::vector<double> dphi;
  return power_at(c, x, dphi);
}

energy_balance::energy_balance(const chain& c) : m_chain(&c) {
  if (c.parameters().pivot.moves())
    throw std::invalid_argument(
        "energy_balance: the pivot moves, and its drive does work on the chain besides the "
        "joints' friction");
}

double energy_balance::add(double t, std::span<const double> x) {
  const double power = power_at(*m_chain, x, m_dphi);
  if (m_started) m_work += (t - m_t) * (power + m_power) / 2;
  m_t = t;
  m_power = power;
  m_energy = m_chain->hamiltonian(x);
  if (!m_started) m_initial = m_energy;
  m_started = true;
  m_max = std::max(m_max, std::fabs(balance() - m_initial));
  return m_energy;
}

}  // namespace npend
