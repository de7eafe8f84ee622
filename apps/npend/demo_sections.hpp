// The sections of `npend demo`, one per part of the paper's story, each in its own file.
#pragma once

#include "npend/chain.hpp"

#include <filesystem>

namespace npend::app {

struct demo_context {
  chain triple;  ///< the paper's triple pendulum: equal masses 1 kg, lengths 1 m, g = 9.81
  std::filesystem::path out = "npend-demo";  ///< the folder the figures go to (--out)
};

/// 1–2: the derived equations and the generated functions at a sample state.
void demo_equations(const demo_context& demo);
/// 3: a weak and a strong excitation integrated with Gauss–Legendre, energy errors.
void demo_motion(const demo_context& demo);
/// 4: the 8 equilibria, the normal modes and the harmonic approximation's range, and the
/// Lyapunov spectra of the weak and the strong excitation.
void demo_stability(const demo_context& demo);
/// 5: the forms of motion (paper §6.6): figures 6.8–6.13 and an index in demo.out.
void demo_forms_of_motion(const demo_context& demo);
/// 6: the physical pendulum: uniform rods against point masses, a damped run, Kapitza's and
/// Acheson's inverted pendulums, the standing pendulum held by LQR; in demo.out/physical/.
void demo_physical(const demo_context& demo);

}  // namespace npend::app
