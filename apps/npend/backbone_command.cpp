// npend backbone: where the harmonic approximation stops being valid — the measured frequency
// of each normal mode against its amplitude (paper §6.4).
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cmath>
#include <iostream>
#include <nlohmann/json.hpp>
#include <numbers>

#include "chain_options.hpp"
#include "command.hpp"
#include "input_parsing.hpp"
#include "npend/analysis/stability/backbone.hpp"
#include "series_output.hpp"
#include "terminal_run.hpp"

namespace npend::app {

namespace {

struct backbone_command_options {
  cli::chain_options chain;
  std::string mode, amplitudes, periods, steps, thresholds;
  bool json = false;
  std::string out;
};

// "a,b,c" or "FROM:TO:STEP" (FROM, FROM + STEP, … up to TO).
std::vector<double> parse_amplitudes(const std::string& text) {
  if (text.empty()) return parse_amplitudes("0.05:1.5:0.05");
  if (text.find(':') == std::string::npos) return cli::parse_number_list(text, "--amplitudes");
  const auto first = text.find(':'), second = text.find(':', first + 1);
  if (second == std::string::npos || text.find(':', second + 1) != std::string::npos)
    throw cli::input_error(
        fmt::format("--amplitudes: '{}' is neither a list a,b,c nor a range FROM:TO:STEP", text));
  const double from = cli::parse_number(text.substr(0, first), "--amplitudes (FROM)");
  const double to =
      cli::parse_number(text.substr(first + 1, second - first - 1), "--amplitudes (TO)");
  const double step = cli::parse_number(text.substr(second + 1), "--amplitudes (STEP)");
  if (!(step > 0) || to < from || (to - from) / step > 10000)
    throw cli::input_error(fmt::format(
        "--amplitudes: the range {} needs FROM <= TO and a positive STEP giving at most 10000 "
        "amplitudes",
        text));
  std::vector<double> out;
  for (long k = 0; from + static_cast<double>(k) * step <= to * (1 + 1e-12); ++k)
    out.push_back(from + static_cast<double>(k) * step);
  return out;
}

backbone_options make_backbone_options(const backbone_command_options& o) {
  backbone_options b;
  if (!o.periods.empty()) b.periods = cli::parse_number(o.periods, "--periods");
  if (!o.steps.empty())
    b.steps_per_period =
        static_cast<int>(cli::parse_whole_number(o.steps, "--steps-per-period", 20, 1e6));
  if (!(b.periods >= 3 && b.periods <= 1e5))
    throw cli::input_error(fmt::format("--periods: must be in 3..1e5, got {}", b.periods));
  if (!o.thresholds.empty()) {
    b.thresholds = cli::parse_number_list(o.thresholds, "--thresholds");
    for (double s : b.thresholds)
      if (!(s > 0 && s < 1))
        throw cli::input_error(
            fmt::format("--thresholds: {} is not a relative shift in (0, 1) (0.01 = 1 %)", s));
  }
  return b;
}

// The ratio ω/ω_k where |ω/ω_k − 1| = shift on the side the curve departs to.
double threshold_ratio(const backbone_result& r, double shift) {
  for (const auto& p : r.points)
    if (p.measured && std::fabs(p.relative_shift) >= shift)
      return p.relative_shift > 0 ? 1 + shift : 1 - shift;
  return 1 - shift;
}

void write_backbone_files(series_output& files, const chain& c,
                          const std::vector<backbone_result>& curves) {
  std::vector<std::vector<double>> table(9), marks(4);
  for (const auto& r : curves) {
    for (const auto& p : r.points) {
      const std::vector<double> row{static_cast<double>(r.mode),
                                    p.amplitude,
                                    p.energy,
                                    p.measured ? 1.0 : 0.0,
                                    p.frequency,
                                    p.measured ? p.frequency / r.linear_frequency : NAN,
                                    p.relative_shift,
                                    p.period_spread,
                                    p.min_mode_share};
      for (std::size_t k = 0; k < row.size(); ++k) table[k].push_back(row[k]);
    }
    for (const auto& t : r.thresholds)
      if (t.amplitude) {
        marks[0].push_back(r.mode);
        marks[1].push_back(t.shift);
        marks[2].push_back(*t.amplitude);
        marks[3].push_back(threshold_ratio(r, t.shift));
      }
  }
  const std::string data = files.write_csv(
      "",
      std::vector<std::string>{"mode", "amplitude", "energy", "measured", "omega", "ratio",
                               "relative_shift", "period_spread", "min_mode_share"},
      table);
  const std::string thresholds = files.write_csv(
      "thresholds", std::vector<std::string>{"mode", "shift", "amplitude", "ratio"}, marks);
  cli::plot_panel panel{
      .title = fmt::format("Backbone curves of the {}-link chain's normal modes", c.links()),
      .xlabel = "ω / ω_k (measured over the linear frequency)",
      .ylabel = "launch amplitude a (rad)",
      .commands = {"set key bottom left"}};
  std::vector<double> shifts;
  for (const auto& t : curves.front().thresholds) shifts.push_back(t.shift);
  for (std::size_t k = 0; k < shifts.size(); ++k)
    panel.commands.push_back(
        fmt::format("set arrow from {0},graph 0 to {0},graph 1 nohead dt 2 lc rgb '#888888'\n"
                    "set label \"{1:g} %\" at {0},graph {2} right offset -0.3,0 tc rgb '#666666'",
                    1 - shifts[k], 100 * shifts[k], 0.97 - 0.05 * static_cast<double>(k)));
  for (const auto& r : curves)
    panel.curves.push_back(
        {data, fmt::format("($1=={0} ? $6 : 1/0):2", r.mode), "linespoints lw 1.5 pt 7 ps 0.6",
         fmt::format("mode {} (ω_{} = {:.4g} rad/s)", r.mode, r.mode, r.linear_frequency)});
  panel.curves.push_back(
      {thresholds, "4:3", "points pt 6 ps 2 lw 2 lc rgb '#d62728'", "1 % / 5 % departures"});
  if (c.links() == 1) {
    // The exact curve of the single pendulum, from the elliptic integral.
    std::vector<double> a, ratio;
    const double top = curves.front().points.back().amplitude;
    for (int k = 1; k <= 200; ++k) {
      a.push_back(top * k / 200);
      ratio.push_back(pendulum_frequency_ratio(a.back()));
    }
    const std::string exact = files.write_csv(
        "exact", std::vector<std::string>{"amplitude", "ratio"}, std::vector{a, ratio});
    panel.curves.push_back(
        {exact, "2:1", "lines lw 1 dt 3 lc rgb 'black'", "exact: π / (2 K(sin(a/2)))"});
  }
  // Beside it, how much of the motion stays in the launched mode: where the share drops, the
  // launch is no longer close to a periodic orbit and the backbone loses its meaning.
  cli::plot_panel share{.title = "Least share of the launched mode in the linear modal energies",
                        .xlabel = "launch amplitude a (rad)",
                        .ylabel = "min_t E_k / Σ_j E_j",
                        .yrange = "[0:1.05]",
                        .commands = {"set key bottom left"}};
  for (const auto& r : curves)
    share.curves.push_back({data, fmt::format("($1=={0} ? $2 : 1/0):9", r.mode),
                            "linespoints lw 1.5 pt 7 ps 0.6", fmt::format("mode {}", r.mode)});
  files.write_plot(
      {.description = {fmt::format("npend backbone: measured frequency against launch amplitude, "
                                   "{}-link chain",
                                   c.links()),
                       fmt::format("data: {} (per mode and amplitude), {} (the departures)", data,
                                   thresholds)},
       .width = 1400,
       .height = 640,
       .columns = 2,
       .panels = {panel, share}});
}

int run_backbone(const backbone_command_options& o) {
  const chain c = o.chain.make_chain(cli::model_support::rigid_links, "npend backbone");
  const int n = c.links();
  std::vector<int> modes;
  if (o.mode.empty()) {
    for (int k = 1; k <= n; ++k) modes.push_back(k);
  } else {
    modes.push_back(static_cast<int>(cli::parse_whole_number(o.mode, "--mode", 1, n)));
  }
  const std::vector<double> amplitudes = parse_amplitudes(o.amplitudes);
  for (double a : amplitudes)
    if (!(a > 0 && a < std::numbers::pi))
      throw cli::input_error(fmt::format("--amplitudes: {} rad is not in (0, pi)", a));
  backbone_options options = make_backbone_options(o);
  series_output files(o.out);

  cli::terminal_run control;
  std::vector<backbone_result> curves;
  for (std::size_t i = 0; i < modes.size(); ++i) {
    run_control_part part(&control, i, modes.size());
    options.control = &part;
    curves.push_back(backbone_curve(c, modes[i], amplitudes, options));
    if (curves.back().stopped) {
      control.finish();
      fmt::print(stderr, "npend backbone: interrupted in mode {}{}\n", modes[i],
                 o.out.empty() ? "" : fmt::format("; nothing written to {}", o.out));
      return control.exit_code();
    }
  }
  control.finish();
  if (files.enabled()) write_backbone_files(files, c, curves);

  if (o.json) {
    nlohmann::json list = nlohmann::json::array();
    for (const auto& r : curves) {
      nlohmann::json points = nlohmann::json::array(), thresholds = nlohmann::json::array();
      for (const auto& p : r.points) {
        nlohmann::json point{{"amplitude", p.amplitude},
                             {"energy", p.energy},
                             {"measured", p.measured},
                             {"frequency", p.frequency},
                             {"relative_shift", p.relative_shift},
                             {"period_spread", p.period_spread},
                             {"min_mode_share", p.min_mode_share}};
        if (n == 1)
          point["exact_frequency"] = r.linear_frequency * pendulum_frequency_ratio(p.amplitude);
        points.push_back(point);
      }
      for (const auto& t : r.thresholds)
        thresholds.push_back(
            {{"shift", t.shift},
             {"amplitude", t.amplitude ? nlohmann::json(*t.amplitude) : nlohmann::json()},
             {"energy", t.amplitude ? nlohmann::json(t.energy) : nlohmann::json()}});
      list.push_back({{"mode", r.mode},
                      {"linear_frequency", r.linear_frequency},
                      {"shape", r.shape},
                      {"points", points},
                      {"thresholds", thresholds}});
    }
    nlohmann::json j = describe_chain(c);
    j.update(nlohmann::json{{"periods", options.periods},
                            {"steps_per_period", options.steps_per_period},
                            {"modes", list}});
    files.add_to(j);
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  fmt::print(
      "Backbone curves of the {}-link chain: the full nonlinear chain launched along a normal "
      "mode\n"
      "of the hanging position (phi(0) = a v / max|v_i|, p = 0), the frequency of the modal\n"
      "coordinate q = v^T M phi from its zero crossings over {:g} linear periods (Gauss-Legendre,\n"
      "{} steps per period). period spread: (max - min)/mean of the single periods (0 for a\n"
      "periodic orbit); mode share: the least share of the mode in the linear modal energies.\n",
      n, options.periods, options.steps_per_period);
  for (const auto& r : curves) {
    fmt::print("\nMode {}: omega_{} = {:.6g} rad/s, shape ({:.4f})\n", r.mode, r.mode,
               r.linear_frequency, fmt::join(r.shape, ", "));
    fmt::print("{:>10}  {:>12}  {:>14}  {:>10}  {:>13}  {:>10}{}\n", "a (rad)", "energy (J)",
               "omega (rad/s)", "shift (%)", "period spread", "mode share",
               n == 1 ? "  exact omega (elliptic)" : "");
    for (const auto& p : r.points) {
      const std::string exact =
          n == 1 ? fmt::format("  {:>23.10g}",
                               r.linear_frequency * pendulum_frequency_ratio(p.amplitude))
                 : "";
      if (p.measured)
        fmt::print("{:>10.4g}  {:>12.5g}  {:>14.8g}  {:>10.4f}  {:>13.2g}  {:>10.4f}{}\n",
                   p.amplitude, p.energy, p.frequency, 100 * p.relative_shift, p.period_spread,
                   p.min_mode_share, exact);
      else
        fmt::print("{:>10.4g}  {:>12.5g}  {:>14}  {:>10}  {:>13}  {:>10.4f}{}\n", p.amplitude,
                   p.energy, "no oscillation", "-", "-", p.min_mode_share, exact);
    }
    for (const auto& t : r.thresholds) {
      if (t.amplitude)
        fmt::print("{:g} % departure from omega_{} at a = {:.4f} rad (E = {:.5g} J)\n",
                   100 * t.shift, r.mode, *t.amplitude, t.energy);
      else
        fmt::print("{:g} % departure from omega_{}: not reached up to a = {:.4g} rad\n",
                   100 * t.shift, r.mode, r.points.back().amplitude);
    }
  }
  if (n > 1)
    fmt::print(
        "\nFor n >= 2 a launch along a linear mode is not a periodic orbit at finite amplitude:\n"
        "energy leaks into the other modes (mode share < 1, period spread > 0), and omega is the\n"
        "mean frequency of the modal coordinate.\n");
  files.print();
  return 0;
}

}  // namespace

void add_backbone_command(CLI::App& app, command_list& commands) {
  auto o = std::make_shared<backbone_command_options>();
  CLI::App* cmd = app.add_subcommand(
      "backbone",
      "Validity of the harmonic approximation: frequency against amplitude along each mode");
  o->chain.add_to(*cmd);
  cmd->add_option("--mode", o->mode, "Only this mode (1 = the slowest; default: all)");
  cmd->add_option("--amplitudes", o->amplitudes,
                  "Launch amplitudes in rad (the largest start angle): a list a,b,c or a "
                  "range FROM:TO:STEP (default: 0.05:1.5:0.05)");
  cmd->add_option("--periods", o->periods, "Linear periods integrated per amplitude (default: 20)");
  cmd->add_option("--steps-per-period", o->steps,
                  "Gauss-Legendre steps per linear period (default: 200)");
  cmd->add_option("--thresholds", o->thresholds,
                  "Relative frequency departures to locate (default: 0.01,0.05)");
  cmd->add_flag("--json", o->json, "Print JSON");
  cmd->add_option("--out", o->out,
                  "Write FILE.csv (per mode and amplitude), FILE_thresholds.csv and the plot "
                  "FILE.png with its gnuplot script FILE.gp");
  commands.push_back({cmd, [o] { return run_backbone(*o); }});
}

}  // namespace npend::app
