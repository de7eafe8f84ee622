#include "npend/analysis/chaos/lyapunov.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <random>
#include <stdexcept>

#include "analysis/detail/argument_checks.hpp"
#include "analysis/detail/explicit_system.hpp"
#include "npend/analysis/motion/energy_drift.hpp"
#include "npend/chain_system.hpp"
#include "npend/integrators/gauss_legendre.hpp"
#include "npend/integrators/integrate_system.hpp"
#include "npend/integrators/integration_error.hpp"
#include "npend/integrators/taylor.hpp"

namespace npend {

void lyapunov_options::validate() const {
  integration.validate();
  if (!(integration.dt > 0))
    throw std::invalid_argument(fmt::format(
        "lyapunov: integration dt is {}: Lyapunov exponents are computed forwards in time (dt > 0)",
        integration.dt));
  if (!(renormalisation_interval > 0) || !std::isfinite(renormalisation_interval))
    throw std::invalid_argument(
        fmt::format("lyapunov: renormalisation_interval is {}: it must be positive and finite",
                    renormalisation_interval));
  if (!(transient >= 0) || !std::isfinite(transient))
    throw std::invalid_argument(
        fmt::format("lyapunov: transient is {}: it must be >= 0 and finite", transient));
  if (!(convergence_fraction > 0 && convergence_fraction <= 1))
    throw std::invalid_argument(fmt::format(
        "lyapunov: convergence_fraction is {}: it must lie in (0, 1]", convergence_fraction));
  if (max_history < 2)
    throw std::invalid_argument(
        fmt::format("lyapunov: max_history is {}: it must be at least 2", max_history));
  if (blocks < 2)
    throw std::invalid_argument(
        fmt::format("lyapunov: blocks is {}: it must be at least 2", blocks));
  if (!serves(integration.stepper, stepper_use::variational))
    throw std::invalid_argument(fmt::format(
        "lyapunov: the {} stepper cannot integrate the variational equations ({}); use one of "
        "{}",
        stepper_name(integration.stepper), variational_refusal(integration.stepper),
        stepper_names(stepper_use::variational)));
}

namespace {

using row_major = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// Told after each step of a chunk how many of its steps are done; true asks to stop there. A
// chunk of a long chain can take minutes: its steps heed Ctrl-C.
using step_poll = std::function<bool(std::size_t)>;

// Advances x (dim d) and the tangent vectors W (d × k) by `steps` steps of dt from t; returns
// the steps done, fewer when `poll` asked to stop before the chunk's last step.
using tangent_advance =
    std::function<std::size_t(std::vector<double>& x, Eigen::MatrixXd& W, double t,
                              std::size_t steps, const step_poll& poll)>;

// The Gauss–Legendre route: each step's exact derivative applied to W.
template <class Stepper>
tangent_advance gauss_legendre_advance(const chain& c, double dt) {
  auto stepper = std::make_shared<Stepper>();
  return [stepper, system = make_implicit_system(c), dt](std::vector<double>& x, Eigen::MatrixXd& W,
                                                         double t, std::size_t steps,
                                                         const step_poll& poll) {
    for (std::size_t k = 0; k < steps; ++k) {
      stepper->do_step_with_tangent(system, x, t + static_cast<double>(k) * dt, dt, W);
      if (poll(k + 1) && k + 1 < steps) return k + 1;
    }
    return steps;
  };
}

// The Taylor route: the variational equations' own Taylor series (taylor_tangents), each
// chunk stepped adaptively to its end. A stop inside the chunk returns the whole steps of dt
// done, with the state and vectors at that time, from the last step's polynomials.
tangent_advance taylor_advance(const chain& c, const integration_options& o, Eigen::Index k) {
  auto integrator = std::make_shared<taylor_tangents>(c.kernels_in_use(), o.abs_tol, o.rel_tol,
                                                      static_cast<int>(k), o.taylor_order);
  return [integrator, dt = o.dt](std::vector<double>& x, Eigen::MatrixXd& W, double t,
                                 std::size_t steps, const step_poll& poll) {
    const double end = t + static_cast<double>(steps) * dt;
    // A step that lands on `end` may stop an ulp short of it in floating point.
    const double slack = 4 * std::numeric_limits<double>::epsilon() * std::fabs(end);
    integrator->reset(t, x.data(), W.data());
    std::size_t done = 0;
    while (end - integrator->time() > slack) {
      integrator->step(1.0, end - integrator->time(), dt);
      done = std::min(steps,
                      static_cast<std::size_t>(std::floor((integrator->time() - t) / dt + 1e-9)));
      if (end - integrator->time() > slack && poll(done)) {
        done = std::min(done, steps - 1);
        integrator->state_at(t + static_cast<double>(done) * dt - integrator->step_begin(),
                             x.data(), W.data());
        return done;
      }
    }
    std::copy(integrator->state().begin(), integrator->state().end(), x.begin());
    std::copy(integrator->tangents().begin(), integrator->tangents().end(), W.data());
    return steps;
  };
}

// A chunk's integration as the step poll sees it: its progress in steps, and the poll's
// answer as the stop request.
class poll_control final : public run_control {
 public:
  poll_control(const step_poll& poll, std::size_t steps) : m_poll(&poll), m_steps(steps) {}
  void progress(double done, double total) override {
    if (total > 0)
      m_stop = (*m_poll)(static_cast<std::size_t>(static_cast<double>(m_steps) * done / total));
  }
  bool stop_requested() override { return m_stop; }

