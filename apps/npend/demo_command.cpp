// npend demo: the paper's story for the triple pendulum, end to end (the README's main job).
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <chain_index.hpp>
#include <cmath>
#include <iostream>
#include <memory>
#include <string>

#include "command.hpp"
#include "demo_sections.hpp"
#include "npend/chain.hpp"
#include "output_file.hpp"

namespace npend::app {

void demo_equations(const demo_context& demo) {
  const chain& c = demo.triple;
  fmt::print("## 1. The equations, derived by npend-gen with GiNaC (LaTeX)\n\n");
  std::cout << c.equations_latex() << "\n";

  fmt::print("## 2. The generated functions at a sample state\n\n");
  const std::vector<double> x{0.3, -0.2, 0.5, 0.1, 0.2, -0.1};
  const std::vector<double> f = c.rhs(x);
  const double h = c.hamiltonian(x), h_closed = c.hamiltonian_closed_form(x);
  fmt::print("state x = [phi_1..3, p_1..3] = {}\n", x);
  fmt::print("H (O(n) articulated-body kernel) = {:.17g} J\n", h);
  fmt::print("H (closed form, 1/(2 det A) p^T adj(A) p + V) = {:.17g} J   (difference {:.2g})\n",
             h_closed, h - h_closed);
  fmt::print("dphi/dt = {}\n", std::vector<double>(f.begin(), f.begin() + 3));
  fmt::print("dp/dt   = {}\n", std::vector<double>(f.begin() + 3, f.end()));
  const std::vector<double> J = c.jacobian(x);
  double trace = 0;
  for (int i = 0; i < 6; ++i) trace += J[static_cast<std::size_t>(i * 6 + i)];
  fmt::print("trace of the Jacobian (div f, 0 for a Hamiltonian flow) = {:.3g}\n\n", trace);
}

namespace {

int run_demo(const std::string& out) {
  // A bad --out fails before anything is computed.
  const demo_context demo{chain(chain_parameters::uniform(3)), cli::output_folder(out, "--out")};
  // Every file or none: an interrupted or failed demo leaves no half set of figures.
  cli::output_batch batch;
  fmt::print("# npend demo: the planar triple pendulum (m = 1 kg, l = 1 m, g = 9.81 m/s^2)\n\n");
  demo_equations(demo);
  demo_motion(demo);
  demo_stability(demo);
  demo_forms_of_motion(demo);
  demo_physical(demo);
  batch.commit_all();
  return 0;
}

}  // namespace

void add_demo_command(CLI::App& app, command_list& commands) {
  CLI::App* cmd = app.add_subcommand(
      "demo", "The paper's study of the triple pendulum, end to end (the README's main job)");
  auto out = std::make_shared<std::string>("npend-demo");
  cmd->add_option("--out", *out,
                  "The folder for the figures 6.8-6.13, their data and index.md (created if "
                  "missing; files in it are replaced)")
      ->capture_default_str();
  commands.push_back({cmd, [out] { return run_demo(*out); }});
}

}  // namespace npend::app
