// The implicit Gauss–Legendre Runge–Kutta methods (s = 2 stages, order 4; s = 3, order 6):
// symplectic and symmetric for any Hamiltonian, separable or not, which is what the chain
// needs (its kinetic energy depends on the angles for n ≥ 2, so odeint's symplectic
// steppers do not apply). A model of odeint's Stepper concept.
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <boost/numeric/odeint/stepper/stepper_categories.hpp>
#include <boost/numeric/odeint/util/unwrap_reference.hpp>
#include <cmath>
#include <cstddef>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "npend/integrators/detail/gauss_legendre_tableau.hpp"
#include "npend/integrators/integration_error.hpp"

namespace npend {

namespace detail {

/// What the s-stage Gauss–Legendre step derives from its tableau: the continuation of the
/// previous step's collocation polynomial u(t0 + θh) = x0 + h Σ_j ∫_0^θ ℓ_j K_j into the next
/// step, Z_i ≈ h Σ_j extrapolation(i, j) K_j (the next step's starting guess), and
/// d = bᵀA⁻¹, with which x1 = x0 + Σ_i d_i Z_i needs no further evaluation.
template <int Stages>
struct gauss_legendre_coefficients {
  Eigen::Matrix<double, Stages, Stages> extrapolation;
  Eigen::Matrix<double, 1, Stages> d;

