#include "npend/analysis/stability/harmonic_corrections.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "analysis/detail/explicit_system.hpp"
#include "npend/analysis/stability/normal_modes.hpp"
#include "npend/integrators/integrate.hpp"
#include "npend/integrators/integrate_system.hpp"

namespace npend {

std::string_view truncation_name(truncation kind) {
  switch (kind) {
    case truncation::harmonic:
      return "harmonic";
    case truncation::paper:
      return "paper";
    case truncation::cubic:
      return "cubic";
  }
  return "?";
}

namespace {

using row_major = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

void check_sizes(const chain& c, std::span<const double> phi, std::span<const double> dphi) {
  const auto n = static_cast<std::size_t>(c.links());
  if (phi.size() != n || dphi.size() != n)
    throw std::invalid_argument(
        fmt::format("phi and dphi have {} and {} entries; the {}-link chain needs {} each",
                    phi.size(), dphi.size(), c.links(), n));
}

// A⁰ = A(0) and the diagonal of K = ∇²V(0) (which is diagonal: K_ii = μ_i g l_i).
struct hanging_matrices {
  Eigen::MatrixXd A0;
  Eigen::VectorXd K;
};

hanging_matrices at_rest(const chain& c) {
  const int n = c.links();
  const std::vector<double> zero(static_cast<std::size_t>(n), 0.0);
  std::vector<double> A(static_cast<std::size_t>(n * n)), H(static_cast<std::size_t>(n * n));
  c.mass_matrix(zero, A);
  c.potential_hessian(zero, H);
  hanging_matrices m{Eigen::Map<const row_major>(A.data(), n, n), Eigen::VectorXd(n)};
  for (int i = 0; i < n; ++i) m.K(i) = H[static_cast<std::size_t>(i * n + i)];
  return m;
}

std::vector<double> solve_truncated(const hanging_matrices& m, truncation kind,
                                    std::span<const double> phi, std::span<const double> dphi) {
  const auto n = static_cast<Eigen::Index>(phi.size());
  Eigen::MatrixXd matrix = m.A0;
  Eigen::VectorXd rhs(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double p = phi[static_cast<std::size_t>(i)];
    double force = m.K(i) * (kind == truncation::cubic ? p - p * p * p / 6 : p);
    if (kind != truncation::harmonic)
      for (Eigen::Index j = 0; j < n; ++j) {
        const double difference = p - phi[static_cast<std::size_t>(j)];
        const double rate = dphi[static_cast<std::size_t>(j)];
        force += m.A0(i, j) * difference * rate * rate;
        if (kind == truncation::cubic) matrix(i, j) *= 1 - difference * difference / 2;
      }
    rhs(i) = -force;
  }
  const Eigen::VectorXd a = matrix.partialPivLu().solve(rhs);
  return {a.data(), a.data() + n};
}

// The first n entries of v (dim 2n) and the rest.
std::span<const double> head(std::span<const double> v) { return v.first(v.size() / 2); }
std::span<const double> tail(std::span<const double> v) { return v.subspan(v.size() / 2); }

}  // namespace

std::vector<double> truncated_acceleration(const chain& c, truncation kind,
                                           std::span<const double> phi,
                                           std::span<const double> dphi) {
  check_sizes(c, phi, dphi);
  return solve_truncated(at_rest(c), kind, phi, dphi);
}

std::vector<double> exact_acceleration(const chain& c, std::span<const double> phi,
                                       std::span<const double> dphi) {
  check_sizes(c, phi, dphi);
  const std::vector<double> x = c.state_from_velocities(phi, dphi);
  const std::vector<double> f = c.rhs(x), J = c.jacobian(x);
  const std::size_t n = phi.size(), d = 2 * n;
  std::vector<double> out(n, 0.0);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < d; ++j) out[i] += J[i * d + j] * f[j];
  return out;
}

std::vector<double> power_series::angles(double t) const {
  std::vector<double> out(a1.size());
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = a1[i] + (a2[i] + a3[i] * t) * t;
  return out;
}

