#include "npend/analysis/statistical/langevin.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <cmath>
#include <random>
#include <stdexcept>

#include "analysis/detail/dense_eigen.hpp"
#include "analysis/detail/sample_statistics.hpp"
#include "npend/chain_system.hpp"
#include "npend/integrators/gauss_legendre.hpp"

namespace npend {

namespace {

// Γ = Dᵀ diag(b) D: joint j's damping b_j on θ_j = φ_j − φ_{j−1}.
Eigen::MatrixXd friction_matrix(const std::vector<double>& b, int n) {
  Eigen::MatrixXd g = Eigen::MatrixXd::Zero(n, n);
  for (int j = 0; j < n; ++j) {
    const double bj = b.empty() ? 0.0 : b[static_cast<std::size_t>(j)];
    g(j, j) += bj;
    if (j > 0) {
      g(j - 1, j - 1) += bj;
      g(j, j - 1) -= bj;
      g(j - 1, j) -= bj;
    }
  }
  return g;
}

// The exact Ornstein–Uhlenbeck step of the momenta over h at fixed angles (file comment).
class momentum_thermostat {
 public:
  momentum_thermostat(const chain& c, const Eigen::MatrixXd& friction, double kt,
                      std::uint64_t seed)
      : m_chain(c), m_friction(friction), m_kt(kt), m_rng(seed), m_mass(c.links() * c.links()) {}

  void step(std::vector<double>& x, double h) {
    const int n = m_chain.links();
    m_chain.mass_matrix(std::span<const double>(x.data(), static_cast<std::size_t>(n)), m_mass);
    const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>
        a(m_mass.data(), n, n);
    const detail::symmetric_eigensystem mass = detail::symmetric_eigen_decomposition(a, true);
    const Eigen::VectorXd root = mass.values.cwiseSqrt();
    const Eigen::MatrixXd half =
        mass.vectors * root.asDiagonal() * mass.vectors.transpose();  // A^{1/2}
    const Eigen::MatrixXd inverse_half =
        mass.vectors * root.cwiseInverse().asDiagonal() * mass.vectors.transpose();
    const detail::symmetric_eigensystem g =
        detail::symmetric_eigen_decomposition(inverse_half * m_friction * inverse_half, true);
    Eigen::Map<Eigen::VectorXd> p(x.data() + n, n);
    Eigen::VectorXd q = g.vectors.transpose() * (inverse_half * p);
    for (int i = 0; i < n; ++i) {
      const double rate = std::max(0.0, g.values(i));
      const double decay = std::exp(-rate * h);
      q(i) = decay * q(i) + std::sqrt(m_kt * (1 - decay * decay)) * m_normal(m_rng);
    }
    p = half * (g.vectors * q);
  }

 private:
  const chain& m_chain;
  Eigen::MatrixXd m_friction;
  double m_kt;
  std::mt19937_64 m_rng;
  std::normal_distribution<double> m_normal;
  std::vector<double> m_mass;
};

}  // namespace

langevin_result langevin_mean_energy(const chain& c, std::span<const double> x0, double temperature,
                                     const langevin_options& o) {
  const chain_parameters& params = c.parameters();
  const int n = c.links();
  if (x0.size() != static_cast<std::size_t>(2 * n))
    throw std::invalid_argument(fmt::format(
        "Langevin: the {}-link chain needs a state of {}, got {}", n, 2 * n, x0.size()));
  if (params.pivot.moves())
    throw std::invalid_argument("Langevin: a moving pivot has no canonical ensemble");
  if (!params.is_damped())
    throw std::invalid_argument(
        "Langevin: the chain needs joint damping (--damping) as the thermostat's friction");
  if (!(temperature > 0) || !std::isfinite(temperature))
    throw std::invalid_argument(
        fmt::format("Langevin: the temperature must be positive, got {}", temperature));
  if (!(o.dt > 0) || !(o.t_end > o.transient) || !(o.transient >= 0) || o.blocks < 2)
    throw std::invalid_argument(fmt::format(
        "Langevin: need dt > 0, t_end > transient >= 0 and >= 2 blocks, got {}, {}, {}, {}", o.dt,
        o.t_end, o.transient, o.blocks));
  const auto steps = static_cast<long long>(std::floor(o.t_end / o.dt));
  const auto skipped = static_cast<long long>(std::ceil(o.transient / o.dt));
  if (steps - skipped < o.blocks)
    throw std::invalid_argument("Langevin: fewer steps after the transient than blocks");

  // The conservative chain for the Hamiltonian step; the friction goes to the thermostat.
  chain_parameters undamped = params;
  undamped.damping.clear();
  const chain conservative(undamped);
  momentum_thermostat thermostat(c, friction_matrix(params.damping, n), o.boltzmann * temperature,
                                 o.seed);
  gauss_legendre<3> stepper;
  const auto system = make_implicit_system(conservative);
  std::vector<double> x(x0.begin(), x0.end());
  const long long averaged = steps - skipped;
  const long long per_block = averaged / o.blocks;
  std::vector<double> block_sums(static_cast<std::size_t>(o.blocks), 0.0);
  langevin_result r;
  for (long long k = 0; k < steps; ++k) {
    const double t = static_cast<double>(k) * o.dt;
    thermostat.step(x, o.dt / 2);
    stepper.do_step(system, x, t, o.dt);
    thermostat.step(x, o.dt / 2);
    const long long index = k - skipped;
    if (index >= 0 && index < per_block * o.blocks)
      block_sums[static_cast<std::size_t>(index / per_block)] += conservative.hamiltonian(x);
    if (k % 1024 == 0 &&
        report_progress(o.control, static_cast<double>(k), static_cast<double>(steps))) {
      r.stopped = true;
      return r;
    }
  }
  for (double& s : block_sums) s /= static_cast<double>(per_block);
  const auto blocks = detail::mean_and_standard_error(block_sums);
  r.mean_energy = blocks.mean;
  r.standard_error = blocks.standard_error;
  r.samples = static_cast<std::size_t>(per_block * o.blocks);
  r.final_state = x;
  return r;
}

}  // namespace npend