  gauss_legendre_coefficients() {
    using tableau = gauss_legendre_tableau<Stages>;
    constexpr int s = Stages;
    // Lagrange polynomials on the nodes in the monomial basis: V α = I, V_ik = c_i^k.
    Eigen::Matrix<double, s, s> V;
    for (int i = 0; i < s; ++i)
      for (int k = 0; k < s; ++k) V(i, k) = std::pow(tableau::c[i], k);
    const Eigen::Matrix<double, s, s> alpha = V.inverse();
    // ∫_0^θ ℓ_j
    const auto integrated = [&](int j, double theta) {
      double sum = 0;
      for (int k = 0; k < s; ++k) sum += alpha(k, j) * std::pow(theta, k + 1) / (k + 1);
      return sum;
    };
    for (int i = 0; i < s; ++i)
      for (int j = 0; j < s; ++j)
        extrapolation(i, j) = integrated(j, 1 + tableau::c[i]) - tableau::b[j];
    Eigen::Matrix<double, s, s> A;
    Eigen::Matrix<double, 1, s> b;
    for (int i = 0; i < s; ++i) {
      b(i) = tableau::b[i];
      for (int j = 0; j < s; ++j) A(i, j) = tableau::a[i][j];
    }
    d = b * A.inverse();
  }
};

// Corrections below this fraction of ‖x‖∞ can be round-off noise: evaluating the stage
// equations loses a few units in the last place, more for long steps (h‖J‖ ~ 1), and the
// solve with the Newton matrix adds rounding that grows with its dimension (a 100-link
// chain stalled at 4e-15 with dt = 1e-3), hence the factor dim/16 beyond 16 coordinates.
inline double gauss_legendre_round_off_level(std::size_t dim) {
  return 16 * std::numeric_limits<double>::epsilon() *
         std::max(1.0, static_cast<double>(dim) / 16.0);
}

// Whether a stage iteration may stop after a correction of size `norm` (∞-norm) that shrank
// by theta against the one before, scale the size of the state and the stages: converged,
// its estimated remaining error θ/(1−θ)‖ΔZ‖ below tolerance·scale; or at the level of
// round-off in the stage equations (`round_off_level`·scale), where corrections that stop
// shrinking (θ ≥ 0.5) are noise, which no iteration removes.
inline bool stage_iteration_done(double theta, double norm, double scale, double tolerance,
                                 double round_off_level) {
  if (theta < 1 && theta / (1 - theta) * norm <= tolerance * scale) return true;
  return norm <= round_off_level * scale && theta >= 0.5;
}

}  // namespace detail

/// Work counters of a gauss_legendre stepper since its construction.
struct gauss_legendre_statistics {
  std::size_t steps = 0;
  std::size_t newton_iterations = 0;
  std::size_t rhs_evaluations = 0;
  std::size_t jacobian_evaluations = 0;
  /// LU factorisations of the sd × sd Newton matrix.
  std::size_t factorizations = 0;
  /// Steps in which the simplified Newton iteration contracted too slowly and the
  /// iteration switched to full Newton (Jacobians at the stage values).
  std::size_t full_newton_steps = 0;
};

/// The s-stage Gauss–Legendre method (order 2s) as an odeint Stepper
/// (`stepper_category = stepper_tag`): use it with `integrate_const`,
/// `integrate_n_steps`, or call `do_step` directly.
///
/// Its System is an implicit system like `rosenbrock4`'s: a `std::pair` (rhs, jacobian)
/// with `rhs(x, dxdt, t)` (x, dxdt: std::vector<double>, dim d) and
/// `jacobian(x, J, t, dfdt)` writing ∂f/∂x into a row-major Eigen matrix J (dim d × d);
/// dfdt is not used. For a chain: `npend::make_implicit_system(chain)`.
///
/// Each step solves the stage equations Z_i = h Σ_j a_ij f(x + Z_j) by simplified Newton
/// with the exact Jacobian at the start of the step — or of an earlier step, as long as the
/// iterations with that matrix contract fast (rate θ ≤ 1e-3). When they contract slowly the
/// matrix is renewed at x (θ > 1e-2), and if that is not enough (θ > 0.1) the iteration
/// switches to full Newton with Jacobians at the stage values. From d = 48 on, where one
/// O(d³) factorisation costs more than 50 of the O(d²) iterations, the limits are 0.25, 0.25
/// and 0.5 and θ is taken above round-off, so that a long chain's step stays O(d²) but for
/// rare renewals (a 100-link chain: 5 factorisations in 200 steps, 20 times faster). The starting
/// guess extrapolates the previous step's collocation polynomial when the step continues
/// the previous one (same dt, start state equal to the previous result); otherwise it is
/// Z = 0. The iteration runs to round-off: it stops when the estimated remaining error
/// θ/(1−θ)‖ΔZ‖ (θ the observed contraction rate) is below `tolerance` relative to ‖x‖∞ —
/// by default 1e-3 of the rounding unit, because the leftover iteration error is not
/// random but smooth along the trajectory, and would add up over many steps into an energy
/// drift (Hairer, McLachlan & Razakarivony 2008) — or when corrections of a few units in
/// the last place of the state stop shrinking (round-off noise).
/// Anything else — a diverging iteration, `max_iterations` reached, non-finite stage
/// values — throws npend::integration_error naming the time and suggesting a smaller dt;
/// a step is never silently accepted unconverged.
template <int Stages>
class gauss_legendre {
 public:
  using tableau = detail::gauss_legendre_tableau<Stages>;
  using state_type = std::vector<double>;
  using deriv_type = std::vector<double>;
  using value_type = double;
  using time_type = double;
  using order_type = unsigned short;
  using stepper_category = boost::numeric::odeint::stepper_tag;
  using matrix_type = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

  static constexpr int stages = Stages;
  static constexpr order_type order_value = 2 * Stages;

  /// The default tolerance: a thousandth of the rounding unit of the state.
  static constexpr double default_tolerance = 1e-3 * std::numeric_limits<double>::epsilon();

  /// tolerance: bound on the estimated remaining Newton error relative to ‖x‖∞;
  /// max_iterations: Newton iterations per step before giving up. Throws
  /// std::invalid_argument for a tolerance that is not positive and finite, or
  /// max_iterations < 2.
  explicit gauss_legendre(double tolerance = default_tolerance, int max_iterations = 30)
      : m_tolerance(tolerance), m_max_iterations(max_iterations) {
    if (!(tolerance > 0) || !std::isfinite(tolerance))
      throw std::invalid_argument("gauss_legendre: tolerance must be positive and finite");
    if (max_iterations < 2)
      throw std::invalid_argument("gauss_legendre: max_iterations must be at least 2");
    init_coefficients();
  }

  order_type order() const { return order_value; }

