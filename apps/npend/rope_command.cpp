// npend rope: the uniform hanging chain's lowest modes for growing n at a fixed total length
// and mass, against the heavy rope's Bessel modes — the continuum limit of paper §6.7,
// measured.
#include <fmt/format.h>

#include <cmath>
#include <iostream>
#include <nlohmann/json.hpp>

#include "command.hpp"
#include "input_parsing.hpp"
#include "npend/analysis/stability/hanging_chain.hpp"
#include "output_file.hpp"
#include "series_output.hpp"

namespace npend::app {

namespace {

struct rope_command_options {
  std::string links = "5,10,20,50,100,200,1000", out;
  int modes = 5;
  double length = 1, mass = 1, g = 9.81;
  bool json = false;
};

constexpr int max_rope_links = 5000;  // a dense eigenvector matrix of n² doubles

std::vector<int> parse_link_counts(const std::string& text) {
  std::vector<int> out;
  for (const double v : cli::parse_number_list(text, "--links")) {
    if (!cli::is_whole_number(v, 1, max_rope_links))
      throw cli::input_error(fmt::format(
          "--links: each link count must be a whole number 1..{}, got {}", max_rope_links, v));
    if (!out.empty() && v <= out.back())
      throw cli::input_error(
          fmt::format("--links: counts must increase, got {} after {}", v, out.back()));
    out.push_back(static_cast<int>(v));
  }
  return out;
}

void require_positive(double value, const char* option, const char* unit) {
  if (!(value > 0) || !std::isfinite(value))
    throw cli::input_error(
        fmt::format("{}: must be a positive number ({}), got {}", option, unit, value));
}

struct chain_result {
  int links = 0;
  std::vector<hanging_chain_mode> modes;
  std::vector<double> relative_error;  ///< ω_k / ω_k(rope) − 1
};

// The observed order p of e ∝ n^−p between the two largest chains, per mode (NaN when a mode
// is missing from either).
std::vector<double> observed_orders(const std::vector<chain_result>& chains, int modes) {
  std::vector<double> out(static_cast<std::size_t>(modes), std::nan(""));
  if (chains.size() < 2) return out;
  const chain_result& a = chains[chains.size() - 2];
  const chain_result& b = chains.back();
  for (std::size_t k = 0; k < out.size(); ++k)
    if (k < a.relative_error.size() && k < b.relative_error.size())
      out[k] = convergence_order(a.relative_error[k], a.links, b.relative_error[k], b.links);
  return out;
}

void write_files(series_output& files, const rope_command_options& o,
                 const std::vector<chain_result>& chains, int modes) {
  std::vector<std::string> names{"links"};
  std::vector<std::vector<double>> columns(1);
  for (int k = 1; k <= modes; ++k) {
    names.push_back(fmt::format("omega_{}", k));
    names.push_back(fmt::format("rel_error_{}", k));
  }
  columns.resize(names.size());
  for (const chain_result& c : chains) {
    columns[0].push_back(c.links);
    for (int k = 0; k < modes; ++k) {
      const bool has = k < static_cast<int>(c.modes.size());
      columns[static_cast<std::size_t>(1 + 2 * k)].push_back(
          has ? c.modes[static_cast<std::size_t>(k)].frequency : std::nan(""));
      columns[static_cast<std::size_t>(2 + 2 * k)].push_back(
          has ? std::fabs(c.relative_error[static_cast<std::size_t>(k)]) : std::nan(""));
    }
  }
  const std::string data = files.write_csv("", names, columns);
  // The shapes of the largest chain against J0(j_0k sqrt(s/L)), s from the free end.
  const chain_result& largest = chains.back();
  const int shown = std::min<int>(modes, static_cast<int>(largest.modes.size()));
  std::vector<std::string> shape_names{"s"};
  std::vector<std::vector<double>> shape_columns(1);
  for (int k = 1; k <= shown; ++k) {
    shape_names.push_back(fmt::format("chain_{}", k));
    shape_names.push_back(fmt::format("rope_{}", k));
  }
  shape_columns.resize(shape_names.size());
  const int n = largest.links;
  for (int i = 0; i <= n; ++i) {  // i = 0: the pivot, x = 0
    const double s = o.length * (n - i) / n;
    shape_columns[0].push_back(s);
    for (int k = 0; k < shown; ++k) {
      const double x = i == 0 ? 0.0
                              : largest.modes[static_cast<std::size_t>(k)]
                                    .displacement[static_cast<std::size_t>(i - 1)];
      shape_columns[static_cast<std::size_t>(1 + 2 * k)].push_back(x);
      shape_columns[static_cast<std::size_t>(2 + 2 * k)].push_back(rope_shape(k + 1, s, o.length));
    }
  }
  const std::string shapes = files.write_csv("shapes", shape_names, shape_columns);

  cli::plot_panel errors{.title = "Relative frequency error against the rope",
                         .xlabel = "links n",
                         .ylabel = "|ω_k / ω_k^{rope} − 1|",
                         .log_x = true,
                         .log_y = true,
                         .commands = {"set key bottom left", "set grid"}};
  cli::plot_panel shape_panel{
      .title = fmt::format("Mode shapes at n = {} (points) and J0 (lines)", n),
      .xlabel = "distance from the free end s (m)",
      .ylabel = "horizontal displacement x / x_{end}",
      .commands = {"set key bottom left", "set grid"}};
  static const char* colours[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd",
                                  "#ff7f0e", "#8c564b", "#e377c2", "#7f7f7f"};
  for (int k = 0; k < modes; ++k) {
    const char* colour = colours[k % 8];
    errors.curves.push_back({data, fmt::format("1:{}", 3 + 2 * k),
                             fmt::format("linespoints lw 2 pt 7 lc rgb '{}'", colour),
                             fmt::format("mode {}", k + 1)});
    if (k >= shown) continue;
    // Every bob for small n; about 60 points per curve for large n.
    shape_panel.curves.push_back(
        {shapes, fmt::format("(int($0) % {} == 0 ? $1 : 1/0):{}", std::max(1, n / 60), 2 + 2 * k),
         fmt::format("points pt 7 ps 0.5 lc rgb '{}'", colour),
         fmt::format("chain, mode {}", k + 1)});
    shape_panel.curves.push_back({shapes, fmt::format("1:{}", 3 + 2 * k),
                                  fmt::format("lines lw 1.5 lc rgb '{}'", colour), ""});
  }
  files.write_plot({.description = {"npend rope: the uniform hanging chain's modes against the "
                                    "heavy rope's (Bessel J0) as the number of links grows",
                                    fmt::format("data: {}, {}", data, shapes)},
                    .width = 1400,
                    .height = 560,
                    .columns = 2,
                    .panels = {errors, shape_panel}});
}

int run_rope(const rope_command_options& o) {
  const std::vector<int> counts = parse_link_counts(o.links);
  if (o.modes < 1 || o.modes > 50)
    throw cli::input_error(fmt::format("--modes: must be 1..50, got {}", o.modes));
  require_positive(o.length, "--length", "the rope's total length in m");
  require_positive(o.mass, "--mass", "the rope's total mass in kg");
  require_positive(o.g, "--g", "m/s^2");
  series_output files(o.out);
  // Every file or none: the CSVs, the script and the plot appear together at the end.
  cli::output_batch batch;

  std::vector<double> rope;
  for (int k = 1; k <= o.modes; ++k) rope.push_back(rope_frequency(k, o.length, o.g));
  std::vector<chain_result> chains;
  for (const int n : counts) {
    chain_result r;
    r.links = n;
    const std::vector<double> masses(static_cast<std::size_t>(n), o.mass / n),
        lengths(static_cast<std::size_t>(n), o.length / n);
    r.modes = hanging_chain_modes(masses, lengths, o.g, std::min(o.modes, n));
    for (std::size_t k = 0; k < r.modes.size(); ++k)
      r.relative_error.push_back(r.modes[k].frequency / rope[k] - 1);
    chains.push_back(std::move(r));
  }
  const std::vector<double> order = observed_orders(chains, o.modes);
  if (files.enabled()) write_files(files, o, chains, o.modes);
  batch.commit_all();

  if (o.json) {
    nlohmann::json j{{"length", o.length}, {"mass", o.mass}, {"g", o.g}, {"modes", o.modes}};
    j["rope_frequencies"] = rope;
    nlohmann::json list = nlohmann::json::array();
    for (const chain_result& c : chains) {
      std::vector<double> w;
      for (const auto& m : c.modes) w.push_back(m.frequency);
      list.push_back(
          {{"links", c.links}, {"frequencies", w}, {"relative_errors", c.relative_error}});
    }
    j["chains"] = list;
    nlohmann::json orders = nlohmann::json::array();
    for (const double p : order) orders.push_back(std::isfinite(p) ? nlohmann::json(p) : nullptr);
    j["order"] = orders;
    files.add_to(j);
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  fmt::print(
      "uniform hanging chain, total length {} m, mass {} kg, g = {} m/s^2: frequencies "
      "(rad/s) and their relative error against the rope\n",
      o.length, o.mass, o.g);
  fmt::print("{:>6}", "n");
  for (int k = 1; k <= o.modes; ++k)
    fmt::print(" {:>12} {:>10}", fmt::format("omega_{}", k), "error");
  fmt::print("\n");
  for (const chain_result& c : chains) {
    fmt::print("{:>6}", c.links);
    for (std::size_t k = 0; k < static_cast<std::size_t>(o.modes); ++k) {
      if (k < c.modes.size())
        fmt::print(" {:>12.8f} {:>+10.2e}", c.modes[k].frequency, c.relative_error[k]);
      else
        fmt::print(" {:>12} {:>10}", "-", "-");
    }
    fmt::print("\n");
  }
  fmt::print("{:>6}", "rope");
  for (const double w : rope) fmt::print(" {:>12.8f} {:>10}", w, "");
  fmt::print("\n");
  if (chains.size() >= 2) {
    fmt::print("observed order p (error ~ n^-p) between n = {} and {}:",
               chains[chains.size() - 2].links, chains.back().links);
    for (const double p : order) fmt::print(" {:.3f}", p);
    fmt::print("\n");
  }
  files.print();
  return 0;
}

}  // namespace

void add_rope_command(CLI::App& app, command_list& commands) {
  auto o = std::make_shared<rope_command_options>();
  CLI::App* cmd = app.add_subcommand(
      "rope",
      "The uniform hanging chain's lowest modes for growing n (fixed total length and mass) "
      "against the heavy rope's Bessel modes: the continuum limit and its order");
  cmd->add_option("--links", o->links,
                  "Increasing link counts, comma-separated (default 5,10,20,50,100,200,1000; "
                  "up to 5000)");
  cmd->add_option("--modes", o->modes, "Number of lowest modes compared (default 5)");
  cmd->add_option("--length", o->length, "Total length L of the chain and rope in m (default 1)");
  cmd->add_option("--mass", o->mass,
                  "Total mass in kg (default 1; the frequencies do not depend on it)");
  cmd->add_option("--g", o->g, "Gravity in m/s^2 (default 9.81)");
  cmd->add_option("--out", o->out,
                  "Write FILE.csv (frequencies and errors per n), FILE_shapes.csv (the largest "
                  "chain's mode shapes against J0) and the plot FILE.gp/FILE.png");
  cmd->add_flag("--json", o->json, "Print JSON");
  commands.push_back({cmd, [o] { return run_rope(*o); }});
}

}  // namespace npend::app