std::vector<double> power_series::rates(double t) const {
  std::vector<double> out(a1.size());
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = a2[i] + 2 * a3[i] * t;
  return out;
}

power_series second_order_series(const chain& c, truncation kind, std::span<const double> phi0,
                                 std::span<const double> dphi0) {
  const std::vector<double> acceleration = truncated_acceleration(c, kind, phi0, dphi0);
  power_series s{{phi0.begin(), phi0.end()}, {dphi0.begin(), dphi0.end()}, acceleration};
  for (double& a : s.a3) a /= 2;
  return s;
}

double correction_function(std::span<const double> phi, std::span<const double> dphi) {
  if (phi.size() < 2 || dphi.size() < 2)
    throw std::invalid_argument(
        "correction_function: Q = phi1 phi2 / (dphi1 dphi2) needs two links");
  const double denominator = dphi[0] * dphi[1];
  if (denominator == 0) return std::numeric_limits<double>::quiet_NaN();
  return phi[0] * phi[1] / denominator;
}

void correction_study_options::validate() const {
  if (!(horizon >= 0) || !std::isfinite(horizon))
    throw std::invalid_argument(
        fmt::format("correction study: horizon is {}: it must be >= 0 (0: automatic)", horizon));
  if (samples < 2)
    throw std::invalid_argument(
        fmt::format("correction study: samples is {}: at least 2 are needed", samples));
  if (scales.size() < 2)
    throw std::invalid_argument("correction study: at least 2 scales are needed for the orders");
  for (std::size_t i = 0; i < scales.size(); ++i) {
    if (!(scales[i] > 0 && scales[i] <= 1))
      throw std::invalid_argument(
          fmt::format("correction study: scale {} is not in (0, 1]", scales[i]));
    for (std::size_t j = 0; j < i; ++j)
      if (scales[j] == scales[i])
        throw std::invalid_argument(
            fmt::format("correction study: scale {} is given twice", scales[i]));
  }
}