  /// One step x(t) → x(t + dt) in place (x: dim d). Throws npend::integration_error if the
  /// stage equations cannot be solved to round-off, std::invalid_argument for a dt that is
  /// zero or not finite.
  template <class System>
  void do_step(System system, state_type& x, time_type t, time_type dt) {
    auto& sys =
        static_cast<typename boost::numeric::odeint::unwrap_reference<System>::type&>(system);
    step(sys, x, t, dt);
  }

  /// One step from `in` at t to `out` at t + dt (both dim d).
  template <class System>
  void do_step(System system, const state_type& in, time_type t, state_type& out, time_type dt) {
    out = in;
    do_step(system, out, t, dt);
  }

  /// One step x(t) → x(t + dt) in place, exactly as do_step, and the tangent vectors in the
  /// columns of `tangent` (d × k, any k ≥ 1) mapped by the exact derivative of that step:
  /// tangent ← (∂x(t + dt)/∂x(t)) · tangent.
  ///
  /// The derivative comes from differentiating the converged stage equations
  /// Z_i = h Σ_j a_ij f(x + Z_j) implicitly: with J_j the Jacobian at the stage value x + Z_j,
  /// (I − h (a_ij J_j)) ∂Z/∂x = h (a_ij J_j) (1 ⊗ I) — the matrix of full Newton — and
  /// ∂x(t + dt)/∂x = I + Σ_i d_i ∂Z_i/∂x. It is the derivative of the discrete flow itself,
  /// so it inherits the method's structure: for a Hamiltonian system it is symplectic
  /// (Mᵀ Ω M = Ω to round-off), and Lyapunov exponents computed from it come in exact ±
  /// pairs. Integrating the variational equations dZ/dt = J(x) Z with the same method
  /// would give the same map, at the cost of a Newton iteration d(k+1)-dimensional.
  /// Costs s Jacobian evaluations and one LU factorisation of the sd × sd matrix per step on
  /// top of do_step (counted in statistics()). Throws as do_step, and
  /// std::invalid_argument if `tangent` does not have d rows.
  template <class System, class Derived>
  void do_step_with_tangent(System system, state_type& x, time_type t, time_type dt,
                            Eigen::MatrixBase<Derived>& tangent) {
    auto& sys =
        static_cast<typename boost::numeric::odeint::unwrap_reference<System>::type&>(system);
    if (tangent.rows() != static_cast<Eigen::Index>(x.size()))
      throw std::invalid_argument("gauss_legendre: the tangent vectors have " +
                                  std::to_string(tangent.rows()) + " rows; the state has " +
                                  std::to_string(x.size()));
    solve_stages(sys, x, t, dt);
    map_tangent(sys, x, t, dt, tangent);
    finish_step(x, dt);
  }

  const gauss_legendre_statistics& statistics() const { return m_stats; }
  /// Forgets the previous step: the next one starts its Newton iteration from Z = 0 with
  /// a Newton matrix factored afresh.
  void reset() {
    m_have_previous = false;
    m_matrix = matrix_state::none;
  }

 private:
  static constexpr int s = Stages;
  // Full Newton's corrections below this fraction of ‖x‖∞ that stop shrinking are rounding,
  // not divergence (see solve_stages).
  static constexpr double stalled_level = 1e-11;
  double round_off_level() const { return detail::gauss_legendre_round_off_level(m_dim); }
  // When to renew the Newton matrix: what one factorisation costs against one iteration
  // decides. Factoring the sd × sd matrix costs ~(sd)³·2/3 flops, an iteration's solve
  // ~2(sd)² and s right-hand sides (O(d) for the loop kernels), so from d = 48 on (chains of
  // 24 links and more) a factorisation is worth 50 and more iterations: there an old matrix
  // is kept while it contracts at all well (θ ≤ 0.25) and a fresh one before full Newton
  // (θ ≤ 0.5), which keeps a step O(d²) but for the rare renewals — at 100 links 4 times
  // faster than renewing every step (tests/runtime/integrators/test_gauss_legendre.cpp counts
  // them). Shorter chains keep the classic thresholds (Hairer & Wanner's RADAU5: reuse only at θ ≤
  // 1e-3), where factoring is cheap and fewer iterations win.
  bool factoring_dominates() const { return m_dim >= 48; }
  double reuse_limit() const { return factoring_dominates() ? 0.25 : 1e-3; }
  double stale_limit() const { return factoring_dominates() ? 0.25 : 1e-2; }
  double fresh_limit() const { return factoring_dominates() ? 0.5 : 0.1; }
  // What the factored Newton matrix holds: nothing yet; the Jacobian at the start of an
  // earlier step (stale) or of this one (fresh); the Jacobians at this step's stages (full).
  enum class matrix_state { none, stale, fresh, full };

