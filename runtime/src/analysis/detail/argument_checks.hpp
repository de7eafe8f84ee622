// The argument checks the time-series analyses share (private to the runtime); each throws
// std::invalid_argument with a message naming the argument.
#pragma once

#include <cstddef>
#include <span>
#include <string_view>

namespace npend::detail {

/// "<name> has N samples; at least <minimum> are needed", "<name>[j] is not finite (v)".
void require_finite_series(std::span<const double> series, std::string_view name,
                           std::size_t minimum);

/// "<prefix>start state entry <i> is not finite" for the first entry (1-based) that is not:
/// the start checks of maximal_lyapunov_exponent (no prefix), chaos_indicators and the maps'
/// batch lanes.
void require_finite_start(std::span<const double> x0, std::string_view prefix = "");

/// "dt must be positive and finite, got <dt>".
void require_sample_spacing(double dt);

/// "<name> is constant: <consequence>" when every sample equals the first.
void require_varying(std::span<const double> series, std::string_view name,
                     std::string_view consequence);

}  // namespace npend::detail
