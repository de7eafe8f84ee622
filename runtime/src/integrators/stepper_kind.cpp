#include "npend/integrators/stepper_kind.hpp"

#include <array>
#include <stdexcept>

namespace npend {

namespace {

struct stepper_info {
  stepper_kind kind;
  std::string_view name;
  std::string_view description;
  bool adaptive;
  bool in_map_lanes;  // the batch lanes of a map implement it
  bool variational;   // its tangent map needs no second derivatives of f
  bool any_system;    // it integrates a system given as functions, not only a chain's kernels
  bool monodromy;     // floquet_analysis carries the monodromy matrix over a period on it
  bool indicators;    // chaos_indicators runs it
};

constexpr std::array<stepper_info, 8> infos{{
    {stepper_kind::rk4, "rk4", "classic Runge-Kutta 4, fixed step (the paper's method)", false,
     true, true, true, false, true},
    {stepper_kind::dopri5, "dopri5", "Dormand-Prince 5(4), adaptive, dense output", true, true,
     true, true, false, false},
    {stepper_kind::rkf78, "rkf78", "Runge-Kutta-Fehlberg 7(8), adaptive", true, false, true, true,
     false, false},
    {stepper_kind::bulirsch_stoer, "bs", "Bulirsch-Stoer extrapolation, adaptive, dense output",
     true, false, true, true, false, false},
    {stepper_kind::rosenbrock4, "rosenbrock4",
     "Rosenbrock 4 with the exact Jacobian, adaptive, dense output", true, false, false, true,
     false, false},
    {stepper_kind::gauss4, "gauss4",
     "implicit Gauss-Legendre, 2 stages, order 4, fixed step, symplectic", false, true, true, true,
     false, false},
    {stepper_kind::gauss6, "gauss6",
     "implicit Gauss-Legendre, 3 stages, order 6, fixed step, symplectic", false, true, true, true,
     true, false},
    {stepper_kind::taylor, "taylor",
     "Taylor's method, adaptive order and step, on the generated recurrences, dense output", true,
     false, true, false, true, true},
}};

constexpr auto kinds = [] {
  std::array<stepper_kind, infos.size()> out{};
  for (std::size_t i = 0; i < infos.size(); ++i) out[i] = infos[i].kind;
  return out;
}();

const stepper_info& info(stepper_kind kind) {
  for (const auto& i : infos)
    if (i.kind == kind) return i;
  throw std::invalid_argument("unknown stepper_kind value");
}

}  // namespace

std::span<const stepper_kind> all_stepper_kinds() { return kinds; }

std::string_view stepper_name(stepper_kind kind) { return info(kind).name; }

std::string_view stepper_description(stepper_kind kind) { return info(kind).description; }

bool is_adaptive(stepper_kind kind) { return info(kind).adaptive; }

bool is_gauss_legendre(stepper_kind kind) {
  return kind == stepper_kind::gauss4 || kind == stepper_kind::gauss6;
}

bool serves(stepper_kind kind, stepper_use use) {
  const auto& i = info(kind);
  switch (use) {
    case stepper_use::any:
      return true;
    case stepper_use::adaptive:
      return i.adaptive;
    case stepper_use::map:
      return i.in_map_lanes;
    case stepper_use::variational:
      return i.variational;
    case stepper_use::system:
      return i.any_system;
    case stepper_use::monodromy:
      return i.monodromy;
    case stepper_use::indicators:
      return i.indicators;
  }
  return false;
}

std::string_view variational_refusal(stepper_kind kind) {
  switch (kind) {
    case stepper_kind::rosenbrock4:
      return "its stages need the Jacobian of the augmented system, which holds second "
             "derivatives of f that the generated kernels do not provide";
    default:
      return "";
  }
}

std::string stepper_names(stepper_use use) {
  std::string out;
  for (const auto& i : infos) {
    if (!serves(i.kind, use)) continue;
    if (!out.empty()) out += ", ";
    out += i.name;
  }
  return out;
}

stepper_kind parse_stepper_kind(std::string_view name) {
  for (const auto& i : infos)
    if (i.name == name) return i.kind;
  throw std::invalid_argument("unknown stepper '" + std::string(name) + "': choose one of " +
                              stepper_names());
}

}  // namespace npend