 private:
  const step_poll* m_poll;
  std::size_t m_steps;
  bool m_stop = false;
};

// dy/dt for y = [x (dim d), W (d × k, column-major)]: [f(x), J(x) W].
class variational_system {
 public:
  variational_system(const chain& c, Eigen::Index k)
      : m_chain(&c), m_d(c.state_size()), m_k(k), m_jac(std::make_shared<row_major>(m_d, m_d)) {}

  void operator()(const std::vector<double>& y, std::vector<double>& dydt, double t) const {
    const auto d = static_cast<std::size_t>(m_d);
    m_chain->rhs(std::span(y).first(d), std::span(dydt).first(d), t);
    if (m_chain->runs_on_loops()) {
      // J·w column by column in O(n) each, instead of forming J in O(n²).
      for (Eigen::Index j = 0; j < m_k; ++j)
        m_chain->jacobian_vector(
            std::span(y).first(d), std::span(y).subspan(d + static_cast<std::size_t>(j) * d, d),
            std::span(dydt).subspan(d + static_cast<std::size_t>(j) * d, d), t);
      return;
    }
    m_chain->jacobian(std::span(y).first(d), std::span(m_jac->data(), d * d), t);
    Eigen::Map<Eigen::MatrixXd>(dydt.data() + m_d, m_d, m_k).noalias() =
        *m_jac * Eigen::Map<const Eigen::MatrixXd>(y.data() + m_d, m_d, m_k);
  }

