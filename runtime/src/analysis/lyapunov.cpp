#include "npend/analysis/lyapunov.hpp"

#include "detail/explicit_system.hpp"
#include "npend/chain_system.hpp"
#include "npend/gauss_legendre.hpp"
#include "npend/integrate_system.hpp"
#include "npend/integration_error.hpp"

#include <Eigen/Dense>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <stdexcept>

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
  if (integration.stepper == stepper_kind::rosenbrock4)
    throw std::invalid_argument(
        "lyapunov: the rosenbrock4 stepper cannot integrate the variational equations (its "
        "stages need their Jacobian, which holds second derivatives of f that the generated "
        "kernels do not provide); use gauss6 (the exact tangent map of its steps), gauss4, or "
        "an explicit stepper (rk4, dopri5, rkf78, bs)");
}

namespace {

using row_major = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// Advances x (dim d) and the tangent vectors W (d × k) by `steps` steps of dt from t.
using tangent_advance =
    std::function<void(std::vector<double>& x, Eigen::MatrixXd& W, double t, std::size_t steps)>;

// The Gauss–Legendre route: each step's exact derivative applied to W.
template <class Stepper>
tangent_advance gauss_legendre_advance(const chain& c, double dt) {
  auto stepper = std::make_shared<Stepper>();
  return [stepper, system = make_implicit_system(c), dt](std::vector<double>& x, Eigen::MatrixXd& W,
                                                         double t, std::size_t steps) {
    for (std::size_t k = 0; k < steps; ++k)
      stepper->do_step_with_tangent(system, x, t + static_cast<double>(k) * dt, dt, W);
  };
}

// dy/dt for y = [x (dim d), W (d × k, column-major)]: [f(x), J(x) W].
class variational_system {
 public:
  variational_system(const chain& c, Eigen::Index k)
      : m_kernels(&c.kernels()),
        m_params(c.packed_parameters().data()),
        m_d(c.state_size()),
        m_k(k),
        m_jac(std::make_shared<row_major>(m_d, m_d)) {}

  void operator()(const std::vector<double>& y, std::vector<double>& dydt, double /*t*/) const {
    m_kernels->rhs(y.data(), m_params, dydt.data());
    m_kernels->jacobian(y.data(), m_params, m_jac->data());
    Eigen::Map<Eigen::MatrixXd>(dydt.data() + m_d, m_d, m_k).noalias() =
        *m_jac * Eigen::Map<const Eigen::MatrixXd>(y.data() + m_d, m_d, m_k);
  }

