// The premise of free periodic orbits, shared by the shooting and the search for unstable
// orbits: a conserved energy and an autonomous flow on a fixed pivot.
#pragma once

#include "npend/chain.hpp"

namespace npend::detail {

/// Throws std::invalid_argument, the message starting with `who`, for a damped chain (every
/// orbit spirals in), a driven pivot (the orbits have the drive's period: Floquet's and
/// forced_orbit's business) and a cart (its conserved momentum adds a second trivial pair of
/// multipliers that the shooting does not separate).
void check_conservative(const chain& c, const char* who);

}  // namespace npend::detail