 private:
  const chain* m_chain;
  Eigen::Index m_d, m_k;
  std::shared_ptr<row_major> m_jac;  // shared work space: odeint copies systems freely
};

// Calls body(advance) with the advance of the chosen route: the Gauss–Legendre tangent
// map, or one stepper, made once, integrating the variational equations chunk by chunk.
template <class Body>
void with_advance(const chain& c, const integration_options& o, Eigen::Index k, std::string& method,
                  Body&& body) {
  switch (o.stepper) {
    case stepper_kind::gauss4:
      method = "tangent map";
      return body(gauss_legendre_advance<gauss_legendre4>(c, o.dt));
    case stepper_kind::gauss6:
      method = "tangent map";
      return body(gauss_legendre_advance<gauss_legendre6>(c, o.dt));
    case stepper_kind::taylor:
      method = "Taylor series of the variational equations";
      return body(taylor_advance(c, o, k));
    default:
      break;
  }
  method = "variational equations";
  // No stepper on this route calls the Jacobian: rosenbrock4 is refused (see
  // lyapunov_options), Gauss–Legendre and Taylor take their own routes.
  const auto system = detail::explicit_system(variational_system(c, k));
  const auto d = static_cast<std::size_t>(c.state_size());
  const std::size_t dim = d + d * static_cast<std::size_t>(k);
  integration_options chunk_options = o;
  visit_stepper(o.stepper, o, system, dim, [&](auto& stepper) {
    std::vector<double> y(dim);
    body(tangent_advance([&](std::vector<double>& x, Eigen::MatrixXd& W, double t,
                             std::size_t steps, const step_poll& poll) {
      std::copy(x.begin(), x.end(), y.begin());
      std::copy(W.data(), W.data() + W.size(), y.begin() + static_cast<std::ptrdiff_t>(d));
      chunk_options.t_start = t;
      chunk_options.t_end = t + static_cast<double>(steps) * o.dt;
      poll_control control(poll, steps);  // the chunks are not the run: run_benettin reports
      chunk_options.control = &control;
      const integration_result r = detail::integrate_visited(stepper, system, y, chunk_options);
      std::copy(r.state.begin(), r.state.begin() + static_cast<std::ptrdiff_t>(d), x.begin());
      std::copy(r.state.begin() + static_cast<std::ptrdiff_t>(d), r.state.end(), W.data());
      return r.stopped ? static_cast<std::size_t>(std::llround((r.t - t) / o.dt)) : steps;
    }));
  });
}

void check_start(const chain& c, std::span<const double> x0) {
  const auto d = static_cast<std::size_t>(c.state_size());
  if (x0.size() != d)
    throw std::invalid_argument(fmt::format(
        "start state x0 has {} entries; the {}-link chain needs {}", x0.size(), c.links(), d));
  detail::require_finite_start(x0);
}

lyapunov_result run_benettin(const chain& c, std::span<const double> x0, const lyapunov_options& o,
                             Eigen::MatrixXd W, const lyapunov_observer& observer) {
  o.validate();
  check_start(c, x0);
  const auto d = static_cast<std::size_t>(c.state_size());

  const double dt = o.integration.dt, t0 = o.integration.t_start;
  const std::size_t total = output_steps(o.integration);
  const std::size_t chunk = std::max<std::size_t>(
      1, static_cast<std::size_t>(std::llround(o.renormalisation_interval / dt)));
  const auto transient_chunks =
      static_cast<std::size_t>(std::ceil(o.transient / (static_cast<double>(chunk) * dt) - 1e-9));
  const std::size_t transient_steps = transient_chunks * chunk;
  if (transient_steps >= total)
    throw std::invalid_argument(fmt::format(
        "lyapunov: the transient of {} s (rounded to {} s) leaves no time to average before "
        "t_end = {} s",
        o.transient, static_cast<double>(transient_steps) * dt, o.integration.t_end));
  const std::size_t averaging_chunks = (total - transient_steps + chunk - 1) / chunk;
  const std::size_t stride = (averaging_chunks + o.max_history - 1) / o.max_history;
  // Block b holds the averaging chunks [b A / B, (b + 1) A / B).
  const std::size_t blocks = std::min(o.blocks, averaging_chunks);
  const auto block_end = [&](std::size_t b) { return (b + 1) * averaging_chunks / blocks; };

  lyapunov_result r;
  r.renormalisation_interval = static_cast<double>(chunk) * dt;
  r.transient = static_cast<double>(transient_steps) * dt;
  const auto k = static_cast<std::size_t>(W.cols());
  std::vector<double> x(x0.begin(), x0.end()), sums(k, 0.0), running, block_sums(k, 0.0);
  energy_drift energy(c, c.hamiltonian(x));
  const double t_average = t0 + r.transient;

  std::size_t done = 0;
  double t_chunk = t0;  // the end of the last chunk whose growth is summed
  run_control* const control = o.integration.control;
  // Inside a chunk only the stop request is polled (cheap, so a long chain's chunk can be
  // cut short); progress is reported once per re-orthonormalisation, below.
  const step_poll poll = [&](std::size_t) { return stop_requested(control); };
  with_advance(c, o.integration, W.cols(), r.method, [&](const tangent_advance& advance) {
    while (done < total) {
      const std::size_t steps = std::min(chunk, total - done);
      const std::size_t did = advance(x, W, t0 + static_cast<double>(done) * dt, steps, poll);
      done += did;
      r.t = t0 + static_cast<double>(done) * dt;
      if (did < steps) {  // stopped inside the chunk: its growth is not summed
        r.stopped = true;
        break;
      }
      t_chunk = r.t;
      if (!W.allFinite())
        throw integration_error(
            fmt::format("lyapunov: the tangent vectors became non-finite before t = {} s; try a "
                        "shorter renormalisation interval or a smaller dt",
                        r.t),
            r.t);
      const Eigen::HouseholderQR<Eigen::MatrixXd> qr(W);
      const Eigen::VectorXd diagonal = qr.matrixQR().diagonal();
      W = qr.householderQ() * Eigen::MatrixXd::Identity(static_cast<Eigen::Index>(d), W.cols());
      energy.add(x);
      r.max_rel_energy_error = energy.max_relative_error();

      if (done > transient_steps) {
        ++r.renormalisations;
        running.resize(k);
        if (r.block_edges.empty()) r.block_edges.push_back(t_average);
        for (std::size_t i = 0; i < k; ++i) {
          const double growth = std::log(std::fabs(diagonal(static_cast<Eigen::Index>(i))));
          sums[i] += growth;
          block_sums[i] += growth;
          running[i] = sums[i] / (r.t - t_average);
        }
        if (r.renormalisations == block_end(r.block_exponents.size())) {
          const double length = r.t - r.block_edges.back();
          std::vector<double> block(k);
          for (std::size_t i = 0; i < k; ++i) block[i] = block_sums[i] / length;
          r.block_exponents.push_back(std::move(block));
          r.block_edges.push_back(r.t);
          block_sums.assign(k, 0.0);
        }
        if (r.renormalisations % stride == 0 || done == total) {
          r.history_t.push_back(r.t);
          r.history.push_back(running);
        }
      }
      const bool observer_stops = observer && observer(r.t, running) == observer_action::stop;
      const bool control_stops =
          report_progress(control, static_cast<double>(done), static_cast<double>(total));
      if ((observer_stops || control_stops) && done < total) {
        r.stopped = true;
        break;
      }
    }
  });
  r.state = x;
  r.averaging_time = std::max(0.0, t_chunk - t_average);
  if (running.empty()) {  // stopped during the transient: nothing averaged
    r.exponents.assign(k, std::numeric_limits<double>::quiet_NaN());
    r.spread.assign(k, std::numeric_limits<double>::quiet_NaN());
    r.block_standard_error.assign(k, std::numeric_limits<double>::quiet_NaN());
    r.sum = std::numeric_limits<double>::quiet_NaN();
    return r;
  }
  if (r.history_t.empty() || r.history_t.back() != t_chunk) {
    r.history_t.push_back(t_chunk);
    r.history.push_back(running);
  }

  // Descending order; the history and the spreads follow the same permutation.
  std::vector<std::size_t> order(k);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return running[a] > running[b]; });
  const auto permuted = [&](const std::vector<double>& v) {
    std::vector<double> out(k);
    for (std::size_t i = 0; i < k; ++i) out[i] = v[order[i]];
    return out;
  };
  r.exponents = permuted(running);
  for (auto& h : r.history) h = permuted(h);
  for (auto& b : r.block_exponents) b = permuted(b);
  r.block_standard_error.assign(k, std::numeric_limits<double>::quiet_NaN());
  if (const std::size_t count = r.block_exponents.size(); count >= 2)
    for (std::size_t i = 0; i < k; ++i) {
      double mean = 0, squares = 0;
      for (const auto& b : r.block_exponents) mean += b[i];
      mean /= static_cast<double>(count);
      for (const auto& b : r.block_exponents) squares += (b[i] - mean) * (b[i] - mean);
      r.block_standard_error[i] =
          std::sqrt(squares / static_cast<double>(count - 1) / static_cast<double>(count));
    }
  r.sum = std::accumulate(r.exponents.begin(), r.exponents.end(), 0.0);
  if (k == x.size()) r.pair_sums = pair_sums(r.exponents);  // the full spectrum

