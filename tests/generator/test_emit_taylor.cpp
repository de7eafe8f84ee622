// The Taylor kernels the generator emitted (generated/taylor_<model>_<n>.cpp, compiled in
// npend_generated) against an independent computation of the same series: the generator's
// GiNaC derivation (mass matrix, potential, generalised forces) turned into Hamilton's
// equations here, and their solution expanded by Picard iteration on truncated power series
// in 40-digit arithmetic. Nothing of the emitter's expression graph is used for the
// reference, so a wrong recurrence, a wrong node order or a wrong input row shows.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include "chain_functions.hpp"
#include "chain_model.hpp"
#include "emit_cpp.hpp"
#include "emit_taylor.hpp"
#include "lagrangian.hpp"
#include "taylor_cart_1.hpp"
#include "taylor_chain_2.hpp"
#include "taylor_chain_3.hpp"
#include "taylor_physical_2.hpp"

namespace emit_taylor_test {

using namespace npend::gen;
using GiNaC::ex;
using GiNaC::numeric;

namespace {

std::size_t u(int i) { return static_cast<std::size_t>(i); }

constexpr int order = 8;  // the coefficients compared: τ^0 .. τ^8

// A number given exactly, so that GiNaC and both kernel types start from the same value to
// within the kernel type's rounding of num/den.
struct exact_value {
  long num, den = 1;
  numeric exact() const { return {num, den}; }
  template <class T>
  T as() const {
    return T(num) / T(den);
  }
};

// The exact rational value of a long double (a double converts to it without rounding):
// CLN would round a mixed double/long-float operation to double, so the comparison is done
// on exact values.
numeric exact_of(long double v) {
  if (v == 0) return 0;
  int e = 0;
  const long double mantissa = std::frexp(std::fabs(v), &e);  // in [1/2, 1)
  const auto bits = static_cast<unsigned long>(std::ldexp(mantissa, 64));
  const numeric out = numeric(bits) * numeric(2).power(e - 64);
  return v < 0 ? -out : out;
}

// The polynomial e in t, expanded, with the powers above t^degree dropped.
ex truncated(const ex& e, const GiNaC::realsymbol& t, int degree) {
  const ex x = e.expand();
  ex out = 0;
  for (int j = 0; j <= degree; ++j) out += x.coeff(t, j) * GiNaC::pow(t, j);
  return out;
}

// GiNaC's floating-point precision in decimal digits while it lives (a global of GiNaC).
class digits {
 public:
  explicit digits(long count) : m_saved(GiNaC::Digits) { GiNaC::Digits = count; }
  ~digits() { GiNaC::Digits = m_saved; }
  digits(const digits&) = delete;
  digits& operator=(const digits&) = delete;

