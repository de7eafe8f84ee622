#include "npend/analysis/partition_function.hpp"

#include <fmt/format.h>

#include <boost/random/sobol.hpp>
#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>

#include "detail/sample_statistics.hpp"

namespace npend {

namespace {

constexpr double two_pi = 2 * std::numbers::pi;
constexpr double max_evaluations = 2e8;

// Σ w, Σ w (V − V_ref), Σ w (V − V_ref)², Σ w cos φ_i over a rule's points at one temperature,
// w = √det A e^{−βV}. V_ref = n k T / 2 (⟨V⟩ of the harmonic limit) keeps the variance from
// cancelling at low temperatures.
struct sums {
  double w = 0, v = 0, v2 = 0;
  std::vector<double> cos;
};

struct temperature_terms {
  double beta = 0, reference = 0;
};

struct point_values {
  double root_det = 0, potential = 0;  // root_det: √det A / √det A(0) (see reference_log_det)
  std::vector<double> cos;
};

void accumulate(sums& s, const point_values& p, const temperature_terms& t) {
  const double w = p.root_det * std::exp(-t.beta * p.potential);
  const double dv = p.potential - t.reference;
  s.w += w;
  s.v += w * dv;
  s.v2 += w * dv * dv;
  for (std::size_t i = 0; i < p.cos.size(); ++i) s.cos[i] += w * p.cos[i];
}

// The thermodynamics of one rule's sums; `volume` is the weight of each point.
canonical_state state_from(const sums& s, double volume, double temperature, int links, double k,
                           double reference, double half_log_det_reference) {
  if (!(s.w > 0))
    throw std::runtime_error(fmt::format(
        "partition function: every weight vanished at T = {} (the temperature is too low for "
        "this rule's points; use a finer grid)",
        temperature));
  canonical_state out;
  const double n = links, kt = k * temperature;
  out.temperature = temperature;
  out.log_partition_function =
      n / 2 * std::log(two_pi * kt) + std::log(volume) + std::log(s.w) + half_log_det_reference;
  out.partition_function = std::exp(out.log_partition_function);
  out.free_energy = -kt * out.log_partition_function;
  const double shift = s.v / s.w;
  out.mean_potential = reference + shift;
  out.mean_energy = n / 2 * kt + out.mean_potential;
  const double variance = std::max(0.0, s.v2 / s.w - shift * shift);
  out.heat_capacity = n / 2 * k + variance / (k * temperature * temperature);
  for (const double c : s.cos) out.mean_cos.push_back(c / s.w);
  return out;
}

// ½ ln det A at the hanging position: the weights carry √det A relative to it, so that they
// neither under- nor overflow for long chains (det A ∝ Π l_k², 1e-400 for 100 links of 1 cm);
// ln Z adds it back.
double half_log_det_reference(const chain& c) {
  return 0.5 * c.log_det_mass_matrix(std::vector<double>(static_cast<std::size_t>(c.links()), 0.0));
}

// Fills p at the angles phi, reusing its storage: called once per point of the rule.
void evaluate(const chain& c, std::span<const double> phi, point_values& p,
              double half_log_det_reference) {
  p.root_det = std::exp(0.5 * c.log_det_mass_matrix(phi) - half_log_det_reference);
  p.potential = c.potential_energy(phi);
  p.cos.resize(phi.size());
  for (std::size_t i = 0; i < phi.size(); ++i) p.cos[i] = std::cos(phi[i]);
}

std::vector<temperature_terms> terms_of(std::span<const double> temperatures, int n, double k) {
  std::vector<temperature_terms> out;
  for (const double t : temperatures) out.push_back({1 / (k * t), n * k * t / 2});
  return out;
}

partition_result trapezoid(const chain& c, std::span<const double> temperatures,
                           const partition_options& o) {
  const int n = c.links();
  const int m = o.grid > 0 ? o.grid : (n == 1 ? 256 : n == 2 ? 128 : 64);
  if (m % 2 != 0 || m < 4)
    throw std::invalid_argument(fmt::format("trapezoid grid: an even number >= 4, got {}", m));
  const double total = std::pow(static_cast<double>(m), n);
  if (total > max_evaluations)
    throw std::invalid_argument(
        fmt::format("trapezoid grid: {}^{} = {:.3g} points is too many (at most {:.0e}); use the "
                    "quasi-Monte Carlo rule for this many links",
                    m, n, total, max_evaluations));
  const auto terms = terms_of(temperatures, n, o.boltzmann);
  const double det_reference = half_log_det_reference(c);
  const sums empty{0, 0, 0, std::vector<double>(static_cast<std::size_t>(n), 0.0)};
  std::vector<sums> full(terms.size(), empty), half = full;
  std::vector<int> index(static_cast<std::size_t>(n), 0);
  std::vector<double> phi(static_cast<std::size_t>(n));
  point_values p;
  partition_result r;
  r.rule = "trapezoid";
  r.grid = m;
  const auto count = static_cast<long long>(total);
  for (long long point = 0; point < count; ++point) {
    bool on_half_grid = true;
    for (std::size_t i = 0; i < phi.size(); ++i) {
      phi[i] = -std::numbers::pi + two_pi * index[i] / m;
      on_half_grid = on_half_grid && index[i] % 2 == 0;
    }
    evaluate(c, phi, p, det_reference);
    for (std::size_t t = 0; t < terms.size(); ++t) {
      accumulate(full[t], p, terms[t]);
      if (on_half_grid) accumulate(half[t], p, terms[t]);
    }
    for (std::size_t i = 0; i < index.size() && ++index[i] == m; ++i) index[i] = 0;
    if (point % 4096 == 0 && report_progress(o.control, static_cast<double>(point), total)) {
      r.stopped = true;
      return r;
    }
  }
  r.evaluations = count;
  const double volume = std::pow(two_pi / m, n), half_volume = std::pow(2 * two_pi / m, n);
  for (std::size_t t = 0; t < terms.size(); ++t) {
    canonical_state s = state_from(full[t], volume, temperatures[t], n, o.boltzmann,
                                   terms[t].reference, det_reference);
    const canonical_state coarse = state_from(half[t], half_volume, temperatures[t], n, o.boltzmann,
                                              terms[t].reference, det_reference);
    s.log_partition_error = std::fabs(s.log_partition_function - coarse.log_partition_function);
    s.free_energy_error = std::fabs(s.free_energy - coarse.free_energy);
    s.mean_energy_error = std::fabs(s.mean_energy - coarse.mean_energy);
    s.heat_capacity_error = std::fabs(s.heat_capacity - coarse.heat_capacity);
    r.states.push_back(std::move(s));
  }
  return r;
}

partition_result quasi_monte_carlo(const chain& c, std::span<const double> temperatures,
                                   const partition_options& o) {
  const int n = c.links();
  if (o.points < 16 || o.replicas < 2)
    throw std::invalid_argument(
        fmt::format("quasi-Monte Carlo: need >= 16 points and >= 2 replicas, got {} and {}",
                    o.points, o.replicas));
  const double total = static_cast<double>(o.points) * o.replicas;
  if (total > max_evaluations)
    throw std::invalid_argument(
        fmt::format("quasi-Monte Carlo: {} points x {} replicas is too many (at most {:.0e})",
                    o.points, o.replicas, max_evaluations));
  const auto terms = terms_of(temperatures, n, o.boltzmann);
  const double det_reference = half_log_det_reference(c);
  const sums empty{0, 0, 0, std::vector<double>(static_cast<std::size_t>(n), 0.0)};
  std::vector<sums> pooled(terms.size(), empty);
  std::vector<std::vector<canonical_state>> replica_states(terms.size());
  std::mt19937_64 rng(o.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double volume = std::pow(two_pi, n) / o.points;
  std::vector<double> phi(static_cast<std::size_t>(n)), shift(phi.size());
  point_values p;
  partition_result r;
  r.rule = "quasi-monte-carlo";
  r.points = o.points;
  r.replicas = o.replicas;
  long long done = 0;
  for (int replica = 0; replica < o.replicas; ++replica) {
    for (double& s : shift) s = unit(rng);
    boost::random::sobol sobol(static_cast<std::size_t>(n));
    constexpr double to_unit = 0x1p-64;
    std::vector<sums> own(terms.size(), empty);
    for (int point = 0; point < o.points; ++point, ++done) {
      for (std::size_t i = 0; i < phi.size(); ++i) {
        double u = static_cast<double>(sobol()) * to_unit + shift[i];
        u -= std::floor(u);
        phi[i] = -std::numbers::pi + two_pi * u;
      }
      evaluate(c, phi, p, det_reference);
      for (std::size_t t = 0; t < terms.size(); ++t) {
        accumulate(own[t], p, terms[t]);
        accumulate(pooled[t], p, terms[t]);
      }
      if (done % 4096 == 0 && report_progress(o.control, static_cast<double>(done), total)) {
        r.stopped = true;
        return r;
      }
    }
    for (std::size_t t = 0; t < terms.size(); ++t)
      replica_states[t].push_back(state_from(own[t], volume, temperatures[t], n, o.boltzmann,
                                             terms[t].reference, det_reference));
  }
  r.evaluations = done;
  for (std::size_t t = 0; t < terms.size(); ++t) {
    canonical_state s = state_from(pooled[t], volume / o.replicas, temperatures[t], n, o.boltzmann,
                                   terms[t].reference, det_reference);
    std::vector<double> log_z, energy, capacity;
    for (const canonical_state& rs : replica_states[t]) {
      log_z.push_back(rs.log_partition_function);
      energy.push_back(rs.mean_energy);
      capacity.push_back(rs.heat_capacity);
    }
    s.log_partition_error = detail::mean_and_standard_error(log_z).standard_error;
    s.free_energy_error = o.boltzmann * temperatures[t] * s.log_partition_error;
    s.mean_energy_error = detail::mean_and_standard_error(energy).standard_error;
    s.heat_capacity_error = detail::mean_and_standard_error(capacity).standard_error;
    r.states.push_back(std::move(s));
  }
  return r;
}

}  // namespace

partition_result canonical_ensemble(const chain& c, std::span<const double> temperatures,
                                    const partition_options& options) {
  const chain_parameters& p = c.parameters();
  if (!p.is_conservative())
    throw std::invalid_argument(
        "partition function: damping or a moving pivot has no canonical ensemble");
  for (const double k : p.stiffness)
    if (k != 0)
      throw std::invalid_argument(
          "partition function: joint springs make V non-periodic in the angles; the "
          "ensemble over [-pi, pi]^n is that of chains without them");
  if (temperatures.empty()) throw std::invalid_argument("partition function: no temperature given");
  for (const double t : temperatures)
    if (!(t > 0) || !std::isfinite(t))
      throw std::invalid_argument(
          fmt::format("partition function: temperatures must be positive, got {}", t));
  if (!(options.boltzmann > 0) || !std::isfinite(options.boltzmann))
    throw std::invalid_argument(fmt::format(
        "partition function: Boltzmann's constant must be positive, got {}", options.boltzmann));
  const bool grid = chosen_partition_rule(options.rule, c.links()) == partition_rule::trapezoid;
  return grid ? trapezoid(c, temperatures, options) : quasi_monte_carlo(c, temperatures, options);
}

}  // namespace npend