  const double tail_start = t_average + (1 - o.convergence_fraction) * r.averaging_time;
  r.spread.assign(k, std::numeric_limits<double>::quiet_NaN());
  std::vector<double> low(k, std::numeric_limits<double>::infinity()),
      high(k, -std::numeric_limits<double>::infinity());
  std::size_t count = 0;
  for (std::size_t j = 0; j < r.history_t.size(); ++j) {
    if (r.history_t[j] < tail_start - 1e-9 * dt) continue;
    ++count;
    for (std::size_t i = 0; i < k; ++i) {
      low[i] = std::min(low[i], r.history[j][i]);
      high[i] = std::max(high[i], r.history[j][i]);
    }
  }
  if (count >= 2)
    for (std::size_t i = 0; i < k; ++i) r.spread[i] = high[i] - low[i];
  return r;
}

}  // namespace

lyapunov_result lyapunov_spectrum(const chain& c, std::span<const double> x0,
                                  const lyapunov_options& options,
                                  const lyapunov_observer& observer) {
  // The unit vectors in the order (φ_1..φ_n, p_n..p_1): then, for every k, the span of the
  // last k columns is J times the span of the first k (J = [[0, I], [−I, 0]]). A symplectic
  // tangent map M keeps that, since (M V)^⊥ = M^{−T} V^⊥ = J M J⁻¹ V^⊥, and so the volume
  // growth of the first 2n − k columns equals that of the first k: R_kk R_{2n+1−k,2n+1−k} = 1
  // at every re-orthonormalisation. With the Gauss–Legendre tangent map the exponents come
  // out in exact ± pairs at every finite time, not only in the limit. (n: the coordinates,
  // the angles after the cart's position on a cart.)
  const int n = c.coordinates();
  Eigen::MatrixXd frame = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  for (int i = 0; i < n; ++i) {
    frame(i, i) = 1;
    frame(n + i, 2 * n - 1 - i) = 1;
  }
  return run_benettin(c, x0, options, frame, observer);
}

