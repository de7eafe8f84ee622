// npend control: the LQR design that holds a chain at an equilibrium (the standing triple
// pendulum of the paper's introduction), and how far off it still catches the chain.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <nlohmann/json.hpp>

#include "chain_options.hpp"
#include "command.hpp"
#include "control_options.hpp"
#include "input_parsing.hpp"
#include "integrator_options.hpp"
#include "series_output.hpp"
#include "terminal_run.hpp"

namespace npend::app {

namespace {

struct control_command_options {
  cli::chain_options chain;
  cli::control_options control;
  bool largest_catch = false;
  double catch_time = 30;
  bool json = false;
};

// The step of the runs that find the largest catch (gauss6).
constexpr double catch_dt = 1e-3;

// Whether the feedback brings the chain started at x* + δ (every angle) back to within 1e-6
// of x* by t_end (gauss6, dt = catch_dt); a run that fails to integrate is not caught.
bool catches(const chain& c, const lqr_design& d, double delta, double t_end,
             run_control* control) {
  std::vector<double> x0 = d.equilibrium;
  for (int i = 0; i < c.links(); ++i) x0[static_cast<std::size_t>(c.angle_index(i))] += delta;
  integration_options o;
  o.stepper = stepper_kind::gauss6;
  o.t_end = t_end;
  o.dt = catch_dt;
  o.control = control;
  try {
    const auto r = integrate_under_feedback(c, d, x0, o);
    double dev = 0;
    for (std::size_t i = 0; i < r.state.size(); ++i)
      dev = std::max(dev, std::fabs(r.state[i] - d.equilibrium[i]));
    return !r.stopped && dev < 1e-6;
  } catch (const std::exception&) {
    return false;
  }
}

struct catch_result {
  double caught = 0, lost = 0;  ///< the bracket bisection ended with
  bool any_lost = false;        ///< false: every deflection tried (up to 3.1 rad) was caught
  bool stopped = false;
};

// Bisection on the deflection between a caught one and a lost one (the largest δ in 0.05 rad
// steps up to π that is still caught, refined to 1e-3 rad). Catching need not be monotone in
// δ far from the equilibrium; the result is the edge of the caught region around x*.
catch_result largest_catch(const chain& c, const lqr_design& d, double t_end,
                           cli::terminal_run& control) {
  catch_result r;
  const int coarse = 62, fine = 6;
  int done = 0;
  const auto step = [&](double delta) {
    run_control_part part(&control, static_cast<std::size_t>(done++),
                          static_cast<std::size_t>(coarse + fine));
    const bool ok = catches(c, d, delta, t_end, &part);
    r.stopped = r.stopped || control.interrupted();
    return ok;
  };
  double lo = 0, hi = 0;
  for (int k = 1; k <= coarse && !r.stopped; ++k) {
    const double delta = 0.05 * k;
    if (delta >= 3.14) break;
    if (!step(delta)) {
      hi = delta;
      break;
    }
    lo = delta;
  }
  r.any_lost = hi > 0;
  if (!r.any_lost) hi = lo;
  for (int k = 0; k < fine && hi > lo && !r.stopped; ++k) {
    const double mid = (lo + hi) / 2;
    (step(mid) ? lo : hi) = mid;
  }
  r.caught = lo;
  r.lost = hi;
  return r;
}

int run_control_design(const control_command_options& o) {
  const chain c = o.chain.make_chain(cli::model_support::any, "npend control", true);
  if (!(o.catch_time > 0) || !std::isfinite(o.catch_time))
    throw cli::input_error(
        fmt::format("--catch-time: must be a positive time in s, got {}", o.catch_time));
  cli::check_step_count(o.catch_time, catch_dt, "--catch-time",
                        "each run steps 0.001 s; use a shorter --catch-time");
  const lqr_design d = o.control.design(c);
  const int n = c.links(), dim = c.state_size(), m = static_cast<int>(d.actuated.size());
  // The actuators by name: joint numbers 1..n, and "cart" for the cart's force.
  std::vector<std::string> joints;
  nlohmann::json joints_json = nlohmann::json::array();
  for (const int k : d.actuated) {
    const int joint = k - (c.actuators() - n) + 1;
    joints.push_back(joint == 0 ? "cart" : std::to_string(joint));
    joints_json.push_back(joint == 0 ? nlohmann::json("cart") : nlohmann::json(joint));
  }

  std::optional<catch_result> caught;
  if (o.largest_catch) {
    cli::terminal_run control;
    caught = largest_catch(c, d, o.catch_time, control);
    control.finish();
    if (caught->stopped) {
      fmt::print(stderr, "npend control: interrupted\n");
      return control.exit_code();
    }
  }

  if (o.json) {
    nlohmann::json j = describe_chain(c);
    j["equilibrium"] = d.equilibrium;
    j["actuated"] = joints_json;
    j["controllable"] = d.controllable;
    j["uncontrollable_eigenvalues"] = json_complex_list(d.uncontrollable);
    j["A"] = json_rows(d.A, static_cast<std::size_t>(dim));
    j["B"] = json_rows(d.B, static_cast<std::size_t>(m));
    j["gain"] = json_rows(d.gain, static_cast<std::size_t>(dim));
    j["riccati"] = json_rows(d.riccati, static_cast<std::size_t>(dim));
    j["riccati_residual"] = d.riccati_residual;
    j["open_loop_eigenvalues"] = json_complex_list(d.open_loop);
    j["closed_loop_eigenvalues"] = json_complex_list(d.closed_loop);
    if (caught) {
      j["largest_catch"] = caught->caught;
      j["first_lost"] = caught->any_lost ? nlohmann::json(caught->lost) : nlohmann::json(nullptr);
      j["catch_time"] = o.catch_time;
    }
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  fmt::print("{}-link chain{} held at phi* = {} with motors at joint{} {}\n", n,
             c.has_cart() ? " on a cart" : "",
             std::vector<double>(d.equilibrium.begin() + c.angle_index(0),
                                 d.equilibrium.begin() + c.angle_index(0) + n),
             m == 1 ? "" : "s", fmt::format("[{}]", fmt::join(joints, ", ")));
  fmt::print("open loop: largest real part {:.6g} 1/s ({})\n", d.open_loop.front().real(),
             d.open_loop.front().real() > 0 ? "unstable" : "not unstable");
  fmt::print("controllable: {}\n", d.controllable ? "yes" : "no");
  for (const auto& l : d.uncontrollable)
    fmt::print("  uncontrollable mode: {:.6g}{:+.6g}i\n", l.real(), l.imag());
  fmt::print("LQR gain K (u = -K (x - x*), rows: joints [{}]):\n", fmt::join(joints, ", "));
  for (int k = 0; k < m; ++k) {
    fmt::print("  ");
    for (int i = 0; i < dim; ++i)
      fmt::print("{:>13.6g}", d.gain[static_cast<std::size_t>(k * dim + i)]);
    fmt::print("\n");
  }
  fmt::print("closed-loop eigenvalues:\n");
  for (const auto& l : d.closed_loop) fmt::print("  {:>14.8g} {:+14.8g}i\n", l.real(), l.imag());
  fmt::print("Riccati residual (relative) {:.2g}\n", d.riccati_residual);
  if (caught && caught->any_lost)
    fmt::print(
        "largest deflection caught (every angle off by delta, back within 1e-6 in {} s): "
        "{:.4g} rad; lost at {:.4g} rad\n",
        o.catch_time, caught->caught, caught->lost);
  else if (caught)
    fmt::print(
        "every deflection tried was caught (every angle off by up to {:.4g} rad, back "
        "within 1e-6 in {} s)\n",
        caught->caught, o.catch_time);
  return 0;
}

}  // namespace

void add_control_command(CLI::App& app, command_list& commands) {
  auto o = std::make_shared<control_command_options>();
  CLI::App* cmd = app.add_subcommand(
      "control",
      "LQR design holding the chain at an equilibrium (e.g. standing, --at pi,pi,pi): "
      "linearisation, controllability, gain, closed-loop eigenvalues");
  o->chain.add_to(*cmd);
  o->control.add_to(*cmd);
  cmd->add_flag("--largest-catch", o->largest_catch,
                "Also find the largest deflection of every angle from which the nonlinear chain "
                "under the feedback returns (bisection, gauss6 runs)");
  cmd->add_option("--catch-time", o->catch_time,
                  "With --largest-catch: the time a run has to return, in s (default 30)");
  cmd->add_flag("--json", o->json, "Print JSON");
  commands.push_back({cmd, [o] { return run_control_design(*o); }});
}

}  // namespace npend::app