  void init_coefficients() {
    const detail::gauss_legendre_coefficients<Stages> coefficients;
    m_extrapolation = coefficients.extrapolation;
    m_d = coefficients.d;
  }

  void resize(std::size_t d) {
    if (m_dim == d) return;
    m_dim = d;
    const auto n = static_cast<Eigen::Index>(d);
    m_z.setZero(s * n);
    m_dz.resize(s * n);
    m_residual.resize(s * n);
    m_newton.resize(s * n, s * n);
    m_lu = Eigen::PartialPivLU<Eigen::MatrixXd>(s * n);
    m_jac.resize(n, n);
    m_stage_x.assign(d, 0.0);
    m_dfdt.assign(d, 0.0);
    for (auto& f : m_f) f.assign(d, 0.0);
    m_previous_x.assign(d, 0.0);
    m_have_previous = false;
    m_matrix = matrix_state::none;
  }

  // Block column j of the Newton matrix I − h (a_ij J_j): the blocks δ_ij I − h a_ij J for
  // the stages i (J: d × d).
  void set_newton_column(Eigen::MatrixXd& newton, int j, const matrix_type& J, time_type dt) const {
    const auto n = static_cast<Eigen::Index>(m_dim);
    for (int i = 0; i < s; ++i) {
      auto block = newton.block(i * n, j * n, n, n);
      block = (-dt * tableau::a[i][j]) * J;
      if (i == j) block.diagonal().array() += 1.0;
    }
  }

  // Factors the Newton matrix I − h (a_ij J_j) (sd × sd, block (i, j) for stages i, j):
  // `fresh` takes every J_j as the Jacobian at x (simplified Newton), `full` the Jacobian at
  // stage j's current value x + Z_j (Newton).
  template <class System>
  void factor_newton_matrix(System& sys, const state_type& x, time_type t, time_type dt,
                            matrix_state kind) {
    const auto n = static_cast<Eigen::Index>(m_dim);
    for (int j = 0; j < s; ++j) {
      if (kind == matrix_state::full) {
        for (std::size_t k = 0; k < m_dim; ++k)
          m_stage_x[k] = x[k] + m_z[j * n + static_cast<Eigen::Index>(k)];
        sys.second(m_stage_x, m_jac, t + tableau::c[j] * dt, m_dfdt);
        ++m_stats.jacobian_evaluations;
      } else if (j == 0) {
        sys.second(x, m_jac, t, m_dfdt);
        ++m_stats.jacobian_evaluations;
      }
      set_newton_column(m_newton, j, m_jac, dt);
    }
    m_lu.compute(m_newton);
    ++m_stats.factorizations;
    m_matrix = kind;
    m_matrix_dt = dt;
  }

  template <class System>
  void step(System& sys, state_type& x, time_type t, time_type dt) {
    solve_stages(sys, x, t, dt);
    finish_step(x, dt);
  }

