// The integrators a user can choose by name.
#pragma once

#include <span>
#include <string>
#include <string_view>

namespace npend {

/// The steppers npend::integrate runs.
enum class stepper_kind {
  rk4,     ///< classic Runge–Kutta 4, fixed step (the paper's method)
  dopri5,  ///< Dormand–Prince 5(4), adaptive, dense output
  rkf78,   ///< Runge–Kutta–Fehlberg 7(8), adaptive (controlled steps to each output time)
  bulirsch_stoer,  ///< Bulirsch–Stoer extrapolation, adaptive, dense output
  rosenbrock4,     ///< Rosenbrock 4 with the exact Jacobian, adaptive, dense output
  gauss4,          ///< implicit Gauss–Legendre, 2 stages, order 4, fixed step, symplectic
  gauss6,          ///< implicit Gauss–Legendre, 3 stages, order 6, fixed step, symplectic
  taylor,          ///< Taylor's method of adaptive order on the generated recurrences, dense output
};

/// Every stepper, in the order above.
std::span<const stepper_kind> all_stepper_kinds();

/// The name users type: "rk4", "dopri5", "rkf78", "bs", "rosenbrock4", "gauss4", "gauss6",
/// "taylor".
std::string_view stepper_name(stepper_kind kind);

/// A one-line description ("classic Runge-Kutta 4, fixed step").
std::string_view stepper_description(stepper_kind kind);

/// The stepper called `name`. Throws std::invalid_argument naming the valid names.
stepper_kind parse_stepper_kind(std::string_view name);

/// Whether the stepper chooses its own steps under abs/rel tolerances.
bool is_adaptive(stepper_kind kind);

/// Whether the stepper is one of the implicit Gauss–Legendre methods (gauss4, gauss6).
bool is_gauss_legendre(stepper_kind kind);

/// What a caller needs of a stepper: the one list of names in messages and help texts is
/// filtered by it, so no message spells the list out by hand.
enum class stepper_use {
  any,          ///< every stepper npend::integrate runs
  adaptive,     ///< steppers that choose their own steps under abs/rel tolerances
  map,          ///< steppers the map's batch lanes run (rk4, dopri5, gauss4, gauss6)
  variational,  ///< steppers that integrate the tangent (variational) equations too
  system,       ///< steppers that integrate any system given as functions (all but taylor, which
                ///< runs a chain's generated Taylor kernels)
  monodromy,    ///< steppers floquet_analysis carries the monodromy matrix on (gauss6, taylor)
  indicators,   ///< steppers chaos_indicators runs (rk4, taylor)
};

/// Whether `kind` serves `use`.
bool serves(stepper_kind kind, stepper_use use);

/// Why `kind` does not integrate the variational equations (empty where it does): for the
/// messages that refuse it.
std::string_view variational_refusal(stepper_kind kind);

/// The names of the steppers that serve `use`, joined by ", " (for messages and help texts).
std::string stepper_names(stepper_use use = stepper_use::any);

}  // namespace npend
