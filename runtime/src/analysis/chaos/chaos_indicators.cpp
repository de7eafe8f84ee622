#include "npend/analysis/chaos/chaos_indicators.hpp"

#include <fmt/format.h>

#include <Eigen/SVD>
#include <algorithm>
#include <array>
#include <boost/numeric/odeint/stepper/runge_kutta4.hpp>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "analysis/detail/argument_checks.hpp"
#include "analysis/detail/dense_eigen.hpp"
#include "npend/integrators/integrate.hpp"
#include "npend/integrators/integration_error.hpp"
#include "npend/integrators/taylor.hpp"

namespace npend {

void chaos_indicator_options::validate() const {
  if (!(dt > 0) || !std::isfinite(dt) || !std::isfinite(t_end) || !(t_end >= dt))
    throw std::invalid_argument(fmt::format(
        "chaos indicators: need 0 < dt <= t_end, both finite, got dt = {}, t_end = {}", dt, t_end));
  if (!(sample_interval >= 0) || !std::isfinite(sample_interval))
    throw std::invalid_argument(fmt::format(
        "chaos indicators: sample_interval is {}: it must be >= 0 and finite", sample_interval));
  if (!serves(stepper, stepper_use::indicators))
    throw std::invalid_argument(fmt::format("chaos indicators: they integrate with {}, not {}",
                                            stepper_names(stepper_use::indicators),
                                            stepper_name(stepper)));
  if (stepper == stepper_kind::taylor && !(tolerance > 0 && tolerance <= 1e-6))
    throw std::invalid_argument(fmt::format(
        "chaos indicators: the taylor tolerance must lie in (0, 1e-6], got {}", tolerance));
}

namespace {

using column_matrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic>;

// The augmented state: x (d), then the k deviation vectors (d each), then MEGNO's integrals
// y = ∫ s ẇ₁·w₁/‖w₁‖² ds and z = ∫ Y ds.
struct layout {
  std::size_t d, k;
  std::size_t vector(std::size_t j) const { return d * (1 + j); }
  std::size_t y() const { return d * (1 + k); }
  std::size_t z() const { return y() + 1; }
  std::size_t size() const { return z() + 1; }
};

// The starting vectors: w₁ = (1, …, 1)/√d, then e₁, e₂, … made orthogonal to those before
// (Gram–Schmidt; e_j is never in the span of the others before it, since w₁ has no zero).
column_matrix starting_vectors(std::size_t d, std::size_t k) {
  column_matrix w = column_matrix::Zero(static_cast<Eigen::Index>(d), static_cast<Eigen::Index>(k));
  w.col(0).setConstant(1.0 / std::sqrt(static_cast<double>(d)));
  for (Eigen::Index j = 1; j < w.cols(); ++j) {
    Eigen::VectorXd v = Eigen::VectorXd::Unit(w.rows(), j - 1);
    for (Eigen::Index i = 0; i < j; ++i) v -= w.col(i).dot(v) * w.col(i);
    w.col(j) = v.normalized();
  }
  return w;
}

class augmented_system {
 public:
  augmented_system(const chain& c, layout l) : m_chain(&c), m_layout(l), m_row_major(l.d * l.d) {}

  void operator()(const std::vector<double>& s, std::vector<double>& ds, double t) {
    const auto d = static_cast<Eigen::Index>(m_layout.d);
    m_chain->evaluate_rhs(s.data(), t, ds.data());
    // The Jacobian arrives row-major; a row-major map reads it as it is.
    m_chain->evaluate_jacobian(s.data(), t, m_row_major.data());
    const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>
        jac(m_row_major.data(), d, d);
    for (std::size_t j = 0; j < m_layout.k; ++j) {
      const Eigen::Map<const Eigen::VectorXd> w(s.data() + m_layout.vector(j), d);
      Eigen::Map<Eigen::VectorXd> dw(ds.data() + m_layout.vector(j), d);
      dw.noalias() = jac * w;
      if (j == 0) {
        const double stretching = w.dot(dw) / w.squaredNorm();
        ds[m_layout.y()] = t * stretching;
        ds[m_layout.z()] = t > 0 ? 2 * s[m_layout.y()] / t : 0.0;
      }
    }
  }

