#include "npend/analysis/chaos_map.hpp"

#include <fmt/format.h>

#include <array>
#include <boost/numeric/odeint/stepper/runge_kutta4.hpp>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "npend/chain_system.hpp"
#include "npend/integration_error.hpp"

namespace npend {

namespace {

void require_conservative(const chain& c, const char* what) {
  if (!c.parameters().is_conservative())
    throw std::invalid_argument(
        fmt::format("{}: the chain must conserve its energy (no damping, a fixed pivot)", what));
}

// G_k = m_k c_k + l_k μ_{k+1}.
std::vector<double> gravity_moments(const chain_parameters& p) {
  const std::size_t n = p.masses.size();
  std::vector<double> g(n);
  double below = 0;
  for (std::size_t k = n; k-- > 0;) {
    const double reach = p.com.empty() ? p.lengths[k] : p.com[k];
    g[k] = p.masses[k] * reach + p.lengths[k] * below;
    below += p.masses[k];
  }
  return g;
}

}  // namespace

bool energy_forbids_flip(const chain& c, std::span<const double> x0, int link) {
  require_conservative(c, "flip");
  const int n = c.links();
  if (link < 0 || link > n)
    throw std::invalid_argument(
        fmt::format("flip: the arm must be 1..{} (or 0: any), got {}", n, link));
  for (const double k : c.parameters().stiffness)
    if (k != 0) throw std::invalid_argument("flip: joint springs change the energy needed to flip");
  const auto moments = gravity_moments(c.parameters());
  double needed = std::numeric_limits<double>::infinity();
  for (int k = 1; k <= n; ++k)
    if (link == 0 || link == k)
      needed = std::min(needed, 2 * c.parameters().g * moments[static_cast<std::size_t>(k - 1)]);
  return c.hamiltonian(x0) < needed;
}

double flip_time(const chain& c, std::span<const double> x0, const flip_options& o) {
  const auto n = static_cast<std::size_t>(c.links());
  if (x0.size() != 2 * n)
    throw std::invalid_argument(
        fmt::format("flip: the {}-link chain needs a state of {}, got {}", n, 2 * n, x0.size()));
  if (!(o.dt > 0) || !(o.t_end >= o.dt) || !std::isfinite(o.t_end))
    throw std::invalid_argument(
        fmt::format("flip: need 0 < dt <= t_end, got dt = {}, t_end = {}", o.dt, o.t_end));
  const double inf = std::numeric_limits<double>::infinity();
  if (energy_forbids_flip(c, x0, o.link)) return inf;
  const auto flipped = [&](const std::vector<double>& x) {
    for (std::size_t k = 0; k < n; ++k)
      if ((o.link == 0 || static_cast<std::size_t>(o.link) == k + 1) &&
          std::fabs(x[k]) >= std::numbers::pi)
        return true;
    return false;
  };
  std::vector<double> x(x0.begin(), x0.end());
  if (flipped(x)) return 0;
  boost::numeric::odeint::runge_kutta4<std::vector<double>> stepper;
  const chain_system system(c);
  const auto steps = static_cast<long long>(std::floor(o.t_end / o.dt + 1e-9));
  for (long long k = 1; k <= steps; ++k) {
    stepper.do_step(system, x, static_cast<double>(k - 1) * o.dt, o.dt);
    if (flipped(x)) return static_cast<double>(k) * o.dt;
    if (!std::isfinite(x[0]))
      throw integration_error(
          fmt::format("flip: the state became non-finite at t = {}; try a smaller dt",
                      static_cast<double>(k) * o.dt),
          static_cast<double>(k) * o.dt);
  }
  return inf;
}

namespace {

constexpr std::array all_map_quantities{map_quantity::flip, map_quantity::lyapunov,
                                        map_quantity::fli,  map_quantity::megno,
                                        map_quantity::sali, map_quantity::gali};

}  // namespace

std::string_view map_quantity_name(map_quantity quantity) {
  switch (quantity) {
    case map_quantity::flip:
      return "flip";
    case map_quantity::lyapunov:
      return "lyapunov";
    case map_quantity::fli:
      return "fli";
    case map_quantity::megno:
      return "megno";
    case map_quantity::sali:
      return "sali";
    case map_quantity::gali:
      return "gali";
  }
  return "?";
}

map_quantity parse_map_quantity(std::string_view name) {
  for (const auto q : all_map_quantities)
    if (name == map_quantity_name(q)) return q;
  throw std::invalid_argument(
      fmt::format("quantity: one of flip, lyapunov, fli, megno, sali, gali, got '{}'", name));
}

namespace {

// What a Lyapunov map integrates: rk4 at dt, one tangent vector.
lyapunov_options map_lyapunov_options(const map_cell_options& o) {
  lyapunov_options lo;
  lo.integration.stepper = stepper_kind::rk4;
  lo.integration.t_end = o.t_end;
  lo.integration.dt = o.dt;
  return lo;
}

// FLI, MEGNO, SALI or GALI_k at t_end: as many deviation vectors as the quantity needs.
double indicator_cell(const chain& c, std::span<const double> x0, const map_cell_options& o) {
  chaos_indicator_options io;
  io.t_end = o.t_end;
  io.dt = o.dt;
  const int k = o.gali_order == 0 ? c.links() + 1 : o.gali_order;
  io.vectors = o.quantity == map_quantity::gali ? static_cast<std::size_t>(k) : 2;
  const auto last = chaos_indicators(c, x0, io).last;
  switch (o.quantity) {
    case map_quantity::fli:
      return last.fli;
    case map_quantity::megno:
      return last.mean_megno;
    case map_quantity::sali:
      return last.sali;
    default:
      return last.gali.back();
  }
}

}  // namespace

void map_cell_options::validate(const chain& c) const {
  if (!(dt > 0) || !(t_end >= dt) || !std::isfinite(t_end))
    throw std::invalid_argument(fmt::format("{}: need 0 < dt <= t_end, got dt = {}, t_end = {}",
                                            map_quantity_name(quantity), dt, t_end));
  if (quantity == map_quantity::flip) {
    energy_forbids_flip(c, std::vector<double>(static_cast<std::size_t>(c.state_size()), 0.0),
                        flip_link);
  } else if (quantity == map_quantity::lyapunov) {
    const auto lo = map_lyapunov_options(*this);
    lo.validate();
    lo.integration.validate();
  } else if (quantity == map_quantity::gali) {
    const int k = gali_order == 0 ? c.links() + 1 : gali_order;
    if (k < 2 || k > c.state_size())
      throw std::invalid_argument(fmt::format(
          "gali: the order k of GALI_k must be 2..{} (2n) for the {}-link chain, got {}",
          c.state_size(), c.links(), gali_order));
  }
}

double map_cell(const chain& c, std::span<const double> x0, const map_cell_options& options) {
  try {
    if (options.quantity == map_quantity::flip)
      return flip_time(c, x0, {options.t_end, options.dt, options.flip_link});
    if (options.quantity == map_quantity::lyapunov)
      return maximal_lyapunov_exponent(c, x0, map_lyapunov_options(options)).exponents.front();
    return indicator_cell(c, x0, options);
  } catch (const integration_error&) {
    return std::numeric_limits<double>::quiet_NaN();
  }
}

double grid_value(double from, double to, int count, int i) {
  return count == 1 ? from : from + (to - from) * static_cast<double>(i) / (count - 1);
}

}  // namespace npend
