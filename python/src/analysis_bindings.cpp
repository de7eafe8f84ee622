// The analyses that are not integrations: time series (spectrum, autocorrelation, embed,
// choose_delay), stability (equilibria, modes) and chaos maps (map, map_cells). The package's
// python/npend/analysis.py wraps them with signatures, docstrings and result classes; these
// return plain dicts whose keys are the result classes' fields.
#include <fmt/format.h>
#include <pybind11/complex.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <filesystem>
#include <limits>
#include <numbers>
#include <optional>

#include "bindings.hpp"
#include "npend/analysis/chaos/chaos_map.hpp"
#include "npend/analysis/chaos/map_grid.hpp"
#include "npend/analysis/chaos/map_run.hpp"
#include "npend/analysis/orbits/periodic_orbit.hpp"
#include "npend/analysis/series/autocorrelation.hpp"
#include "npend/analysis/series/delay_embedding.hpp"
#include "npend/analysis/series/power_spectrum.hpp"
#include "npend/analysis/stability/equilibria.hpp"
#include "npend/analysis/stability/normal_modes.hpp"
#include "npend/atomic_file.hpp"
#include "npend/spec/section_spec.hpp"
#include "npend/spec/thread_count.hpp"

namespace npend::python {

namespace {

std::vector<double> series(const py::handle& x) {
  const double_array a = as_array(x, "x");
  if (a.ndim() != 1)
    throw std::invalid_argument("x must be a 1-D array of samples (a time series)");
  return {a.data(), a.data() + a.shape(0)};
}

py::dict spectrum(const py::handle& x, double dt, const std::string& window,
                  std::size_t segment_length, double overlap) {
  spectrum_options o;
  const auto w = spectral_window_from_name(window);
  if (!w)
    throw std::invalid_argument(
        fmt::format("window: one of none, hann, hamming, blackman, got '{}'", window));
  o.window = *w;
  o.segment_length = segment_length;
  o.overlap = overlap;
  const auto r = power_spectrum(series(x), dt, o);
  py::dict d;
  d["omega"] = py::array(py::cast(r.omega));
  d["power"] = py::array(py::cast(r.power));
  d["resolution"] = r.resolution;
  d["segment_length"] = r.segment_length;
  d["segments"] = r.segments;
  return d;
}

py::dict autocorrelation_of(const py::handle& x, double dt, std::size_t max_lag,
                            const std::string& estimator) {
  const auto e = autocorrelation_estimator_from_name(estimator);
  if (!e)
    throw std::invalid_argument(
        fmt::format("estimator: one of biased, unbiased, got '{}'", estimator));
  const auto r = autocorrelation(series(x), dt, max_lag, *e);
  py::dict d;
  d["lag"] = py::array(py::cast(r.lag));
  d["value"] = py::array(py::cast(r.value));
  d["first_zero"] = r.first_zero ? py::cast(*r.first_zero) : py::none();
  d["first_minimum"] = r.first_minimum ? py::cast(*r.first_minimum) : py::none();
  return d;
}

py::array_t<double> embed(const py::handle& x, std::size_t delay, std::size_t dimension) {
  auto v = delay_embedding(series(x), delay, dimension);
  return to_numpy(std::move(v.points),
                  {static_cast<py::ssize_t>(v.count), static_cast<py::ssize_t>(v.dimension)});
}

py::dict delay_of(const py::handle& x, double dt, const std::string& method) {
  const auto m = delay_method_from_name(method);
  if (!m)
    throw std::invalid_argument(
        fmt::format("method: one of auto, T/4, acf-zero, acf-min, ami, got '{}'", method));
  const auto r = choose_delay(series(x), dt, *m);
  py::dict d;
  d["found"] = r.found;
  d["method"] = std::string(delay_method_name(r.method));
  d["samples"] = r.samples;
  d["seconds"] = r.seconds;
  return d;
}

py::list equilibria(const chain& c) {
  py::list out;
  for (const auto& e : find_equilibria(c)) {
    py::dict d;
    d["angles"] = py::array(py::cast(e.angles));
    d["energy"] = e.energy;
    d["eigenvalues"] = py::array(py::cast(e.eigenvalues));
    d["stable"] = e.stable;
    d["unstable_directions"] = e.unstable_directions;
    out.append(d);
  }
  return out;
}

py::dict modes(const chain& c, const py::object& angles_in) {
  const auto n = static_cast<std::size_t>(c.links());
  const std::vector<double> angles =
      angles_in.is_none() ? std::vector<double>(n, 0.0) : to_vector(angles_in, n, "angles");
  const auto lin = normal_modes(c, angles);
  std::vector<double> omega2, freq, growth, shapes;
  for (const auto& m : lin.modes) {
    omega2.push_back(m.omega_squared);
    freq.push_back(m.frequency);
    growth.push_back(m.growth_rate);
    shapes.insert(shapes.end(), m.shape.begin(), m.shape.end());
  }
  const auto s = static_cast<py::ssize_t>(n);
  py::dict d;
  d["omega_squared"] = py::array(py::cast(omega2));
  d["frequencies"] = py::array(py::cast(freq));
  d["growth_rates"] = py::array(py::cast(growth));
  d["shapes"] = to_numpy(std::move(shapes), {s, s});
  d["mass_matrix"] = to_numpy(std::vector<double>(lin.mass_matrix), {s, s});
  d["stiffness_matrix"] = to_numpy(std::vector<double>(lin.stiffness_matrix), {s, s});
  return d;
}

// A state map's coordinate: phi1..phin or p1..pn.
void set_component(map_cell_options& o, const chain& c, const std::string& component) {
  if (o.quantity == map_quantity::state)
    o.component = static_cast<int>(spec::parse_coordinate(component, c.links(), "component"));
}

// The `device` keyword: "cpu", or "cuda" where the GPU maps take the map and a GPU is
// usable (RuntimeError naming the keyword where none is).
map_device device_of(const std::string& name, const chain& c, const map_cell_options& o) {
  map_device device{};
  try {
    device = parse_map_device(name);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(fmt::format("device: {}", e.what()));
  }
  if (device == map_device::cpu) return device;
  try {
    check_cuda_map(c, o);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(fmt::format("device=\"cuda\": {}", e.what()));
  }
  if (const cuda_status s = find_cuda(); !s.usable)
    throw std::runtime_error(
        fmt::format("device=\"cuda\": CUDA is not usable here: {} (device=\"cpu\" runs on the CPU)",
                    s.problem));
  return device;
}

// Every start must be finite (the library's message would name its own argument).
void check_finite(const state_batch& b) {
  for (std::size_t i = 0; i < b.count * b.width; ++i)
    if (!std::isfinite(b.array.data()[i]))
      throw std::invalid_argument(
          fmt::format("x: start state {} has a non-finite entry", i / b.width));
}

py::array_t<double> map_cells(const chain& c, const py::handle& x, const std::string& quantity,
                              double t_end, double dt, int flip_link, int gali_order,
                              const std::string& component, const std::string& stepper, double atol,
                              double rtol, int threads, const std::string& device,
                              const py::object& progress) {
  const state_batch b = to_states(x, c.state_size(), "x");
  map_cell_options o =
      make_map_cell_options(quantity, t_end, dt, flip_link, gali_order, stepper, atol, rtol);
  set_component(o, c, component);
  o.validate(c);
  check_finite(b);
  spec::check_thread_count(threads, "threads");
  const map_device where = device_of(device, c, o);
  python_interrupt interrupt(progress);
  std::vector<double> values;
  {
    py::gil_scoped_release no_gil;
    values = map_cell_values(c, {b.row(0), b.count * b.width}, o, threads, &interrupt, where);
  }
  interrupt.raise_if_interrupted();
  interrupt.report_last();
  std::vector<py::ssize_t> shape;
  if (!b.single) shape.push_back(static_cast<py::ssize_t>(b.count));
  return to_numpy(std::move(values), shape);
}

map_axis axis_from(const py::tuple& spec, int links, const char* what) {
  if (spec.size() != 4)
    throw std::invalid_argument(
        fmt::format("{}: expected (name, from, to, count), e.g. ('phi1', -3.14, 3.14, 256)", what));
  try {
    return make_map_axis(spec[0].cast<std::string>(), spec[1].cast<double>(),
                         spec[2].cast<double>(), spec[3].cast<int>(), links);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(fmt::format("{}: {}", what, e.what()));
  }
}

// The axis's values, the cells' x (or y) coordinates.
py::array_t<double> axis_values(const map_axis& a) {
  std::vector<double> v;
  for (int i = 0; i < a.count; ++i) v.push_back(a.value(i));
  return to_numpy(std::move(v), {static_cast<py::ssize_t>(a.count)});
}

// The folder of a map run from Python: its messages cite the keywords of npend.map.
const map_folder_words python_folder_words{.out = "out",
                                           .resume = "resume",
                                           .force = "force",
                                           .part = "part",
                                           .resume_hint = "resume=True",
                                           .force_hint = "force=True"};

// The map as a run in `folder` (map_run): its tiles written there as they finish, those a
// resumed run finds done read back. The tiles stay, so the same call with resume=True
// returns the map from them. A tile that a resumed run finds unsound is computed again, and
// `redone` hears why (for a RuntimeWarning once the GIL is back). Called without the GIL.
std::vector<double> map_in_folder(map_run_description description, const std::string& folder,
                                  bool resume, bool force, int threads, python_interrupt& interrupt,
                                  std::vector<std::string>& redone) {
  const map_run run(std::move(description), folder);
  // run.json's record of how the run was asked for: by Python, whose folders the command
  // line's `npend map merge` does not rebuild.
  run.open_folder(resume  ? map_folder_start::resume
                  : force ? map_folder_start::force
                          : map_folder_start::fresh,
                  R"json({"front_end": "npend.map (Python)"})json", python_folder_words);
  try {
    const std::vector<int> pending =
        run.pending_tiles(resume, [&](const std::string& problem) { redone.push_back(problem); });
    local_map_tile_queue queue(pending);
    const map_tiles_outcome outcome = run.compute_tiles(
        queue, map_team_size(threads), interrupt,
        [](const std::filesystem::path& path, std::string_view bytes) {
          write_file_whole(path, bytes, false);  // checked when read back, as the CLI's tiles
        },
        static_cast<long>(pending.size()), true);
    if (outcome.error) std::rethrow_exception(outcome.error);
    if (outcome.stopped) return {};
    std::optional<std::vector<double>> values = run.assemble(&interrupt);
    return values ? std::move(*values) : std::vector<double>{};
  } catch (const map_tile_error& e) {
    if (e.is_folder())
      throw std::invalid_argument(
          fmt::format("out: {}; remove it and call again with "
                      "resume=True",
                      e.what()));
    throw;
  }
}

py::dict map(const chain& c, const py::tuple& x_axis, const py::tuple& y_axis,
             const std::string& quantity, double t_end, double dt, int flip_link, int gali_order,
             const std::string& component, const py::object& x0, const py::object& velocities,
             const std::string& stepper, double atol, double rtol, int threads,
             const std::string& device, const py::object& progress, const py::object& out,
             bool resume, bool force, int tile) {
  const auto n = static_cast<std::size_t>(c.links());
  map_grid grid;
  grid.parameters = c.parameters();
  grid.x = axis_from(x_axis, c.links(), "x");
  grid.y = axis_from(y_axis, c.links(), "y");
  const std::vector<double> base =
      x0.is_none() ? std::vector<double>(2 * n, 0.0) : to_vector(x0, 2 * n, "x0");
  grid.angles.assign(base.begin(), base.begin() + static_cast<long>(n));
  grid.momenta.assign(base.begin() + static_cast<long>(n), base.end());
  if (!velocities.is_none()) {
    if (!x0.is_none() &&
        std::any_of(grid.momenta.begin(), grid.momenta.end(), [](double p) { return p != 0; }))
      throw std::invalid_argument(
          "velocities: give the start's momenta (in x0) or its velocities, not both");
    grid.momenta = to_vector(velocities, n, "velocities");
    grid.velocities = true;
  }
  map_cell_options o =
      make_map_cell_options(quantity, t_end, dt, flip_link, gali_order, stepper, atol, rtol);
  set_component(o, c, component);
  grid.validate(o);
  spec::check_thread_count(threads, "threads");
  const map_device where = device_of(device, c, o);
  if (out.is_none() && (resume || force))
    throw std::invalid_argument(resume ? "resume: only with out, the folder of the run"
                                       : "force: only with out, the folder of the run");
  if (resume && force)
    throw std::invalid_argument("force: only for a fresh run (resume keeps the folder's tiles)");
  const std::string folder =
      out.is_none() ? ""
                    : py::str(py::module_::import("os").attr("fspath")(out)).cast<std::string>();
  if (!out.is_none() && folder.empty())
    throw std::invalid_argument("out: the folder name is empty");
  python_interrupt interrupt(progress);
  std::vector<double> values;
  std::vector<std::string> redone;
  {
    py::gil_scoped_release no_gil;
    values = out.is_none() ? map_values(grid, o, threads, &interrupt, where)
                           : map_in_folder({grid, o, tile, {}, where}, folder, resume, force,
                                           threads, interrupt, redone);
  }
  // As the command line's notes: a resumed run says which tiles it could not use.
  for (const std::string& problem : redone)
    if (PyErr_WarnEx(PyExc_RuntimeWarning, (problem + "; computed again").c_str(), 1) < 0)
      throw py::error_already_set();  // warnings turned into errors
  interrupt.raise_if_interrupted();
  interrupt.report_last();
  py::dict d;
  d["values"] = to_numpy(std::move(values), {static_cast<py::ssize_t>(grid.y.count),
                                             static_cast<py::ssize_t>(grid.x.count)});
  d["x"] = axis_values(grid.x);
  d["y"] = axis_values(grid.y);
  return d;
}

// A periodic orbit's fields (PeriodicOrbit in python/npend/results.py).
py::dict point_dict(const nnm_point& p, bool converged = true) {
  py::dict d;
  d["converged"] = converged;
  d["x0"] = py::array(py::cast(p.x0));
  d["period"] = p.period;
  d["frequency"] = p.frequency;
  d["energy"] = p.energy;
  d["closure"] = p.closure;
  d["iterations"] = p.iterations;
  d["amplitudes"] = py::array(py::cast(p.amplitudes));
  d["multipliers"] = py::array(py::cast(p.multipliers));
  d["max_multiplier"] = p.max_multiplier;
  d["stable"] = p.stable;
  return d;
}

orbit_phase parse_phase(const std::string& phase) {
  if (phase == "turning_point") return orbit_phase::turning_point;
  if (phase == "poincare") return orbit_phase::poincare;
  throw std::invalid_argument(fmt::format("phase: turning_point or poincare, got '{}'", phase));
}

periodic_orbit_options shooting_options(std::optional<double> energy, const std::string& phase,
                                        int steps, double tol, int max_iterations,
                                        const std::string& stepper, double integration_tol) {
  periodic_orbit_options o;
  if (energy) o.energy = *energy;
  o.phase = parse_phase(phase);
  o.steps = steps;
  o.tolerance = tol;
  o.max_iterations = max_iterations;
  o.stepper = parse_stepper_kind(stepper);
  o.integration_tolerance = integration_tol;
  return o;
}

continuation_method parse_continuation(const std::string& name) {
  if (const auto method = continuation_method_from_name(name)) return *method;
  throw std::invalid_argument(fmt::format("continuation: arclength or natural, got '{}'", name));
}

py::dict periodic_orbit_of(const chain& c, const py::handle& x0_in, double period,
                           std::optional<double> energy, const std::string& phase, int steps,
                           double tol, int max_iterations, int segments,
                           std::optional<std::vector<int>> winding, const std::string& stepper,
                           double integration_tol) {
  const std::vector<double> x0 = to_vector(x0_in, static_cast<std::size_t>(c.state_size()), "x0");
  periodic_orbit_options o =
      shooting_options(energy, phase, steps, tol, max_iterations, stepper, integration_tol);
  o.segments = segments;
  if (winding) o.winding = *winding;
  python_interrupt interrupt;
  o.control = &interrupt;
  periodic_orbit_result r;
  {
    py::gil_scoped_release no_gil;
    r = periodic_orbit(c, x0, period, o);
  }
  interrupt.raise_if_interrupted();
  py::dict d = point_dict(to_nnm_point(r), r.converged);
  d["winding"] = py::tuple(py::cast(r.winding));
  return d;
}

py::dict continue_mode_of(const chain& c, int mode, double energy_max, double start_amplitude,
                          int steps, int max_points, const std::vector<double>& thresholds,
                          int segments, const std::string& continuation, bool branches,
                          const std::string& stepper, double integration_tol) {
  if (mode < 1 || mode > c.links())
    throw std::invalid_argument(
        fmt::format("mode: 1..{} (1 = the slowest), got {}", c.links(), mode));
  continuation_options o;
  o.orbit.steps = steps;
  o.orbit.segments = segments;
  o.orbit.stepper = parse_stepper_kind(stepper);
  o.orbit.integration_tolerance = integration_tol;
  o.method = parse_continuation(continuation);
  o.energy_max = energy_max;
  o.start_amplitude = start_amplitude;
  o.max_points = max_points;
  for (const double shift : thresholds)
    if (!(shift > 0 && shift < 1))
      throw std::invalid_argument(
          fmt::format("thresholds: {} is not a relative shift in (0, 1) (0.01 = 1 %)", shift));
  python_interrupt interrupt;
  o.orbit.control = &interrupt;
  nnm_branch b;
  std::vector<std::optional<nnm_point>> departures;
  std::vector<nnm_bifurcation> changes;
  std::vector<nnm_branch> families;
  {
    py::gil_scoped_release no_gil;
    b = continue_mode(c, mode - 1, o);
    for (const double shift : thresholds)
      if (!b.stopped) departures.push_back(locate_departure(c, b, shift, o.orbit));
    if (!b.stopped) changes = locate_bifurcations(c, b, o.orbit);
    if (branches && !b.stopped)
      for (const nnm_bifurcation& f : changes)
        families.push_back(switch_branch(c, f, energy_max, o));
  }
  interrupt.raise_if_interrupted();
  const auto k = static_cast<py::ssize_t>(b.points.size());
  const auto n = static_cast<py::ssize_t>(c.links());
  std::vector<double> energy, period, frequency, max_multiplier, closure, amplitudes, x0;
  std::vector<bool> stable;
  py::list multipliers;
  for (const nnm_point& p : b.points) {
    energy.push_back(p.energy);
    period.push_back(p.period);
    frequency.push_back(p.frequency);
    max_multiplier.push_back(p.max_multiplier);
    closure.push_back(p.closure);
    stable.push_back(p.stable);
    amplitudes.insert(amplitudes.end(), p.amplitudes.begin(), p.amplitudes.end());
    x0.insert(x0.end(), p.x0.begin(), p.x0.end());
    multipliers.append(py::array(py::cast(p.multipliers)));
  }
  py::dict d;
  d["mode"] = mode;
  d["linear_frequency"] = b.linear_frequency;
  d["shape"] = py::array(py::cast(b.shape));
  d["energy"] = to_numpy(std::move(energy), {k});
  d["period"] = to_numpy(std::move(period), {k});
  d["frequency"] = to_numpy(std::move(frequency), {k});
  d["amplitudes"] = to_numpy(std::move(amplitudes), {k, n});
  d["x0"] = to_numpy(std::move(x0), {k, 2 * n});
  d["multipliers"] = multipliers;
  d["max_multiplier"] = to_numpy(std::move(max_multiplier), {k});
  d["stable"] = py::array(py::cast(stable));
  d["closure"] = to_numpy(std::move(closure), {k});
  d["end_reason"] = b.end_reason;
  py::list folds;
  for (const nnm_fold& f : b.folds) folds.append(py::make_tuple(f.after, f.energy));
  d["folds"] = py::tuple(folds);
  py::dict found;
  for (std::size_t i = 0; i < departures.size(); ++i)
    found[py::float_(thresholds[i])] =
        departures[i] ? py::object(point_dict(*departures[i])) : py::object(py::none());
  d["departures"] = found;
  py::list bifurcations;
  for (std::size_t c_index = 0; c_index < changes.size(); ++c_index) {
    const nnm_bifurcation& f = changes[c_index];
    py::dict change;
    change["kind"] = std::string(nnm_bifurcation_name(f.kind));
    change["energy"] = f.energy;
    change["loses_stability"] = f.loses_stability;
    change["stable_side"] = point_dict(f.stable_side);
    change["unstable_side"] = point_dict(f.unstable_side);
    py::list family;
    if (c_index < families.size())
      for (const nnm_point& p : families[c_index].points) family.append(point_dict(p));
    change["family"] = family;
    bifurcations.append(change);
  }
  d["bifurcations"] = bifurcations;
  return d;
}

}  // namespace

void bind_orbits(py::module_& m) {
  m.def("periodic_orbit", &periodic_orbit_of, py::arg("chain"), py::arg("x0"), py::arg("period"),
        py::kw_only(), py::arg("energy") = py::none(), py::arg("phase") = "turning_point",
        py::arg("steps") = 400, py::arg("tol") = 1e-11, py::arg("max_iterations") = 20,
        py::arg("segments") = 1, py::arg("winding") = py::none(), py::arg("stepper") = "gauss6",
        py::arg("integration_tol") = 1e-14);
  m.def("continue_mode", &continue_mode_of, py::arg("chain"), py::arg("mode"),
        py::arg("energy_max"), py::kw_only(), py::arg("start_amplitude") = 0.01,
        py::arg("steps") = 400, py::arg("max_points") = 200,
        py::arg("thresholds") = std::vector<double>{0.01, 0.05}, py::arg("segments") = 1,
        py::arg("continuation") = "arclength", py::arg("branches") = false,
        py::arg("stepper") = "gauss6", py::arg("integration_tol") = 1e-14);
}

void bind_series(py::module_& m) {
  m.def("spectrum", &spectrum, py::arg("x"), py::arg("dt"), py::kw_only(),
        py::arg("window") = "hann", py::arg("segment_length") = 0, py::arg("overlap") = 0.5);
  m.def("autocorrelation", &autocorrelation_of, py::arg("x"), py::arg("dt"), py::kw_only(),
        py::arg("max_lag") = 0, py::arg("estimator") = "biased");
  m.def("embed", &embed, py::arg("x"), py::arg("delay"), py::arg("dimension"));
  m.def("choose_delay", &delay_of, py::arg("x"), py::arg("dt"), py::kw_only(),
        py::arg("method") = "auto");
}

void bind_stability(py::module_& m) {
  m.def("equilibria", &equilibria, py::arg("chain"));
  m.def("modes", &modes, py::arg("chain"), py::arg("angles") = py::none());
}

void bind_maps(py::module_& m) {
  m.def("map_cells", &map_cells, py::arg("chain"), py::arg("x"), py::kw_only(),
        py::arg("quantity") = "flip", py::arg("t_end") = 100.0, py::arg("dt") = 0.01,
        py::arg("flip_link") = 0, py::arg("gali_order") = 0, py::arg("component") = "phi1",
        py::arg("stepper") = "rk4", py::arg("atol") = 1e-10, py::arg("rtol") = 1e-10,
        py::arg("threads") = 0, py::arg("device") = "cpu", py::arg("progress") = py::none());
  m.def("map", &map, py::arg("chain"), py::arg("x"), py::arg("y"), py::kw_only(),
        py::arg("quantity") = "flip", py::arg("t_end") = 100.0, py::arg("dt") = 0.01,
        py::arg("flip_link") = 0, py::arg("gali_order") = 0, py::arg("component") = "phi1",
        py::arg("x0") = py::none(), py::arg("velocities") = py::none(), py::arg("stepper") = "rk4",
        py::arg("atol") = 1e-10, py::arg("rtol") = 1e-10, py::arg("threads") = 0,
        py::arg("device") = "cpu", py::arg("progress") = py::none(), py::arg("out") = py::none(),
        py::arg("resume") = false, py::arg("force") = false, py::arg("tile") = 16);
}

}  // namespace npend::python
