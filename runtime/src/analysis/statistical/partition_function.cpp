#include "npend/analysis/statistical/partition_function.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <boost/random/sobol.hpp>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <stdexcept>

#include "analysis/detail/sample_statistics.hpp"

namespace npend {

namespace {

constexpr double two_pi = 2 * std::numbers::pi;
constexpr double max_evaluations = 2e8;
// The box around the hanging position leaves out the angles where β a_i (1 − cos φ_i) > this:
// a part e^{-50} ≈ 2e-22 of the integral at most (see well_box).
constexpr double box_exponent = 50;

// Σ w, Σ w u, Σ w u², Σ w cos φ_i over a rule's points at one temperature, w = √det A e^{−βV}
// and u = βV − n/2: the potential in units of k T about its harmonic mean, so that neither
// ⟨V⟩ nor its variance cancels or underflows at low temperatures (V ~ kT ~ 1e-300).
struct sums {
  double w = 0, v = 0, v2 = 0;
  std::vector<double> cos;
};

struct point_values {
  double root_det = 0, potential = 0;  // root_det: √det A / √det A(0) (see reference_log_det)
  std::vector<double> cos;
};

void accumulate(sums& s, const point_values& p, double beta, double half_n) {
  const double bv = beta * p.potential;
  const double w = p.root_det * std::exp(-bv);
  const double u = bv - half_n;
  s.w += w;
  s.v += w * u;
  s.v2 += w * u * u;
  for (std::size_t i = 0; i < p.cos.size(); ++i) s.cos[i] += w * p.cos[i];
}

// The thermodynamics of one rule's sums; `log_volume` is ln of the weight of each point.
canonical_state state_from(const sums& s, double log_volume, double temperature, int links,
                           double k, double half_log_det_reference) {
  if (!(s.w > 0))
    throw std::runtime_error(fmt::format(
        "partition function: every weight vanished at T = {} (the temperature is too low for "
        "this rule's points; use a finer grid)",
        temperature));
  canonical_state out;
  const double n = links, kt = k * temperature;
  out.temperature = temperature;
  out.log_partition_function =
      n / 2 * std::log(two_pi * kt) + log_volume + std::log(s.w) + half_log_det_reference;
  out.partition_function = std::exp(out.log_partition_function);
  out.free_energy = -kt * out.log_partition_function;
  const double shift = s.v / s.w;
  out.mean_potential = kt * (n / 2 + shift);
  out.mean_energy = n / 2 * kt + out.mean_potential;
  const double variance = std::max(0.0, s.v2 / s.w - shift * shift);  // Var(βV)
  out.heat_capacity = k * (n / 2 + variance);
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

// The box [−L_i, L_i] of angles around the hanging position that the rule covers at inverse
// temperature β. Without springs V = Σ a_i (1 − cos φ_i), a_i = g (m_i c_i + l_i Σ_{j>i} m_j),
// separable: outside the box some β a_i (1 − cos φ_i) exceeds box_exponent, and since
// 1 − cos φ ≥ 0.458 φ² on |φ| ≤ 1 (and ≥ 0.46 beyond) the integral leaves out e^{-50} of
// itself at most. L_i = π (the whole circle) while β a_i ≤ box_exponent / 2; below that
// temperature the well is narrower than the circle, and a grid over the circle would miss
// it (at T = 1e-4 J all of a 2-link chain's weight sat on the single point φ = 0, C came out
// n/2 with an error estimate of 0). The box follows the well down to any temperature, with
// the rule's points spread over it: L_i → √(2 box_exponent k T / a_i), ten widths of the
// Gaussian (harmonic) well. Both its ends move continuously with T.
std::vector<double> well_box(const chain_parameters& p, double beta) {
  const std::size_t n = p.masses.size();
  std::vector<double> half_width(n, std::numbers::pi);
  double below = 0;
  for (std::size_t i = n; i-- > 0;) {
    const double c = p.com.empty() ? p.lengths[i] : p.com[i];
    const double a = p.g * (p.masses[i] * c + p.lengths[i] * below);
    below += p.masses[i];
    const double sine_squared = box_exponent / 2 / (beta * a);  // sin²(L/2)
    if (sine_squared < 1) half_width[i] = 2 * std::asin(std::sqrt(sine_squared));
  }
  return half_width;
}

// The temperatures that share a box (all of them on the whole torus at high T; one each
// below), in the given order of their first member.
struct temperature_group {
  std::vector<double> half_width;
  std::vector<std::size_t> members;
};

std::vector<temperature_group> group_by_box(const chain& c, std::span<const double> temperatures,
                                            double k) {
  std::vector<temperature_group> groups;
  for (std::size_t t = 0; t < temperatures.size(); ++t) {
    std::vector<double> box = well_box(c.parameters(), 1 / (k * temperatures[t]));
    auto same = std::find_if(groups.begin(), groups.end(),
                             [&](const temperature_group& g) { return g.half_width == box; });
    if (same == groups.end())
      groups.push_back({std::move(box), {t}});
    else
      same->members.push_back(t);
  }
  return groups;
}

// Progress over all groups of temperatures.
struct progress {
  run_control* control;
  double done = 0, total = 0;
  bool stop(double now) { return report_progress(control, done + now, total); }
};

// The trapezoid rule with m points per angle over the box of one group of temperatures,
// appended to r.states at the members' positions.
bool trapezoid(const chain& c, std::span<const double> temperatures, const temperature_group& g,
               int m, const partition_options& o, progress& pr, std::vector<canonical_state>& out) {
  const int n = c.links();
  const double k = o.boltzmann;
  const double det_reference = half_log_det_reference(c);
  const sums empty{0, 0, 0, std::vector<double>(static_cast<std::size_t>(n), 0.0)};
  std::vector<sums> full(g.members.size(), empty), half = full;
  std::vector<int> index(static_cast<std::size_t>(n), 0);
  std::vector<double> phi(static_cast<std::size_t>(n)), betas;
  for (const std::size_t t : g.members) betas.push_back(1 / (k * temperatures[t]));
  point_values p;
  const auto count = static_cast<long long>(std::pow(static_cast<double>(m), n));
  for (long long point = 0; point < count; ++point) {
    bool on_half_grid = true;
    for (std::size_t i = 0; i < phi.size(); ++i) {
      const double l = g.half_width[i];
      phi[i] = -l + 2 * l * index[i] / m;
      on_half_grid = on_half_grid && index[i] % 2 == 0;
    }
    evaluate(c, phi, p, det_reference);
    for (std::size_t t = 0; t < betas.size(); ++t) {
      accumulate(full[t], p, betas[t], 0.5 * n);
      if (on_half_grid) accumulate(half[t], p, betas[t], 0.5 * n);
    }
    for (std::size_t i = 0; i < index.size() && ++index[i] == m; ++i) index[i] = 0;
    if (point % 4096 == 0 && pr.stop(static_cast<double>(point))) return false;
  }
  pr.done += static_cast<double>(count);
  double log_volume = 0;
  for (const double l : g.half_width) log_volume += std::log(2 * l / m);
  const double log_half_volume = log_volume + n * std::log(2.0);
  for (std::size_t t = 0; t < g.members.size(); ++t) {
    const double temperature = temperatures[g.members[t]];
    canonical_state s = state_from(full[t], log_volume, temperature, n, k, det_reference);
    const canonical_state coarse =
        state_from(half[t], log_half_volume, temperature, n, k, det_reference);
    s.log_partition_error = std::fabs(s.log_partition_function - coarse.log_partition_function);
    s.free_energy_error = std::fabs(s.free_energy - coarse.free_energy);
    s.mean_energy_error = std::fabs(s.mean_energy - coarse.mean_energy);
    s.heat_capacity_error = std::fabs(s.heat_capacity - coarse.heat_capacity);
    out[g.members[t]] = std::move(s);
  }
  return true;
}

// Randomised quasi-Monte Carlo over the box of one group of temperatures.
bool quasi_monte_carlo(const chain& c, std::span<const double> temperatures,
                       const temperature_group& g, const partition_options& o, progress& pr,
                       std::vector<canonical_state>& out) {
  const int n = c.links();
  const double k = o.boltzmann;
  const double det_reference = half_log_det_reference(c);
  const sums empty{0, 0, 0, std::vector<double>(static_cast<std::size_t>(n), 0.0)};
  const std::size_t members = g.members.size();
  std::vector<sums> pooled(members, empty);
  std::vector<std::vector<canonical_state>> replica_states(members);
  std::vector<double> betas;
  for (const std::size_t t : g.members) betas.push_back(1 / (k * temperatures[t]));
  std::mt19937_64 rng(o.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  double log_volume = -std::log(static_cast<double>(o.points));
  for (const double l : g.half_width) log_volume += std::log(2 * l);
  std::vector<double> phi(static_cast<std::size_t>(n)), shift(phi.size());
  point_values p;
  long long done = 0;
  for (int replica = 0; replica < o.replicas; ++replica) {
    for (double& s : shift) s = unit(rng);
    boost::random::sobol sobol(static_cast<std::size_t>(n));
    constexpr double to_unit = 0x1p-64;
    std::vector<sums> own(members, empty);
    for (int point = 0; point < o.points; ++point, ++done) {
      for (std::size_t i = 0; i < phi.size(); ++i) {
        double u = static_cast<double>(sobol()) * to_unit + shift[i];
        u -= std::floor(u);
        phi[i] = g.half_width[i] * (2 * u - 1);
      }
      evaluate(c, phi, p, det_reference);
      for (std::size_t t = 0; t < members; ++t) {
        accumulate(own[t], p, betas[t], 0.5 * n);
        accumulate(pooled[t], p, betas[t], 0.5 * n);
      }
      if (done % 4096 == 0 && pr.stop(static_cast<double>(done))) return false;
    }
    for (std::size_t t = 0; t < members; ++t)
      replica_states[t].push_back(
          state_from(own[t], log_volume, temperatures[g.members[t]], n, k, det_reference));
  }
  pr.done += static_cast<double>(done);
  for (std::size_t t = 0; t < members; ++t) {
    const double temperature = temperatures[g.members[t]];
    canonical_state s =
        state_from(pooled[t], log_volume - std::log(o.replicas), temperature, n, k, det_reference);
    std::vector<double> log_z, energy, capacity;
    for (const canonical_state& rs : replica_states[t]) {
      log_z.push_back(rs.log_partition_function);
      energy.push_back(rs.mean_energy);
      capacity.push_back(rs.heat_capacity);
    }
    s.log_partition_error = detail::mean_and_standard_error(log_z).standard_error;
    s.free_energy_error = k * temperature * s.log_partition_error;
    s.mean_energy_error = detail::mean_and_standard_error(energy).standard_error;
    s.heat_capacity_error = detail::mean_and_standard_error(capacity).standard_error;
    out[g.members[t]] = std::move(s);
  }
  return true;
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
  if (!(options.boltzmann > 0) || !std::isfinite(options.boltzmann))
    throw std::invalid_argument(fmt::format(
        "partition function: Boltzmann's constant must be positive, got {}", options.boltzmann));
  for (const double t : temperatures) {
    if (!(t > 0) || !std::isfinite(t))
      throw std::invalid_argument(
          fmt::format("partition function: temperatures must be positive, got {}", t));
    const double kt = options.boltzmann * t;
    if (!(kt >= std::numeric_limits<double>::min()))
      throw std::invalid_argument(fmt::format(
          "partition function: k T = {:g} J at T = {:g} is below the smallest normal double "
          "({:g} J): 1/(k T) would overflow",
          kt, t, std::numeric_limits<double>::min()));
    if (!std::isfinite(kt))
      throw std::invalid_argument(fmt::format(
          "partition function: k T at T = {:g} overflows (k = {:g})", t, options.boltzmann));
  }
  const int n = c.links();
  const bool grid = chosen_partition_rule(options.rule, n) == partition_rule::trapezoid;
  const auto groups = group_by_box(c, temperatures, options.boltzmann);
  partition_result r;
  double per_group = 0;
  int m = 0;
  if (grid) {
    m = options.grid > 0 ? options.grid : (n == 1 ? 256 : n == 2 ? 128 : 64);
    if (m % 2 != 0 || m < 4)
      throw std::invalid_argument(fmt::format("trapezoid grid: an even number >= 4, got {}", m));
    per_group = std::pow(static_cast<double>(m), n);
    if (per_group * static_cast<double>(groups.size()) > max_evaluations)
      throw std::invalid_argument(fmt::format(
          "trapezoid grid: {}^{} = {:.3g} points{} is too many (at most {:.0e}); use the "
          "quasi-Monte Carlo rule for this many links",
          m, n, per_group * static_cast<double>(groups.size()),
          groups.size() > 1 ? fmt::format(" over {} boxes", groups.size()) : "", max_evaluations));
    r.rule = "trapezoid";
    r.grid = m;
  } else {
    if (options.points < 16 || options.replicas < 2)
      throw std::invalid_argument(
          fmt::format("quasi-Monte Carlo: need >= 16 points and >= 2 replicas, got {} and {}",
                      options.points, options.replicas));
    per_group = static_cast<double>(options.points) * options.replicas;
    if (per_group * static_cast<double>(groups.size()) > max_evaluations)
      throw std::invalid_argument(fmt::format(
          "quasi-Monte Carlo: {} points x {} replicas{} is too many (at most {:.0e})",
          options.points, options.replicas,
          groups.size() > 1 ? fmt::format(" x {} boxes", groups.size()) : "", max_evaluations));
    r.rule = "quasi-monte-carlo";
    r.points = options.points;
    r.replicas = options.replicas;
  }
  progress pr{options.control, 0, per_group * static_cast<double>(groups.size())};
  std::vector<canonical_state> states(temperatures.size());
  for (const temperature_group& g : groups) {
    const bool finished = grid ? trapezoid(c, temperatures, g, m, options, pr, states)
                               : quasi_monte_carlo(c, temperatures, g, options, pr, states);
    if (!finished) {
      r.stopped = true;
      return r;
    }
  }
  r.evaluations = static_cast<long long>(pr.done);
  r.states = std::move(states);
  return r;
}

}  // namespace npend