 private:
  const chain* m_chain;
  layout m_layout;
  std::vector<double> m_row_major;
};

// The volume spanned by the first j columns: the product of their singular values.
double gali(const column_matrix& w, Eigen::Index j) {
  return detail::singular_values(w.leftCols(j)).prod();
}

chaos_indicator_sample sample_at(double t, double fli, const std::vector<double>& s,
                                 const layout& l) {
  return chaos_indicator_sample_of(t, fli, s[l.y()], s[l.z()],
                                   std::span(s).subspan(l.vector(0), l.d * l.k), l.d);
}

}  // namespace

std::vector<double> chaos_indicator_start(std::size_t d, std::size_t k) {
  const column_matrix w = starting_vectors(d, k);
  return {w.data(), w.data() + w.size()};
}

chaos_indicator_sample chaos_indicator_sample_of(double t, double fli, double y, double z,
                                                 std::span<const double> vectors, std::size_t d) {
  chaos_indicator_sample out;
  out.t = t;
  out.fli = fli;
  out.megno = t > 0 ? 2 * y / t : 0.0;
  out.mean_megno = t > 0 ? z / t : 0.0;
  const auto k = static_cast<Eigen::Index>(vectors.size() / d);
  const Eigen::Map<const column_matrix> w(vectors.data(), static_cast<Eigen::Index>(d), k);
  out.sali = std::min((w.col(0) + w.col(1)).norm(), (w.col(0) - w.col(1)).norm());
  for (Eigen::Index j = 2; j <= w.cols(); ++j) out.gali.push_back(gali(w, j));
  return out;
}

namespace {

// rk4 at dt on the augmented state: x, the vectors and MEGNO's two integrals.
chaos_indicator_result rk4_indicators(const chain& c, std::span<const double> x0,
                                      const chaos_indicator_options& o, const layout& l) {
  const std::size_t d = l.d;
  std::vector<double> s(l.size(), 0.0);
  std::copy(x0.begin(), x0.end(), s.begin());
  const column_matrix w0 = starting_vectors(d, l.k);
  for (std::size_t j = 0; j < l.k; ++j)
    for (std::size_t i = 0; i < d; ++i)
      s[l.vector(j) + i] = w0(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j));

