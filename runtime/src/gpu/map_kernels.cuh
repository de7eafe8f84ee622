// The cells of a map on a GPU: flip times, final coordinates and maximal Lyapunov exponents,
// one thread a cell, the same steps as the library's (chaos_map.cpp and the batch lanes):
// odeint's rk4 with its coefficients and sums, odeint's dopri5 with its step control and
// dense output, the flip located in its step as flip_time locates it.
//
// The text is compiled twice. At run time NVRTC compiles it as CUDA after a prelude and one
// model's generated device functions (generated/gpu_<model>_<n>.cuh) and an adapter
// `npend::gpu::model` (map_device.cpp writes both); in the tests the host compiler compiles
// it as C++, so that the cell functions are checked against the library on machines with no
// GPU. The includer defines NPEND_GPU_FUNCTION, NPEND_GPU_INF and NPEND_GPU_NAN and makes
// sin, cos, sqrt, fabs, log, pow, fmax, fmin and copysign visible.
//
// npend::gpu::model provides: links, dim (2n), params (the doubles of one chain's block) and
//   NPEND_GPU_FUNCTION static void rhs(const double* x, const double* params, double t,
//                                      double* dxdt);
//   NPEND_GPU_FUNCTION static double hamiltonian(const double* x, const double* params,
//                                                double t);
//   template <int K>
//   NPEND_GPU_FUNCTION static void tangents(const double* x, const double* params, double t,
//                                           const double* w, double* dw);
// the last J(x, t)·w_j for the K vectors w_j = w + j·dim into dw + j·dim (map_models.cuh).

