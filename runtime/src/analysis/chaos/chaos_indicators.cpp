#include "npend/analysis/chaos/chaos_indicators.hpp"

#include <fmt/format.h>

#include <Eigen/SVD>
#include <algorithm>
#include <boost/numeric/odeint/stepper/runge_kutta4.hpp>
#include <cmath>
#include <stdexcept>

#include "analysis/detail/argument_checks.hpp"
#include "analysis/detail/dense_eigen.hpp"
#include "npend/integrators/integration_error.hpp"

namespace npend {

void chaos_indicator_options::validate() const {
  if (!(dt > 0) || !std::isfinite(dt) || !std::isfinite(t_end) || !(t_end >= dt))
    throw std::invalid_argument(fmt::format(
        "chaos indicators: need 0 < dt <= t_end, both finite, got dt = {}, t_end = {}", dt, t_end));
  if (!(sample_interval >= 0) || !std::isfinite(sample_interval))
    throw std::invalid_argument(fmt::format(
        "chaos indicators: sample_interval is {}: it must be >= 0 and finite", sample_interval));
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

}  // namespace npend