 private:
  const generated::chain_kernels* m_kernels;
  const double* m_params;
  Eigen::Index m_d, m_k;
  std::shared_ptr<row_major> m_jac;  // shared work space: odeint copies systems freely
};

tangent_advance variational_advance(const chain& c, const integration_options& base,
                                    Eigen::Index k) {
  // No stepper on this route calls the Jacobian: rosenbrock4 is refused (see
  // lyapunov_options) and Gauss–Legendre takes the tangent-map route.
  const auto system = detail::explicit_system(variational_system(c, k));
  const auto d = static_cast<std::size_t>(c.state_size());
  return [system, base, d, k](std::vector<double>& x, Eigen::MatrixXd& W, double t,
                              std::size_t steps) {
    std::vector<double> y(d + d * static_cast<std::size_t>(k));
    std::copy(x.begin(), x.end(), y.begin());
    std::copy(W.data(), W.data() + W.size(), y.begin() + static_cast<std::ptrdiff_t>(d));
    integration_options o = base;
    o.t_start = t;
    o.t_end = t + static_cast<double>(steps) * base.dt;
    const integration_result r = integrate_system(system, y, o);
    std::copy(r.state.begin(), r.state.begin() + static_cast<std::ptrdiff_t>(d), x.begin());
    std::copy(r.state.begin() + static_cast<std::ptrdiff_t>(d), r.state.end(), W.data());
  };
}

tangent_advance make_advance(const chain& c, const integration_options& o, Eigen::Index k,
                             std::string& method) {
  switch (o.stepper) {
    case stepper_kind::gauss4:
      method = "tangent map";
      return gauss_legendre_advance<gauss_legendre4>(c, o.dt);
    case stepper_kind::gauss6:
      method = "tangent map";
      return gauss_legendre_advance<gauss_legendre6>(c, o.dt);
    default:
      method = "variational equations";
      return variational_advance(c, o, k);
  }
}

lyapunov_result run_benettin(const chain& c, std::span<const double> x0, const lyapunov_options& o,
                             Eigen::MatrixXd W, const lyapunov_observer& observer) {
  o.validate();
  const auto d = static_cast<std::size_t>(c.state_size());
  if (x0.size() != d)
    throw std::invalid_argument(fmt::format(
        "start state x0 has {} entries; the {}-link chain needs {}", x0.size(), c.links(), d));
  for (std::size_t i = 0; i < d; ++i)
    if (!std::isfinite(x0[i]))
      throw std::invalid_argument(fmt::format("start state entry {} is not finite", i + 1));

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

  lyapunov_result r;
  r.renormalisation_interval = static_cast<double>(chunk) * dt;
  r.transient = static_cast<double>(transient_steps) * dt;
  const tangent_advance advance = make_advance(c, o.integration, W.cols(), r.method);
  const auto k = static_cast<std::size_t>(W.cols());
  std::vector<double> x(x0.begin(), x0.end()), sums(k, 0.0), running;
  const double h0 = c.hamiltonian(x);
  const double t_average = t0 + r.transient;

  std::size_t done = 0;
  while (done < total) {
    const std::size_t steps = std::min(chunk, total - done);
    advance(x, W, t0 + static_cast<double>(done) * dt, steps);
    done += steps;
    r.t = t0 + static_cast<double>(done) * dt;
    if (!W.allFinite())
      throw integration_error(
          fmt::format("lyapunov: the tangent vectors became non-finite before t = {} s; try a "
                      "shorter renormalisation interval or a smaller dt",
                      r.t),
          r.t);
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr(W);
    const Eigen::VectorXd diagonal = qr.matrixQR().diagonal();
    W = qr.householderQ() * Eigen::MatrixXd::Identity(static_cast<Eigen::Index>(d), W.cols());
    const double h = c.hamiltonian(x);
    r.max_rel_energy_error =
        std::max(r.max_rel_energy_error, std::fabs(h - h0) / (h0 != 0 ? std::fabs(h0) : 1.0));

    if (done > transient_steps) {
      ++r.renormalisations;
      running.resize(k);
      for (std::size_t i = 0; i < k; ++i) {
        sums[i] += std::log(std::fabs(diagonal(static_cast<Eigen::Index>(i))));
        running[i] = sums[i] / (r.t - t_average);
      }
      if (r.renormalisations % stride == 0 || done == total) {
        r.history_t.push_back(r.t);
        r.history.push_back(running);
      }
    }
    if (observer && observer(r.t, running) == observer_action::stop && done < total) {
      r.stopped = true;
      break;
    }
  }
  r.state = x;
  r.averaging_time = std::max(0.0, r.t - t_average);
  if (running.empty()) {  // stopped during the transient: nothing averaged
    r.exponents.assign(k, std::numeric_limits<double>::quiet_NaN());
    r.spread.assign(k, std::numeric_limits<double>::quiet_NaN());
    r.sum = std::numeric_limits<double>::quiet_NaN();
    return r;
  }
  if (r.history_t.empty() || r.history_t.back() != r.t) {
    r.history_t.push_back(r.t);
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
  r.sum = std::accumulate(r.exponents.begin(), r.exponents.end(), 0.0);

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
  // out in exact ± pairs at every finite time, not only in the limit.
  const int n = c.links();
  Eigen::MatrixXd frame = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  for (int i = 0; i < n; ++i) {
    frame(i, i) = 1;
    frame(n + i, 2 * n - 1 - i) = 1;
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

}  // namespace npend
