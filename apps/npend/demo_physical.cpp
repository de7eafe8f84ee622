// npend demo, section 6: the physical pendulum (docs/model.md) — the uniform-rod triple
// pendulum next to the paper's point masses, a damped run and its energy balance, Kapitza's
// and Acheson's pendulums held upside down by a shaken pivot, and the standing triple
// pendulum held by LQR-controlled motors. Figures and an index in <out>/physical/.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>

#include "demo_sections.hpp"
#include "figure_index.hpp"
#include "npend/analysis/motion/energy_drift.hpp"
#include "npend/analysis/stability/floquet.hpp"
#include "npend/analysis/stability/lqr.hpp"
#include "npend/analysis/stability/normal_modes.hpp"
#include "npend/integrators/integrate.hpp"
#include "output_file.hpp"

namespace npend::app {

namespace {

constexpr double pi = std::numbers::pi;

struct trajectory {
  std::vector<double> t;
  std::vector<std::vector<double>> x;  ///< x[i][k]: entry i of the state at t[k]
};

// Integrates with gauss6 at dt = 1e-3, the chain free or under the feedback of `design`, and
// keeps every `every`-th grid point.
trajectory run(const chain& c, const lqr_design* design, const std::vector<double>& x0,
               double t_end, std::size_t every) {
  integration_options o;
  o.stepper = stepper_kind::gauss6;
  o.dt = 1e-3;
  o.t_end = t_end;
  trajectory tr;
  tr.x.resize(x0.size());
  std::size_t k = 0;
  const auto keep = [&](double t, std::span<const double> x) {
    if (k++ % every == 0) {
      tr.t.push_back(t);
      for (std::size_t i = 0; i < x.size(); ++i) tr.x[i].push_back(x[i]);
    }
    return observer_action::proceed;
  };
  if (design != nullptr)
    integrate_under_feedback(c, *design, x0, o, keep);
  else
    integrate(c, x0, o, keep);
  return tr;
}

std::string frequencies_text(const chain& c) {
  std::vector<std::string> w;
  for (const auto& m : normal_modes(c, std::vector<double>(3, 0.0)).modes)
    w.push_back(fmt::format("{:.3f}", m.frequency));
  return fmt::format("{}", fmt::join(w, ", "));
}

double largest(const std::vector<double>& v) {
  double m = 0;
  for (const double x : v) m = std::max(m, std::fabs(x));
  return m;
}

// The start of (a) and (b): every arm at 1.2 rad, at rest.
std::vector<double> swing_start(const chain& c) {
  const std::vector<double> angles{1.2, 1.2, 1.2}, rest(3, 0.0);
  return c.state_from_velocities(angles, rest);
}

// (a) Uniform rods against point masses, the same links, masses and start.
void add_rods_against_points(figure_folder& folder, const chain& points, const chain& rods) {
  auto& index = folder.index();
  const auto point_run = run(points, nullptr, swing_start(points), 20, 10);
  const auto rod_run = run(rods, nullptr, swing_start(rods), 20, 10);
  index.facts.push_back(
      {"normal-mode frequencies, point masses (rad/s)", frequencies_text(points)});
  index.facts.push_back({"normal-mode frequencies, uniform rods (rad/s)", frequencies_text(rods)});
  folder.add(
      "rods_vs_points", "Uniform rods against point masses: φ₃(t)",
      fmt::format(
          "Both triple pendulums start at rest with every arm at 1.2 rad. The rods carry their "
          "mass spread along the arm (c = l/2) and the inertia m l²/12. That makes them "
          "stiffer pendulums (one rod has omega^2 = 3g/(2l), one point mass g/l): normal modes "
          "{} rad/s against the point masses' {} rad/s. From the same start the rods swing "
          "wider: |phi_3| reaches {:.2f} rad (points) and {:.2f} rad (rods).",
          frequencies_text(rods), frequencies_text(points), largest(point_run.x[2]),
          largest(rod_run.x[2])),
      [&](series_output& out) {
        const std::string p = out.write_csv("points", std::vector<std::string>{"t", "phi3"},
                                            std::vector{point_run.t, point_run.x[2]});
        const std::string r = out.write_csv("rods", std::vector<std::string>{"t", "phi3"},
                                            std::vector{rod_run.t, rod_run.x[2]});
        cli::plot_panel panel{.title = "φ₃(t), started at rest from φ = (1.2, 1.2, 1.2)",
                              .xlabel = "t (s)",
                              .ylabel = "φ_3 (rad)"};
        panel.curves.push_back({p, "1:2", "lines lw 1.5 lc rgb '#1f77b4'", "point masses"});
        panel.curves.push_back({r, "1:2", "lines lw 1.5 lc rgb '#d62728'", "uniform rods"});
        return std::vector{panel};
      },
      {1300, 520, 1});
}

// (b) A damped run: H(t) falls by exactly the work of the joint friction.
void add_damped_rods(figure_folder& folder, const chain_parameters& rod_params) {
  auto& index = folder.index();
  chain_parameters damped_params = rod_params;
  damped_params.damping = {0.05, 0.05, 0.05};
  const chain damped(damped_params);
  const auto damped_run = run(damped, nullptr, swing_start(damped), 60, 1);
  std::vector<double> energy, balance;
  energy_balance books(damped);
  for (std::size_t k = 0; k < damped_run.t.size(); ++k) {
    std::vector<double> x(6);
    for (std::size_t i = 0; i < 6; ++i) x[i] = damped_run.x[i][k];
    energy.push_back(books.add(damped_run.t[k], x));
    balance.push_back(books.balance());
  }
  const double worst = books.max_imbalance();
  index.facts.push_back(
      {"damped rods (b = 0.05 N m s/rad)",
       fmt::format("H from {:.4f} J to {:.4f} J in 60 s; H − ∫P dt constant to {:.1e} J",
                   energy.front(), energy.back(), worst)});
  folder.add(
      "damped", "A damped triple pendulum: the energy and its balance",
      fmt::format(
          "The uniform-rod triple pendulum with damping b = 0.05 N m s/rad at every joint, from "
          "the same start. H(t) falls from {:.4f} J to {:.4f} J in 60 s. The friction's power "
          "is P = -sum b_j (theta_j')^2, from the joint rates. Integrated by the trapezoid rule "
          "at the 1 ms grid, H(t) - integral of P dt stays at H(0) to {:.1e} J, the trapezoid "
          "rule's own error. gauss6 is not symplectic for a damped chain, but it stays an "
          "order-6 method, and the balance shows it.",
          energy.front(), energy.back(), worst),
      [&](series_output& out) {
        std::vector<double> t, h, b;
        for (std::size_t k = 0; k < damped_run.t.size(); k += 20) {
          t.push_back(damped_run.t[k]);
          h.push_back(energy[k]);
          b.push_back(balance[k]);
        }
        const std::string data = out.write_csv(
            "", std::vector<std::string>{"t", "H", "H_minus_work"}, std::vector{t, h, b});
        cli::plot_panel panel{
            .title = "Energy of the damped rods", .xlabel = "t (s)", .ylabel = "energy (J)"};
        panel.curves.push_back({data, "1:2", "lines lw 2 lc rgb '#1f77b4'", "H(t)"});
        panel.curves.push_back(
            {data, "1:3", "lines lw 2 dt 2 lc rgb '#2ca02c'", "H(t) − ∫ P dt (balance)"});
        return std::vector{panel};
      },
      {1100, 560, 1});
}

// (c) Kapitza and Acheson: the inverted chains on a shaken pivot.
void add_inverted_chains(figure_folder& folder) {
  auto& index = folder.index();
  const double amplitude = 0.002, link = 0.2;
  std::vector<std::vector<double>> chart(4);  // Ω, then max |μ| of 1, 2, 3 links
  std::vector<double> threshold(3, 0.0);
  for (int k = 0; k <= 90; ++k) chart[0].push_back(400 + 40.0 * k);
  for (int n = 1; n <= 3; ++n) {
    chain_parameters p = chain_parameters::uniform(n, 1.0, link);
    p.pivot = pivot_motion::vertical(amplitude, chart[0].front());
    std::vector<double> upright(static_cast<std::size_t>(2 * n), 0.0);
    for (int i = 0; i < n; ++i) upright[static_cast<std::size_t>(i)] = pi;
    const floquet_scan_result scan = floquet_frequency_scan(chain(p), upright, chart[0]);
    for (const auto& point : scan.points)
      chart[static_cast<std::size_t>(n)].push_back(point.max_modulus);
    if (!scan.stable_windows.empty())
      threshold[static_cast<std::size_t>(n - 1)] = scan.stable_windows.front().first;
  }
  index.facts.push_back(
      {"inverted chains held by a shaken pivot (a = 2 mm, l = 0.2 m)",
       fmt::format("from Ω = {:g}, {:g}, {:g} rad/s for 1, 2, 3 links (aΩ = {:.2f}, {:.2f}, "
                   "{:.2f} m/s)",
                   threshold[0], threshold[1], threshold[2], amplitude * threshold[0],
                   amplitude * threshold[1], amplitude * threshold[2])});
  folder.add(
      "kapitza_acheson", "Kapitza's and Acheson's pendulums: held upside down by shaking",
      fmt::format(
          "The largest Floquet multiplier of the upside-down chain (every arm at pi) over one "
          "period of a vertical pivot vibration of amplitude 2 mm, against its frequency, for 1, "
          "2 and 3 point masses on 0.2 m links. Where max |mu| = 1 the inverted chain is "
          "stable. One link is held from {:g} rad/s: Kapitza's (a Omega)^2 > 2 g l gives "
          "{:.0f} rad/s. Two links are held from {:g} rad/s and three from {:g} rad/s, as "
          "Acheson's theorem (1993) predicts and Acheson and Mullin showed by experiment. "
          "Grid: 40 rad/s; the thresholds agree with Kapitza's averaged potential to 3e-5 "
          "(tests/runtime/stability/test_floquet.cpp).",
          threshold[0], std::sqrt(2 * 9.81 * link) / amplitude, threshold[1], threshold[2]),
      [&](series_output& out) {
        const std::string data =
            out.write_csv("", std::vector<std::string>{"omega", "one", "two", "three"}, chart);
        cli::plot_panel panel{.title = "Inverted chains on a vertically shaken pivot (a = 2 mm)",
                              .xlabel = "drive frequency Ω (rad/s)",
                              .ylabel = "largest Floquet multiplier |μ|_{max}",
                              .yrange = "[0.995:*]",
                              .commands = {"set key top right", "set grid",
                                           "set arrow from graph 0, first 1 to graph 1, first 1 "
                                           "nohead dt 2 lc rgb 'gray'"}};
        panel.curves.push_back({data, "1:2", "linespoints lw 2 pt 7 ps 0.4", "1 link"});
        panel.curves.push_back({data, "1:3", "linespoints lw 2 pt 7 ps 0.4", "2 links"});
        panel.curves.push_back({data, "1:4", "linespoints lw 2 pt 7 ps 0.4", "3 links"});
        return std::vector{panel};
      },
      {1100, 600, 1});
}

// (d) The standing triple pendulum held by motors (LQR).
void add_standing_chain(figure_folder& folder, const chain& points) {
  auto& index = folder.index();
  const std::vector<double> up{pi, pi, pi};
  const lqr_design design = lqr(points, up);
  std::vector<double> x0{pi + 0.1, pi + 0.1, pi + 0.1, 0, 0, 0};
  const auto held = run(points, &design, x0, 8, 10);
  std::vector<std::vector<double>> deviation(3), torque(3);
  const feedback_rhs law(points, design);
  for (std::size_t k = 0; k < held.t.size(); ++k) {
    std::vector<double> x(6);
    for (std::size_t i = 0; i < 6; ++i) x[i] = held.x[i][k];
    const auto u = law.torques(x);
    for (std::size_t i = 0; i < 3; ++i) {
      deviation[i].push_back(x[i] - pi);
      torque[i].push_back(u[i]);
    }
  }
  double final_deviation = 0;
  for (std::size_t i = 0; i < 3; ++i)
    final_deviation = std::max(final_deviation, std::fabs(deviation[i].back()));
  index.facts.push_back({"standing triple pendulum, LQR motors at all joints",
                         fmt::format("from 0.1 rad off to {:.1e} rad in 8 s; open-loop growth "
                                     "rate {:.3f} 1/s",
                                     final_deviation, design.open_loop.front().real())});
  folder.add(
      "standing_lqr", "The standing triple pendulum, held by motors (LQR)",
      fmt::format(
          "Every arm upright (phi = pi) is an equilibrium, unstable with growth rate {:.3f} 1/s. "
          "Motors at the three joints apply u = -K(x - x*). K is the LQR gain from the exact "
          "linearisation, found by SLICOT's Riccati solver with weights 10:1:1 (npend control "
          "--links 3 --at pi). Started 0.1 rad off at every arm, the nonlinear chain is back "
          "within {:.1e} rad in 8 s. With a single motor at the pivot the chain is still "
          "controllable, but the design catches it only from about 0.07 rad "
          "(docs/commands.md, npend control).",
          design.open_loop.front().real(), final_deviation),
      [&](series_output& out) {
        const std::string a =
            out.write_csv("angles", std::vector<std::string>{"t", "dphi1", "dphi2", "dphi3"},
                          std::vector{held.t, deviation[0], deviation[1], deviation[2]});
        const std::string u =
            out.write_csv("torques", std::vector<std::string>{"t", "u1", "u2", "u3"},
                          std::vector{held.t, torque[0], torque[1], torque[2]});
        cli::plot_panel angles{
            .title = "Angles from upright", .xlabel = "t (s)", .ylabel = "φ_i − π (rad)"};
        cli::plot_panel torques{.title = "Motor torques", .xlabel = "t (s)", .ylabel = "u_i (N m)"};
        for (int i = 1; i <= 3; ++i) {
          angles.curves.push_back(
              {a, fmt::format("1:{}", i + 1), "lines lw 2", fmt::format("arm {}", i)});
          torques.curves.push_back(
              {u, fmt::format("1:{}", i + 1), "lines lw 2", fmt::format("joint {}", i)});
        }
        return std::vector{angles, torques};
      },
      {1400, 560, 2});
}

}  // namespace

void demo_physical(const demo_context& demo) {
  const auto started = std::chrono::steady_clock::now();
  figure_folder folder(cli::output_folder((demo.out / "physical").string(), "--out"),
                       "npend demo (physical pendulum): ", {}, true);
  fmt::print(
      "## 6. The physical pendulum (paper section 6.2's remark): written to {}/\n\n"
      "Rigid links with inertia, joint damping, a shaken pivot and joint motors, derived by\n"
      "npend-gen --model physical (docs/model.md).\n\n",
      folder.dir().string());
  auto& index = folder.index();
  index.title = "npend demo: the physical triple pendulum, damped, shaken and standing";
  index.preamble = {
      "The paper's model is point masses on massless rods; its §6.2 remarks that the physical "
      "pendulum, whose arms have moments of inertia, \"should not be hard\". These figures use "
      "the general chain npend derives for it (docs/model.md): uniform rods (c = l/2, "
      "J = m l²/12), joint damping, a pivot shaken vertically, and motors at the joints."};

  const chain& points = demo.triple;
  chain_parameters rod_params = points.parameters();
  rod_params.make_uniform_rods();
  add_rods_against_points(folder, points, chain(rod_params));
  add_damped_rods(folder, rod_params);
  add_inverted_chains(folder);
  add_standing_chain(folder, points);

  for (const auto& note : folder.notes()) folder.index().notes.push_back(note);
  const auto index_path = folder.write_index();
  for (const auto& note : folder.index().notes) fmt::print("note: {}\n", note);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  fmt::print("Section 6 took {:.1f} s: {} files in {}/; open {}\n\n", seconds,
             folder.files().size(), folder.dir().string(), index_path.string());
}

}  // namespace npend::app
