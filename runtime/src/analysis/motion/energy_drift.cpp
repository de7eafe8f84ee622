#include "npend/analysis/motion/energy_drift.hpp"

#include <algorithm>
#include <cmath>

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

}  // namespace npend