  // Solves the stage equations for the step from x at t (m_z holds the converged Z).
  template <class System>
  void solve_stages(System& sys, const state_type& x, time_type t, time_type dt) {
    if (!std::isfinite(dt) || dt == 0)
      throw std::invalid_argument("gauss_legendre: the step dt must be finite and non-zero");
    resize(x.size());
    const auto n = static_cast<Eigen::Index>(m_dim);

    const bool continuing = m_have_previous && dt == m_previous_dt && x == m_previous_x;
    if (continuing) {
      for (int i = 0; i < s; ++i)
        for (Eigen::Index k = 0; k < n; ++k) {
          double z = 0;
          for (int j = 0; j < s; ++j)
            z += m_extrapolation(i, j) * m_f[j][static_cast<std::size_t>(k)];
          m_z[i * n + k] = dt * z;
        }
    } else {
      m_z.setZero();
    }

    // The Newton matrix of an earlier step is kept while iterations with it contract fast
    // (the converged Z does not depend on it, only the speed of getting there).
    if (m_matrix != matrix_state::none && m_matrix_reusable && dt == m_matrix_dt)
      m_matrix = matrix_state::stale;
    else
      factor_newton_matrix(sys, x, t, dt, matrix_state::fresh);
    double x_norm = 0;
    for (double v : x) x_norm = std::max(x_norm, std::fabs(v));

    double previous_norm = 0, theta = 0;
    // The contraction rate while the corrections are well above round-off: near round-off θ
    // measures noise (it ends many a converged iteration at θ ≥ 0.5), not the matrix.
    double contraction = 0;
    int diverging = 0;
    for (int iteration = 1;; ++iteration) {
      ++m_stats.newton_iterations;
      for (int i = 0; i < s; ++i) {
        for (std::size_t k = 0; k < m_dim; ++k)
          m_stage_x[k] = x[k] + m_z[i * n + static_cast<Eigen::Index>(k)];
        sys.first(m_stage_x, m_f[i], t + tableau::c[i] * dt);
      }
      m_stats.rhs_evaluations += s;
      // −G(Z) = h Σ_j a_ij f(x + Z_j) − Z_i
      for (int i = 0; i < s; ++i)
        for (Eigen::Index k = 0; k < n; ++k) {
          double sum = 0;
          for (int j = 0; j < s; ++j) sum += tableau::a[i][j] * m_f[j][static_cast<std::size_t>(k)];
          m_residual[i * n + k] = dt * sum - m_z[i * n + k];
        }
      m_dz.noalias() = m_lu.solve(m_residual);
      m_z += m_dz;

      const double norm = m_dz.template lpNorm<Eigen::Infinity>();
      const double scale = std::max(x_norm, m_z.template lpNorm<Eigen::Infinity>());
      if (!std::isfinite(norm) || !std::isfinite(scale))
        fail(t, dt, iteration, "the stage values became non-finite");
      if (norm == 0) break;
      if (iteration >= 2) {
        theta = norm / previous_norm;
        if (norm > 100 * round_off_level() * scale) contraction = std::max(contraction, theta);
        if (detail::stage_iteration_done(theta, norm, scale, m_tolerance, round_off_level())) break;
        if (norm <= round_off_level() * scale) {
          // At round-off and still shrinking: iterate on with the matrix as it is.
        } else if (m_matrix == matrix_state::stale && theta > stale_limit()) {
          // Too slow: an older matrix is renewed at x, ...
          factor_newton_matrix(sys, x, t, dt, matrix_state::fresh);
        } else if (m_matrix == matrix_state::fresh && theta > fresh_limit()) {
          // ... a fresh one gives way to full Newton.
          m_matrix = matrix_state::full;
          ++m_stats.full_newton_steps;
        } else if (m_matrix == matrix_state::full && theta >= 1 && ++diverging >= 2) {
          // Full Newton that stops shrinking at a tiny correction has reached the rounding of
          // its own matrix: for long chains of light, short links the blocks h A⁻¹ and h ∂ṗ/∂φ
          // differ by many orders (1e6 against 1e-3 for 100 links of 1 cm and 10 g), and the
          // solve's rounding then lies above round_off_level (measured: 8e-14 of the state).
          if (norm <= stalled_level * scale) break;
          fail(t, dt, iteration, "the Newton iteration diverges", norm / scale);
        }
        if (m_matrix == matrix_state::full) factor_newton_matrix(sys, x, t, dt, matrix_state::full);
      }
      if (iteration >= m_max_iterations)
        fail(t, dt, iteration, "the iteration limit was reached", norm / scale);
      previous_norm = norm;
    }
    m_matrix_reusable = m_matrix != matrix_state::full &&
                        (factoring_dominates() ? contraction : theta) <= reuse_limit();
  }

