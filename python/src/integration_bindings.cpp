// npend.simulate, npend.lyapunov and npend.poincare: integrations run without the GIL, with
// Ctrl-C stopping them (KeyboardInterrupt) instead of waiting for the end.
#include <fmt/format.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>

#include "bindings.hpp"
#include "npend/analysis/chaos/chaos_indicators.hpp"
#include "npend/analysis/chaos/lyapunov.hpp"
#include "npend/analysis/chaos/poincare_section.hpp"
#include "npend/spec/section_spec.hpp"

namespace npend::python {

namespace {

std::vector<double> start_state(const chain& c, const py::handle& x0) {
  return to_vector(x0, static_cast<std::size_t>(c.state_size()), "x0");
}

// An event of simulate's, with SciPy's `terminal` and `direction`: a Python function g(t, y),
// or one named by a string and evaluated here without Python: "flip" (any arm) or "flipK"
// (arm K) passing the upright position, g = max |φ_k| − π; or a section as npend poincare
// takes it ("phi1=0", "p2=0.5", "phi1=phi2"), g = w·x − c. A section of angles lies on the
// circle: each step takes the branch c + 2πj it crosses (section_plane::branch_level), so
// that g is continuous across the step and changes sign only where the section is crossed.
struct python_event {
  py::object g;                          ///< the Python function; null for a named event
  std::optional<section_plane> section;  ///< a named section
  int flip_link = -1;                    ///< a named flip: 0 any arm, K arm K; -1 none
  int links = 0;
  double level = 0;  ///< the section's branch in the current step
  bool terminal = false;
  double direction = 0;  ///< > 0: only g rising through 0, < 0: only falling, 0: both
  double last = 0;       ///< g at the end of the previous step
  std::vector<double> times, states;

  double operator()(double t, std::span<const double> x) const {
    if (section) {
      double v = -level;
      for (std::size_t i = 0; i < x.size(); ++i) v += section->normal[i] * x[i];
      return v;
    }
    if (flip_link >= 0) {
      double largest = 0;
      for (int k = 1; k <= links; ++k)
        if (flip_link == 0 || flip_link == k)
          largest = std::max(largest, std::fabs(x[static_cast<std::size_t>(k - 1)]));
      return largest - std::numbers::pi;
    }
    py::array_t<double> y(static_cast<py::ssize_t>(x.size()));
    std::copy(x.begin(), x.end(), y.mutable_data());
    return g(t, y).cast<double>();
  }
  bool fires(double before, double after) const {
    const bool rising = before < 0 && after >= 0, falling = before > 0 && after <= 0;
    return direction > 0 ? rising : direction < 0 ? falling : rising || falling;
  }
  /// g at the step's two ends: a section's from the branch this step crosses, any other's
  /// from the end of the previous step.
  std::pair<double, double> at_ends(const integration_step& step) {
    if (section) {
      level = section->branch_level(step.x_begin(), step.x_end());
      return {(*this)(step.t_begin(), step.x_begin()), (*this)(step.t_end(), step.x_end())};
    }
    return {last, (*this)(step.t_end(), step.x_end())};
  }
};

// The event a string names: "flip", "flipK" or a section spec (see python_event).
python_event named_event(const chain& c, const std::string& name) {
  python_event e;
  e.links = c.links();
  if (name.rfind("flip", 0) == 0) {
    const std::string arm = name.substr(4);
    if (arm.empty()) {
      e.flip_link = 0;
    } else {
      if (arm.size() > 3 || arm.find_first_not_of("0123456789") != std::string::npos ||
          std::stoi(arm) < 1 || std::stoi(arm) > c.links())
        throw std::invalid_argument(fmt::format(
            "events: '{}' names no arm: flip (any arm) or flip1..flip{}", name, c.links()));
      e.flip_link = std::stoi(arm);
    }
    if (c.has_cart())
      throw std::invalid_argument("events: a flip event is for a chain on a fixed pivot");
    return e;
  }
  e.section =
      spec::section_from_spec(spec::parse_section_spec(name, "events"), c.links(), "events");
  if (c.has_cart())
    throw std::invalid_argument("events: a section event is for a chain on a fixed pivot");
  return e;
}

// Where g crosses zero inside `step`, from g_begin at its start to g_end at its end (of
// opposite signs, or g_end = 0): the Illinois variant of regula falsi on the step's dense
// output, to a few units of rounding in t. `x` receives the state there.
double locate_event(const python_event& e, const integration_step& step, double g_begin,
                    double g_end, std::vector<double>& x) {
  double a = step.t_begin(), b = step.t_end(), ga = g_begin, gb = g_end;
  int side = 0;
  for (int i = 0; i < 100 && gb != 0; ++i) {
    if (std::fabs(b - a) <=
        4 * std::numeric_limits<double>::epsilon() * std::max(std::fabs(a), std::fabs(b)))
      break;
    const double t = (a * gb - b * ga) / (gb - ga);
    step.state_at(t, x);
    const double gt = e(t, x);
    if ((gt < 0) == (gb < 0) && gt != 0) {
      b = t, gb = gt;
      if (side == -1) ga /= 2;  // Illinois: halve the stale end's weight
      side = -1;
    } else {
      a = t, ga = gt;
      if (side == +1) gb /= 2;
      side = +1;
      if (gt == 0) b = t, gb = 0;
    }
  }
  step.state_at(b, x);
  return b;
}

// Solution.sol of simulate(dense_output=True): the stepper's dense output over every step,
// kept as degree() + 1 of its values per step at the step's Chebyshev points (of the second
// kind), from which the barycentric formula gives the same polynomial back at any t, to
// round-off, and stably for the high degrees of taylor.
class dense_solution {
 public:
  explicit dense_solution(std::size_t dim) : m_dim(dim) {}

