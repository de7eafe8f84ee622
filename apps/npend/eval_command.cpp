// npend eval: the generated functions at one state.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <chain_index.hpp>
#include <cmath>
#include <iostream>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "chain_options.hpp"
#include "command.hpp"
#include "input_parsing.hpp"
#include "series_output.hpp"

namespace npend::app {

namespace {

struct eval_options {
  cli::chain_options chain;
  std::string state, time;
  bool json = false;
};

// The given input furthest from 1 in magnitude, e.g. "--inertia (1e+300)": what to name when
// a result overflows or underflows double precision (the inputs are finite, each alone valid).
std::string most_extreme_input(const eval_options& o) {
  const cli::chain_options c = o.chain.with_file();  // the values of --chain FILE too
  const std::pair<const char*, const std::string*> lists[] = {{"--masses", &c.masses},
                                                              {"--lengths", &c.lengths},
                                                              {"--g", &c.g},
                                                              {"--com", &c.com},
                                                              {"--inertia", &c.inertia},
                                                              {"--stiffness", &c.stiffness},
                                                              {"--rest-angles", &c.rest_angles},
                                                              {"--damping", &c.damping},
                                                              {"--state", &o.state},
                                                              {"--time", &o.time}};
  std::string name;
  double worst = 0, worst_value = 0;
  const auto consider = [&](const std::string& option, double v) {
    if (v == 0) return;
    const double distance = std::fabs(std::log10(std::fabs(v)));
    if (distance > worst) worst = distance, worst_value = v, name = option;
  };
  for (const auto& [option, text] : lists)
    if (!text->empty())
      for (const std::string_view item : cli::split_list(*text))
        consider(option, cli::parse_number(item, option));
  if (!c.pivot.empty()) {
    const pivot_motion drive = cli::parse_pivot(c.pivot);
    consider("--pivot", drive.amplitude);
    consider("--pivot", drive.frequency);
  }
  return name.empty() ? std::string("the inputs") : fmt::format("{} ({:g})", name, worst_value);
}

// Every result must be a finite number, and det A > 0 (A is positive definite for every chain
// the library accepts): anything else is double precision running out of range.
void require_finite(const eval_options& o, const char* what, std::span<const double> values) {
  for (const double v : values)
    if (!std::isfinite(v))
      throw std::runtime_error(fmt::format(
          "{} is not a finite number ({}): the values are beyond the range of double precision; "
          "the most extreme input is {}",
          what, std::isnan(v) ? std::fabs(v) : v, most_extreme_input(o)));  // "nan", not "-nan"
}

void print_matrix(const char* name, const std::vector<double>& m, int n) {
  fmt::print("{} =\n", name);
  for (int i = 0; i < n; ++i) {
    fmt::print("  ");
    for (int j = 0; j < n; ++j) fmt::print("{:>13.6g}", m[static_cast<std::size_t>(i * n + j)]);
    fmt::print("\n");
  }
}

int run_eval(const eval_options& o) {
  const chain c = o.chain.make_chain(cli::model_support::any, "npend eval", true);
  const int n = c.coordinates();  // q = phi, or [x_c, phi] on a cart
  const auto nn = static_cast<std::size_t>(n);
  const std::vector<double> x = cli::parse_state(o.state, c);
  const double time = o.time.empty() ? 0.0 : cli::parse_number(o.time, "--time");
  const std::span<const double> phi(x.data(), nn), p(x.data() + n, nn);

  std::vector<double> dphi(nn), A(nn * nn);
  c.velocities(phi, p, dphi);
  c.mass_matrix(phi, A);
  const int dim = c.state_size(), inputs = c.input_size();
  std::vector<double> f(static_cast<std::size_t>(dim)), J(static_cast<std::size_t>(dim * dim)),
      dfdt(f.size()), dfdw(static_cast<std::size_t>(dim * inputs));
  c.rhs(x, f, time);
  c.jacobian(x, J, time);
  c.time_derivative(x, dfdt, time);
  c.input_matrix(phi, dfdw);
  const double H = c.hamiltonian(x, time), T = c.kinetic_energy(phi, dphi),
               V = c.potential_energy(phi, time);
  const double detA = c.det_mass_matrix(phi);
  const bool closed_form = n <= 3 && !c.is_physical();
  const double H_closed = closed_form ? c.hamiltonian_closed_form(x) : 0.0;
  require_finite(o, "H", std::span(&H, 1));
  require_finite(o, "T", std::span(&T, 1));
  require_finite(o, "V", std::span(&V, 1));
  require_finite(o, "H (closed form)", std::span(&H_closed, 1));
  require_finite(o, "dphi/dt", dphi);
  require_finite(o, "the mass matrix A", A);
  require_finite(o, "det A", std::span(&detA, 1));
  if (!(detA > 0))
    throw std::runtime_error(fmt::format(
        "det A is {} although the mass matrix is positive definite: it under- or overflows "
        "double precision; the most extreme input is {}",
        detA, most_extreme_input(o)));
  require_finite(o, "f (the right-hand side)", f);
  require_finite(o, "the Jacobian", J);
  require_finite(o, "df/dt", dfdt);
  require_finite(o, "df/dw", dfdw);

  if (o.json) {
    nlohmann::json j = describe_chain(c);
    j["state"] = x;
    j["hamiltonian"] = H;
    j["kinetic_energy"] = T;
    j["potential_energy"] = V;
    j["velocities"] = dphi;
    j["rhs"] = f;
    j["jacobian"] = json_rows(J, static_cast<std::size_t>(2 * n));
    j["mass_matrix"] = json_rows(A, nn);
    j["det_mass_matrix"] = detA;
    j["time"] = time;
    j["time_derivative"] = dfdt;
    j["input_matrix"] = json_rows(dfdw, static_cast<std::size_t>(inputs));
    if (closed_form) j["hamiltonian_closed_form"] = H_closed;
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  fmt::print("{}-link chain: masses {} kg, lengths {} m, g = {} m/s^2\n", c.links(),
             c.parameters().masses, c.parameters().lengths, c.parameters().g);
  fmt::print(
      fmt::runtime(c.has_cart() ? "q = [x_c, phi] = {} (m, rad)\np   = {} (kg m/s, kg m^2/s)\n"
                                : "phi = {} rad\np   = {} kg m^2/s\n"),
      std::vector<double>(phi.begin(), phi.end()), std::vector<double>(p.begin(), p.end()));
  fmt::print("H = {:.17g} J   (T = {:.17g}, V = {:.17g})\n", H, T, V);
  if (c.is_physical()) fmt::print("physical chain: {}; t = {} s\n", describe_chain(c).dump(), time);
  if (closed_form) fmt::print("H (closed form) = {:.17g} J\n", H_closed);
  fmt::print("dphi/dt = {}\n", dphi);
  fmt::print("dp/dt   = {}\n", std::vector<double>(f.begin() + n, f.end()));
  fmt::print("det A = {:.17g}\n", detA);
  print_matrix("A (mass matrix)", A, n);
  print_matrix("J (Jacobian df/dx, x = [phi, p])", J, 2 * n);
  fmt::print("df/dw (w = [{}, u_1..u_{}]) =\n", c.has_cart() ? "F" : "a_x, a_y", c.links());
  for (int i = 0; i < dim; ++i) {
    fmt::print("  ");
    for (int k = 0; k < inputs; ++k)
      fmt::print("{:>13.6g}", dfdw[static_cast<std::size_t>(i * inputs + k)]);
    fmt::print("\n");
  }
  return 0;
}

}  // namespace

void add_eval_command(CLI::App& app, command_list& commands) {
  auto opts = std::make_shared<eval_options>();
  CLI::App* cmd = app.add_subcommand(
      "eval", "Evaluate the generated functions (H, f, Jacobian, mass matrix) at one state");
  opts->chain.add_to(*cmd);
  cmd->add_option("--state", opts->state,
                  "The state phi_1,...,phi_n,p_1,...,p_n (rad, kg m^2/s); with --cart "
                  "x_c,phi_1,...,phi_n,p_x,p_1,...,p_n")
      ->required();
  cmd->add_option("--time", opts->time,
                  "The time t in s (a moving pivot's phase; default 0): rhs, jacobian, H and "
                  "df/dt at t");
  cmd->add_flag("--json", opts->json, "Print one JSON object");
  commands.push_back({cmd, [opts] { return run_eval(*opts); }});
}

void add_equations_command(CLI::App& app, command_list& commands) {
  struct equations_options {
    cli::chain_options chain;
    bool physical = false;
  };
  auto opts = std::make_shared<equations_options>();
  CLI::App* cmd = app.add_subcommand(
      "equations", "Print the derived equations of the n-link chain as LaTeX (from npend-gen)");
  cmd->add_option("--links,-n", opts->chain.links, "Number of links n")->required();
  cmd->add_flag("--physical", opts->physical,
                "The physical chain's equations (rigid links, joint springs, damping and torques, "
                "a moving pivot) instead of the paper's");
  commands.push_back({cmd, [opts] {
                        const chain c = opts->chain.make_chain(cli::model_support::any);
                        std::cout << (opts->physical ? c.physical_table().equations_latex()
                                                     : c.equations_latex());
                        return 0;
                      }});
}

}  // namespace npend::app