namespace {

// Every approximation, and the true motion, from one start over the sample times.
struct followed {
  std::vector<std::vector<double>> true_angles;
  std::vector<double> true_q, true_turns;
  // In the order of correction_track's names; turns: φ̇₁φ̇₂ at every sample.
  std::vector<std::vector<std::vector<double>>> angles;
  std::vector<std::vector<double>> q, turns;
};

// The first sign change of d(t) on the grid t, linearly interpolated; NaN if none.
double first_sign_change(const std::vector<double>& t, const std::vector<double>& d) {
  for (std::size_t j = 1; j < d.size(); ++j)
    if ((d[j - 1] < 0) != (d[j] < 0) || d[j] == 0)
      return d[j] == d[j - 1] ? t[j] : t[j - 1] + (t[j] - t[j - 1]) * d[j - 1] / (d[j - 1] - d[j]);
  return std::numeric_limits<double>::quiet_NaN();
}

const std::vector<std::string> track_names{"harmonic solution", "harmonic series", "paper series",
                                           "paper equations", "cubic equations"};

// The (φ, φ̇) trajectory of the truncated equations `kind` on the grid (rkf78 at 1e-13).
std::vector<std::vector<double>> integrate_truncated(const hanging_matrices& m, truncation kind,
                                                     std::span<const double> phi0,
                                                     std::span<const double> dphi0, double dt,
                                                     double t_end) {
  const std::size_t n = phi0.size();
  auto rhs = [&m, kind, n](const std::vector<double>& y, std::vector<double>& dydt, double) {
    const std::span<const double> state(y);
    const std::vector<double> a = solve_truncated(m, kind, head(state), tail(state));
    std::copy(y.begin() + static_cast<std::ptrdiff_t>(n), y.end(), dydt.begin());
    std::copy(a.begin(), a.end(), dydt.begin() + static_cast<std::ptrdiff_t>(n));
  };
  std::vector<double> y0(phi0.begin(), phi0.end());
  y0.insert(y0.end(), dphi0.begin(), dphi0.end());
  integration_options o;
  o.stepper = stepper_kind::rkf78;
  o.dt = dt;
  o.t_end = t_end;
  o.abs_tol = o.rel_tol = 1e-13;
  std::vector<std::vector<double>> out;
  integrate_system(detail::explicit_system(rhs), y0, o, [&](double, std::span<const double> y) {
    out.emplace_back(y.begin(), y.end());
    return observer_action::proceed;
  });
  return out;
}

followed follow(const chain& c, const hanging_matrices& m, const linearisation& lin,
                std::span<const double> phi0, std::span<const double> dphi0,
                const std::vector<double>& t) {
  const std::size_t n = phi0.size();
  const double dt = t[1] - t[0], t_end = t.back();
  followed f;
  f.angles.resize(track_names.size());
  f.q.resize(track_names.size());
  f.turns.resize(track_names.size());
  const auto add = [&](std::size_t track, std::span<const double> phi,
                       std::span<const double> dphi) {
    f.angles[track].emplace_back(phi.begin(), phi.end());
    f.q[track].push_back(correction_function(phi, dphi));
    f.turns[track].push_back(dphi[0] * dphi[1]);
  };

  // The chain itself.
  integration_options o;
  o.stepper = stepper_kind::gauss6;
  o.dt = dt;
  o.t_end = t_end;
  std::vector<double> rates(n);
  integrate(c, c.state_from_velocities(phi0, dphi0), o, [&](double, std::span<const double> x) {
    c.velocities(head(x), tail(x), rates);
    f.true_angles.emplace_back(x.begin(), x.begin() + static_cast<std::ptrdiff_t>(n));
    f.true_q.push_back(correction_function(head(x), rates));
    f.true_turns.push_back(rates[0] * rates[1]);
  });

  // The harmonic solution by normal modes: φ = Σ_k v_k (q_k cos ω_k t + q̇_k/ω_k sin ω_k t)
  // with q = Vᵀ M φ(0), q̇ = Vᵀ M φ̇(0).
  const Eigen::Map<const row_major> M(lin.mass_matrix.data(), static_cast<Eigen::Index>(n),
                                      static_cast<Eigen::Index>(n));
  const Eigen::Map<const Eigen::VectorXd> p0(phi0.data(), static_cast<Eigen::Index>(n)),
      v0(dphi0.data(), static_cast<Eigen::Index>(n));
  const Eigen::VectorXd Mp = M * p0, Mv = M * v0;
  for (double time : t) {
    Eigen::VectorXd phi = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(n)), dphi = phi;
    for (const auto& mode : lin.modes) {
      const Eigen::Map<const Eigen::VectorXd> v(mode.shape.data(), static_cast<Eigen::Index>(n));
      const double q = v.dot(Mp), dq = v.dot(Mv), w = mode.frequency;
      const double cosine = std::cos(w * time), sine = std::sin(w * time);
      phi += (q * cosine + dq / w * sine) * v;
      dphi += (-q * w * sine + dq * cosine) * v;
    }
    add(0, {phi.data(), n}, {dphi.data(), n});
  }

  // The paper's power series, of the harmonic and of the corrected equations.
  const power_series harmonic = second_order_series(c, truncation::harmonic, phi0, dphi0);
  const power_series paper = second_order_series(c, truncation::paper, phi0, dphi0);
  for (double time : t) {
    add(1, harmonic.angles(time), harmonic.rates(time));
    add(2, paper.angles(time), paper.rates(time));
  }

  // The corrected equations themselves, integrated.
  for (const auto& [track, kind] :
       {std::pair{std::size_t{3}, truncation::paper}, std::pair{std::size_t{4}, truncation::cubic}})
    for (const auto& y : integrate_truncated(m, kind, phi0, dphi0, dt, t_end))
      add(track, head(y), tail(y));
  return f;
}

double max_error(const std::vector<std::vector<double>>& a,
                 const std::vector<std::vector<double>>& b) {
  double worst = 0;
  for (std::size_t j = 0; j < std::min(a.size(), b.size()); ++j)
    for (std::size_t i = 0; i < a[j].size(); ++i)
      worst = std::max(worst, std::fabs(a[j][i] - b[j][i]));
  return worst;
}