  // The step's polynomial; `until` cuts the solution short inside the last step (a
  // terminal event).
  void add(const integration_step& step, std::optional<double> until = std::nullopt) {
    const int m = step.degree();
    if (m < 1) throw std::logic_error("dense_output: the stepper's dense output has no degree");
    if (m_edges.empty()) m_edges.push_back(step.t_begin());
    const double a = step.t_begin(), b = step.t_end();
    m_edges.push_back(until.value_or(b));
    m_span.push_back({a, b});
    m_degree.push_back(m);
    m_offset.push_back(m_samples.size());
    std::vector<double> x(m_dim);
    for (int j = 0; j <= m; ++j) {
      step.state_at(node(a, b, m, j), x);
      m_samples.insert(m_samples.end(), x.begin(), x.end());
    }
  }

  // Ends the solution at t inside its last step (a dense stepper's last step passes t_end).
  void end_at(double t) {
    if (!m_edges.empty()) m_edges.back() = t;
  }

  double t_min() const { return std::min(m_edges.front(), m_edges.back()); }
  double t_max() const { return std::max(m_edges.front(), m_edges.back()); }
  std::size_t bytes() const { return m_samples.size() * sizeof(double); }

  // The state at t (inside [t_min, t_max], checked by the caller) into x.
  void at(double t, double* x, std::size_t stride) const {
    const std::size_t k = step_of(t);
    const auto [a, b] = m_span[k];
    const int m = m_degree[k];
    const double* v = m_samples.data() + m_offset[k];
    double denominator = 0;
    for (std::size_t i = 0; i < m_dim; ++i) x[i * stride] = 0;
    for (int j = 0; j <= m; ++j) {
      const double tj = node(a, b, m, j);
      if (t == tj) {
        for (std::size_t i = 0; i < m_dim; ++i) x[i * stride] = v[j * m_dim + i];
        return;
      }
      const double w = ((j % 2) ? -1.0 : 1.0) * (j == 0 || j == m ? 0.5 : 1.0) / (t - tj);
      denominator += w;
      for (std::size_t i = 0; i < m_dim; ++i) x[i * stride] += w * v[j * m_dim + i];
    }
    for (std::size_t i = 0; i < m_dim; ++i) x[i * stride] /= denominator;
  }

