// npend map's options parsed into the library's map description (map_options.hpp).
#include "map_options.hpp"

#include <fmt/format.h>

#include <stdexcept>
#include <string_view>

#include "input_parsing.hpp"
#include "integrator_options.hpp"
#include "npend/integrators/stepper_kind.hpp"
#include "section_spec.hpp"

namespace npend::app {

namespace {

using axis = map_axis;

// NAME:FROM:TO:COUNT: count values from `from` to `to`, both ends included, of a start
// coordinate, the energy or a parameter of the chain (map_grid.hpp).
axis parse_axis(const std::string& text, const char* option, int links) {
  const auto parts = cli::split_list(text, ':');
  if (parts.size() != 4)
    throw cli::input_error(fmt::format(
        "{}: expected NAME:FROM:TO:COUNT (e.g. phi1:-3.14:3.14:256), got '{}'", option, text));
  const double from = cli::parse_number(parts[1], option);
  const double to = cli::parse_number(parts[2], option);
  const double count = cli::parse_number(parts[3], option);
  if (!cli::is_whole_number(count, 1, 16384))
    throw cli::input_error(
        fmt::format("{}: the count must be a whole number 1..16384, got {}", option, parts[3]));
  try {
    return make_map_axis(cli::trim(parts[0]), from, to, static_cast<int>(count), links);
  } catch (const std::invalid_argument& e) {
    throw cli::input_error(fmt::format("{}: {}", option, e.what()));
  }
}

// --stepper, --abs-tol and --rel-tol. Throws input_error naming the option.
map_stepping map_stepping_of(const map_command_options& o, map_quantity quantity) {
  map_stepping stepping;
  if (!o.stepper.empty()) {
    try {
      stepping.stepper = parse_stepper_kind(o.stepper);
    } catch (const std::invalid_argument& e) {
      throw cli::input_error(fmt::format("--stepper: {}", e.what()));
    }
    if (!is_map_stepper(stepping.stepper))
      throw cli::input_error(fmt::format("--stepper: a map integrates with one of {}, not {}",
                                         map_stepper_names(), o.stepper));
  }
  if (!map_takes_stepper(quantity, stepping.stepper)) {
    if (stepping.stepper == stepper_kind::taylor)
      throw cli::input_error(fmt::format(
          "--stepper: taylor maps only the chaos indicators (fli, megno, sali, gali), not {}",
          map_quantity_name(quantity)));
    throw cli::input_error(fmt::format(
        "--stepper: the chaos indicators ({}) integrate with one of {}; {} takes "
        "flip, lyapunov and state",
        map_quantity_name(quantity), stepper_names(stepper_use::indicators), o.stepper));
  }
  const bool adaptive =
      stepping.stepper == stepper_kind::dopri5 || stepping.stepper == stepper_kind::taylor;
  cli::parse_tolerances(o.abs_tol, o.rel_tol, o.tol,
                        adaptive ? ""
                                 : "only with --stepper dopri5 or taylor (the others take a "
                                   "fixed --dt)",
                        stepping.abs_tol, stepping.rel_tol);
  return stepping;
}

// What each cell computes. Throws input_error for an unknown quantity or component.
map_cell_options cell_options(const map_command_options& o, int links) {
  map_cell_options cell;
  try {
    cell.quantity = parse_map_quantity(o.quantity);
  } catch (const std::invalid_argument& e) {
    throw cli::input_error(fmt::format("--{}", e.what()));
  }
  cell.t_end = o.t_end;
  cell.dt = o.dt;
  cell.flip_link = o.flip_link;
  cell.gali_order = o.gali_order;
  cell.stepping = map_stepping_of(o, cell.quantity);
  if (cell.quantity == map_quantity::state)
    cell.component = static_cast<int>(
        cli::parse_coordinate(o.component.empty() ? "phi1" : o.component, links, "--component"));
  else if (!o.component.empty())
    throw cli::input_error("--component: only with --quantity state");
  return cell;
}

// map_grid::validate's message with the option it is about: "--x: m2 = -1: ...".
std::string axis_message(const map_grid& grid, std::string_view what) {
  constexpr std::string_view both = "x and y: ";
  if (what.substr(0, both.size()) == both)
    return fmt::format("--x and --y: {}", what.substr(both.size()));
  const auto names = [&](const axis& a) {
    return what.substr(0, a.name.size()) == a.name && what.find_first_of(": =") == a.name.size();
  };
  if (names(grid.x)) return fmt::format("--x: {}", what);
  if (names(grid.y)) return fmt::format("--y: {}", what);
  return std::string(what);
}

// The start every cell shares: --phi, and --p or --dphi (default 0).
void set_base_start(const map_command_options& o, int n, map_grid& grid) {
  grid.angles.assign(static_cast<std::size_t>(n), 0.0);
  grid.momenta.assign(static_cast<std::size_t>(n), 0.0);
  if (!o.phi.empty()) grid.angles = cli::parse_angle_list(o.phi, "--phi", n);
  if (!o.p.empty() && !o.dphi.empty())
    throw cli::input_error("--p and --dphi: give the start's momenta or its velocities, not both");
  grid.velocities = !o.dphi.empty();
  if (!o.p.empty())
    grid.momenta = cli::parse_number_list(o.p, "--p", static_cast<std::size_t>(n),
                                          fmt::format("p_1..p_{}", n));
  if (!o.dphi.empty())
    grid.momenta = cli::parse_number_list(o.dphi, "--dphi", static_cast<std::size_t>(n),
                                          fmt::format("dphi_1..dphi_{}", n));
}

}  // namespace

void add_map_view_options(CLI::App& cmd, map_command_options& o) {
  o.chain.add_to(cmd, false);  // --links is required all the same: the callers check it
  cmd.add_option("--x", o.x,
                 "NAME:FROM:TO:COUNT (required), NAME a start coordinate (phiK, pK, or dphiK with "
                 "--dphi), energy (J: the start's momenta scaled to it), or a parameter of the "
                 "chain (mK, lK, g, kK, bK: joint K's stiffness and damping, drive-amplitude and "
                 "drive-frequency of a --pivot drive)");
  cmd.add_option("--y", o.y, "NAME:FROM:TO:COUNT for the rows (row 0 = FROM) (required)");
  cmd.add_option("--quantity", o.quantity,
                 "flip (default: the time to the first flip), lyapunov (the maximal exponent), "
                 "a fast indicator at --t-end: fli, megno (<Y>), sali, gali (GALI_k), or state "
                 "(a coordinate of the state at --t-end, see --component)");
  cmd.add_option("--component", o.component,
                 "state: which coordinate at --t-end, phi1..phiN or p1..pN (default phi1)");
  cmd.add_option("--gali-order", o.gali_order,
                 "--quantity gali only: k of GALI_k, 2..2n (default 0: n + 1, the least k "
                 "beyond a torus's dimension)");
  cmd.add_option("--phi", o.phi, "The start's other angles (rad; default 0)");
  cmd.add_option("--p", o.p, "The start's other momenta (kg m^2/s; default 0)");
  cmd.add_option("--dphi", o.dphi,
                 "The start's velocities instead of momenta (rad/s; p = A(phi) dphi per cell)");
  cmd.add_option("--t-end", o.t_end, "Integration time per cell in s (default 100)");
  cmd.add_option("--dt", o.dt,
                 "The step in s of rk4, gauss4 and gauss6; dopri5's first trial step (default "
                 "0.01)");
  cmd.add_option("--stepper", o.stepper,
                 "rk4 (default: fixed step --dt), dopri5 (adaptive, each cell under its own "
                 "step control; flip times located inside the step by its dense output), or "
                 "the symplectic gauss4 or gauss6 (fixed step --dt); other than rk4 for flip, "
                 "lyapunov and state only");
  cli::add_tolerance_options(cmd, o.abs_tol, o.rel_tol, o.tol,
                             "dopri5: absolute error tolerance (default 1e-10)",
                             "dopri5: relative error tolerance (default 1e-10)",
                             "dopri5: both tolerances at once, --abs-tol and --rel-tol TOL");
  cmd.add_option("--flip-link", o.flip_link, "flip: only arm K counts (default 0: any arm)");
}

map_view describe_map(const map_command_options& o) {
  // The lanes read NPEND_LANE_ISA when the first cell runs; a name they cannot run is
  // refused here, before any file is touched.
  try {
    batch_lane_isa();
  } catch (const std::invalid_argument& e) {
    throw cli::input_error(e.what());
  }
  // Any chain: damping, springs and a driven pivot are axes too; map_grid::validate refuses
  // what a quantity or axis cannot take (an energy axis on a chain that loses energy).
  const chain c = o.chain.make_chain(cli::model_support::any, "npend map");
  const int n = c.links();
  map_view view{{}, cell_options(o, n)};
  const map_cell_options& cell = view.cell;
  map_grid& grid = view.grid;
  grid.parameters = c.parameters();
  grid.x = parse_axis(o.x, "--x", n);
  grid.y = parse_axis(o.y, "--y", n);
  if (!(o.t_end > 0) || !(o.dt > 0) || o.dt > o.t_end)
    throw cli::input_error(
        fmt::format("--t-end and --dt: need 0 < dt <= t-end, got {} and {}", o.dt, o.t_end));
  // Each cell steps dt (dopri5: lays its grid of dt) to t_end, the limit every command keeps.
  cli::check_step_count(o.t_end, o.dt, "--t-end/--dt", "use a larger --dt (the limit is per cell)");
  if (o.flip_link < 0 || o.flip_link > n)
    throw cli::input_error(
        fmt::format("--flip-link: 1..{} (or 0: any arm), got {}", n, o.flip_link));
  set_base_start(o, n, grid);
  // The chain and options a cell can take, checked before any thread starts.
  if (cell.quantity != map_quantity::gali && o.gali_order != 0)
    throw cli::input_error(fmt::format("--gali-order: only with --quantity gali, not {}",
                                       map_quantity_name(cell.quantity)));
  if (cell.quantity == map_quantity::gali && o.gali_order != 0 &&
      (o.gali_order < 2 || o.gali_order > 2 * n))
    throw cli::input_error(
        fmt::format("--gali-order: 2..{} (2n), or 0 for n + 1, got {}", 2 * n, o.gali_order));
  try {
    cell.validate(c);
  } catch (const std::invalid_argument& e) {
    throw cli::input_error(e.what());
  }
  try {
    grid.validate(cell);
  } catch (const std::invalid_argument& e) {
    throw cli::input_error(axis_message(grid, e.what()));
  }
  return view;
}

quantity_style style_of(const map_command_options& o, map_quantity quantity) {
  const auto over = fmt::format(" over {:g} s; red: failed", o.t_end);
  switch (quantity) {
    case map_quantity::flip:
      return {
          fmt::format("Time to the first flip (s); white: no flip by {:g} s; red: failed", o.t_end),
          "t_{flip} (s)", true};
    case map_quantity::lyapunov:
      return {"Maximal Lyapunov exponent (1/s)" + over, "λ_1 (1/s)"};
    case map_quantity::fli:
      return {"Fast Lyapunov indicator" + over, "FLI"};
    case map_quantity::megno:
      return {"MEGNO <Y> (2: regular, growing: chaotic)" + over, "<Y>"};
    case map_quantity::sali:
      return {"SALI (0: chaotic)" + over + "; below 1e-16 shown as 1e-16", "SALI", true};
    case map_quantity::gali:
      return {"GALI (0: chaotic)" + over + "; below 1e-16 shown as 1e-16", "GALI", true};
    case map_quantity::state: {
      const std::string name = o.component.empty() ? "phi1" : o.component;
      const bool angle = name.rfind("phi", 0) == 0;
      return {fmt::format("{} at t = {:g} s ({}); red: failed", name, o.t_end,
                          angle ? "rad, not wrapped" : "kg m^2/s"),
              fmt::format("{} ({})", name, angle ? "rad" : "kg m^2/s")};
    }
  }
  return {};
}

// The .npy format (version 1.0): a C-order array of shape (rows, cols) of `descr` ('<f8':
// little-endian float64, '|u1': bytes).
std::string npy_header(int rows, int cols, std::string_view descr) {
  std::string dict = fmt::format("{{'descr': '{}', 'fortran_order': False, 'shape': ({}, {}), }}",
                                 descr, rows, cols);
  // Magic (6) + version (2) + length (2) + dict + padding + '\n', a multiple of 64 bytes.
  const std::size_t unpadded = 10 + dict.size() + 1;
  dict.append((64 - unpadded % 64) % 64, ' ');
  dict += '\n';
  std::string out("\x93NUMPY\x01\x00", 8);
  out += static_cast<char>(dict.size() & 0xff);
  out += static_cast<char>(dict.size() >> 8);
  return out + dict;
}

}  // namespace npend::app
