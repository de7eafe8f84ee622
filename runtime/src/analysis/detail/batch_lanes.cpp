#include "batch_lanes.hpp"

#include <batch_index.hpp>

#include <algorithm>
#include <cmath>

namespace npend::detail {

const batch_kernels* lane_kernels(const chain& c) {
  if (c.is_physical()) return nullptr;
  const batch_kernels* k = generated::find_batch(c.links());
  // The kernels must have been compiled for this translation unit's lane count.
  return k != nullptr && k->width == batch_width ? k : nullptr;
}

void lane_system::operator()(const double* x, double* dxdt) {
  if (m_tangent == 0) {
    m_kernels.rhs_batch(x, m_params, dxdt);
    return;
  }
  const auto at = [](std::size_t i) { return i * W; };
  m_kernels.tangent_batch(x, x + at(vector(0)), m_params, dxdt, dxdt + at(vector(0)));
  for (std::size_t j = 1; j < m_tangent; ++j)
    m_kernels.tangent_batch(x, x + at(vector(j)), m_params, m_scratch.data(),
                            dxdt + at(vector(j)));
  if (!m_indicators) return;
  const double* w = x + at(vector(0));
  const double* dw = dxdt + at(vector(0));
  for (std::size_t l = 0; l < W; ++l) {
    double along = 0, squares = 0;
    for (std::size_t i = 0; i < m_d; ++i) {
      along += w[at(i) + l] * dw[at(i) + l];
      squares += w[at(i) + l] * w[at(i) + l];
    }
    const double t = x[at(time()) + l];
    dxdt[at(time()) + l] = 1;
    dxdt[at(y()) + l] = t * (along / squares);
    dxdt[at(z()) + l] = t > 0 ? 2 * x[at(y()) + l] / t : 0.0;
  }
}

void lane_rk4::step(int blocks) {
  const std::size_t size = m_block * static_cast<std::size_t>(blocks);
  double* x = m_x.data();
  double *k1 = m_k1.data(), *k2 = m_k2.data(), *k3 = m_k3.data(), *k4 = m_k4.data();
  double* tmp = m_tmp.data();
  const double half = m_half, zero = m_zero, full = m_full, sixth = m_sixth, third = m_third;
  rhs(blocks, x, k1);
#pragma omp simd
  for (std::size_t i = 0; i < size; ++i) tmp[i] = x[i] + half * k1[i];
  rhs(blocks, tmp, k2);
  // odeint keeps the zero coefficients of its Butcher rows (0 · k is not always 0).
#pragma omp simd
  for (std::size_t i = 0; i < size; ++i) tmp[i] = x[i] + zero * k1[i] + half * k2[i];
  rhs(blocks, tmp, k3);
#pragma omp simd
  for (std::size_t i = 0; i < size; ++i)
    tmp[i] = x[i] + zero * k1[i] + zero * k2[i] + full * k3[i];
  rhs(blocks, tmp, k4);
#pragma omp simd
  for (std::size_t i = 0; i < size; ++i)
    x[i] = x[i] + sixth * k1[i] + third * k2[i] + third * k3[i] + sixth * k4[i];
}

void lane_rk4::rhs(int blocks, const double* x, double* dxdt) {
  for (int b = 0; b < blocks; ++b) {
    const std::size_t o = m_block * static_cast<std::size_t>(b);
    m_system(x + o, dxdt + o);
  }
}

void lane_rk4::copy_lane(std::size_t to, std::size_t from) {
  for (std::size_t i = 0; i < coordinates(); ++i) m_x[at(i, to)] = m_x[at(i, from)];
}

namespace {

// odeint's runge_kutta_dopri5 tableau, each coefficient rounded as odeint rounds it: the
// stage rows b_ij, the fifth-order weights c_i and the error weights dc_i (fifth minus
// fourth order). A lane's coefficient j is its step h times tableau[j].
enum coefficient : int {
  b21, b31, b32, b41, b42, b43, b51, b52, b53, b54, b61, b62, b63, b64, b65,
  c1, c3, c4, c5, c6, dc1, dc3, dc4, dc5, dc6, dc7, coefficient_count
};

constexpr double ratio(double a, double b) { return a / b; }

const std::array<double, coefficient_count> tableau = [] {
  std::array<double, coefficient_count> t{};
  t[b21] = ratio(1, 5);
  t[b31] = ratio(3, 40);
  t[b32] = ratio(9, 40);
  t[b41] = ratio(44, 45);
  t[b42] = ratio(-56, 15);
  t[b43] = ratio(32, 9);
  t[b51] = ratio(19372, 6561);
  t[b52] = ratio(-25360, 2187);
  t[b53] = ratio(64448, 6561);
  t[b54] = ratio(-212, 729);
  t[b61] = ratio(9017, 3168);
  t[b62] = ratio(-355, 33);
  t[b63] = ratio(46732, 5247);
  t[b64] = ratio(49, 176);
  t[b65] = ratio(-5103, 18656);
  t[c1] = ratio(35, 384);
  t[c3] = ratio(500, 1113);
  t[c4] = ratio(125, 192);
  t[c5] = ratio(-2187, 6784);
  t[c6] = ratio(11, 84);
  t[dc1] = t[c1] - ratio(5179, 57600);
  t[dc3] = t[c3] - ratio(7571, 16695);
  t[dc4] = t[c4] - ratio(393, 640);
  t[dc5] = t[c5] - ratio(-92097, 339200);
  t[dc6] = t[c6] - ratio(187, 2100);
  t[dc7] = ratio(-1, 40);
  return t;
}();

// odeint's default_step_adjuster for dopri5 (error order 4, stepper order 5).
double decreased_step(double h, double error) {
  return h * std::max(0.9 * std::pow(error, -1.0 / 3.0), 0.2);
}
double increased_step(double h, double error) {
  if (error >= 0.5) return h;
  error = std::max(std::pow(5.0, -5.0), error);
  return h * (0.9 * std::pow(error, -1.0 / 5.0));
}

}  // namespace

lane_dopri5::lane_dopri5(lane_system system, double abs_tol, double rel_tol)
    : m_system(std::move(system)),
      m_block(m_system.coordinates() * W),
      m_abs_tol(abs_tol),
      m_rel_tol(rel_tol),
      m_x(m_block * lane_blocks),
      m_f(m_x.size()),
      m_x_old(m_x.size()),
      m_f_old(m_x.size()),
      m_k2(m_x.size()),
      m_k3(m_x.size()),
      m_k4(m_x.size()),
      m_k5(m_x.size()),
      m_k6(m_x.size()),
      m_tmp(m_x.size()),
      m_out(m_x.size()),
      m_f_out(m_x.size()),
      m_err(m_x.size()),
      m_coefficient(static_cast<std::size_t>(coefficient_count) * lanes) {}

void lane_dopri5::restart(std::size_t l, double t, double h) {
  m_lane[l] = lane{t, h, t, 0, true, false};
}

void lane_dopri5::rhs(int blocks, const double* x, double* dxdt) {
  for (int b = 0; b < blocks; ++b) {
    const std::size_t o = m_block * static_cast<std::size_t>(b);
    m_system(x + o, dxdt + o);
  }
}

void lane_dopri5::combine(int blocks, double* out, const double* x,
                          std::initializer_list<std::pair<const double*, int>> terms) {
  const std::size_t d = coordinates();
  for (int b = 0; b < blocks; ++b) {
    const std::size_t block = m_block * static_cast<std::size_t>(b);
    for (std::size_t i = 0; i < d; ++i) {
      const std::size_t o = block + i * W;
#pragma omp simd
      for (std::size_t l = 0; l < W; ++l) out[o + l] = x[o + l];
      for (const auto& [k, j] : terms) {
        const double* c = m_coefficient.data() + static_cast<std::size_t>(j) * lanes +
                          static_cast<std::size_t>(b) * W;
#pragma omp simd
        for (std::size_t l = 0; l < W; ++l) out[o + l] = out[o + l] + c[l] * k[o + l];
      }
    }
  }
}

void lane_dopri5::step(int blocks) {
  const std::size_t used = static_cast<std::size_t>(blocks) * W, d = coordinates();
  // A lane that was restarted takes its derivative first (odeint's FSAL start).
  for (int b = 0; b < blocks; ++b) {
    const std::size_t first = static_cast<std::size_t>(b) * W;
    bool any = false;
    for (std::size_t l = first; l < first + W; ++l) any |= m_lane[l].fresh;
    if (!any) continue;
    const std::size_t o = m_block * static_cast<std::size_t>(b);
    m_system(m_x.data() + o, m_tmp.data() + o);
    for (std::size_t l = first; l < first + W; ++l) {
      if (!m_lane[l].fresh) continue;
      for (std::size_t i = 0; i < d; ++i) m_f[at(i, l)] = m_tmp[at(i, l)];
      m_lane[l].fresh = false;
    }
  }
  for (std::size_t l = 0; l < used; ++l) {
    lane& s = m_lane[l];
    if (s.accepted) s.tries = 0;
    ++s.tries;
    for (int j = 0; j < coefficient_count; ++j)
      m_coefficient[static_cast<std::size_t>(j) * lanes + l] = s.h * tableau[static_cast<std::size_t>(j)];
  }
  const double *x = m_x.data(), *f = m_f.data();
  double *k2 = m_k2.data(), *k3 = m_k3.data(), *k4 = m_k4.data(), *k5 = m_k5.data(),
         *k6 = m_k6.data(), *tmp = m_tmp.data(), *out = m_out.data(), *f_out = m_f_out.data();
  combine(blocks, tmp, x, {{f, b21}});
  rhs(blocks, tmp, k2);
  combine(blocks, tmp, x, {{f, b31}, {k2, b32}});
  rhs(blocks, tmp, k3);
  combine(blocks, tmp, x, {{f, b41}, {k2, b42}, {k3, b43}});
  rhs(blocks, tmp, k4);
  combine(blocks, tmp, x, {{f, b51}, {k2, b52}, {k3, b53}, {k4, b54}});
  rhs(blocks, tmp, k5);
  combine(blocks, tmp, x, {{f, b61}, {k2, b62}, {k3, b63}, {k4, b64}, {k5, b65}});
  rhs(blocks, tmp, k6);
  combine(blocks, out, x, {{f, c1}, {k3, c3}, {k4, c4}, {k5, c5}, {k6, c6}});
  rhs(blocks, out, f_out);
  // The error estimate, summed as odeint sums it (its first term dt·dc1·f, not x + …).
  double* err = m_err.data();
  std::fill(err, err + m_block * static_cast<std::size_t>(blocks), 0.0);
  for (std::size_t l = 0; l < used; ++l)
    for (std::size_t i = 0; i < d; ++i) {
      const std::size_t a = at(i, l);
      const double* c = m_coefficient.data() + l;
      const auto coef = [&](int j) { return c[static_cast<std::size_t>(j) * lanes]; };
      err[a] = coef(dc1) * f[a] + coef(dc3) * k3[a] + coef(dc4) * k4[a] + coef(dc5) * k5[a] +
               coef(dc6) * k6[a] + coef(dc7) * f_out[a];
    }
  for (std::size_t l = 0; l < used; ++l) {
    lane& s = m_lane[l];
    double error = 0;
    for (std::size_t i = 0; i < d; ++i) {
      const std::size_t a = at(i, l);
      const double e = std::fabs(err[a]) /
                       (m_abs_tol + m_rel_tol * (std::fabs(x[a]) + std::fabs(s.h) * std::fabs(f[a])));
      error = std::max(error, e);
    }
    s.accepted = !(error > 1.0);
    if (!s.accepted) {
      s.h = decreased_step(s.h, error);
      continue;
    }
    for (std::size_t i = 0; i < d; ++i) {
      const std::size_t a = at(i, l);
      m_x_old[a] = x[a];
      m_f_old[a] = f[a];
      m_x[a] = out[a];
      m_f[a] = f_out[a];
    }
    s.t_old = s.t;
    s.t += s.h;
    s.h = increased_step(s.h, error);
  }
}

void lane_dopri5::state_at(std::size_t l, double t, std::size_t first, std::size_t count,
                           double* out) const {
  // odeint's runge_kutta_dopri5::calc_state (Hairer, Nørsett and Wanner, Solving Ordinary
  // Differential Equations I, p. 191f), term for term.
  const lane& s = m_lane[l];
  const double h = s.t - s.t_old;
  const double theta = (t - s.t_old) / h;
  const double X1 = 5.0 * (2558722523.0 - 31403016.0 * theta) / 11282082432.0;
  const double X3 = 100.0 * (882725551.0 - 15701508.0 * theta) / 32700410799.0;
  const double X4 = 25.0 * (443332067.0 - 31403016.0 * theta) / 1880347072.0;
  const double X5 = 32805.0 * (23143187.0 - 3489224.0 * theta) / 199316789632.0;
  const double X6 = 55.0 * (29972135.0 - 7076736.0 * theta) / 822651844.0;
  const double X7 = 10.0 * (7414447.0 - 829305.0 * theta) / 29380423.0;
  const double theta_m_1 = theta - 1.0;
  const double theta_sq = theta * theta;
  const double A = theta_sq * (3.0 - 2.0 * theta);
  const double B = theta_sq * theta_m_1;
  const double C = theta_sq * theta_m_1 * theta_m_1;
  const double D = theta * theta_m_1 * theta_m_1;
  const double w1 = h * (A * tableau[c1] - C * X1 + D);
  const double w3 = h * (A * tableau[c3] + C * X3);
  const double w4 = h * (A * tableau[c4] - C * X4);
  const double w5 = h * (A * tableau[c5] + C * X5);
  const double w6 = h * (A * tableau[c6] - C * X6);
  const double w7 = h * (B + C * X7);
  for (std::size_t i = first; i < first + count; ++i) {
    const std::size_t a = at(i, l);
    out[i - first] = m_x_old[a] + w1 * m_f_old[a] + w3 * m_k3[a] + w4 * m_k4[a] +
                     w5 * m_k5[a] + w6 * m_k6[a] + w7 * m_f[a];
  }
}

void lane_dopri5::copy_lane(std::size_t to, std::size_t from) {
  for (std::size_t i = 0; i < coordinates(); ++i) {
    m_x[at(i, to)] = m_x[at(i, from)];
    m_f[at(i, to)] = m_f[at(i, from)];
  }
  m_lane[to] = m_lane[from];
}

}  // namespace npend::detail
