// npend equilibria, npend modes, npend toda-brumer: the linear stability analysis of the paper
// (§6.4, §6.5) for any link count.
#include <fmt/format.h>

#include <cmath>
#include <cstdint>
#include <iostream>
#include <nlohmann/json.hpp>
#include <numbers>

#include "chain_options.hpp"
#include "command.hpp"
#include "input_parsing.hpp"
#include "npend/analysis/stability/equilibria.hpp"
#include "npend/analysis/stability/normal_modes.hpp"
#include "npend/analysis/chaos/toda_brumer.hpp"
#include "series_output.hpp"
#include "stability_tables.hpp"
#include "work_estimate.hpp"

namespace npend::app {

namespace {

std::string angle_text(double a) { return a == 0.0 ? "0" : "pi"; }

// The eigenvalues come in ± pairs: show each pair once, real pairs first.
std::string eigenvalue_pairs(const std::vector<std::complex<double>>& values) {
  std::string out;
  for (const auto& z : values) {
    if (z.real() > 0)
      out += fmt::format("±{:.6g}  ", z.real());
    else if (z.real() == 0.0 && z.imag() > 0)
      out += fmt::format("±{:.6g}i  ", z.imag());
  }
  return out;
}

}  // namespace

void print_equilibria_table(const chain& c, const std::vector<equilibrium>& eqs) {
  const bool all = c.links() <= max_equilibria_links &&
                   eqs.size() == (std::size_t{1} << static_cast<unsigned>(c.links()));
  if (all)
    fmt::print("The {} equilibria of the {}-link chain (p = 0, each angle 0 or pi):\n\n",
               eqs.size(), c.links());
  else
    fmt::print("{} of the 2^{} equilibria of the {}-link chain (p = 0, each angle 0 or pi):\n\n",
               eqs.size(), c.links(), c.links());
  fmt::print("{:>4}  {:<{}}  {:>14}  {:<8}  {:>8}  {}\n", "#", "angles", 3 * c.links(),
             "energy (J)", "stable", "unstable", "Jacobian eigenvalues (1/s)");
  for (std::size_t k = 0; k < eqs.size(); ++k) {
    const auto& e = eqs[k];
    std::string angles;
    for (double a : e.angles) angles += fmt::format("{:<3}", angle_text(a));
    const std::string values = eigenvalue_pairs(e.eigenvalues);
    fmt::print("{:>4}  {:<{}}  {:>14.6g}  {:<8}  {:>8}  {}\n", k + 1, angles, 3 * c.links(),
               e.energy, e.stable ? "yes" : "no", e.unstable_directions, values);
  }
  fmt::print(
      "\nstable = elliptic (all eigenvalues imaginary); unstable = eigenvalues with "
      "positive real part.\n");
}

void print_modes_table(const linearisation& lin) {
  const auto n = lin.angles.size();
  std::string where;
  for (double a : lin.angles) where += (where.empty() ? "" : ", ") + fmt::format("{:.6g}", a);
  fmt::print("Linearisation M y'' + K y = 0 of the {}-link chain at phi = ({}):\n\n", n, where);
  fmt::print("{:>4}  {:>14}  {:>16}  {}\n", "mode", "omega^2 (1/s^2)", "frequency",
             "shape (M-normalised)");
  for (std::size_t k = 0; k < lin.modes.size(); ++k) {
    const auto& m = lin.modes[k];
    const std::string f = m.omega_squared > 0 ? fmt::format("{:.6g} rad/s", m.frequency)
                                              : fmt::format("unstable, {:.4g}/s", m.growth_rate);
    std::string shape;
    for (double v : m.shape) shape += fmt::format("{:>10.4f}", v);
    fmt::print("{:>4}  {:>14.6g}  {:>16}  {}\n", k + 1, m.omega_squared, f, shape);
  }
}

namespace {

// Refuses, before it starts, linearisations of a chain too long for the dense n x n
// generalised eigenproblem each of them is (normal_modes): about 10 matrices of n² doubles and
// 12 n³ operations (Cholesky, reduction to tridiagonal form, QR with eigenvectors).
void require_dense_modes(const chain& c, double count, std::string_view what) {
  const double n = c.links();
  cli::require_feasible(
      {.bytes = 10 * 8 * n * n, .flops = count * 12 * n * n * n},
      fmt::format("{} of {} links ({}a dense {} x {} eigenproblem)", what, c.links(),
                  count > 1 ? fmt::format("{:g} times ", count) : "", c.links(), c.links()),
      "npend rope gives the modes of a long hanging chain of point masses in O(n) memory");
}

// ---- npend equilibria -------------------------------------------------------------------

struct equilibria_options {
  cli::chain_options chain;
  std::vector<std::string> at;
  bool json = false;
};

// The equilibria asked for with --at; without it all 2^n, or for a chain too long to list
// them the hanging and the standing one.
std::vector<equilibrium> chosen_equilibria(const chain& c, const std::vector<std::string>& at) {
  const int n = c.links();
  std::vector<std::vector<double>> chosen;
  for (const auto& text : at) chosen.push_back(cli::parse_angle_list(text, "--at", n));
  if (chosen.empty()) {
    if (n <= max_equilibria_links) return find_equilibria(c);
    chosen = {std::vector<double>(static_cast<std::size_t>(n), 0.0),
              std::vector<double>(static_cast<std::size_t>(n), std::numbers::pi)};
  }
  std::vector<equilibrium> out;
  for (auto& angles : chosen) {
    try {
      out.push_back(classify_equilibrium(c, std::move(angles)));
    } catch (const std::invalid_argument& e) {
      throw cli::input_error(fmt::format("--at: {}", e.what()));
    }
  }
  return out;
}

int run_equilibria(const equilibria_options& o) {
  const chain c = o.chain.make_chain(cli::model_support::rigid_links, "npend equilibria");
  if (c.links() > max_equilibria_links)
    require_dense_modes(c, o.at.empty() ? 2.0 : static_cast<double>(o.at.size()),
                        "the linear stability");
  const auto eqs = chosen_equilibria(c, o.at);
  if (o.json) {
    nlohmann::json list = nlohmann::json::array();
    for (const auto& e : eqs) {
      list.push_back({{"angles", e.angles},
                      {"energy", e.energy},
                      {"eigenvalues", json_complex_list(e.eigenvalues)},
                      {"stable", e.stable},
                      {"unstable_directions", e.unstable_directions}});
    }
    std::cout << nlohmann::json{{"links", c.links()}, {"equilibria", list}}.dump(2) << "\n";
    return 0;
  }
  print_equilibria_table(c, eqs);
  return 0;
}

// ---- npend modes --------------------------------------------------------------------------

struct modes_options {
  cli::chain_options chain;
  std::string at;
  bool json = false;
};

int run_modes(const modes_options& o) {
  const chain c = o.chain.make_chain(cli::model_support::rigid_links, "npend modes");
  require_dense_modes(c, 1, "the normal modes");
  const int n = c.links();
  std::vector<double> at(static_cast<std::size_t>(n), 0.0);
  if (!o.at.empty()) at = cli::parse_angle_list(o.at, "--at", n);
  linearisation lin;
  try {
    lin = normal_modes(c, at);
  } catch (const std::invalid_argument& e) {
    throw cli::input_error(fmt::format("--at: {}", e.what()));
  }
  if (o.json) {
    nlohmann::json shapes = nlohmann::json::array(), omega2 = nlohmann::json::array(),
                   freq = nlohmann::json::array(), growth = nlohmann::json::array();
    for (const auto& m : lin.modes) {
      shapes.push_back(m.shape);
      omega2.push_back(m.omega_squared);
      if (m.omega_squared > 0)
        freq.push_back(m.frequency);
      else
        growth.push_back(m.growth_rate);
    }
    nlohmann::json j{{"links", n},
                     {"at", lin.angles},
                     {"omega_squared", omega2},
                     {"frequencies", freq},
                     {"growth_rates", growth},
                     {"shapes", shapes},
                     {"mass_matrix", lin.mass_matrix},
                     {"stiffness_matrix", lin.stiffness_matrix}};
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  print_modes_table(lin);
  return 0;
}

// ---- npend toda-brumer -------------------------------------------------------------------

struct toda_options {
  cli::chain_options chain;
  std::string phi, fixed;
  bool json = false;
};

std::vector<int> parse_fixed(const std::string& text, int links) {
  std::vector<int> out;
  if (text.empty()) return out;
  for (const double v : cli::parse_number_list(text, "--fixed")) {
    if (!cli::is_whole_number(v, 1, links))
      throw cli::input_error(fmt::format("--fixed: {} is not a link number 1..{}", v, links));
    out.push_back(static_cast<int>(v));
  }
  return out;
}

int run_toda(const toda_options& o) {
  const chain c = o.chain.make_chain(cli::model_support::rigid_links, "npend toda-brumer");
  const int n = c.links();
  const auto links = toda_brumer_links(c);
  const std::vector<int> fixed = parse_fixed(o.fixed, n);
  if (static_cast<int>(fixed.size()) >= n && !fixed.empty()) {
    std::vector<bool> seen(static_cast<std::size_t>(n), false);
    for (int k : fixed) seen[static_cast<std::size_t>(k - 1)] = true;
    if (std::all_of(seen.begin(), seen.end(), [](bool b) { return b; }))
      throw cli::input_error("--fixed: every link is fixed; leave at least one free");
  }
  const double critical = toda_brumer_critical_energy(c, fixed);
  std::vector<double> lambda;
  bool unstable = false;
  if (!o.phi.empty()) {
    const auto phi = cli::parse_number_list(o.phi, "--phi", static_cast<std::size_t>(n),
                                            fmt::format("phi_1..phi_{}", n));
    lambda = toda_brumer_eigenvalues(c, phi);
    unstable = lambda.back() > 0;
  }
  if (o.json) {
    nlohmann::json list = nlohmann::json::array();
    for (const auto& l : links)
      list.push_back({{"link", l.link},
                      {"curvature", l.curvature},
                      {"unstable_interval", {std::numbers::pi / 2, 3 * std::numbers::pi / 2}},
                      {"critical_energy", l.critical_energy}});
    nlohmann::json j{
        {"links", n}, {"per_link", list}, {"fixed", fixed}, {"critical_energy", critical}};
    if (!lambda.empty()) {
      j["eigenvalues"] = lambda;
      j["unstable"] = unstable;
    }
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  fmt::print(
      "Toda-Brumer: eigenvalues of -d2V/dphi2 are Lambda_k = -g mu_k l_k cos(phi_k); some\n"
      "Lambda_k > 0 (pi/2 < phi_k < 3pi/2 mod 2pi) marks a locally unstable region.\n\n");
  fmt::print("{:>5}  {:>18}  {:>28}\n", "link", "g mu_k l_k (J)", "E_c entering from rest (J)");
  for (const auto& l : links)
    fmt::print("{:>5}  {:>18.6g}  {:>28.6g}\n", l.link, l.curvature, l.critical_energy);
  std::string family = "p = 0";
  for (int k : fixed) family += fmt::format(", phi_{} = 0", k);
  fmt::print("\nCritical energy for the family {}: E_c = {:.6g} J\n", family, critical);
  if (!lambda.empty()) {
    std::string values;
    for (double v : lambda) values += fmt::format(" {:.6g}", v);
    fmt::print("At phi = ({}): Lambda ={}; {}\n", o.phi, values,
               unstable ? "in a locally unstable region" : "locally stable");
  }
  return 0;
}

}  // namespace

void add_stability_commands(CLI::App& app, command_list& commands) {
  {
    auto o = std::make_shared<equilibria_options>();
    CLI::App* cmd = app.add_subcommand(
        "equilibria", "All 2^n equilibria with their energy, Jacobian eigenvalues and stability");
    o->chain.add_to(*cmd);
    cmd->add_option("--at", o->at,
                    "Only this equilibrium, phi_1,...,phi_n each 0 or pi (one value for all "
                    "links); repeat for several (default: all 2^n up to 16 links, the hanging "
                    "and the standing chain beyond)");
    cmd->add_flag("--json", o->json, "Print JSON");
    commands.push_back({cmd, [o] { return run_equilibria(*o); }});
  }
  {
    auto o = std::make_shared<modes_options>();
    CLI::App* cmd = app.add_subcommand(
        "modes", "Normal modes of the linearisation M y'' + K y = 0 around an equilibrium");
    o->chain.add_to(*cmd);
    cmd->add_option("--at", o->at,
                    "The equilibrium phi_1,...,phi_n, each 0 or pi (one value for all links; "
                    "default: hanging)");
    cmd->add_flag("--json", o->json, "Print JSON");
    commands.push_back({cmd, [o] { return run_modes(*o); }});
  }
  {
    auto o = std::make_shared<toda_options>();
    CLI::App* cmd = app.add_subcommand(
        "toda-brumer", "Toda-Brumer criterion: unstable regions and critical energies");
    o->chain.add_to(*cmd);
    cmd->add_option("--phi", o->phi, "Evaluate the eigenvalues Lambda at phi_1,...,phi_n");
    cmd->add_option("--fixed", o->fixed,
                    "Links held at phi = 0 for the critical energy of a family, e.g. 1,2");
    cmd->add_flag("--json", o->json, "Print JSON");
    commands.push_back({cmd, [o] { return run_toda(*o); }});
  }
}

}  // namespace npend::app