// Least-squares slope of log y against log x.
double log_slope(const std::vector<double>& x, const std::vector<double>& y) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const auto m = static_cast<double>(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double lx = std::log(x[i]), ly = std::log(y[i]);
    sx += lx;
    sy += ly;
    sxx += lx * lx;
    sxy += lx * ly;
  }
  return (m * sxy - sx * sy) / (m * sxx - sx * sx);
}

std::vector<double> scaled(std::span<const double> v, double s) {
  std::vector<double> out(v.begin(), v.end());
  for (double& e : out) e *= s;
  return out;
}

}  // namespace

correction_study harmonic_correction_study(const chain& c, std::span<const double> phi0,
                                           std::span<const double> dphi0,
                                           const correction_study_options& options) {
  options.validate();
  if (c.links() < 2)
    throw std::invalid_argument(
        "correction study: needs at least 2 links (Q = phi1 phi2 / (dphi1 dphi2); for one link "
        "the paper's correction terms vanish)");
  check_sizes(c, phi0, dphi0);
  bool moving = false;
  for (std::size_t i = 0; i < phi0.size(); ++i) {
    if (!std::isfinite(phi0[i]) || !std::isfinite(dphi0[i]))
      throw std::invalid_argument(
          fmt::format("correction study: start value {} is not finite", i + 1));
    moving = moving || phi0[i] != 0 || dphi0[i] != 0;
  }
  if (!moving)
    throw std::invalid_argument(
        "correction study: the start is the hanging chain at rest: nothing moves");

  const std::size_t n = phi0.size();
  const linearisation lin = normal_modes(c, std::vector<double>(n, 0.0));
  const hanging_matrices m = at_rest(c);

  correction_study s;
  s.phi0.assign(phi0.begin(), phi0.end());
  s.dphi0.assign(dphi0.begin(), dphi0.end());
  s.scales = options.scales;
  s.horizon = options.horizon > 0 ? options.horizon
                                  : 0.25 * 2 * std::numbers::pi / lin.modes.back().frequency;
  for (std::size_t j = 0; j < options.samples; ++j)
    s.t.push_back(s.horizon * static_cast<double>(j) / static_cast<double>(options.samples - 1));

  const followed main = follow(c, m, lin, phi0, dphi0, s.t);
  s.true_angles = main.true_angles;
  s.true_q = main.true_q;
  s.true_q_pole = first_sign_change(s.t, main.true_turns);
  for (std::size_t k = 0; k < track_names.size(); ++k) {
    correction_track track;
    track.name = track_names[k];
    track.angles = main.angles[k];
    track.q = main.q[k];
    track.max_error = max_error(main.angles[k], main.true_angles);
    track.q_pole = first_sign_change(s.t, main.turns[k]);
    s.tracks.push_back(std::move(track));
  }
  for (double scale : options.scales) {
    const followed f = follow(c, m, lin, scaled(phi0, scale), scaled(dphi0, scale), s.t);
    for (std::size_t k = 0; k < track_names.size(); ++k)
      s.tracks[k].scaled_errors.push_back(max_error(f.angles[k], f.true_angles));
  }
  for (auto& track : s.tracks) track.order = log_slope(options.scales, track.scaled_errors);

  for (const truncation kind : {truncation::harmonic, truncation::paper, truncation::cubic}) {
    acceleration_defect d;
    d.kind = kind;
    for (double scale : options.scales) {
      const auto phi = scaled(phi0, scale), dphi = scaled(dphi0, scale);
      const auto exact = exact_acceleration(c, phi, dphi);
      const auto approximate = solve_truncated(m, kind, phi, dphi);
      double worst = 0;
      for (std::size_t i = 0; i < n; ++i)
        worst = std::max(worst, std::fabs(approximate[i] - exact[i]));
      d.errors.push_back(worst);
    }
    d.order = log_slope(options.scales, d.errors);
    s.defects.push_back(d);
  }
  return s;
}

}  // namespace npend
