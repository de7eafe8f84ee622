// npend demo, section 5: the forms of motion of the triple pendulum (paper §6.6) — the
// paper's figures 6.8–6.13 for a regular (weak) and a chaotic (strong) excitation, in one
// folder with their data, gnuplot scripts and an index, each with a short text.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <tuple>

#include "demo_sections.hpp"
#include "figure_index.hpp"
#include "npend/analysis/motion/motion_analysis.hpp"
#include "npend/analysis/stability/normal_modes.hpp"
#include "npend/excitation.hpp"
#include "output_file.hpp"
#include "series_figures.hpp"
#include "series_output.hpp"
#include "time_series_source.hpp"

namespace npend::app {

namespace {

namespace fs = std::filesystem;

// The paper's series: 2¹⁴ samples at dt = 1 ms; the Poincaré sections and the events over a
// longer run, for enough points.
constexpr std::size_t samples = std::size_t{1} << 14;
constexpr double dt = 1e-3;
constexpr double section_time = 600;

// One excitation of the triple pendulum and everything computed for it.
struct demo_case {
  std::string key;    // in file names
  std::string label;  // panel titles
  double epsilon = 0;
  std::vector<double> x0;
  motion_analysis a;
};

simulated_start simulation(const chain& c, std::vector<double> x0) {
  integration_options o;
  o.stepper = stepper_kind::gauss6;
  o.dt = dt;
  o.t_end = section_time;
  const std::string source =
      fmt::format("simulation: 3 links, E = {:.6g} J, gauss6, dt = {:g} s", c.hamiltonian(x0), dt);
  return {c, std::move(x0), o, samples, source};
}

// A panel with the case's label as its title.
cli::plot_panel titled(cli::plot_panel panel, const std::string& title) {
  panel.title = title;
  return panel;
}

// The largest |x_j| of a series.
double largest_magnitude(const std::vector<double>& x) {
  double largest = 0;
  for (const double v : x) largest = std::max(largest, std::fabs(v));
  return largest;
}

// The largest |φ_i| of any link over the sampled motion (rad).
double largest_angle(const sampled_signals& s) {
  double largest = 0;
  for (std::size_t i = 0; i < s.values.size() / 2; ++i)
    largest = std::max(largest, largest_magnitude(s.values[i]));
  return largest;
}

// The largest |C_xx(τ)| for τ ≥ from (s): how much correlation is left late.
double late_correlation(const autocorrelation_result& c, double from) {
  double largest = 0;
  for (std::size_t k = 0; k < c.lag.size(); ++k)
    if (c.lag[k] >= from) largest = std::max(largest, std::fabs(c.value[k]));
  return largest;
}

std::string omegas(const std::vector<spectral_peak>& peaks, std::size_t count) {
  std::vector<std::string> list;
  for (std::size_t k = 0; k < std::min(count, peaks.size()); ++k)
    list.push_back(fmt::format("{:.3f}", peaks[k].omega));
  std::sort(list.begin(), list.end(),
            [](const std::string& a, const std::string& b) { return std::stod(a) < std::stod(b); });
  return fmt::format("{}", fmt::join(list, ", "));
}

// At rest, the arms deflected in a zigzag φ = (s, −s, s) with the energy E = ε m g l.
std::vector<double> zigzag_start(const chain& c, double epsilon) {
  const std::vector<double> zigzag{1.0, -1.0, 1.0};
  return deflected_state(c, energy_from_epsilon(c, epsilon), zigzag);
}

// The weak and the strong excitation, each simulated and analysed.
std::vector<demo_case> analysed_cases(const chain& c) {
  std::vector<demo_case> cases;
  for (const auto& [key, label, epsilon] :
       {std::tuple{"weak", "(a) weak excitation, ε = 0.01: regular", 0.01},
        std::tuple{"strong", "(b) strong excitation, ε = 1.5: chaotic", 1.5}}) {
    demo_case k{key, label, epsilon, zigzag_start(c, epsilon), {}};
    motion_analysis_options options;
    options.coordinate = 2;                                  // φ₃
    options.section = section_plane::coordinate(3, 0, 0.0);  // φ₁ = 0, upwards
    options.event = section_plane::coordinate(3, 2, 0.0);    // φ₃ = 0, both ways
    k.a = cli::on_terminal(simulation(c, k.x0), [&](const simulated_start& run) {
      return analyze_motion(run, options);
    });
    cases.push_back(std::move(k));
  }
  return cases;
}

// A single normal mode (the slowest), 0.1 rad at its largest: periodic motion, and its
// Poincaré section.
struct mode_motion {
  std::vector<normal_mode> modes;  // all of them, the slowest first
  std::vector<section_crossing> section;
};

mode_motion single_mode_motion(const chain& c) {
  auto modes = normal_modes(c, std::vector<double>{0, 0, 0}).modes;
  std::vector<double> mode_start(6, 0.0);
  const auto& shape = modes[0].shape;
  const double largest = std::fabs(*std::max_element(
      shape.begin(), shape.end(), [](double a, double b) { return std::fabs(a) < std::fabs(b); }));
  for (std::size_t i = 0; i < 3; ++i) mode_start[i] = 0.1 * shape[i] / largest;
  const auto mode_run = simulation(c, mode_start);
  auto mode_section =
      poincare_section(c, mode_start, section_plane::coordinate(3, 0, 0.0), mode_run.integration)
          .crossings;
  return {std::move(modes), std::move(mode_section)};
}

// The index's title, preamble and facts; returns the normal-mode frequencies as written.
std::vector<std::string> write_index_head(figure_folder& folder, const chain& c,
                                          const std::vector<demo_case>& cases,
                                          const std::vector<normal_mode>& modes) {
  auto& index = folder.index();
  index.title = "npend demo: forms of motion of the triple pendulum (paper §6.6, Abb. 6.8–6.13)";
  index.preamble = {
      "The planar triple pendulum with equal masses m = 1 kg and lengths l = 1 m, g = 9.81 m/s², "
      "integrated by npend's symplectic Gauss–Legendre method (order 6, dt = 1 ms). The time "
      "series are φ₃(t) with 2¹⁴ samples at dt = 1 ms, as in the paper; the Poincaré sections "
      "and the recurrence times come from 600 s runs, located on the integrator's steps (dense "
      "output and Hénon's trick), not on the samples.",
      "Both excitations start at rest with the arms deflected in a zigzag, φ = (s, −s, s), so "
      "that the energy is E = ε m g l. The weak one moves regularly — quasi-periodically, a "
      "superposition of the three normal modes, what the paper calls periodic; the strong one "
      "moves chaotically."};
  for (const auto& k : cases)
    index.facts.push_back({fmt::format("{} excitation", k.key),
                           fmt::format("ε = {}, E = {:.4g} J, s = {:.4f} rad", k.epsilon,
                                       c.hamiltonian(k.x0), k.x0[0])});
  std::vector<std::string> mode_frequencies;
  for (const auto& m : modes) mode_frequencies.push_back(fmt::format("{:.3f}", m.frequency));
  index.facts.push_back(
      {"normal-mode frequencies (rad/s)", fmt::format("{}", fmt::join(mode_frequencies, ", "))});
  return mode_frequencies;
}

void add_time_series_figure(figure_folder& folder, const std::vector<demo_case>& cases) {
  const demo_case &weak = cases[0], &strong = cases[1];
  // The motions themselves (the beats the paper mentions with Abb. 6.9a).
  folder.add("time_series", "The two motions: φ₃(t)",
             fmt::format(
                 "phi_3(t) over the 2^14 samples. Weak: a beat of the three normal modes, "
                 "|phi_3| <= {:.3f} rad. Strong: irregular swings, calm stretches and sudden "
                 "flurries taking turns, |phi_3| up to {:.2f} rad; {}.",
                 largest_magnitude(weak.a.series.values), largest_magnitude(strong.a.series.values),
                 largest_angle(strong.a.signals) < std::numbers::pi
                     ? "no arm goes over the top, as in the paper's runs"
                     : "an arm goes over the top"),
             [&](series_output& out) {
               std::vector<cli::plot_panel> panels;
               for (const auto& k : cases)
                 panels.push_back(titled(time_series_panel(out, k.key, k.a.signals, 2), k.label));
               return panels;
             },
             {1400, 520, 2});
}

void add_animations(figure_folder& folder, const chain& c) {
  // The two kinds of motion to watch: section 3's weak excitation (ε = 0.01 would move the
  // bobs by a few pixels only) and the strong one.
  for (const auto& [key, epsilon] : {std::pair{"weak", 0.1}, std::pair{"strong", 1.5}}) {
    const auto x0 = zigzag_start(c, epsilon);
    add_demo_animation(
        folder, c, x0, fmt::format("animation_{}", key),
        fmt::format("The {} excitation, animated (ε = {})", key, epsilon),
        fmt::format("The first 6 s from the zigzag at rest, s = {:.3f} rad, frames at 20 fps from "
                    "gauss6 (npend animate); the red trail is the last bob's path over 1.5 s. {}",
                    x0[0],
                    epsilon < 1 ? "Small regular oscillations about the hanging chain: the "
                                  "bobs move by centimetres."
                                : "Large irregular swings of all three arms, bending against "
                                  "each other; below epsilon = 2 no arm goes over the top."));
  }
}

void add_poincare_figure(figure_folder& folder, const chain& c, const std::vector<demo_case>& cases,
                         const mode_motion& mode) {
  const demo_case &weak = cases[0], &strong = cases[1];
  const auto& modes = mode.modes;
  const auto& mode_section = mode.section;
  // Abb. 6.8: the Poincaré section.
  double mode_spread = 0;
  for (const auto& x : mode_section)
    mode_spread = std::max(mode_spread, std::fabs(x.state[2] - mode_section.front().state[2]));
  folder.add(
      "fig6_8_poincare", "Abb. 6.8: Poincaré section, projected on (φ₃, p₃)",
      fmt::format(
          "The crossings of phi_1 = 0 (upwards) in {:g} s, projected on (phi_3, p_3). (a) A "
          "single normal mode (omega = {:.3f} rad/s, 0.1 rad): periodic motion, all {} points "
          "within {:.1e} rad of one point (the small closed curve is the nonlinear correction "
          "to the linear mode; note the axis scale). (b) Weak excitation: quasi-periodic, {} "
          "points on closed curves, the cut through an invariant torus. (c) Strong excitation: "
          "chaotic, {} points scattered over an area. (The paper names the section phi_3 = 0 and "
          "the projection phi_3-p_3, which would put every point on the line phi_3 = 0; the "
          "section here is phi_1 = 0.)",
          section_time, modes[0].frequency, mode_section.size(), mode_spread, weak.a.section.size(),
          strong.a.section.size()),
      [&](series_output& out) {
        const std::pair<std::size_t, std::size_t> projection{2, 5};
        return std::vector{
            titled(poincare_panel(out, "mode", c, mode_section, projection, "phi1=0"),
                   "(a) a normal mode: periodic"),
            titled(poincare_panel(out, weak.key, c, weak.a.section, projection, "phi1=0"),
                   "(b) weak excitation: quasi-periodic"),
            titled(poincare_panel(out, strong.key, c, strong.a.section, projection, "phi1=0"),
                   "(c) strong excitation: chaotic")};
      },
      {1500, 540, 3});
}

void add_spectrum_figures(figure_folder& folder, const std::vector<demo_case>& cases,
                          const std::vector<std::string>& mode_frequencies) {
  const demo_case &weak = cases[0], &strong = cases[1];
  // Abb. 6.9 and 6.10: spectral density and autocorrelation.
  folder.add(
      "fig6_9_spectral_density", "Abb. 6.9: spectral density of φ₃",
      fmt::format("rho(omega) = |x(omega)|^2 of phi_3 (mean removed, Hann window, resolution "
                  "{:.3f} rad/s), log scale, peaks marked. (a) Weak: sharp lines at omega = {} "
                  "rad/s, the normal modes {} rad/s. (b) Strong: a broad, continuous spectrum "
                  "({} peaks stand out of it, the strongest at {:.3f} rad/s).",
                  weak.a.spectrum.resolution, omegas(weak.a.peaks, 3),
                  fmt::join(mode_frequencies, ", "), strong.a.peaks.size(),
                  strong.a.peaks.empty() ? 0.0 : strong.a.peaks.front().omega),
      [&](series_output& out) {
        std::vector<cli::plot_panel> panels;
        for (const auto& k : cases)
          panels.push_back(titled(
              spectrum_panel(out, k.key, k.a.series, k.a.spectrum, k.a.peaks, 25.0), k.label));
        return panels;
      },
      {1400, 560, 2});
  folder.add(
      "fig6_10_autocorrelation", "Abb. 6.10: autocorrelation of φ₃",
      fmt::format("C_xx(tau) of phi_3, normalised to C_xx(0) = 1 (Wiener-Khinchin, zero-padded). "
                  "(a) Weak: it keeps oscillating, a long memory of the discrete spectrum (|C_xx| "
                  "still reaches {:.2f} beyond tau = 4 s). (b) Strong: it decays, the modes "
                  "cancel out (|C_xx| <= {:.2f} beyond 4 s).",
                  late_correlation(weak.a.autocorrelation, 4),
                  late_correlation(strong.a.autocorrelation, 4)),
      [&](series_output& out) {
        std::vector<cli::plot_panel> panels;
        for (const auto& k : cases)
          panels.push_back(
              titled(autocorrelation_panel(out, k.key, k.a.series, k.a.autocorrelation), k.label));
        return panels;
      },
      {1400, 520, 2});
}

void add_recurrence_figures(figure_folder& folder, const std::vector<demo_case>& cases) {
  const demo_case &weak = cases[0], &strong = cases[1];
  // Abb. 6.11 and 6.12: recurrence times of φ₃ = 0.
  std::vector<recurrence_panels> recurrence;
  std::vector<std::string> interval_spectra;
  folder.add(
      "fig6_11_recurrence_histogram", "Abb. 6.11: distribution of the recurrence times of φ₃ = 0",
      fmt::format("The probability density of the intervals between successive zero crossings "
                  "of phi_3 (both directions) in {:g} s. (a) Weak: {} intervals, all within a "
                  "band from {:.3f} to {:.3f} s and piling up at its edges: the beat of the modes "
                  "shifts the zero crossings smoothly to and fro. (b) Strong: {} intervals spread "
                  "broadly around the mean T = {:.3f} s (standard deviation {:.3f} s), with a "
                  "tail of long ones.",
                  section_time, weak.a.recurrence.value().intervals.size(),
                  *std::min_element(weak.a.recurrence.value().intervals.begin(),
                                    weak.a.recurrence.value().intervals.end()),
                  *std::max_element(weak.a.recurrence.value().intervals.begin(),
                                    weak.a.recurrence.value().intervals.end()),
                  strong.a.recurrence.value().intervals.size(), strong.a.recurrence.value().mean,
                  strong.a.recurrence.value().standard_deviation),
      [&](series_output& out) {
        std::vector<cli::plot_panel> panels;
        for (const auto& k : cases) {
          recurrence.push_back(
              recurrence_figure(out, k.key, "phi3=0", k.a.event_times, k.a.recurrence.value()));
          interval_spectra.push_back(out.file_name(table_name(k.key, "spectrum")));
          panels.push_back(titled(recurrence.back().distribution, k.label));
        }
        return panels;
      },
      {1400, 520, 2});
  folder.add(
      "fig6_12_recurrence_spectrum", "Abb. 6.12: spectrum of the sequence of recurrence times",
      "The spectral density of the interval sequence T_j against the event number j (omega in "
      "radians per event). (a) Weak: discrete lines, the intervals follow the beat's pattern. (b) "
      "Strong: broadband, as the paper expects for chaotic motion.",
      [&](series_output&) {
        std::vector<cli::plot_panel> panels;
        for (std::size_t k = 0; k < cases.size(); ++k)
          panels.push_back(titled(recurrence[k].spectrum, cases[k].label));
        return panels;
      },
      {1400, 520, 2}, interval_spectra);
}

void add_delay_figure(figure_folder& folder, const std::vector<demo_case>& cases) {
  const demo_case &weak = cases[0], &strong = cases[1];
  // Abb. 6.13: delay coordinates.
  const auto tau_text = [](const demo_case& k) {
    return fmt::format("tau = {:.3f} s by {}, dimension {}", k.a.tau.seconds,
                       delay_method_name(k.a.tau.method),
                       k.a.dimension ? std::to_string(*k.a.dimension) : "none up to 10");
  };
  folder.add(
      "fig6_13_delay_plot", "Abb. 6.13: delay plot φ₃(t) against φ₃(t − τ)",
      fmt::format("Top: phi_3(t) against phi_3(t - tau), tau chosen automatically (ami: the "
                  "first minimum of the mutual information; else the first zero of C_xx). (a) Weak "
                  "({}): a band of smooth loops, the few modes unfolded. "
                  "(b) Strong ({}): an irregular tangle. Bottom: the fraction of false nearest "
                  "neighbours and Cao's E1, E2 against the embedding dimension m; the dimension "
                  "is the first m with fewer than 1% false neighbours. Chaotic Hamiltonian motion "
                  "has no low-dimensional attractor to embed (phase-space volume is conserved, "
                  "the trajectory fills its 5-dimensional energy shell), and 2^14 samples are far "
                  "too few to fill that: the false neighbours do not vanish.",
                  tau_text(weak), tau_text(strong)),
      [&](series_output& out) {
        std::vector<cli::plot_panel> delays, dimensions;
        for (const auto& k : cases) {
          auto [delay, dimension] = embedding_figure(out, k.key, k.a.series, k.a.tau, k.a.vectors,
                                                     k.a.fnn, k.a.cao, k.a.dimension, "fnn");
          delays.push_back(
              titled(delay, fmt::format("{}, τ = {:.3f} s", k.label, k.a.tau.seconds)));
          dimensions.push_back(
              titled(dimension, fmt::format("{}: {}", k.label.substr(0, 3), dimension.title)));
        }
        delays.insert(delays.end(), dimensions.begin(), dimensions.end());
        return delays;
      },
      {1300, 1200, 2});
}

}  // namespace

void demo_forms_of_motion(const demo_context& demo) {
  const auto started = std::chrono::steady_clock::now();
  const chain& c = demo.triple;
  figure_folder folder(cli::output_folder(demo.out.string(), "--out"), "npend demo: ", {}, true);
  fmt::print(
      "## 5. Forms of motion (paper section 6.6): figures 6.8-6.13, written to {}/\n\n"
      "The paper's setting: equal masses and lengths, the time series of phi_3 with 2^14 samples\n"
      "at dt = {:g} s, integrated here by gauss6. Two excitations like those of section 3 (a\n"
      "zigzag at rest): weak, epsilon = 0.01 (at section 3's 0.1 the nonlinearity already\n"
      "pulls the highest mode down to 7.6 rad/s), and strong, epsilon = 1.5; the Poincare\n"
      "sections and the recurrence times come from a {:g} s run of each, located on the\n"
      "integrator's steps.\n\n",
      folder.dir().string(), dt, section_time);

  const std::vector<demo_case> cases = analysed_cases(c);
  const mode_motion mode = single_mode_motion(c);
  const std::vector<std::string> mode_frequencies = write_index_head(folder, c, cases, mode.modes);
  add_time_series_figure(folder, cases);
  add_animations(folder, c);
  add_poincare_figure(folder, c, cases, mode);
  add_spectrum_figures(folder, cases, mode_frequencies);
  add_recurrence_figures(folder, cases);
  add_delay_figure(folder, cases);

  for (const auto& k : cases)
    for (const auto& note : k.a.notes) folder.index().notes.push_back(k.key + ": " + note);
  for (const auto& note : folder.notes()) folder.index().notes.push_back(note);
  const fs::path index_path = folder.write_index();
  for (const auto& note : folder.index().notes) fmt::print("note: {}\n", note);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  fmt::print(
      "Section 5 took {:.1f} s. The figures, their data (CSV) and gnuplot scripts: {} "
      "files in {}/; open {}\n",
      seconds, folder.files().size(), folder.dir().string(), index_path.string());
}

}  // namespace npend::app
