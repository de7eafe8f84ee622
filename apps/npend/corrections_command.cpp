// npend corrections: the paper's nonlinear corrections to the harmonic approximation and its
// power series against the true motion (§6.4).
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <nlohmann/json.hpp>

#include "chain_options.hpp"
#include "command.hpp"
#include "input_parsing.hpp"
#include "npend/analysis/stability/harmonic_corrections.hpp"
#include "npend/analysis/stability/normal_modes.hpp"
#include "series_output.hpp"
#include "start_options.hpp"

namespace npend::app {

namespace {

struct corrections_command_options {
  cli::chain_options chain;
  cli::start_options start;
  std::string amplitude, horizon, samples;
  bool json = false;
  std::string out;
};

// "harmonic solution" → "harmonic_solution"
std::string slug(const std::string& name) {
  std::string s = name;
  std::replace(s.begin(), s.end(), ' ', '_');
  return s;
}

void write_corrections_files(series_output& files, const correction_study& s) {
  const std::size_t n = s.phi0.size();
  std::vector<std::string> names{"t"};
  std::vector<std::vector<double>> columns{s.t};
  const auto add = [&](const std::string& suffix, const std::vector<std::vector<double>>& angles,
                       const std::vector<double>& q) {
    for (std::size_t i = 0; i < n; ++i) {
      names.push_back(fmt::format("phi_{}_{}", i + 1, suffix));
      std::vector<double> column;
      for (const auto& a : angles) column.push_back(a[i]);
      columns.push_back(std::move(column));
    }
    names.push_back("Q_" + suffix);
    columns.push_back(q);
  };
  add("true", s.true_angles, s.true_q);
  for (const auto& t : s.tracks) add(slug(t.name), t.angles, t.q);
  const std::string data = files.write_csv("", names, columns);

  // Column numbers (1-based) of φ_1 and Q for the true motion and each track.
  const auto phi1 = [&](std::size_t block) { return 2 + block * (n + 1); };
  cli::plot_panel angles{.title = "φ_1(t): the chain and the approximations",
                         .xlabel = "t (s)",
                         .ylabel = "φ_1 (rad)"};
  cli::plot_panel q{.title = "The paper's correction function Q = φ_1 φ_2 / (φ̇_1 φ̇_2)",
                    .xlabel = "t (s)",
                    .ylabel = "Q (s^2)"};
  // Q has poles where φ̇_1 or φ̇_2 vanishes (turning points): scale the axis to the bulk of
  // the true Q (its 10th to 90th percentile, widened), and let the poles run off it.
  std::vector<double> finite_q;
  for (double v : s.true_q)
    if (std::isfinite(v)) finite_q.push_back(v);
  std::sort(finite_q.begin(), finite_q.end());
  if (finite_q.size() >= 10) {
    const double low = finite_q[finite_q.size() / 10], high = finite_q[finite_q.size() * 9 / 10];
    const double pad = std::max(high - low, 1e-3 * std::max(std::fabs(low), std::fabs(high)));
    q.yrange = fmt::format("[{}:{}]", low - 2 * pad, high + 2 * pad);
  }
  const std::vector<std::string> styles{"lines lw 1.5 dt 2", "lines lw 1.2 dt 3",
                                        "lines lw 1.2 dt 4", "lines lw 1.5 dt 5",
                                        "lines lw 1.5 dt 6"};
  angles.curves.push_back(
      {data, fmt::format("1:{}", phi1(0)), "lines lw 3 lc rgb 'black'", "true motion"});
  q.curves.push_back(
      {data, fmt::format("1:{}", phi1(0) + n), "lines lw 3 lc rgb 'black'", "true motion"});
  for (std::size_t k = 0; k < s.tracks.size(); ++k) {
    angles.curves.push_back({data, fmt::format("1:{}", phi1(k + 1)), styles[k], s.tracks[k].name});
    q.curves.push_back({data, fmt::format("1:{}", phi1(k + 1) + n), styles[k], s.tracks[k].name});
  }
  files.write_plot({.description = {"npend corrections: the paper's nonlinear corrections to the "
                                    "harmonic approximation against the true motion",
                                    fmt::format("data: {}", data)},
                    .height = 900,
                    .panels = {angles, q}});
}

int run_corrections(const corrections_command_options& o) {
  const chain c = o.chain.make_chain(cli::model_support::rigid_links, "npend corrections");
  const int n = c.links();
  if (n < 2)
    throw cli::input_error(
        "--links: the correction study needs at least 2 links (for one link the paper's "
        "correction terms vanish, and Q needs two angles)");
  std::vector<double> phi0, dphi0(static_cast<std::size_t>(n));
  const bool own_start = !o.start.phi.empty() || !o.start.energy.empty() || !o.start.p.empty() ||
                         !o.start.dphi.empty() || !o.start.style.empty();
  if (own_start) {
    if (!o.amplitude.empty())
      throw cli::input_error("--amplitude: only for the default start, not with --phi or --energy");
    const std::vector<double> x = o.start.make_state(c);
    phi0.assign(x.begin(), x.begin() + n);
    c.velocities(phi0, std::span(x).subspan(static_cast<std::size_t>(n)), dphi0);
  } else {
    // The default start: the arms zigzag by ±a and all turn at a·ω_1.
    const double a = o.amplitude.empty() ? 0.3 : cli::parse_number(o.amplitude, "--amplitude");
    if (!(a > 0 && a < 1.5))
      throw cli::input_error(fmt::format("--amplitude: must be in (0, 1.5) rad, got {}", a));
    const double omega1 = normal_modes(c, std::vector<double>(static_cast<std::size_t>(n), 0.0))
                              .modes.front()
                              .frequency;
    for (int i = 0; i < n; ++i) {
      phi0.push_back(i % 2 == 0 ? a : -a);
      dphi0[static_cast<std::size_t>(i)] = a * omega1;
    }
  }
  correction_study_options options;
  if (!o.horizon.empty()) {
    options.horizon = cli::parse_number(o.horizon, "--horizon");
    if (!(options.horizon > 0))
      throw cli::input_error(fmt::format("--horizon: must be positive, got {}", o.horizon));
  }
  if (!o.samples.empty())
    options.samples =
        static_cast<std::size_t>(cli::parse_whole_number(o.samples, "--samples", 2, 1e6));
  series_output files(o.out);
  correction_study s;
  try {
    s = harmonic_correction_study(c, phi0, dphi0, options);
  } catch (const std::invalid_argument& e) {
    throw cli::input_error(e.what());
  }
  if (files.enabled()) write_corrections_files(files, s);

  const auto finite = [](double v) {
    return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json();
  };
  if (o.json) {
    nlohmann::json tracks = nlohmann::json::array(), defects = nlohmann::json::array();
    for (const auto& t : s.tracks)
      tracks.push_back({{"name", t.name},
                        {"max_error", t.max_error},
                        {"scaled_errors", t.scaled_errors},
                        {"order", t.order},
                        {"q_end", finite(t.q.back())},
                        {"q_pole", finite(t.q_pole)}});
    for (const auto& d : s.defects)
      defects.push_back(
          {{"truncation", truncation_name(d.kind)}, {"errors", d.errors}, {"order", d.order}});
    nlohmann::json j = describe_chain(c);
    j.update(nlohmann::json{{"phi0", s.phi0},
                            {"dphi0", s.dphi0},
                            {"horizon", s.horizon},
                            {"samples", s.t.size()},
                            {"scales", s.scales},
                            {"true_q_end", finite(s.true_q.back())},
                            {"true_q_pole", finite(s.true_q_pole)},
                            {"tracks", tracks},
                            {"acceleration_defects", defects}});
    files.add_to(j);
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  fmt::print(
      "The paper's nonlinear corrections to the harmonic approximation (section 6.4), {}-link "
      "chain\n",
      n);
  fmt::print("start phi = ({:.4g}) rad, dphi = ({:.4g}) rad/s; horizon {:.4g} s\n\n",
             fmt::join(s.phi0, ", "), fmt::join(s.dphi0, ", "), s.horizon);
  const auto pole = [](double t) { return std::isfinite(t) ? fmt::format("{:.4f}", t) : "none"; };
  fmt::print("{:<20}  {:>26}  {:>18}  {:>18}  {:>14}\n", "", "max |phi - phi_true| (rad)",
             "order in amplitude", "Q at horizon (s^2)", "Q's pole (s)");
  fmt::print("{:<20}  {:>26}  {:>18}  {:>18.5g}  {:>14}\n", "true motion", "-", "-",
             s.true_q.back(), pole(s.true_q_pole));
  for (const auto& t : s.tracks)
    fmt::print("{:<20}  {:>26.3e}  {:>18.2f}  {:>18.5g}  {:>14}\n", t.name, t.max_error, t.order,
               t.q.back(), pole(t.q_pole));
  fmt::print("\nAcceleration error |phi'' - phi''_exact| at t = 0, start scaled by ({:g}):\n",
             fmt::join(s.scales, ", "));
  for (const auto& d : s.defects)
    fmt::print("{:<10} {:.3e}  order {:.2f}\n", truncation_name(d.kind), fmt::join(d.errors, "  "),
               d.order);
  fmt::print(
      "\nharmonic: A0 phi'' + K phi = 0; paper: + the velocity terms A0_ij (phi_i - phi_j) "
      "dphi_j^2\n"
      "(the paper's equations 6.4.1/6.4.2 for any n); cubic: every third-order term (also from\n"
      "sin phi and cos(phi_i - phi_j)). The series are the paper's power series a1 + a2 t + a3 "
      "t^2.\n"
      "Q's pole: the first time phi1' phi2' = 0 (a turning point of phi1 or phi2).\n"
      "Orders: the error's slope against the start's scale. The paper's terms leave terms of the\n"
      "same order out, so its error stays O(a^3) like the harmonic one; the cubic one's is "
      "O(a^5).\n");
  files.print();
  return 0;
}

}  // namespace

void add_corrections_command(CLI::App& app, command_list& commands) {
  auto o = std::make_shared<corrections_command_options>();
  CLI::App* cmd = app.add_subcommand(
      "corrections",
      "The paper's nonlinear corrections and power series against the true motion (Q)");
  o->chain.add_to(*cmd);
  o->start.add_to(*cmd);
  cmd->add_option("--amplitude", o->amplitude,
                  "Default start: phi_i = +-a alternately, dphi_i = a omega_1 (default: 0.3 rad)");
  cmd->add_option("--horizon", o->horizon,
                  "Compare over this time in s (default: a quarter of the shortest linear period)");
  cmd->add_option("--samples", o->samples, "Sample times over the horizon (default: 201)");
  cmd->add_flag("--json", o->json, "Print JSON");
  cmd->add_option("--out", o->out,
                  "Write FILE.csv (t, phi_i and Q of the chain and of every approximation) and "
                  "the plot FILE.png with its gnuplot script FILE.gp");
  commands.push_back({cmd, [o] { return run_corrections(*o); }});
}

}  // namespace npend::app