namespace npend::gpu {

/// What every cell of a launch computes (the same layout on the host and the GPU: doubles
/// first, then 64-bit, then 32-bit integers).
struct map_job {
  double t_end;
  double dt;                ///< rk4's step; dopri5's first trial step
  double abs_tol, rel_tol;  ///< dopri5
  double min_step;          ///< dopri5 fails below this step (integrate's min_step_ratio·dt)
  double rest;              ///< state with rk4: the last, shorter step onto t_end (0: none)
  double energy_tolerance;  ///< flip: flip_energy_tolerance
  double lyapunov_time;     ///< lyapunov: steps·dt, the time the exponent divides by
  long long steps;          ///< rk4: whole steps of dt up to t_end
  long long chunk;          ///< lyapunov: steps between renormalisations
  int quantity;             ///< job_flip, job_state, job_lyapunov or job_indicators
  int stepper;              ///< job_rk4 or job_dopri5
  int flip_link;            ///< flip: 0 any arm, k the arm k
  int component;            ///< state: the coordinate
  int energy_check;         ///< flip: energy_none (driven), energy_conserved, energy_falls
  int max_tries;            ///< dopri5: attempts of one step before it fails
  int indicator;            ///< indicators: indicator_fli, _megno, _sali or _gali
};

enum : int { job_flip = 0, job_state = 1, job_lyapunov = 2, job_indicators = 3 };
enum : int { indicator_fli = 0, indicator_megno = 1, indicator_sali = 2, indicator_gali = 3 };
enum : int { job_rk4 = 0, job_dopri5 = 1 };
enum : int { energy_none = 0, energy_conserved = 1, energy_falls = 2 };

constexpr double upright = 3.14159265358979323846;

// Whether v is finite (inf − inf and NaN − NaN are NaN): the same test on the host and the
// GPU without either's isfinite.
NPEND_GPU_FUNCTION bool is_finite(double v) { return v - v == 0; }

// Whether an arm (or arm `link`) of x is at or past the upright position.
template <class M>
NPEND_GPU_FUNCTION bool has_flipped(const double* x, int link) {
  for (int k = 0; k < M::links; ++k)
    if ((link == 0 || link == k + 1) && fabs(x[k]) >= upright) return true;
  return false;
}

// The first θ in [0, 1] at which the cubic Hermite interpolant of an angle over a step of h
// — p(0) = y0, p(1) = y1, p'(0) = h f0, p'(1) = h f1 — reaches the upright ±π it passed
// (the sign of y1; |y0| < π ≤ |y1|). The cubic is cut at its turning points into monotone
// pieces, searched in order; the first whose end is upright is bisected down to adjacent
// doubles. 1 where rounding leaves the cubic just short of π at the end. The CPU's maps
// (chaos_map.cpp) call this same function.
NPEND_GPU_FUNCTION double hermite_upright_fraction(double y0, double f0, double y1, double f1,
                                                   double h) {
  const double s = y1 < 0 ? -1.0 : 1.0;
  const double d0 = h * f0, d1 = h * f1, rise = y1 - y0;
  const double c0 = s * y0 - upright, c1 = s * d0, c2 = s * (3 * rise - 2 * d0 - d1),
               c3 = s * (d0 + d1 - 2 * rise);
  double ends[3] = {0, 0, 0};
  int count = 0;
  const double a = 3 * c3, b = 2 * c2;
  if (a != 0) {
    const double discriminant = b * b - 4 * a * c1;
    if (discriminant > 0) {
      const double q = -0.5 * (b + copysign(sqrt(discriminant), b));
      const double r1 = q / a;
      if (r1 > 0 && r1 < 1) ends[count++] = r1;
      if (q != 0) {
        const double r2 = c1 / q;
        if (r2 > 0 && r2 < 1) ends[count++] = r2;
      }
    }
  } else if (b != 0) {
    const double r = -c1 / b;
    if (r > 0 && r < 1) ends[count++] = r;
  }
  if (count == 2 && ends[1] < ends[0]) {
    const double swap = ends[0];
    ends[0] = ends[1];
    ends[1] = swap;
  }
  ends[count++] = 1;
  double lo = 0;
  for (int i = 0; i < count; ++i) {
    double hi = ends[i];
    const double g_hi = c0 + hi * (c1 + hi * (c2 + hi * c3));
    if (!(g_hi >= 0)) {
      lo = hi;
      continue;
    }
    for (;;) {
      const double mid = lo + 0.5 * (hi - lo);
      if (mid <= lo || mid >= hi) return hi;
      const double g_mid = c0 + mid * (c1 + mid * (c2 + mid * c3));
      if (g_mid >= 0)
        hi = mid;
      else
        lo = mid;
    }
  }
  return 1;
}

// Whether the energy at the end of the flip's step lets the flip be believed
// (chaos_map.cpp's flip_energy_holds).
template <class M>
NPEND_GPU_FUNCTION bool flip_energy_holds(const map_job& job, const double* params, double h0,
                                          const double* x1, double t1) {
  if (job.energy_check == energy_none) return true;
  const double drift = M::hamiltonian(x1, params, t1) - h0;
  const double allowed = job.energy_tolerance * h0;
  return job.energy_check == energy_falls ? drift <= allowed : fabs(drift) <= allowed;
}

// The system a cell integrates: the chain's state, and with `Tangent` its tangent vector
// after it (d/dt w = J(x) w).
template <class M, bool Tangent>
struct cell_system {
  static constexpr int size = Tangent ? 2 * M::dim : M::dim;
  NPEND_GPU_FUNCTION static void rhs(const double* y, const double* params, double t,
                                     double* dydt) {
    M::rhs(y, params, t, dydt);
    if constexpr (Tangent) M::template tangents<1>(y, params, t, y + M::dim, dydt + M::dim);
  }
};

// One rk4 step of h from (y, t), odeint's runge_kutta4: its coefficients a_ij h and b_i h as
// it rounds them, the zero ones kept (0·k is not always 0), its sums in its order.
template <class S>
NPEND_GPU_FUNCTION void rk4_step(const double* params, double t, double h, double* y) {
  double k1[S::size], k2[S::size], k3[S::size], k4[S::size], tmp[S::size];
  const double half = 0.5 * h, zero = 0.0 * h, full = 1.0 * h, sixth = (1.0 / 6.0) * h,
               third = (1.0 / 3.0) * h;
  S::rhs(y, params, t, k1);
  for (int i = 0; i < S::size; ++i) tmp[i] = y[i] + half * k1[i];
  S::rhs(tmp, params, t + half, k2);
  for (int i = 0; i < S::size; ++i) tmp[i] = y[i] + zero * k1[i] + half * k2[i];
  S::rhs(tmp, params, t + half, k3);
  for (int i = 0; i < S::size; ++i) tmp[i] = y[i] + zero * k1[i] + zero * k2[i] + full * k3[i];
  S::rhs(tmp, params, t + full, k4);
  for (int i = 0; i < S::size; ++i)
    y[i] = y[i] + sixth * k1[i] + third * k2[i] + third * k3[i] + sixth * k4[i];
}

// Dormand–Prince 5(4) as odeint's make_dense_output of runge_kutta_dopri5 runs it: FSAL, the
// error norm max_i |err_i| / (abs_tol + rel_tol (|x_i| + |h| |f_i|)), odeint's step
// adjustment, and its dense output over the last accepted step.
template <class S>
struct dopri5_state {
  double x[S::size], f[S::size];          // now
  double x_old[S::size], f_old[S::size];  // at the last accepted step's start
  double k3[S::size], k4[S::size], k5[S::size], k6[S::size];
  double t, t_old, h;
  int tries;           // attempts of the step under way (odeint's failed_step_checker)
  bool last_accepted;  // the last attempt was accepted: the next one starts a new step
};

struct dopri5_tableau {
  static constexpr double b21 = 1.0 / 5, b31 = 3.0 / 40, b32 = 9.0 / 40, b41 = 44.0 / 45,
                          b42 = -56.0 / 15, b43 = 32.0 / 9, b51 = 19372.0 / 6561,
                          b52 = -25360.0 / 2187, b53 = 64448.0 / 6561, b54 = -212.0 / 729,
                          b61 = 9017.0 / 3168, b62 = -355.0 / 33, b63 = 46732.0 / 5247,
                          b64 = 49.0 / 176, b65 = -5103.0 / 18656, c1 = 35.0 / 384,
                          c3 = 500.0 / 1113, c4 = 125.0 / 192, c5 = -2187.0 / 6784, c6 = 11.0 / 84,
                          dc1 = c1 - 5179.0 / 57600, dc3 = c3 - 7571.0 / 16695,
                          dc4 = c4 - 393.0 / 640, dc5 = c5 - -92097.0 / 339200,
                          dc6 = c6 - 187.0 / 2100, dc7 = -1.0 / 40;
};

template <class S>
NPEND_GPU_FUNCTION void dopri5_restart(dopri5_state<S>& s, const double* params, double t,
                                       double h) {
  s.t = t;
  s.t_old = t;
  s.h = h;
  s.tries = 0;
  s.last_accepted = false;
  S::rhs(s.x, params, t, s.f);
}

// One attempt; true where it was accepted (then x, f, t moved on; x_old, f_old, t_old hold
// the step's start for the dense output).
template <class S>
NPEND_GPU_FUNCTION bool dopri5_attempt(dopri5_state<S>& s, const double* params,
                                       const map_job& job) {
  using T = dopri5_tableau;
  constexpr int d = S::size;
  const double h = s.h;
  double k2[d], tmp[d], out[d], f_out[d];
  if (s.last_accepted) s.tries = 0;
  ++s.tries;
  s.last_accepted = false;
  for (int i = 0; i < d; ++i) tmp[i] = s.x[i] + (h * T::b21) * s.f[i];
  S::rhs(tmp, params, s.t + h * (1.0 / 5), k2);
  for (int i = 0; i < d; ++i) tmp[i] = s.x[i] + (h * T::b31) * s.f[i] + (h * T::b32) * k2[i];
  S::rhs(tmp, params, s.t + h * (3.0 / 10), s.k3);
  for (int i = 0; i < d; ++i)
    tmp[i] = s.x[i] + (h * T::b41) * s.f[i] + (h * T::b42) * k2[i] + (h * T::b43) * s.k3[i];
  S::rhs(tmp, params, s.t + h * (4.0 / 5), s.k4);
  for (int i = 0; i < d; ++i)
    tmp[i] = s.x[i] + (h * T::b51) * s.f[i] + (h * T::b52) * k2[i] + (h * T::b53) * s.k3[i] +
             (h * T::b54) * s.k4[i];
  S::rhs(tmp, params, s.t + h * (8.0 / 9), s.k5);
  for (int i = 0; i < d; ++i)
    tmp[i] = s.x[i] + (h * T::b61) * s.f[i] + (h * T::b62) * k2[i] + (h * T::b63) * s.k3[i] +
             (h * T::b64) * s.k4[i] + (h * T::b65) * s.k5[i];
  S::rhs(tmp, params, s.t + h, s.k6);
  for (int i = 0; i < d; ++i)
    out[i] = s.x[i] + (h * T::c1) * s.f[i] + (h * T::c3) * s.k3[i] + (h * T::c4) * s.k4[i] +
             (h * T::c5) * s.k5[i] + (h * T::c6) * s.k6[i];
  S::rhs(out, params, s.t + h, f_out);
  double error = 0;
  for (int i = 0; i < d; ++i) {
    const double err = (h * T::dc1) * s.f[i] + (h * T::dc3) * s.k3[i] + (h * T::dc4) * s.k4[i] +
                       (h * T::dc5) * s.k5[i] + (h * T::dc6) * s.k6[i] + (h * T::dc7) * f_out[i];
    const double scaled =
        fabs(err) / (job.abs_tol + job.rel_tol * (fabs(s.x[i]) + fabs(h) * fabs(s.f[i])));
    // A non-finite entry rejects the attempt (its norm is +inf) rather than accepting it.
    if (scaled != scaled)
      error = NPEND_GPU_INF;
    else if (error < scaled)
      error = scaled;
  }
  if (error > 1.0) {
    s.h = h * fmax(0.9 * pow(error, -1.0 / 3.0), 0.2);
    return false;
  }
  s.t_old = s.t;
  s.t = s.t + h;
  if (error < 0.5) s.h = h * (0.9 * pow(fmax(pow(5.0, -5.0), error), -1.0 / 5.0));
  for (int i = 0; i < d; ++i) {
    s.x_old[i] = s.x[i];
    s.f_old[i] = s.f[i];
    s.x[i] = out[i];
    s.f[i] = f_out[i];
  }
  s.last_accepted = true;
  return true;
}

// The dense output of the last accepted step at t: coordinates first..first + count - 1 into
// out (odeint's runge_kutta_dopri5::calc_state).
template <class S>
NPEND_GPU_FUNCTION void dopri5_state_at(const dopri5_state<S>& s, double t, int first, int count,
                                        double* out) {
  using T = dopri5_tableau;
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
  const double w1 = h * (A * T::c1 - C * X1 + D);
  const double w3 = h * (A * T::c3 + C * X3);
  const double w4 = h * (A * T::c4 - C * X4);
  const double w5 = h * (A * T::c5 + C * X5);
  const double w6 = h * (A * T::c6 - C * X6);
  const double w7 = h * (B + C * X7);
  for (int i = first; i < first + count; ++i)
    out[i - first] = s.x_old[i] + w1 * s.f_old[i] + w3 * s.k3[i] + w4 * s.k4[i] + w5 * s.k5[i] +
                     w6 * s.k6[i] + w7 * s.f[i];
}

// Where a dopri5 step has gone wrong, as npend::integrate finds it: too many tries, a
// non-finite state, a collapsed step.
template <class S>
NPEND_GPU_FUNCTION bool dopri5_failed(const dopri5_state<S>& s, bool accepted, const map_job& job) {
  if (s.tries >= job.max_tries) return true;
  if (!accepted) return false;
  for (int i = 0; i < S::size; ++i)
    if (!is_finite(s.x[i])) return true;
  return s.h < job.min_step;
}

template <class M>
NPEND_GPU_FUNCTION bool state_finite(const double* x) {
  for (int i = 0; i < M::dim; ++i)
    if (!is_finite(x[i])) return false;
  return true;
}

// The flip time with rk4 steps of dt (flip_time's rk4 path).
template <class M>
NPEND_GPU_FUNCTION double flip_rk4(const double* x0, const double* params, const map_job& job) {
  using S = cell_system<M, false>;
  double x[M::dim], before[M::dim], f0[M::dim], f1[M::dim];
  for (int i = 0; i < M::dim; ++i) x[i] = x0[i];
  const double h0 = M::hamiltonian(x0, params, 0.0);
  for (long long k = 1; k <= job.steps; ++k) {
    const double t0 = static_cast<double>(k - 1) * job.dt;
    for (int i = 0; i < M::dim; ++i) before[i] = x[i];
    rk4_step<S>(params, t0, job.dt, x);
    if (has_flipped<M>(x, job.flip_link)) {
      if (!flip_energy_holds<M>(job, params, h0, x, t0 + job.dt)) return NPEND_GPU_NAN;
      M::rhs(before, params, t0, f0);
      M::rhs(x, params, t0 + job.dt, f1);
      double theta = 1;
      for (int a = 0; a < M::links; ++a)
        if ((job.flip_link == 0 || job.flip_link == a + 1) && fabs(x[a]) >= upright)
          theta = fmin(theta, hermite_upright_fraction(before[a], f0[a], x[a], f1[a], job.dt));
      return t0 + theta * job.dt;
    }
    if (!is_finite(x[0])) return NPEND_GPU_NAN;
  }
  return NPEND_GPU_INF;
}

// The flip time with dopri5: bisection of the dense output inside the step where an arm is
// first seen upright (flip_time_dopri5).
template <class M>
NPEND_GPU_FUNCTION double flip_dopri5(const double* x0, const double* params, const map_job& job) {
  using S = cell_system<M, false>;
  dopri5_state<S> s;
  for (int i = 0; i < M::dim; ++i) s.x[i] = x0[i];
  dopri5_restart(s, params, 0.0, job.dt);
  const double h0 = M::hamiltonian(x0, params, 0.0);
  double angles[M::links];
  for (;;) {
    const bool accepted = dopri5_attempt(s, params, job);
    if (dopri5_failed(s, accepted, job)) return NPEND_GPU_NAN;
    if (!accepted) continue;
    if (has_flipped<M>(s.x, job.flip_link)) {
      double lo = s.t_old, hi = s.t;
      for (;;) {
        const double mid = lo + 0.5 * (hi - lo);
        if (mid <= lo || mid >= hi) break;
        dopri5_state_at(s, mid, 0, M::links, angles);
        if (has_flipped<M>(angles, job.flip_link))
          hi = mid;
        else
          lo = mid;
      }
      if (hi > job.t_end) return NPEND_GPU_INF;
      return flip_energy_holds<M>(job, params, h0, s.x, s.t) ? hi : NPEND_GPU_NAN;
    }
    if (s.t >= job.t_end) return NPEND_GPU_INF;
  }
}

// Coordinate job.component at t_end: rk4 steps of dt and a last shorter one onto t_end, or
// dopri5's dense output at t_end (final_coordinate).
template <class M, int Stepper>
NPEND_GPU_FUNCTION double final_coordinate(const double* x0, const double* params,
                                           const map_job& job) {
  using S = cell_system<M, false>;
  double x[M::dim];
  if constexpr (Stepper == job_dopri5) {
    dopri5_state<S> s;
    for (int i = 0; i < M::dim; ++i) s.x[i] = x0[i];
    dopri5_restart(s, params, 0.0, job.dt);
    for (;;) {
      const bool accepted = dopri5_attempt(s, params, job);
      if (dopri5_failed(s, accepted, job)) return NPEND_GPU_NAN;
      if (accepted && s.t >= job.t_end) break;
    }
    dopri5_state_at(s, job.t_end, 0, M::dim, x);
  } else {
    for (int i = 0; i < M::dim; ++i) x[i] = x0[i];
    for (long long k = 1; k <= job.steps; ++k)
      rk4_step<S>(params, static_cast<double>(k - 1) * job.dt, job.dt, x);
    if (job.rest > 0) rk4_step<S>(params, static_cast<double>(job.steps) * job.dt, job.rest, x);
  }
  return state_finite<M>(x) ? x[job.component] : NPEND_GPU_NAN;
}

// The maximal Lyapunov exponent with rk4 (the batch lanes' lyapunov_on_lanes): the tangent
// starts as (1, …, 1)/√(2n), renormalised every job.chunk steps and at the end.
template <class M>
NPEND_GPU_FUNCTION double lyapunov_rk4(const double* x0, const double* params, const map_job& job) {
  using S = cell_system<M, true>;
  double y[S::size];
  const double w0 = 1.0 / sqrt(static_cast<double>(M::dim));
  for (int i = 0; i < M::dim; ++i) {
    y[i] = x0[i];
    y[M::dim + i] = w0;
  }
  double sum = 0;
  for (long long k = 1; k <= job.steps; ++k) {
    rk4_step<S>(params, static_cast<double>(k - 1) * job.dt, job.dt, y);
    if (k % job.chunk != 0 && k != job.steps) continue;
    for (int i = 0; i < S::size; ++i)
      if (!is_finite(y[i])) return NPEND_GPU_NAN;
    double squares = 0;
    for (int i = 0; i < M::dim; ++i) squares = squares + y[M::dim + i] * y[M::dim + i];
    const double norm = sqrt(squares);
    sum = sum + log(norm);
    for (int i = 0; i < M::dim; ++i) y[M::dim + i] = y[M::dim + i] / norm;
  }
  return sum / job.lyapunov_time;
}

// The maximal Lyapunov exponent with dopri5 (the batch lanes' lyapunov_on_dopri5_lanes): each
// renormalisation interval (job.chunk steps of dt, the last one shorter) a run of its own,
// the stepper restarted with the trial step dt, the state and tangent taken from its dense
// output at the interval's end, then the tangent renormalised.
template <class M>
NPEND_GPU_FUNCTION double lyapunov_dopri5(const double* x0, const double* params,
                                          const map_job& job) {
  using S = cell_system<M, true>;
  dopri5_state<S> s;
  const double w0 = 1.0 / sqrt(static_cast<double>(M::dim));
  for (int i = 0; i < M::dim; ++i) {
    s.x[i] = x0[i];
    s.x[M::dim + i] = w0;
  }
  dopri5_restart(s, params, 0.0, job.dt);
  long long reached = 0;
  double sum = 0, y[S::size];
  for (;;) {
    const bool accepted = dopri5_attempt(s, params, job);
    if (dopri5_failed(s, accepted, job)) return NPEND_GPU_NAN;
    if (!accepted) continue;
    const long long steps = job.chunk < job.steps - reached ? job.chunk : job.steps - reached;
    const double target =
        static_cast<double>(reached) * job.dt + static_cast<double>(steps) * job.dt;
    if (s.t < target) continue;
    dopri5_state_at(s, target, 0, S::size, y);
    for (int i = 0; i < S::size; ++i) {
      if (!is_finite(y[i])) return NPEND_GPU_NAN;
      s.x[i] = y[i];
    }
    reached += steps;
    double squares = 0;
    for (int i = 0; i < M::dim; ++i) squares = squares + s.x[M::dim + i] * s.x[M::dim + i];
    const double norm = sqrt(squares);
    sum = sum + log(norm);
    for (int i = 0; i < M::dim; ++i) s.x[M::dim + i] = s.x[M::dim + i] / norm;
    if (reached == job.steps) return sum / job.lyapunov_time;
    dopri5_restart(s, params, static_cast<double>(reached) * job.dt, job.dt);
  }
}

// The state, K deviation vectors (d each) and MEGNO's integrals y = ∫ s ẇ₁·w₁/‖w₁‖² ds and
// z = ∫ Y ds, integrated together (chaos_indicators' augmented system): ẇ = J(x, t) w.
template <class M, int K>
struct indicator_system {
  static constexpr int d = M::dim, size = d * (1 + K) + 2, y = d * (1 + K), z = y + 1;
  NPEND_GPU_FUNCTION static void rhs(const double* s, const double* params, double t, double* ds) {
    M::rhs(s, params, t, ds);
    M::template tangents<K>(s, params, t, s + d, ds + d);
    double along = 0, squares = 0;
    for (int i = 0; i < d; ++i) {
      along = along + s[d + i] * ds[d + i];
      squares = squares + s[d + i] * s[d + i];
    }
    ds[y] = t * (along / squares);
    ds[z] = t > 0 ? 2 * s[y] / t : 0.0;
  }
};

// The volume spanned by the K columns w + j·d: the product of their singular values, as
// |R_11 ⋯ R_KK| of a Householder QR (the same product, without an SVD on the GPU).
template <int d, int K>
NPEND_GPU_FUNCTION double spanned_volume(const double* w) {
  double a[d * K];
  for (int i = 0; i < d * K; ++i) a[i] = w[i];
  double volume = 1;
  for (int j = 0; j < K; ++j) {
    double* col = a + j * d;
    double squares = 0;
    for (int i = j; i < d; ++i) squares = squares + col[i] * col[i];
    const double norm = sqrt(squares);
    volume = volume * norm;
    if (norm == 0) return 0;
    // The reflection taking col[j..] onto −sign(col[j])·norm·e_j, applied to the later columns.
    double v[d];
    for (int i = 0; i < d; ++i) v[i] = i < j ? 0.0 : col[i];
    v[j] = v[j] + (col[j] > 0 ? norm : -norm);
    double vv = 0;
    for (int i = j; i < d; ++i) vv = vv + v[i] * v[i];
    for (int c = j + 1; c < K; ++c) {
      double* other = a + c * d;
      double dot = 0;
      for (int i = j; i < d; ++i) dot = dot + v[i] * other[i];
      const double f = 2 * dot / vv;
      for (int i = j; i < d; ++i) other[i] = other[i] - f * v[i];
    }
  }
  return volume;
}

// FLI, MEGNO ⟨Y⟩, SALI or GALI_K at t_end by rk4 at dt with K deviation vectors, normalised
// after every step (chaos_indicators, as the batch lanes run it). The vectors start as the
// library's: w₁ = (1, …, 1)/√d, then e₁, e₂, … made orthogonal to those before.
template <class M, int K>
NPEND_GPU_FUNCTION double indicator_rk4(const double* x0, const double* params,
                                        const map_job& job) {
  using S = indicator_system<M, K>;
  constexpr int d = S::d;
  double s[S::size];
  for (int i = 0; i < d; ++i) s[i] = x0[i];
  for (int i = 0; i < d; ++i) s[d + i] = 1.0 / sqrt(static_cast<double>(d));
  for (int j = 1; j < K; ++j) {
    double* w = s + d * (1 + j);
    for (int i = 0; i < d; ++i) w[i] = i == j - 1 ? 1.0 : 0.0;
    for (int p = 0; p < j; ++p) {
      const double* q = s + d * (1 + p);
      double dot = 0;
      for (int i = 0; i < d; ++i) dot = dot + q[i] * w[i];
      for (int i = 0; i < d; ++i) w[i] = w[i] - dot * q[i];
    }
    double squares = 0;
    for (int i = 0; i < d; ++i) squares = squares + w[i] * w[i];
    const double norm = sqrt(squares);
    for (int i = 0; i < d; ++i) w[i] = w[i] / norm;
  }
  s[S::y] = 0;
  s[S::z] = 0;
  double log_stretch = 0, fli = 0;
  for (long long k = 1; k <= job.steps; ++k) {
    rk4_step<S>(params, static_cast<double>(k - 1) * job.dt, job.dt, s);
    for (int j = 0; j < K; ++j) {
      double* w = s + d * (1 + j);
      double squares = 0;
      for (int i = 0; i < d; ++i) squares = squares + w[i] * w[i];
      const double norm = sqrt(squares);
      if (!is_finite(norm) || norm == 0 || !is_finite(s[0])) return NPEND_GPU_NAN;
      for (int i = 0; i < d; ++i) w[i] = w[i] / norm;
      if (j == 0) {
        log_stretch = log_stretch + log(norm);
        fli = fmax(fli, log_stretch);
      }
    }
  }
  const double t = static_cast<double>(job.steps) * job.dt;
  switch (job.indicator) {
    case indicator_fli:
      return fli;
    case indicator_megno:
      return t > 0 ? s[S::z] / t : 0.0;
    case indicator_sali: {
      double plus = 0, minus = 0;
      for (int i = 0; i < d; ++i) {
        const double a = s[d + i], b = s[2 * d + i];
        plus = plus + (a + b) * (a + b);
        minus = minus + (a - b) * (a - b);
      }
      return fmin(sqrt(plus), sqrt(minus));
    }
    default:
      return spanned_volume<d, K>(s + d);
  }
}

/// The value of one cell started at x0 on the chain of `params`: quantity Quantity with
/// stepper Stepper (job_* of job.quantity and job.stepper), the indicators with Vectors
/// deviation vectors. One kernel per combination, so that each holds only its own code and
/// keeps only its own registers.
template <class M, int Quantity, int Stepper, int Vectors = 2>
NPEND_GPU_FUNCTION double cell_value_of(const double* x0, const double* params,
                                        const map_job& job) {
  if constexpr (Quantity == job_flip) {
    if (has_flipped<M>(x0, job.flip_link)) return 0;
    if constexpr (Stepper == job_dopri5)
      return flip_dopri5<M>(x0, params, job);
    else
      return flip_rk4<M>(x0, params, job);
  } else if constexpr (Quantity == job_lyapunov) {
    if constexpr (Stepper == job_dopri5)
      return lyapunov_dopri5<M>(x0, params, job);
    else
      return lyapunov_rk4<M>(x0, params, job);
  } else if constexpr (Quantity == job_indicators) {
    return indicator_rk4<M, Vectors>(x0, params, job);
  } else {
    return final_coordinate<M, Stepper>(x0, params, job);
  }
}

/// cell_value_of for job.quantity and job.stepper, but not the indicators, whose vector count
/// is the kernel's own (the tests' way in).
template <class M>
NPEND_GPU_FUNCTION double cell_value(const double* x0, const double* params, const map_job& job) {
  const bool dopri5 = job.stepper == job_dopri5;
  switch (job.quantity) {
    case job_flip:
      return dopri5 ? cell_value_of<M, job_flip, job_dopri5>(x0, params, job)
                    : cell_value_of<M, job_flip, job_rk4>(x0, params, job);
    case job_lyapunov:
      return dopri5 ? cell_value_of<M, job_lyapunov, job_dopri5>(x0, params, job)
                    : cell_value_of<M, job_lyapunov, job_rk4>(x0, params, job);
    default:
      return dopri5 ? cell_value_of<M, job_state, job_dopri5>(x0, params, job)
                    : cell_value_of<M, job_state, job_rk4>(x0, params, job);
  }
}

#ifdef __CUDACC_RTC__
/// The cells 0..count - 1: start i at starts + i·dim, its chain's parameters at
/// params + chain_of[i]·M::params; each thread takes the next cell from *next as soon as its
/// last is done, so that cells that end early (a flip, a forbidden start) free their thread
/// for the rest. The program's one kernel (map_device.cpp) calls it for its quantity and
/// stepper.
template <class M, int Quantity, int Stepper, int Vectors>
__device__ void run_cells(const double* starts, const int* chain_of, const double* params,
                          long long count, const map_job& job, double* values,
                          unsigned long long* next) {
  for (;;) {
    const unsigned long long i = atomicAdd(next, 1ULL);
    if (i >= static_cast<unsigned long long>(count)) return;
    values[i] = cell_value_of<M, Quantity, Stepper, Vectors>(
        starts + i * M::dim, params + static_cast<long long>(chain_of[i]) * M::params, job);
  }
}
#endif

}  // namespace npend::gpu
