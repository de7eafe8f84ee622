// The sections of `npend demo`, one per part of the paper's story, each in its own file.
#pragma once

#include <filesystem>
#include <span>
#include <string>

#include "figure_index.hpp"
#include "npend/chain.hpp"

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
/// The motion of the demo's chain `c` from x0 (dim 6) over 6 s as a 320x320 GIF at 20 fps,
/// STEM.gif in the folder, with its frames as STEM_frames.csv (npend animate --frames-csv),
/// listed in the folder's index under `heading` with `text`; returns the GIF's path, or ""
/// with a note in the index when gnuplot is missing or fails. Throws cli::interrupted on
/// Ctrl-C.
std::string add_demo_animation(figure_folder& folder, const chain& c, std::span<const double> x0,
                               const std::string& stem, const std::string& heading,
                               const std::string& text);
/// 6: the physical pendulum: uniform rods against point masses, a damped run, Kapitza's and
/// Acheson's inverted pendulums, the standing pendulum held by LQR; in demo.out/physical/.
void demo_physical(const demo_context& demo);

}  // namespace npend::app