  augmented_system system(c, l);
  boost::numeric::odeint::runge_kutta4<std::vector<double>> stepper;
  const auto steps = static_cast<long long>(std::floor(o.t_end / o.dt + 1e-9));
  const long long sample_every =
      o.sample_interval > 0 ? std::max(1LL, std::llround(o.sample_interval / o.dt)) : 0;
  chaos_indicator_result r;
  double log_stretch = 0, fli = 0, t = 0;
  for (long long step = 1; step <= steps; ++step) {
    stepper.do_step(std::ref(system), s, t, o.dt);
    t = static_cast<double>(step) * o.dt;
    for (std::size_t j = 0; j < l.k; ++j) {
      Eigen::Map<Eigen::VectorXd> w(s.data() + l.vector(j), static_cast<Eigen::Index>(d));
      const double norm = w.norm();
      if (!std::isfinite(norm) || norm == 0 || !std::isfinite(s[0]))
        throw integration_error(
            fmt::format("chaos indicators: the state or a deviation vector became non-finite "
                        "at t = {}; try a smaller dt",
                        t),
            t);
      w /= norm;
      if (j == 0) {
        log_stretch += std::log(norm);
        fli = std::max(fli, log_stretch);
      }
    }
    if (sample_every > 0 && step % sample_every == 0) r.history.push_back(sample_at(t, fli, s, l));
    if (step % 64 == 0 && report_progress(o.control, t, o.t_end)) {
      r.stopped = true;
      break;
    }
  }
  r.last = sample_at(t, fli, s, l);
  r.state.assign(s.begin(), s.begin() + static_cast<std::ptrdiff_t>(d));
  return r;
}

// The nodes (on [0, 1]) and weights of the 8-point Gauss–Legendre rule, by Newton's method
// on the Legendre polynomial P_8 from the usual cosine guesses.
struct quadrature_rule {
  static constexpr int size = 8;
  std::array<double, size> node{}, weight{};
};

quadrature_rule gauss_legendre_rule() {
  constexpr int m = quadrature_rule::size;
  quadrature_rule rule;
  // P_m(x) and its derivative by the three-term recurrence.
  const auto legendre = [](double x) {
    double p0 = 1, p1 = x;
    for (int k = 2; k <= m; ++k) {
      const double p2 = ((2 * k - 1) * x * p1 - (k - 1) * p0) / k;
      p0 = p1;
      p1 = p2;
    }
    return std::pair{p1, m * (x * p1 - p0) / (x * x - 1)};
  };
  for (int i = 0; i < m; ++i) {
    double x = std::cos(std::numbers::pi * (i + 0.75) / (m + 0.5));
    for (int iteration = 0; iteration < 50; ++iteration) {
      const auto [p, dp] = legendre(x);
      const double dx = p / dp;
      x -= dx;
      if (std::fabs(dx) <= 1e-16) break;
    }
    const double dp = legendre(x).second;
    rule.node[static_cast<std::size_t>(i)] = (1 - x) / 2;
    // 2 / ((1 − x²) P'²) on [−1, 1], halved for [0, 1].
    rule.weight[static_cast<std::size_t>(i)] = 1 / ((1 - x * x) * dp * dp);
  }
  return rule;
}

// The largest value of the smooth function `f` over a step from its samples (u, f(u)), the
// step's ends among them: where the largest sample lies inside, the maximum between its
// neighbours by golden-section search (FLI is the running maximum of ln‖w_1‖, which a
// sample at a node would underestimate by about (spacing)² f'').
template <class Function>
double largest_within(std::vector<std::pair<double, double>>& samples, const Function& f) {
  std::sort(samples.begin(), samples.end());
  const auto best =
      std::max_element(samples.begin(), samples.end(),
                       [](const auto& p, const auto& q) { return p.second < q.second; });
  if (best == samples.begin() || best + 1 == samples.end()) return best->second;
  const double ratio = (std::sqrt(5.0) - 1) / 2;
  double lo = (best - 1)->first, hi = (best + 1)->first, largest = best->second;
  double u1 = hi - ratio * (hi - lo), u2 = lo + ratio * (hi - lo);
  double f1 = f(u1), f2 = f(u2);
  for (int iteration = 0; iteration < 40 && hi - lo > 1e-12 * std::fabs(hi); ++iteration) {
    if (f1 >= f2) {
      hi = u2;
      u2 = u1;
      f2 = f1;
      u1 = hi - ratio * (hi - lo);
      f1 = f(u1);
    } else {
      lo = u1;
      u1 = u2;
      f1 = f2;
      u2 = lo + ratio * (hi - lo);
      f2 = f(u2);
    }
    largest = std::max({largest, f1, f2});
  }
  return largest;
}

// Taylor's method on the state and the k vectors, normalised after every step. MEGNO's
// integrals, with L(u) = ln‖w_1(u)‖ over a step [a, b] from a unit w_1 (so L(a) = 0 and
// ẇ_1·w_1/‖w_1‖² = L'), integrated by parts:
//   y(b) − y(a) = ∫ u L'(u) du = b L(b) − ∫ L du,
//   z(b) − z(a) = ∫ 2 y(s)/s ds = 2 y(a) ln(b/a) + ∫ 2 L(u) (1 − ln(b/u)) du,
// the integrals by the Gauss–Legendre rule on the step's polynomials.
chaos_indicator_result taylor_indicators(const chain& c, std::span<const double> x0,
                                         const chaos_indicator_options& o, const layout& l) {
  static const quadrature_rule rule = gauss_legendre_rule();
  const std::size_t d = l.d, k = l.k;
  taylor_tangents integrator(c.kernels_in_use(), o.tolerance, o.tolerance, static_cast<int>(k));
  std::vector<double> x(x0.begin(), x0.end()), w = chaos_indicator_start(d, k);
  std::vector<double> node_x(d), node_w(d * k);
  std::vector<std::pair<double, double>> samples;  // (u, L(u)) in the step
  integrator.reset(0.0, x.data(), w.data());
  const auto first_norm = [&](const double* v) {
    return Eigen::Map<const Eigen::VectorXd>(v, static_cast<Eigen::Index>(d)).norm();
  };
  // A step that lands on a stop may end an ulp short of it in floating point.
  const double slack = 4 * std::numeric_limits<double>::epsilon() * o.t_end;
  chaos_indicator_result r;
  double log_stretch = 0, fli = 0, y = 0, z = 0, t = 0;
  std::size_t next_sample = 1;
  const auto sample_time = [&] {
    return o.sample_interval > 0 ? static_cast<double>(next_sample) * o.sample_interval
                                 : std::numeric_limits<double>::infinity();
  };
  while (o.t_end - t > slack) {
    const double stop = std::min(sample_time(), o.t_end);
    integrator.step(1.0, stop - t, o.dt);
    const double a = integrator.step_begin();
    const double b = stop - integrator.time() <= slack ? stop : integrator.time();
    // L(u) = ln‖w_1(u)‖ from the step's polynomials.
    const auto stretch_at = [&](double u) {
      integrator.state_at(u - a, node_x.data(), node_w.data());
      return std::log(first_norm(node_w.data()));
    };
    double integral_l = 0, integral_z = 0;
    samples.clear();
    // From t = 0 the factor ln(b/u) is singular at the step's start: the first step is cut
    // into pieces that halve towards 0, on each of which it is smooth (the rest below
    // 2^-30 b adds about (2^-30 b)² to the integrals).
    const int pieces = a > 0 ? 1 : 30;
    for (int piece = 0; piece < pieces; ++piece) {
      const double lo = a > 0 ? a : std::ldexp(b, -(piece + 1));
      const double hi = a > 0 ? b : std::ldexp(b, -piece);
      for (int i = 0; i < quadrature_rule::size; ++i) {
        const double u = lo + rule.node[static_cast<std::size_t>(i)] * (hi - lo);
        const double L = stretch_at(u);
        const double weight = rule.weight[static_cast<std::size_t>(i)] * (hi - lo);
        integral_l += weight * L;
        integral_z += weight * 2 * L * (1 - std::log(b / u));
        samples.emplace_back(u, L);
      }
    }
    const double stretch = first_norm(integrator.tangents().data());
    samples.emplace_back(a, 0.0);
    samples.emplace_back(b, std::log(stretch));
    fli = std::max(fli, log_stretch + largest_within(samples, stretch_at));
    if (!std::isfinite(stretch) || !std::isfinite(integral_l) || !std::isfinite(integral_z))
      throw integration_error(
          fmt::format("chaos indicators: the state or a deviation vector became non-finite at "
                      "t = {}; try a smaller tolerance",
                      b),
          b);
    x = integrator.state();
    w = integrator.tangents();
    z += (a > 0 ? 2 * y * std::log(b / a) : 0.0) + integral_z;
    y += b * std::log(stretch) - integral_l;
    log_stretch += std::log(stretch);
    for (std::size_t j = 0; j < k; ++j) {
      Eigen::Map<Eigen::VectorXd> v(w.data() + j * d, static_cast<Eigen::Index>(d));
      const double norm = v.norm();
      if (!std::isfinite(norm) || norm == 0 ||
          !std::all_of(x.begin(), x.end(), [](double e) { return std::isfinite(e); }))
        throw integration_error(
            fmt::format("chaos indicators: the state or a deviation vector became non-finite "
                        "at t = {}; try a smaller tolerance",
                        b),
            b);
      v /= norm;
    }
    t = b;
    integrator.reset(t, x.data(), w.data());
    if (t == sample_time()) {
      r.history.push_back(chaos_indicator_sample_of(t, fli, y, z, w, d));
      ++next_sample;
    }
    if (report_progress(o.control, t, o.t_end)) {
      r.stopped = true;
      break;
    }
  }
  r.last = chaos_indicator_sample_of(t, fli, y, z, w, d);
  r.state = x;
  return r;
}

}  // namespace

chaos_indicator_result chaos_indicators(const chain& c, std::span<const double> x0,
                                        const chaos_indicator_options& o) {
  o.validate();
  const auto d = static_cast<std::size_t>(c.state_size());
  if (x0.size() != d)
    throw std::invalid_argument(
        fmt::format("chaos indicators: the {}-link chain needs a start of {} entries, got {}",
                    c.links(), d, x0.size()));
  detail::require_finite_start(x0, "chaos indicators: ");
  if (o.vectors < 2 || o.vectors > d)
    throw std::invalid_argument(
        fmt::format("chaos indicators: vectors is {}: it must be 2..{} (2n) for the {}-link chain",
                    o.vectors, d, c.links()));
  const layout l{d, o.vectors};
  if (o.stepper == stepper_kind::taylor) {
    check_stepper_fits(c, stepper_kind::taylor);
    return taylor_indicators(c, x0, o, l);
  }
  return rk4_indicators(c, x0, o, l);
}

}  // namespace npend
