// Compiled as C++17: see detail/rosenbrock4_dense_output.hpp.
#include "npend/integrators/detail/rosenbrock4_dense_output.hpp"

#include <algorithm>
#include <boost/numeric/odeint/stepper/generation.hpp>
#include <boost/numeric/odeint/stepper/rosenbrock4.hpp>
#include <boost/numeric/odeint/stepper/rosenbrock4_controller.hpp>
#include <boost/numeric/odeint/stepper/rosenbrock4_dense_output.hpp>
#include <memory>
#include <utility>

namespace npend::detail {

namespace {

namespace odeint = boost::numeric::odeint;
using ublas_vector = boost::numeric::ublas::vector<double>;
using ublas_matrix = boost::numeric::ublas::matrix<double>;  // row-major

// The (rhs, jacobian) pair in the form rosenbrock4 calls it, made autonomous: the state
// carries the time as its last entry τ (τ̇ = 1), and ∂f/∂t becomes the Jacobian's last
// column. odeint's rosenbrock4 (Boost 1.74) converges only to first order when it is handed
// ∂f/∂t for a time-dependent system (measured on ẋ = −x + 30 sin 25t: its error falls
// tenfold per tenfold more steps); on the autonomous form it keeps its order 4.
struct rhs_adapter {
  const rosenbrock4_dense_output::rhs_function* f;
  void operator()(const ublas_vector& x, ublas_vector& dxdt, double /*t*/) const {
    const std::size_t d = x.size() - 1;
    (*f)(&x[0], &dxdt[0], x[d]);
    dxdt[d] = 1.0;
  }
};

struct jacobian_adapter {
  const rosenbrock4_dense_output::jacobian_function* f;
  std::shared_ptr<std::vector<double>> work;  // the d × d block and ∂f/∂t
  void operator()(const ublas_vector& x, ublas_matrix& J, double /*t*/, ublas_vector& dfdt) const {
    const std::size_t d = x.size() - 1;
    std::vector<double>& w = *work;
    w.resize(d * d + d);
    (*f)(&x[0], w.data(), x[d], w.data() + d * d);
    for (std::size_t i = 0; i < d; ++i) {
      for (std::size_t j = 0; j < d; ++j) J(i, j) = w[i * d + j];
      J(i, d) = w[d * d + i];
    }
    for (std::size_t j = 0; j <= d; ++j) J(d, j) = 0.0;
    std::fill(dfdt.begin(), dfdt.end(), 0.0);
  }
};

using dense_stepper =
    odeint::rosenbrock4_dense_output<odeint::rosenbrock4_controller<odeint::rosenbrock4<double>>>;

}  // namespace

struct rosenbrock4_dense_output::impl {
  impl(std::size_t dim, double abs_tol, double rel_tol, rhs_function rhs_f, jacobian_function jac_f)
      : rhs(std::move(rhs_f)),
        jacobian(std::move(jac_f)),
        stepper(odeint::make_dense_output(abs_tol, rel_tol, odeint::rosenbrock4<double>())),
        state(dim),
        scratch(dim + 1) {}

  rhs_function rhs;
  jacobian_function jacobian;
  dense_stepper stepper;
  std::vector<double> state;
  ublas_vector scratch;

  std::shared_ptr<std::vector<double>> work = std::make_shared<std::vector<double>>();

  std::pair<rhs_adapter, jacobian_adapter> system() const {
    return {rhs_adapter{&rhs}, jacobian_adapter{&jacobian, work}};
  }
};

rosenbrock4_dense_output::rosenbrock4_dense_output(std::size_t dim, double abs_tol, double rel_tol,
                                                   rhs_function rhs, jacobian_function jacobian)
    : m_impl(std::make_unique<impl>(dim, abs_tol, rel_tol, std::move(rhs), std::move(jacobian))) {}

rosenbrock4_dense_output::~rosenbrock4_dense_output() = default;
rosenbrock4_dense_output::rosenbrock4_dense_output(rosenbrock4_dense_output&&) noexcept = default;
rosenbrock4_dense_output& rosenbrock4_dense_output::operator=(rosenbrock4_dense_output&&) noexcept =
    default;

void rosenbrock4_dense_output::initialize(const std::vector<double>& x0, double t0, double dt0) {
  std::copy(x0.begin(), x0.end(), m_impl->scratch.begin());
  m_impl->scratch[x0.size()] = t0;
  m_impl->stepper.initialize(m_impl->scratch, t0, dt0);
  m_impl->state = x0;
}

void rosenbrock4_dense_output::step() {
  m_impl->stepper.do_step(m_impl->system());
  const ublas_vector& x = m_impl->stepper.current_state();
  std::copy(x.begin(), x.end() - 1, m_impl->state.begin());
}

double rosenbrock4_dense_output::current_time() const { return m_impl->stepper.current_time(); }

double rosenbrock4_dense_output::current_time_step() const {
  return m_impl->stepper.current_time_step();
}

const std::vector<double>& rosenbrock4_dense_output::current_state() const { return m_impl->state; }

void rosenbrock4_dense_output::calc_state(double t, std::vector<double>& x) const {
  m_impl->stepper.calc_state(t, m_impl->scratch);
  std::copy(m_impl->scratch.begin(), m_impl->scratch.end() - 1, x.begin());
}

}  // namespace npend::detail