lyapunov_result largest_lyapunov_exponents(const chain& c, std::span<const double> x0,
                                           const lyapunov_options& options, int count,
                                           const lyapunov_observer& observer) {
  const int n = c.coordinates();
  if (count < 1 || count > 2 * n)
    throw std::invalid_argument(
        fmt::format("lyapunov: the number of exponents must be 1..{} (2n), got {}", 2 * n, count));
  // The first `count` columns of lyapunov_spectrum's frame (φ_1..φ_n, p_n..p_1).
  Eigen::MatrixXd frame = Eigen::MatrixXd::Zero(2 * n, count);
  for (int j = 0; j < count; ++j) {
    if (j < n)
      frame(j, j) = 1;
    else
      frame(n + (2 * n - 1 - j), j) = 1;
  }
  return run_benettin(c, x0, options, frame, observer);
}

lyapunov_result maximal_lyapunov_exponent(const chain& c, std::span<const double> x0,
                                          const lyapunov_options& options,
                                          const lyapunov_observer& observer) {
  const Eigen::Index d = c.state_size();
  return run_benettin(c, x0, options,
                      Eigen::MatrixXd::Constant(d, 1, 1.0 / std::sqrt(static_cast<double>(d))),
                      observer);
}

namespace {

// ∇H = (−ṗ, φ̇) from Hamilton's equations f = (∂H/∂p, −∂H/∂φ).
std::vector<double> energy_gradient(const chain& c, std::span<const double> x) {
  const std::vector<double> f = c.rhs(x);
  const std::size_t n = static_cast<std::size_t>(c.coordinates());
  std::vector<double> g(2 * n);
  for (std::size_t i = 0; i < n; ++i) {
    g[i] = -f[n + i];
    g[n + i] = f[i];
  }
  return g;
}

// x moved along ∇H(x) until H = energy: Newton on s ↦ H(x + s ∇H(x)), whose derivative is
// ∇H(x + s∇H) · ∇H(x).
std::vector<double> onto_energy_surface(const chain& c, std::vector<double> x, double energy) {
  const std::vector<double> direction = energy_gradient(c, x);
  double norm = 0;
  for (double v : direction) norm += v * v;
  if (!(norm > 0))
    throw std::invalid_argument(
        "energy_surface_neighbours: the gradient of H vanishes at a perturbed start");
  const double tolerance =
      8 * std::numeric_limits<double>::epsilon() * std::max(1.0, std::fabs(energy));
  std::vector<double> y = x;
  double s = 0;
  for (int iteration = 0; iteration < 50; ++iteration) {
    for (std::size_t i = 0; i < x.size(); ++i) y[i] = x[i] + s * direction[i];
    const double defect = c.hamiltonian(y) - energy;
    if (std::fabs(defect) <= tolerance) return y;
    const std::vector<double> g = energy_gradient(c, y);
    double slope = 0;
    for (std::size_t i = 0; i < x.size(); ++i) slope += g[i] * direction[i];
    if (!(slope != 0) || !std::isfinite(slope)) break;
    s -= defect / slope;
  }
  throw std::invalid_argument(fmt::format(
      "energy_surface_neighbours: could not bring a perturbed start back to H = {} J; use a "
      "smaller radius",
      energy));
}

}  // namespace