 private:
  long m_saved;
};

// One model at one point: the generator's mechanics, the parameters (in the kernels' layout
// order), the inputs' series w_j(t) = Σ_{k<order} w_j[k] t^k (input_symbols order) and the
// state x0 = [q, p].
struct model_point {
  chain_symbols sym;
  chain_mechanics mech;
  std::vector<exact_value> params;
  std::vector<std::vector<numeric>> inputs;
  std::vector<exact_value> state;
};

// The parameter symbols in the kernels' layout (chain_layout / cart_layout).
std::vector<GiNaC::realsymbol> parameter_symbols(const chain_symbols& sym) {
  std::vector<GiNaC::realsymbol> out(sym.mass.begin(), sym.mass.end());
  out.insert(out.end(), sym.length.begin(), sym.length.end());
  out.push_back(sym.g);
  if (has_rigid_links(sym.kind)) {
    out.insert(out.end(), sym.com.begin(), sym.com.end());
    out.insert(out.end(), sym.inertia.begin(), sym.inertia.end());
  }
  if (has_joint_forces(sym.kind)) {
    out.insert(out.end(), sym.stiffness.begin(), sym.stiffness.end());
    out.insert(out.end(), sym.rest_angle.begin(), sym.rest_angle.end());
    out.insert(out.end(), sym.damping.begin(), sym.damping.end());
  }
  if (on_cart(sym.kind)) {
    out.push_back(sym.cart_mass);
    out.push_back(sym.cart_damping);
  }
  return out;
}

// The reference: coefficients x_i^[k] (row i, k = 0..order) of the solution of Hamilton's
// equations through x0,
//   q̇ = v = A(q)⁻¹ p,   ṗ_k = ½ vᵀ (∂A/∂q_k) v − ∂V/∂q_k + Q_k(q̇ = v, w),
// (−∂H/∂q_k of H = ½ pᵀA⁻¹p + V, plus the generalised forces of damping and inputs), by
// Picard iteration x_{m+1}(t) = x0 + ∫_0^t f(x_m(s), s) ds: x_m is exact to degree m, so
// f(x_m) is kept to degree m and `order` iterations give degree `order`. sin and cos of an
// angle's series are GiNaC's series; A(t)⁻¹ p(t) is solved order by order with the numeric
// matrices A(t) = Σ A_j t^j: A_0 v_k = p_k − Σ_{j=1..k} A_j v_{k−j} (no symbolic inverse).
std::vector<std::vector<numeric>> picard_coefficients(const model_point& point) {
  const chain_symbols& sym = point.sym;
  const chain_mechanics& mech = point.mech;
  const coordinates& q = sym.coords;
  const int N = q.size();
  const GiNaC::realsymbol t("t");
  const digits precision(40);

  GiNaC::exmap values;
  const std::vector<GiNaC::realsymbol> params = parameter_symbols(sym);
  REQUIRE(params.size() == point.params.size());
  for (std::size_t i = 0; i < params.size(); ++i) values[params[i]] = point.params[i].exact();
  const std::vector<GiNaC::realsymbol> w = input_symbols(sym);
  REQUIRE(w.size() == point.inputs.size());
  for (std::size_t j = 0; j < w.size(); ++j) {
    ex series = 0;
    for (int k = 0; k < order; ++k) series += point.inputs[j][u(k)] * GiNaC::pow(t, k);
    values[w[j]] = series;
  }

  // sin q_i and cos q_i become symbols first: GiNaC substitutes inside a function's argument
  // before it matches the function, so sin q_i would not be found once q_i is a series.
  std::vector<GiNaC::realsymbol> sines, cosines;
  for (int i = 0; i < N; ++i) {
    sines.emplace_back("S" + std::to_string(i));
    cosines.emplace_back("C" + std::to_string(i));
    values[GiNaC::sin(q.q[u(i)])] = sines.back();
    values[GiNaC::cos(q.q[u(i)])] = cosines.back();
  }

  // The equations' pieces with the parameters and inputs in: functions of q, q̇ (Q) and t.
  const std::vector<GiNaC::matrix> dA = mass_matrix_derivatives(q, mech);
  std::vector<ex> A, dA_entries, grad_V, force;
  for (int i = 0; i < N; ++i)
    for (int j = 0; j < N; ++j) A.push_back(mech.mass_matrix(u(i), u(j)).subs(values));
  for (int k = 0; k < N; ++k)
    for (int i = 0; i < N; ++i)
      for (int j = 0; j < N; ++j) dA_entries.push_back(dA[u(k)](u(i), u(j)).subs(values));
  for (int k = 0; k < N; ++k) {
    grad_V.push_back(mech.grad_potential[u(k)].subs(values));
    force.push_back(mech.force[u(k)].subs(values));
  }

  std::vector<ex> x(u(2 * N));
  for (int i = 0; i < 2 * N; ++i) x[u(i)] = point.state[u(i)].exact();
  for (int m = 0; m < order; ++m) {
    // q_i, sin q_i, cos q_i and p_i as series in t, to degree m.
    GiNaC::exmap at;
    for (int i = 0; i < N; ++i) {
      const ex qi = x[u(i)];
      at[sines[u(i)]] = GiNaC::series_to_poly(GiNaC::sin(qi).series(t == 0, m + 1)).evalf();
      at[cosines[u(i)]] = GiNaC::series_to_poly(GiNaC::cos(qi).series(t == 0, m + 1)).evalf();
      at[q.q[u(i)]] = qi;
      at[q.p[u(i)]] = x[u(N + i)];
    }
    const auto of_state = [&](const ex& e) {
      const ex s = truncated(e.subs(at), t, m);
      REQUIRE_FALSE(s.has(GiNaC::sin(GiNaC::wild())));
      REQUIRE_FALSE(s.has(GiNaC::cos(GiNaC::wild())));
      return s;
    };

    // v = A⁻¹ p, order by order.
    std::vector<GiNaC::matrix> A_j(u(m + 1), GiNaC::matrix(u(N), u(N)));
    for (int i = 0; i < N; ++i)
      for (int j = 0; j < N; ++j) {
        const ex entry = of_state(A[u(i * N + j)]);
        for (int d = 0; d <= m; ++d) A_j[u(d)](u(i), u(j)) = entry.coeff(t, d).evalf();
      }
    const GiNaC::matrix A0_inverse = A_j[0].inverse();
    std::vector<GiNaC::matrix> v_j;
    for (int d = 0; d <= m; ++d) {
      GiNaC::matrix rhs(u(N), 1);
      for (int i = 0; i < N; ++i) rhs(u(i), 0) = x[u(N + i)].expand().coeff(t, d);
      for (int j = 1; j <= d; ++j) rhs = rhs.sub(A_j[u(j)].mul(v_j[u(d - j)]));
      v_j.push_back(A0_inverse.mul(rhs));
    }
    std::vector<ex> v(u(N), 0);
    for (int i = 0; i < N; ++i)
      for (int d = 0; d <= m; ++d) v[u(i)] += v_j[u(d)](u(i), 0) * GiNaC::pow(t, d);

    // f = [v, −∂H/∂q + Q].
    std::vector<ex> f(v);
    GiNaC::exmap rates;
    for (int i = 0; i < N; ++i) rates[q.dq[u(i)]] = v[u(i)];
    for (int k = 0; k < N; ++k) {
      ex pdot = -of_state(grad_V[u(k)]) + of_state(force[u(k)].subs(rates));
      for (int i = 0; i < N; ++i)
        for (int j = 0; j < N; ++j)
          pdot += v[u(i)] * of_state(dA_entries[u((k * N + i) * N + j)]) * v[u(j)] / 2;
      f.push_back(truncated(pdot, t, m));
    }

    // x_{m+1} = x0 + ∫ f.
    for (int i = 0; i < 2 * N; ++i) {
      const ex fi = truncated(f[u(i)], t, m);
      ex next = point.state[u(i)].exact();
      for (int d = 0; d <= m; ++d) next += fi.coeff(t, d) * GiNaC::pow(t, d + 1) / (d + 1);
      x[u(i)] = next.evalf();
    }
  }

  std::vector<std::vector<numeric>> out(u(2 * N));
  for (int i = 0; i < 2 * N; ++i)
    for (int k = 0; k <= order; ++k)
      out[u(i)].push_back(GiNaC::ex_to<numeric>(x[u(i)].expand().coeff(t, k).evalf()));
  return out;
}

// The kernel's coefficients in T, from the same parameters, inputs and state.
template <class T, class Kernel>
std::vector<std::vector<T>> kernel_coefficients(const model_point& point, int work_slots,
                                                Kernel coefficients) {
  const int P = order + 1;
  std::vector<T> params, inputs(point.inputs.size() * u(P), T(0));
  for (const exact_value& value : point.params) params.push_back(value.as<T>());
  for (std::size_t j = 0; j < point.inputs.size(); ++j)
    for (int k = 0; k < order; ++k) {
      const numeric& c = point.inputs[j][u(k)];
      inputs[j * u(P) + u(k)] = exact_value{c.numer().to_long(), c.denom().to_long()}.as<T>();
    }
  const std::size_t rows = point.state.size();
  std::vector<T> series(rows * u(P), T(0)), work(u(work_slots * P));
  for (std::size_t i = 0; i < rows; ++i) series[i * u(P)] = point.state[i].as<T>();
  coefficients(params.data(), inputs.data(), order, series.data(), work.data());
  std::vector<std::vector<T>> out(rows);
  for (std::size_t i = 0; i < rows; ++i)
    out[i].assign(series.begin() + static_cast<long>(i * u(P)),
                  series.begin() + static_cast<long>((i + 1) * u(P)));
  return out;
}

// The largest relative difference between the kernel's and the reference coefficients of
// orders 1..order. Each coefficient is measured against itself, or against a hundredth of
// the largest of its order where it is smaller: a coefficient near zero carries the
// rounding of its order's large terms.
template <class T>
double largest_relative_difference(const std::vector<std::vector<T>>& kernel,
                                   const std::vector<std::vector<numeric>>& reference) {
  REQUIRE(kernel.size() == reference.size());
  double worst = 0;
  for (int k = 1; k <= order; ++k) {
    numeric scale = 0;
    for (const auto& row : reference) scale = std::max(scale, GiNaC::abs(row[u(k)]));
    REQUIRE(scale.is_positive());
    for (std::size_t i = 0; i < reference.size(); ++i) {
      const numeric ref = reference[i][u(k)];
      const numeric denominator = std::max(GiNaC::abs(ref), scale / numeric(100));
      const numeric difference = GiNaC::abs(exact_of(kernel[i][u(k)]) - ref) / denominator;
      worst = std::max(worst, difference.to_double());
    }
  }
  return worst;
}

// Checks `point`'s kernel in double and long double against the Picard reference;
// `coefficients` is callable with the pointers of either type.
// Both within 1000 ε of their type (2.2e-13 in double, 1.1e-16 in an x87 long double):
// a coefficient of order 8 sums a few hundred rounded products, and one near a hundredth of
// its order's largest coefficient is measured against that scale.
template <class Kernel>
void check_kernel(const model_point& point, int work_slots, Kernel coefficients) {
  const std::vector<std::vector<numeric>> reference = picard_coefficients(point);
  const auto in_double = kernel_coefficients<double>(point, work_slots, coefficients);
  const auto in_long = kernel_coefficients<long double>(point, work_slots, coefficients);
  const double double_difference = largest_relative_difference(in_double, reference);
  const double long_difference = largest_relative_difference(in_long, reference);
  MESSAGE(std::string(link_kind_name(point.sym.kind)), " n = ", point.sym.n,
          ": largest relative difference, double ", double_difference, ", long double ",
          long_difference);
  CHECK(double_difference < 1000 * std::numeric_limits<double>::epsilon());
  CHECK(long_difference < 1000 * std::numeric_limits<long double>::epsilon());
}

// The Taylor coefficients a w² (−1)^{k/2} w^k / k! of a w² cos(w t) (even k) and
// a w² (−1)^{(k−1)/2} w^k / k! of a w² sin(w t) (odd k), k < order.
std::vector<numeric> harmonic(const numeric& a, const numeric& w, bool sine) {
  std::vector<numeric> out;
  numeric term = a * w * w;  // a w² w^k / k!
  for (int k = 0; k < order; ++k) {
    const bool present = (k % 2 == 1) == sine;
    const int sign = ((sine ? k - 1 : k) / 2) % 2 == 0 ? 1 : -1;
    out.push_back(present ? numeric(sign) * term : numeric(0));
    term = term * w / (k + 1);
  }
  return out;
}

}  // namespace

TEST_CASE("taylor kernels: coefficients equal GiNaC's series of the solution, n = 2 and 3") {
  // Unequal masses and lengths, angles away from any symmetry, momenta of both signs.
  for (const int n : {2, 3}) {
    INFO("n = ", n);
    model_point point{chain_symbols(n), {}, {}, {}, {}};
    point.mech = derive_mechanics(point.sym);
    const std::vector<exact_value> masses{{13, 10}, {7, 10}, {9, 10}};
    const std::vector<exact_value> lengths{{11, 10}, {6, 10}, {85, 100}};
    const std::vector<exact_value> angles{{7, 10}, {-4, 10}, {11, 10}};
    const std::vector<exact_value> momenta{{3, 10}, {-5, 10}, {2, 10}};
    for (const auto* values : {&masses, &lengths})
      point.params.insert(point.params.end(), values->begin(), values->begin() + n);
    point.params.push_back({981, 100});
    point.state.assign(angles.begin(), angles.begin() + n);
    point.state.insert(point.state.end(), momenta.begin(), momenta.begin() + n);
    if (n == 2)
      check_kernel(point, npend::generated::taylor_chain_2::work_slots,
                   [](auto... a) { npend::generated::taylor_chain_2::coefficients(a...); });
    else
      check_kernel(point, npend::generated::taylor_chain_3::work_slots,
                   [](auto... a) { npend::generated::taylor_chain_3::coefficients(a...); });
  }
}

TEST_CASE("taylor kernels: the physical chain's coefficients on a moving pivot, n = 2") {
  // Rigid links (c ≠ l, J > 0), joint springs with rest angles, joint damping, motor torques
  // (constant and linear in t), and a pivot that moves on an ellipse: a = (a_x, a_y) =
  // a w² (sin w t, cos w t).
  model_point point{chain_symbols(2, link_kind::physical), {}, {}, {}, {}};
  point.mech = derive_mechanics(point.sym);
  // [m_1, m_2, l_1, l_2, g, c_1, c_2, J_1, J_2, k_1, k_2, θ⁰_1, θ⁰_2, b_1, b_2]
  point.params = {{5, 4},  {3, 4}, {1},    {4, 5},  {981, 100}, {11, 20}, {7, 20}, {9, 100},
                  {1, 25}, {5, 2}, {3, 2}, {1, 10}, {-1, 5},    {3, 10},  {3, 20}};
  const numeric a(1, 8), w(3, 2);
  point.inputs = {harmonic(a, w, true), harmonic(numeric(3) * a, w, false),
                  std::vector<numeric>(order, 0), std::vector<numeric>(order, 0)};
  point.inputs[2][0] = numeric(1, 4);
  point.inputs[3][0] = numeric(-1, 2);
  point.inputs[3][1] = numeric(1, 8);
  point.state = {{7, 10}, {-4, 10}, {35, 100}, {-6, 10}};
  check_kernel(point, npend::generated::taylor_physical_2::work_slots,
               [](auto... a) { npend::generated::taylor_physical_2::coefficients(a...); });
}

TEST_CASE("taylor kernels: the cart's coefficients under a force and a torque, n = 1") {
  // The cart's coordinate x is cyclic; its force F(t) = 1/2 − t/4 and the cart's damping
  // make its momentum vary.
  model_point point{chain_symbols(1, link_kind::cart), {}, {}, {}, {}};
  point.mech = derive_mechanics(point.sym);
  // [m, l, g, c, J, k, θ⁰, b, M, b_x]
  point.params = {{5, 4}, {1},     {981, 100}, {11, 20}, {9, 100},
                  {5, 2}, {1, 10}, {3, 10},    {2},      {1, 5}};
  point.inputs = {std::vector<numeric>(order, 0), std::vector<numeric>(order, 0)};
  point.inputs[0][0] = numeric(1, 2);
  point.inputs[0][1] = numeric(-1, 4);
  point.inputs[1][0] = numeric(3, 10);
  point.state = {{1, 5}, {7, 10}, {-3, 10}, {45, 100}};
  check_kernel(point, npend::generated::taylor_cart_1::work_slots,
               [](auto... a) { npend::generated::taylor_cart_1::coefficients(a...); });
}

namespace {

// Whether node id reads the state or the time-dependent inputs (a series in the kernel).
bool varies(const expr_graph& g, int id) {
  const node& nd = g.at(id);
  if (nd.kind == op::constant) return false;
  if (nd.kind == op::input) {
    switch (nd.input) {
      case input_kind::phi:
      case input_kind::p:
      case input_kind::drive:
      case input_kind::torque:
      case input_kind::cart_position:
      case input_kind::cart_momentum:
      case input_kind::cart_force:
        return true;
      default:
        return false;
    }
  }
  return (nd.lhs >= 0 && varies(g, nd.lhs)) || (nd.rhs >= 0 && varies(g, nd.rhs));
}

std::size_t occurrences(const std::string& text, const std::string& word) {
  std::size_t count = 0;
  for (auto at = text.find(word); at != std::string::npos; at = text.find(word, at + 1)) ++count;
  return count;
}

chain_sources emitted(const chain_symbols& sym, std::set<int>* arguments = nullptr) {
  const chain_mechanics mech = derive_mechanics(sym);
  const std::vector<emitted_function> functions =
      build_chain_functions(sym, mech, default_solver(sym));
  const auto rhs = std::find_if(functions.begin(), functions.end(),
                                [](const emitted_function& f) { return f.name == "rhs"; });
  REQUIRE(rhs != functions.end());
  if (arguments)
    for (const int id : evaluation_order(*rhs->graph, rhs->outputs)) {
      const node& nd = rhs->graph->at(id);
      if ((nd.kind == op::sin || nd.kind == op::cos) && varies(*rhs->graph, nd.lhs))
        arguments->insert(nd.lhs);
    }
  return emit_taylor(sym.n, *rhs, "", sym.kind);
}

}  // namespace

TEST_CASE("emit_taylor: the same text twice, and every sin/cos pair one recurrence") {
  for (const link_kind kind : {link_kind::point_mass, link_kind::physical, link_kind::cart}) {
    for (const int n : {2, 3}) {
      INFO(link_kind_name(kind), " n = ", n);
      // Two derivations, so GiNaC's term order (seeded by addresses) differs between them.
      std::set<int> arguments;
      const chain_sources first = emitted(chain_symbols(n, kind), &arguments);
      const chain_sources second = emitted(chain_symbols(n, kind));
      CHECK(first.header == second.header);
      CHECK(first.source == second.source);
      REQUIRE_FALSE(arguments.empty());
      CHECK(occurrences(first.source, "taylor::sin_cos(") == arguments.size());
    }
  }
}

}  // namespace emit_taylor_test