  py::array_t<double> call(const py::handle& t_in) const {
    const double_array t = as_array(t_in, "t");
    const bool scalar = t.ndim() == 0;
    if (t.ndim() > 1) throw std::invalid_argument("t: expected a time or a 1-D array of times");
    const auto count = static_cast<std::size_t>(t.size());
    for (std::size_t k = 0; k < count; ++k)
      if (!(t.data()[k] >= t_min() && t.data()[k] <= t_max()))
        throw std::invalid_argument(fmt::format("t: {} is outside the solution's span [{}, {}]",
                                                t.data()[k], t_min(), t_max()));
    std::vector<double> out(m_dim * count);
    for (std::size_t k = 0; k < count; ++k) at(t.data()[k], out.data() + k, count);
    if (scalar) return to_numpy(std::move(out), {static_cast<py::ssize_t>(m_dim)});
    return to_numpy(std::move(out),
                    {static_cast<py::ssize_t>(m_dim), static_cast<py::ssize_t>(count)});
  }

 private:
  // Chebyshev point j of m on [a, b], from a (j = 0) to b (j = m).
  static double node(double a, double b, int m, int j) {
    if (j == 0) return a;
    if (j == m) return b;
    const double c = std::cos(std::numbers::pi * j / m);  // 1 .. -1
    return 0.5 * (a + b) + 0.5 * (a - b) * c;
  }

  // The step that holds t: edges run in the integration's direction.
  std::size_t step_of(double t) const {
    const bool forwards = m_edges.back() >= m_edges.front();
    const auto later = [forwards](double u, double v) { return forwards ? u < v : u > v; };
    const auto it = std::upper_bound(m_edges.begin() + 1, m_edges.end() - 1, t, later);
    return static_cast<std::size_t>(it - (m_edges.begin() + 1));
  }