std::vector<std::vector<double>> energy_surface_neighbours(const chain& c,
                                                           std::span<const double> x0,
                                                           std::size_t count, double radius,
                                                           std::uint64_t seed) {
  check_start(c, x0);
  if (count == 0)
    throw std::invalid_argument("energy_surface_neighbours: count must be at least 1");
  if (!(radius > 0) || !std::isfinite(radius))
    throw std::invalid_argument(fmt::format(
        "energy_surface_neighbours: radius is {}: it must be positive and finite", radius));
  std::vector<std::vector<double>> starts{std::vector<double>(x0.begin(), x0.end())};
  if (count == 1) return starts;
  const std::vector<double> gradient = energy_gradient(c, x0);
  double scale = 0;
  for (double v : gradient) scale = std::max(scale, std::fabs(v));
  if (!(scale > 0))
    throw std::invalid_argument(
        "energy_surface_neighbours: x0 is an equilibrium (grad H = 0): no nearby state has its "
        "energy");
  const double energy = c.hamiltonian(x0);
  const std::size_t n = static_cast<std::size_t>(c.coordinates());
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal;
  while (starts.size() < count) {
    std::vector<double> direction(n);
    double norm = 0;
    for (double& v : direction) {
      v = normal(rng);
      norm += v * v;
    }
    norm = std::sqrt(norm);
    if (!(norm > 0)) continue;
    std::vector<double> x(x0.begin(), x0.end());
    for (std::size_t i = 0; i < n; ++i) x[i] += radius * direction[i] / norm;
    starts.push_back(onto_energy_surface(c, std::move(x), energy));
  }
  return starts;
}

lyapunov_ensemble_result lyapunov_ensemble(const chain& c, std::span<const double> x0,
                                           const lyapunov_options& options,
                                           const lyapunov_ensemble_options& ensemble,
                                           const lyapunov_ensemble_observer& observer) {
  options.validate();
  if (ensemble.members < 2)
    throw std::invalid_argument(
        fmt::format("lyapunov_ensemble: members is {}: it must be at least 2", ensemble.members));
  lyapunov_ensemble_result r;
  r.starts = energy_surface_neighbours(c, x0, ensemble.members, ensemble.radius, ensemble.seed);
  for (std::size_t m = 0; m < r.starts.size(); ++m) {
    lyapunov_observer member;
    if (observer)
      member = [&observer, m](double t, std::span<const double> running) {
        return observer(m, t, running);
      };
    // Member m is the m-th of `members` equal parts of the run control's progress.
    run_control_part part(options.integration.control, m, r.starts.size());
    lyapunov_options member_options = options;
    member_options.integration.control = &part;
    lyapunov_result run = ensemble.maximal
                              ? maximal_lyapunov_exponent(c, r.starts[m], member_options, member)
                              : lyapunov_spectrum(c, r.starts[m], member_options, member);
    r.stopped = run.stopped;
    if (!run.stopped) r.runs.push_back(std::move(run));
    if (r.stopped) break;
  }
  const std::size_t k = ensemble.maximal ? 1 : static_cast<std::size_t>(c.state_size());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  r.mean.assign(k, nan);
  r.standard_deviation.assign(k, nan);
  r.standard_error.assign(k, nan);
  const std::size_t count = r.runs.size();
  if (count < 2) return r;
  for (std::size_t i = 0; i < k; ++i) {
    double mean = 0, squares = 0;
    for (const auto& run : r.runs) mean += run.exponents[i];
    mean /= static_cast<double>(count);
    for (const auto& run : r.runs) squares += (run.exponents[i] - mean) * (run.exponents[i] - mean);
    r.mean[i] = mean;
    r.standard_deviation[i] = std::sqrt(squares / static_cast<double>(count - 1));
    r.standard_error[i] = r.standard_deviation[i] / std::sqrt(static_cast<double>(count));
  }
  return r;
}

std::vector<double> pair_sums(std::span<const double> exponents) {
  std::vector<double> sums;
  const std::size_t d = exponents.size();
  for (std::size_t i = 0; i < d / 2; ++i) sums.push_back(exponents[i] + exponents[d - 1 - i]);
  return sums;
}

}  // namespace npend
