// clang-format off
// The lanes' own headers last: in a lane variant's unit (cmake/npend_lanes.cmake), the
// first of them switches what follows to the variant's ISA (npend/batch_math.hpp).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <optional>
#include <utility>
#include <vector>

#include "npend/chain.hpp"
#include "npend/integrators/gauss_legendre.hpp"

#include "batch_lanes.hpp"
#include <batch_index.hpp>
// clang-format on

namespace npend::detail {
inline namespace NPEND_BATCH_ISA_NAMESPACE {

const batch_kernels* lane_kernels(const chain& c) {
  if (c.is_physical()) return nullptr;
  const batch_kernels* k = generated::find_batch(c.links());
  // The kernels must have been compiled for this translation unit's lane count.
  return k != nullptr && k->width == batch_width ? k : nullptr;
}

void lane_system::operator()(int blocks, std::size_t stride, const double* x, double* dxdt) {
  if (m_tangent == 0) {
    m_kernels.rhs_batch(x, m_params, dxdt, blocks, stride);
    return;
  }
  const auto at = [](std::size_t i) { return i * W; };
  // The vectors lie one after another, as tangents_batch takes them.
  if (m_tangent == 1)
    m_kernels.tangent_batch(x, x + at(vector(0)), m_params, dxdt, dxdt + at(vector(0)), blocks,
                            stride);
  else
    m_kernels.tangents_batch(x, x + at(vector(0)), static_cast<int>(m_tangent), m_params, dxdt,
                             dxdt + at(vector(0)), blocks, stride);
  if (!m_indicators) return;
  for (int b = 0; b < blocks; ++b) {
    const std::size_t o = stride * static_cast<std::size_t>(b);
    megno_integrands(x + o, dxdt + o);
  }
}

void lane_system::megno_integrands(const double* x, double* dxdt) const {
  const auto at = [](std::size_t i) { return i * W; };
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
  for (std::size_t i = 0; i < size; ++i) tmp[i] = x[i] + zero * k1[i] + zero * k2[i] + full * k3[i];
  rhs(blocks, tmp, k4);
  // The new state into the other buffer, which then becomes state(): the old one stays.
  double* next = m_before.data();
#pragma omp simd
  for (std::size_t i = 0; i < size; ++i)
    next[i] = x[i] + sixth * k1[i] + third * k2[i] + third * k3[i] + sixth * k4[i];
  m_x.swap(m_before);
}

void lane_layout::rhs(int blocks, const double* x, double* dxdt) {
  m_system(blocks, m_block, x, dxdt);
}

void lane_layout::derivative_at(const double* x, std::size_t l, std::size_t first,
                                std::size_t count, double* out) {
  m_probe.resize(m_block);
  m_probe_f.resize(m_block);
  for (std::size_t i = 0; i < coordinates(); ++i)
    std::fill_n(m_probe.begin() + static_cast<std::ptrdiff_t>(i * W), W, x[at(i, l)]);
  m_system(1, m_block, m_probe.data(), m_probe_f.data());
  for (std::size_t i = first; i < first + count; ++i) out[i - first] = m_probe_f[i * W + l % W];
}

void lane_rk4::copy_lane(std::size_t to, std::size_t from) {
  for (std::size_t i = 0; i < coordinates(); ++i) m_x[at(i, to)] = m_x[at(i, from)];
}

namespace {

// odeint's runge_kutta_dopri5 tableau, each coefficient rounded as odeint rounds it: the
// stage rows b_ij, the fifth-order weights c_i and the error weights dc_i (fifth minus
// fourth order). A lane's coefficient j is its step h times tableau[j].
enum coefficient : int {
  b21,
  b31,
  b32,
  b41,
  b42,
  b43,
  b51,
  b52,
  b53,
  b54,
  b61,
  b62,
  b63,
  b64,
  b65,
  c1,
  c3,
  c4,
  c5,
  c6,
  dc1,
  dc3,
  dc4,
  dc5,
  dc6,
  dc7,
  coefficient_count
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
    : lane_layout(std::move(system)),
      m_abs_tol(abs_tol),
      m_rel_tol(rel_tol),
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
      m_coefficient(static_cast<std::size_t>(coefficient_count) * lanes) {}

void lane_dopri5::restart(std::size_t l, double t, double h) {
  m_lane[l] = lane{t, t, 0, true};
  m_h[l] = h;
  m_accept[l] = 0;
}

template <std::size_t K>
void lane_dopri5::combine(int blocks, double* out, const double* x,
                          const std::array<std::pair<const double*, int>, K>& terms) {
  const std::size_t d = coordinates();
  for (int b = 0; b < blocks; ++b) {
    const std::size_t block = m_block * static_cast<std::size_t>(b);
    std::array<const double*, K> c;
    for (std::size_t t = 0; t < K; ++t)
      c[t] = m_coefficient.data() + static_cast<std::size_t>(terms[t].second) * lanes +
             static_cast<std::size_t>(b) * W;
    for (std::size_t i = 0; i < d; ++i) {
      const std::size_t o = block + i * W;
#pragma omp simd
      for (std::size_t l = 0; l < W; ++l) {
        double v = x[o + l];
        for (std::size_t t = 0; t < K; ++t) v = v + c[t][l] * terms[t].first[o + l];
        out[o + l] = v;
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
    m_system(1, m_block, m_x.data() + o, m_tmp.data() + o);
    for (std::size_t l = first; l < first + W; ++l) {
      if (!m_lane[l].fresh) continue;
      for (std::size_t i = 0; i < d; ++i) m_f[at(i, l)] = m_tmp[at(i, l)];
      m_lane[l].fresh = false;
    }
  }
  for (std::size_t l = 0; l < used; ++l) {
    lane& s = m_lane[l];
    if (m_accept[l] != 0) s.tries = 0;
    ++s.tries;
  }
  for (int j = 0; j < coefficient_count; ++j) {
    double* c = m_coefficient.data() + static_cast<std::size_t>(j) * lanes;
    const double tj = tableau[static_cast<std::size_t>(j)];
#pragma omp simd
    for (std::size_t l = 0; l < used; ++l) c[l] = m_h[l] * tj;
  }
  const double *x = m_x.data(), *f = m_f.data();
  double *k2 = m_k2.data(), *k3 = m_k3.data(), *k4 = m_k4.data(), *k5 = m_k5.data(),
         *k6 = m_k6.data(), *tmp = m_tmp.data(), *out = m_out.data(), *f_out = m_f_out.data();
  combine<1>(blocks, tmp, x, {{{f, b21}}});
  rhs(blocks, tmp, k2);
  combine<2>(blocks, tmp, x, {{{f, b31}, {k2, b32}}});
  rhs(blocks, tmp, k3);
  combine<3>(blocks, tmp, x, {{{f, b41}, {k2, b42}, {k3, b43}}});
  rhs(blocks, tmp, k4);
  combine<4>(blocks, tmp, x, {{{f, b51}, {k2, b52}, {k3, b53}, {k4, b54}}});
  rhs(blocks, tmp, k5);
  combine<5>(blocks, tmp, x, {{{f, b61}, {k2, b62}, {k3, b63}, {k4, b64}, {k5, b65}}});
  rhs(blocks, tmp, k6);
  combine<5>(blocks, out, x, {{{f, c1}, {k3, c3}, {k4, c4}, {k5, c5}, {k6, c6}}});
  rhs(blocks, out, f_out);
  // The error estimate, summed as odeint sums it (from dt·dc1·f, not x + …), and its norm
  // max_i |err_i| / (abs_tol + rel_tol (|x_i| + |h| |f_i|)) per lane.
  const auto coefficient = [&](int j, int b) {
    return m_coefficient.data() + static_cast<std::size_t>(j) * lanes +
           static_cast<std::size_t>(b) * W;
  };
  const double abs_tol = m_abs_tol, rel_tol = m_rel_tol;
  constexpr double infinity = std::numeric_limits<double>::infinity();
  std::fill(m_error.begin(), m_error.end(), 0.0);
  for (int b = 0; b < blocks; ++b) {
    const double *e1 = coefficient(dc1, b), *e3 = coefficient(dc3, b), *e4 = coefficient(dc4, b),
                 *e5 = coefficient(dc5, b), *e6 = coefficient(dc6, b), *e7 = coefficient(dc7, b);
    const double* h = m_h.data() + static_cast<std::size_t>(b) * W;
    double* error = m_error.data() + static_cast<std::size_t>(b) * W;
    for (std::size_t i = 0; i < d; ++i) {
      const std::size_t o = m_block * static_cast<std::size_t>(b) + i * W;
#pragma omp simd
      for (std::size_t l = 0; l < W; ++l) {
        const std::size_t a = o + l;
        const double err = e1[l] * f[a] + e3[l] * k3[a] + e4[l] * k4[a] + e5[l] * k5[a] +
                           e6[l] * k6[a] + e7[l] * f_out[a];
        const double scaled =
            std::fabs(err) /
            (abs_tol + rel_tol * (std::fabs(x[a]) + std::fabs(h[l]) * std::fabs(f[a])));
        // A non-finite entry makes the norm +inf (npend's rejecting_range_algebra), so that a
        // trial step that overflowed is rejected and shrunk rather than accepted.
        error[l] = scaled == scaled && error[l] < scaled ? scaled : error[l];
        error[l] = scaled != scaled ? infinity : error[l];
      }
    }
  }
  // Accept or reject each lane's attempt, and size its next one, as odeint's controller.
  for (std::size_t l = 0; l < used; ++l) {
    lane& s = m_lane[l];
    const bool accepted = !(m_error[l] > 1.0);
    m_accept[l] = accepted ? 1.0 : 0.0;
    if (!accepted) {
      m_h[l] = decreased_step(m_h[l], m_error[l]);
      continue;
    }
    s.t_old = s.t;
    s.t += m_h[l];
    m_h[l] = increased_step(m_h[l], m_error[l]);
  }
  // The accepted lanes move on; the old state and derivative stay for the dense output.
  double *x_old = m_x_old.data(), *f_old = m_f_old.data(), *xs = m_x.data(), *fs = m_f.data();
  for (int b = 0; b < blocks; ++b) {
    const double* accept = m_accept.data() + static_cast<std::size_t>(b) * W;
    for (std::size_t i = 0; i < d; ++i) {
      const std::size_t o = m_block * static_cast<std::size_t>(b) + i * W;
#pragma omp simd
      for (std::size_t l = 0; l < W; ++l) {
        const std::size_t a = o + l;
        const bool move = accept[l] != 0;
        x_old[a] = move ? xs[a] : x_old[a];
        f_old[a] = move ? fs[a] : f_old[a];
        xs[a] = move ? out[a] : xs[a];
        fs[a] = move ? f_out[a] : fs[a];
      }
    }
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
    out[i - first] = m_x_old[a] + w1 * m_f_old[a] + w3 * m_k3[a] + w4 * m_k4[a] + w5 * m_k5[a] +
                     w6 * m_k6[a] + w7 * m_f[a];
  }
}

void lane_dopri5::copy_lane(std::size_t to, std::size_t from) {
  for (std::size_t i = 0; i < coordinates(); ++i) {
    m_x[at(i, to)] = m_x[at(i, from)];
    m_f[at(i, to)] = m_f[at(i, from)];
  }
  m_lane[to] = m_lane[from];
  m_h[to] = m_h[from];
  m_accept[to] = m_accept[from];
}

template <int Stages>
lane_gauss<Stages>::lane_gauss(lane_system system, double dt)
    : lane_layout(std::move(system)), m_dt(dt), m_tmp(m_x.size()), m_before(m_x.size()) {
  for (int i = 0; i < s; ++i) {
    m_z[static_cast<std::size_t>(i)].assign(m_x.size(), 0.0);
    m_f[static_cast<std::size_t>(i)].assign(m_x.size(), 0.0);
    m_f_kept[static_cast<std::size_t>(i)].assign(m_x.size(), 0.0);
  }
  // gauss_legendre's own coefficients.
  const gauss_legendre_coefficients<Stages> coefficients;
  for (int i = 0; i < s; ++i) {
    m_d[static_cast<std::size_t>(i)] = coefficients.d(i);
    for (int j = 0; j < s; ++j)
      m_extrapolation[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)] =
          coefficients.extrapolation(i, j);
  }
}

template <int Stages>
void lane_gauss<Stages>::step(int blocks) {
  using tableau = gauss_legendre_tableau<Stages>;
  const std::size_t used = static_cast<std::size_t>(blocks) * W, d = coordinates(),
                    size = m_block * static_cast<std::size_t>(blocks);
  const double h = m_dt;
  // gauss_legendre's stopping rule, with its default tolerance.
  const double round_off = gauss_legendre_round_off_level(d);
  constexpr double tolerance = gauss_legendre<Stages>::default_tolerance;
  // The loops below run block by block, coordinate by coordinate, over the W lanes of a
  // block: element o + l of an array, per-lane value [first + l], first = b*W.
  const auto each = [&](const auto& body) {
    for (int b = 0; b < blocks; ++b)
      for (std::size_t k = 0; k < d; ++k)
        body(m_block * static_cast<std::size_t>(b) + k * W, static_cast<std::size_t>(b) * W);
  };
  std::array<const double*, Stages> f, kept;
  for (int j = 0; j < s; ++j) {
    f[static_cast<std::size_t>(j)] = m_f[static_cast<std::size_t>(j)].data();
    kept[static_cast<std::size_t>(j)] = m_f_kept[static_cast<std::size_t>(j)].data();
  }
  std::array<double, lanes> previous{};
  for (std::size_t l = 0; l < used; ++l) {
    previous[l] = m_previous[l] ? 1.0 : 0.0;
    m_active[l] = m_failed[l] ? 0.0 : 1.0;
    m_x_norm[l] = 0;
    m_last_norm[l] = 0;
  }
  // The starting guess: the previous step's collocation polynomial continued, or Z = 0.
  const double* x = m_x.data();
  for (int i = 0; i < s; ++i) {
    double* z = m_z[static_cast<std::size_t>(i)].data();
    const auto& e = m_extrapolation[static_cast<std::size_t>(i)];
    each([&](std::size_t o, std::size_t first) {
      const double* from = previous.data() + first;
#pragma omp simd
      for (std::size_t l = 0; l < W; ++l) {
        double guess = 0;
        for (int j = 0; j < s; ++j)
          guess += e[static_cast<std::size_t>(j)] * kept[static_cast<std::size_t>(j)][o + l];
        z[o + l] = from[l] != 0 ? h * guess : 0.0;
      }
    });
  }
  each([&](std::size_t o, std::size_t first) {
    double* norm = m_x_norm.data() + first;
#pragma omp simd
    for (std::size_t l = 0; l < W; ++l) {
      const double v = std::fabs(x[o + l]);
      norm[l] = norm[l] < v ? v : norm[l];
    }
  });
  for (int iteration = 1;; ++iteration) {
    bool any = false;
    for (std::size_t l = 0; l < used; ++l) any |= m_active[l] != 0;
    if (!any) break;
    for (int i = 0; i < s; ++i) {
      const double* z = m_z[static_cast<std::size_t>(i)].data();
      double* tmp = m_tmp.data();
#pragma omp simd
      for (std::size_t a = 0; a < size; ++a) tmp[a] = x[a] + z[a];
      rhs(blocks, m_tmp.data(), m_f[static_cast<std::size_t>(i)].data());
    }
    // Z_i += (h Σ_j a_ij f_j − Z_i) on the lanes still iterating; their correction norms.
    std::array<double, lanes> norm{}, scale{};
    for (std::size_t l = 0; l < used; ++l) scale[l] = m_x_norm[l];
    for (int i = 0; i < s; ++i) {
      double* z = m_z[static_cast<std::size_t>(i)].data();
      const auto& a = tableau::a[static_cast<std::size_t>(i)];
      each([&](std::size_t o, std::size_t first) {
        const double* active = m_active.data() + first;
        double *zo = z + o, *n = norm.data() + first, *sc = scale.data() + first;
#pragma omp simd
        for (std::size_t l = 0; l < W; ++l) {
          double sum = 0;
          for (int j = 0; j < s; ++j)
            sum += a[static_cast<std::size_t>(j)] * f[static_cast<std::size_t>(j)][o + l];
          const double dz = h * sum - zo[l];
          const double moved = active[l] != 0 ? zo[l] + dz : zo[l];
          const double change = active[l] != 0 ? std::fabs(dz) : 0.0;
          zo[l] = moved;
          n[l] = n[l] < change ? change : n[l];
          sc[l] = sc[l] < std::fabs(moved) ? std::fabs(moved) : sc[l];
        }
      });
    }
    for (std::size_t l = 0; l < used; ++l) {
      if (m_active[l] == 0) continue;
      bool done = false, failed = false;
      if (!std::isfinite(norm[l]) || !std::isfinite(scale[l])) {
        failed = true;
      } else if (norm[l] == 0) {
        done = true;
      } else if (iteration >= 2) {
        done =
            stage_iteration_done(norm[l] / m_last_norm[l], norm[l], scale[l], tolerance, round_off);
      }
      if (!done && !failed && iteration >= max_iterations) failed = true;
      m_last_norm[l] = norm[l];
      if (failed) {
        m_failed[l] = 1;
        m_active[l] = 0;
      } else if (done) {
        // The f of the iteration that converged, for the next step's guess, kept apart so
        // that the neighbours' further iterations do not touch it.
        for (int j = 0; j < s; ++j)
          for (std::size_t k = 0; k < d; ++k)
            m_f_kept[static_cast<std::size_t>(j)][at(k, l)] =
                m_f[static_cast<std::size_t>(j)][at(k, l)];
        m_active[l] = 0;
      }
    }
  }
  // x1 = x0 + Σ_i d_i Z_i, into the other buffer, which then becomes state(): x0 stays.
  double* xs = m_x.data();
  double* next = m_before.data();
  std::array<const double*, Stages> zs;
  for (int i = 0; i < s; ++i)
    zs[static_cast<std::size_t>(i)] = m_z[static_cast<std::size_t>(i)].data();
  each([&](std::size_t o, std::size_t) {
#pragma omp simd
    for (std::size_t l = 0; l < W; ++l) {
      double increment = 0;
      for (int i = 0; i < s; ++i)
        increment += m_d[static_cast<std::size_t>(i)] * zs[static_cast<std::size_t>(i)][o + l];
      next[o + l] = xs[o + l] + increment;
    }
  });
  m_x.swap(m_before);
  for (std::size_t l = 0; l < used; ++l) m_previous[l] = 1;
}

template <int Stages>
void lane_gauss<Stages>::copy_lane(std::size_t to, std::size_t from) {
  for (std::size_t k = 0; k < coordinates(); ++k) {
    m_x[at(k, to)] = m_x[at(k, from)];
    for (int j = 0; j < s; ++j)
      m_f_kept[static_cast<std::size_t>(j)][at(k, to)] =
          m_f_kept[static_cast<std::size_t>(j)][at(k, from)];
  }
  m_previous[to] = m_previous[from];
  m_failed[to] = m_failed[from];
}

template class lane_gauss<2>;
template class lane_gauss<3>;

}  // namespace NPEND_BATCH_ISA_NAMESPACE
}  // namespace npend::detail