  std::size_t m_dim;
  std::vector<double> m_edges;  // t_begin of the first step, then each step's end
  std::vector<std::pair<double, double>> m_span;
  std::vector<int> m_degree;
  std::vector<std::size_t> m_offset;
  std::vector<double> m_samples;
};

// npend.simulate's run: the grid's rows (every `every`-th) or the states at `t_eval` from the
// stepper's dense output, the events located on it, the energy's largest change.
py::dict simulate(const chain& c, const py::handle& x0_in, double t_start, double t_end, double dt,
                  const std::string& stepper, double atol, double rtol, int order,
                  std::size_t every, const py::object& t_eval_in, const py::list& event_functions,
                  const py::object& progress, bool dense_output) {
  const auto x0 = start_state(c, x0_in);
  auto o = integration_from(t_end, dt, stepper, t_start, atol, rtol, order);
  if (every == 0) throw std::invalid_argument("every: must be 1 or more");
  std::vector<double> t_eval;
  const bool at_times = !t_eval_in.is_none();
  if (at_times) {
    const double_array a = as_array(t_eval_in, "t_eval");
    t_eval.assign(a.data(), a.data() + a.size());
  }
  std::vector<python_event> events;
  for (const auto& g : event_functions) {
    // A string, an npend.Event (its `spec`), or a function.
    const py::object spec = py::isinstance<py::str>(g) ? py::reinterpret_borrow<py::object>(g)
                                                       : py::getattr(g, "spec", py::none());
    python_event e;
    if (spec.is_none())
      e.g = py::reinterpret_borrow<py::object>(g);
    else
      e = named_event(c, spec.cast<std::string>());
    e.terminal = py::bool_(py::getattr(g, "terminal", py::bool_(false)));
    e.direction = py::getattr(g, "direction", py::float_(0.0)).cast<double>();
    events.push_back(std::move(e));
  }
  const auto d = static_cast<std::size_t>(c.state_size());
  const output_grid grid = make_output_grid(o);
  const double h0 = c.hamiltonian(x0, t_start);
  double energy_change = 0;

  // The arrays grow as the run goes: memory for what was computed, not for what was asked.
  std::vector<double> t, states;
  const auto record = [&](double time, std::span<const double> x) {
    t.push_back(time);
    states.insert(states.end(), x.begin(), x.end());
    const double h = c.hamiltonian(x, time);
    energy_change = std::max(energy_change, std::fabs(h - h0) / (h0 != 0 ? std::fabs(h0) : 1.0));
  };
  const double direction = dt > 0 ? 1.0 : -1.0;
  const auto before = [&](double a, double b) { return direction * (b - a) > 0; };
  std::size_t grid_k = 0, next_eval = 0;  // the next grid point and t_eval entry to record
  bool terminated = false;
  std::vector<double> x(d);

  observer_function on_grid;
  if (!at_times)
    on_grid = [&](double time, std::span<const double> state) {
      if (grid_k++ % every == 0) record(time, state);
      return observer_action::proceed;
    };
  std::optional<dense_solution> dense;
  if (dense_output) dense.emplace(d);
  step_observer_function on_step;
  if (at_times || !events.empty() || dense_output)
    on_step = [&](const integration_step& step) {
      double stop_at = step.t_end();
      if (!events.empty()) {
        py::gil_scoped_acquire gil;
        for (auto& e : events) {
          const auto [g_begin, g_end] = e.at_ends(step);
          if (e.fires(g_begin, g_end)) {
            const double te = locate_event(e, step, g_begin, g_end, x);
            e.times.push_back(te);
            e.states.insert(e.states.end(), x.begin(), x.end());
            if (e.terminal && (!terminated || before(te, stop_at))) terminated = true, stop_at = te;
          }
          e.last = g_end;
        }
      }
      if (dense) dense->add(step, terminated ? std::optional(stop_at) : std::nullopt);
      // The outputs up to a terminal event come from the dense output: the grid observer
      // does not see the step that ends the run.
      while (at_times && next_eval < t_eval.size() && !before(stop_at, t_eval[next_eval])) {
        step.state_at(t_eval[next_eval], x);
        record(t_eval[next_eval++], x);
      }
      if (terminated && !at_times)
        for (; before(grid.time(grid_k), stop_at); ++grid_k)
          if (grid_k % every == 0) {
            step.state_at(grid.time(grid_k), x);
            record(grid.time(grid_k), x);
          }
      return terminated ? observer_action::stop : observer_action::proceed;
    };
  for (auto& e : events)
    if (!e.section) e.last = e(t_start, x0);

  python_interrupt interrupt(progress);
  o.control = &interrupt;
  integration_result r;
  {
    py::gil_scoped_release no_gil;
    r = integrate(c, x0, o, on_grid, on_step);
  }
  interrupt.raise_if_interrupted();
  interrupt.report_last();
  const std::size_t rows = t.size();
  py::dict out;
  out["t"] = to_numpy(std::move(t), {static_cast<py::ssize_t>(rows)});
  out["X"] =
      to_numpy(std::move(states), {static_cast<py::ssize_t>(rows), static_cast<py::ssize_t>(d)});
  out["terminated"] = terminated;
  out["nsteps"] = r.steps;
  out["nfev"] = r.evaluations;
  out["njev"] = r.jacobian_evaluations;
  out["energy_error"] = energy_change;
  py::list t_events, y_events;
  for (auto& e : events) {
    const auto k = static_cast<py::ssize_t>(e.times.size());
    t_events.append(to_numpy(std::move(e.times), {k}));
    y_events.append(to_numpy(std::move(e.states), {k, static_cast<py::ssize_t>(d)}));
  }
  out["t_events"] = t_events;
  out["y_events"] = y_events;
  if (dense && !terminated) dense->end_at(r.t);
  // Before the first step (a run stopped at once) there is no polynomial to give.
  out["sol"] = dense && dense->bytes() > 0 ? py::cast(std::move(*dense)) : py::object(py::none());
  return out;
}

py::array_t<double> rows_array(const std::vector<std::vector<double>>& rows, std::size_t width) {
  std::vector<double> flat;
  flat.reserve(rows.size() * width);
  for (const auto& r : rows) flat.insert(flat.end(), r.begin(), r.end());
  return to_numpy(std::move(flat),
                  {static_cast<py::ssize_t>(rows.size()), static_cast<py::ssize_t>(width)});
}

py::dict lyapunov(const chain& c, const py::handle& x0_in, double t_end, double dt,
                  const std::string& stepper, bool maximal, int exponents, double renormalise_every,
                  double transient, std::size_t blocks, double atol, double rtol) {
  const auto x0 = start_state(c, x0_in);
  if (maximal && exponents != 0)
    throw std::invalid_argument("maximal and exponents: ask for the largest exponent or for K");
  lyapunov_options o;
  o.integration = integration_from(t_end, dt, stepper, 0, atol, rtol);
  o.renormalisation_interval = renormalise_every;
  o.transient = transient;
  o.blocks = blocks;
  python_interrupt interrupt;
  o.integration.control = &interrupt;
  lyapunov_result r;
  {
    py::gil_scoped_release no_gil;
    r = maximal          ? maximal_lyapunov_exponent(c, x0, o)
        : exponents != 0 ? largest_lyapunov_exponents(c, x0, o, exponents)
                         : lyapunov_spectrum(c, x0, o);
  }
  interrupt.raise_if_interrupted();
  py::dict d;
  d["exponents"] = py::array(py::cast(r.exponents));
  d["sum"] = r.sum;
  d["pair_sums"] = py::array(py::cast(r.pair_sums));
  d["standard_error"] = py::array(py::cast(r.block_standard_error));
  d["spread"] = py::array(py::cast(r.spread));
  d["history_t"] = py::array(py::cast(r.history_t));
  d["history"] = rows_array(r.history, r.exponents.size());
  d["t"] = r.t;
  d["averaging_time"] = r.averaging_time;
  d["renormalisations"] = r.renormalisations;
  d["max_rel_energy_error"] = r.max_rel_energy_error;
  d["method"] = r.method;
  d["state"] = py::array(py::cast(r.state));
  return d;
}

py::dict poincare(const chain& c, const py::handle& x0_in, const std::string& section_text,
                  double t_end, double dt, const std::string& stepper, const std::string& direction,
                  std::size_t max_crossings, bool unwrapped, double atol, double rtol) {
  const auto x0 = start_state(c, x0_in);
  const auto section = spec::section_from_spec(
      spec::parse_section_spec(section_text, "section"), c.links(), "section",
      unwrapped ? spec::angle_mode::unwrapped : spec::angle_mode::circle);
  auto o = integration_from(t_end, dt, stepper, 0, atol, rtol);
  poincare_options po;
  po.direction = spec::parse_direction(direction, "direction");
  po.max_crossings = max_crossings;
  python_interrupt interrupt;
  o.control = &interrupt;
  poincare_result r;
  {
    py::gil_scoped_release no_gil;
    r = poincare_section(c, x0, section, o, po);
  }
  interrupt.raise_if_interrupted();
  std::vector<std::vector<double>> states;
  for (const auto& k : r.crossings) states.push_back(k.state);
  py::dict d;
  d["t"] = py::array(py::cast(crossing_times(r.crossings)));
  d["states"] = rows_array(states, static_cast<std::size_t>(c.state_size()));
  d["t_end"] = r.integration.t;
  return d;
}

py::dict indicators(const chain& c, const py::handle& x0_in, double t_end, double dt,
                    std::size_t vectors, double sample_interval, const std::string& stepper,
                    double tol) {
  const auto x0 = start_state(c, x0_in);
  chaos_indicator_options o;
  o.t_end = t_end;
  o.stepper = parse_stepper_kind(stepper);
  o.tolerance = tol;
  o.dt = dt;
  o.vectors = vectors;
  o.sample_interval = sample_interval;
  python_interrupt interrupt;
  o.control = &interrupt;
  chaos_indicator_result r;
  {
    py::gil_scoped_release no_gil;
    r = chaos_indicators(c, x0, o);
  }
  interrupt.raise_if_interrupted();
  std::vector<chaos_indicator_sample> samples = r.history;
  if (samples.empty() || samples.back().t != r.last.t) samples.push_back(r.last);
  std::vector<double> t, fli, megno, mean_megno, sali;
  std::vector<std::vector<double>> gali;
  for (const auto& s : samples) {
    t.push_back(s.t);
    fli.push_back(s.fli);
    megno.push_back(s.megno);
    mean_megno.push_back(s.mean_megno);
    sali.push_back(s.sali);
    gali.push_back(s.gali);
  }
  py::dict d;
  d["t"] = py::array(py::cast(t));
  d["fli"] = py::array(py::cast(fli));
  d["megno"] = py::array(py::cast(megno));
  d["mean_megno"] = py::array(py::cast(mean_megno));
  d["sali"] = py::array(py::cast(sali));
  d["gali"] = rows_array(gali, vectors - 1);
  d["state"] = py::array(py::cast(r.state));
  return d;
}

}  // namespace

void bind_integration(py::module_& m) {
  // The rows of simulate's grid, for its memory estimate before the run.
  m.def("output_points", [](double t_start, double t_end, double dt) {
    integration_options o;
    o.t_start = t_start;
    o.t_end = t_end;
    o.dt = dt;
    return output_intervals(o) + 1;
  });
  // python/npend/analysis.py wraps it (npend.simulate: SciPy's keywords, checks, Solution).
  py::class_<dense_solution>(m, "DenseOutput", R"doc(The continuous solution of
npend.simulate(dense_output=True): sol(t) for a time t gives the state, shape (2n,); for an
array of m times, shape (2n, m), as SciPy's OdeSolution. It is the stepper's own dense
output over each step, kept exactly. t outside [t_min, t_max] raises ValueError.)doc")
      .def("__call__", &dense_solution::call, py::arg("t"))
      .def_property_readonly("t_min", &dense_solution::t_min)
      .def_property_readonly("t_max", &dense_solution::t_max)
      .def_property_readonly("nbytes", &dense_solution::bytes)
      .def("__repr__", [](const dense_solution& s) {
        return fmt::format("DenseOutput(t_min={}, t_max={}, nbytes={})", s.t_min(), s.t_max(),
                           s.bytes());
      });
  m.def("simulate", &simulate, py::arg("chain"), py::arg("x0"), py::arg("t_start"),
        py::arg("t_end"), py::arg("dt"), py::arg("stepper"), py::arg("atol"), py::arg("rtol"),
        py::arg("order"), py::arg("every"), py::arg("t_eval"), py::arg("events"),
        py::arg("progress"), py::arg("dense_output"));
  // python/npend/analysis.py wraps lyapunov, chaos_indicators and poincare (signatures,
  // docstrings, result classes): they return plain dicts whose keys are the classes' fields.
  m.def("lyapunov", &lyapunov, py::arg("chain"), py::arg("x0"), py::arg("t_end"), py::kw_only(),
        py::arg("dt") = 1e-3, py::arg("stepper") = "gauss6", py::arg("maximal") = false,
        py::arg("exponents") = 0, py::arg("renormalise_every") = 0.1, py::arg("transient") = 0.0,
        py::arg("blocks") = 10, py::arg("atol") = 1e-10, py::arg("rtol") = 1e-10);
  m.def("chaos_indicators", &indicators, py::arg("chain"), py::arg("x0"), py::arg("t_end"),
        py::kw_only(), py::arg("dt") = 0.01, py::arg("vectors") = 2,
        py::arg("sample_interval") = 0.0, py::arg("stepper") = "rk4", py::arg("tol") = 1e-12);
  m.def("poincare", &poincare, py::arg("chain"), py::arg("x0"), py::arg("section"),
        py::arg("t_end"), py::kw_only(), py::arg("dt") = 1e-3, py::arg("stepper") = "gauss6",
        py::arg("direction") = "up", py::arg("max_crossings") = 0, py::arg("unwrapped") = false,
        py::arg("atol") = 1e-10, py::arg("rtol") = 1e-10);
}

}  // namespace npend::python