  // x1 = x0 + Σ_i d_i Z_i from the converged stages, and the bookkeeping of a finished step.
  void finish_step(state_type& x, time_type dt) {
    const auto n = static_cast<Eigen::Index>(m_dim);
    for (std::size_t k = 0; k < m_dim; ++k) {
      double increment = 0;
      for (int i = 0; i < s; ++i) increment += m_d(i) * m_z[i * n + static_cast<Eigen::Index>(k)];
      x[k] += increment;
    }
    ++m_stats.steps;
    m_previous_x = x;
    m_previous_dt = dt;
    m_have_previous = true;
  }

  // tangent ← (I + Σ_i d_i ∂Z_i/∂x) tangent, from the converged stages in m_z (see
  // do_step_with_tangent). Its own matrix and factorisation: the stage iteration's Newton
  // matrix, and so the next step, stay exactly as without tangents.
  template <class System, class Derived>
  void map_tangent(System& sys, const state_type& x, time_type t, time_type dt,
                   Eigen::MatrixBase<Derived>& tangent) {
    const auto n = static_cast<Eigen::Index>(m_dim);
    const Eigen::Index k = tangent.cols();
    m_tangent_newton.resize(s * n, s * n);
    m_tangent_rhs.setZero(s * n, k);
    for (int j = 0; j < s; ++j) {
      for (std::size_t e = 0; e < m_dim; ++e)
        m_stage_x[e] = x[e] + m_z[j * n + static_cast<Eigen::Index>(e)];
      sys.second(m_stage_x, m_jac, t + tableau::c[j] * dt, m_dfdt);
      ++m_stats.jacobian_evaluations;
      set_newton_column(m_tangent_newton, j, m_jac, dt);
      // Right-hand side h Σ_j a_ij J_j W, block row i.
      m_tangent_product.noalias() = m_jac * tangent;
      for (int i = 0; i < s; ++i)
        m_tangent_rhs.middleRows(i * n, n) += (dt * tableau::a[i][j]) * m_tangent_product;
    }
    m_tangent_lu.compute(m_tangent_newton);
    ++m_stats.factorizations;
    m_tangent_dz.noalias() = m_tangent_lu.solve(m_tangent_rhs);
    for (int i = 0; i < s; ++i) tangent += m_d(i) * m_tangent_dz.middleRows(i * n, n);
  }

  [[noreturn]] void fail(time_type t, time_type dt, int iteration, const char* why,
                         double relative_correction = std::numeric_limits<double>::quiet_NaN()) {
    m_have_previous = false;
    m_matrix = matrix_state::none;
    std::ostringstream msg;
    msg.precision(6);
    msg << "Gauss-Legendre (order " << order_value << ") step from t = " << t << " with dt = " << dt
        << " failed: " << why << " (Newton iteration " << iteration;
    if (!std::isnan(relative_correction))
      msg << ", last correction " << relative_correction << " of the state";
    msg << "); try a smaller dt";
    throw integration_error(msg.str(), t);
  }

  double m_tolerance;
  int m_max_iterations;
  Eigen::Matrix<double, s, s> m_extrapolation;
  Eigen::Matrix<double, 1, s> m_d;

  std::size_t m_dim = 0;
  Eigen::VectorXd m_z, m_dz, m_residual;
  Eigen::MatrixXd m_newton;
  Eigen::PartialPivLU<Eigen::MatrixXd> m_lu;
  matrix_type m_jac;
  state_type m_stage_x, m_dfdt;
  std::array<deriv_type, s> m_f;
  // do_step_with_tangent's work space.
  Eigen::MatrixXd m_tangent_newton, m_tangent_rhs, m_tangent_dz, m_tangent_product;
  Eigen::PartialPivLU<Eigen::MatrixXd> m_tangent_lu;

  matrix_state m_matrix = matrix_state::none;
  time_type m_matrix_dt = 0;
  bool m_matrix_reusable = false;

  bool m_have_previous = false;
  state_type m_previous_x;
  time_type m_previous_dt = 0;
  gauss_legendre_statistics m_stats;
};

/// Two stages, order 4.
using gauss_legendre4 = gauss_legendre<2>;
/// Three stages, order 6.
using gauss_legendre6 = gauss_legendre<3>;

}  // namespace npend
