// npend.simulate, npend.lyapunov and npend.poincare: integrations run without the GIL, with
// Ctrl-C stopping them (KeyboardInterrupt) instead of waiting for the end.
#include <fmt/format.h>
#include <pybind11/stl.h>

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

py::tuple simulate(const chain& c, const py::handle& x0_in, double t_end, double dt,
                   const std::string& stepper, double t_start, double abs_tol, double rel_tol,
                   int order) {
  const auto x0 = start_state(c, x0_in);
  auto o = integration_from(t_end, dt, stepper, t_start, abs_tol, rel_tol, order);
  // The arrays grow as the run goes: memory for what was computed, not for what was asked.
  const std::size_t rows_asked = output_intervals(o) + 1;
  const auto d = static_cast<std::size_t>(c.state_size());
  std::vector<double> t, states;
  t.reserve(std::min<std::size_t>(rows_asked, 1 << 16));
  states.reserve(t.capacity() * d);
  python_interrupt interrupt;
  o.control = &interrupt;
  {
    py::gil_scoped_release no_gil;
    integrate(c, x0, o, [&](double time, std::span<const double> x) {
      t.push_back(time);
      states.insert(states.end(), x.begin(), x.end());
    });
  }
  interrupt.raise_if_interrupted();
  const std::size_t rows = t.size();
  return py::make_tuple(
      to_numpy(std::move(t), {static_cast<py::ssize_t>(rows)}),
      to_numpy(std::move(states), {static_cast<py::ssize_t>(rows), static_cast<py::ssize_t>(d)}));
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
                    std::size_t vectors, double sample_interval) {
  const auto x0 = start_state(c, x0_in);
  chaos_indicator_options o;
  o.t_end = t_end;
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
  // The stepper names come from the one list in stepper_kind.cpp; pybind11 copies the text.
  const std::string simulate_doc =
      fmt::format(R"(Integrates Hamilton's equations from x0 (shape (2n,)) on the grid
t_k = t_start + k dt up to t_end, as `npend simulate` does.

Returns (t, X): t of shape (N+1,), X of shape (N+1, 2n), row k the state at t_k.
stepper: one of {} (default gauss6); the adaptive ones ({})
use abs_tol and rel_tol; order fixes the taylor stepper's order (2..{}; 0: from the
tolerances). Raises ValueError for bad input, RuntimeError when the integration
cannot go on, KeyboardInterrupt on Ctrl-C.)",
                  stepper_names(), stepper_names(stepper_use::adaptive), taylor_max_order);
  m.def("simulate", &simulate, py::arg("chain"), py::arg("x0"), py::arg("t_end"), py::kw_only(),
        py::arg("dt") = 1e-3, py::arg("stepper") = "gauss6", py::arg("t_start") = 0.0,
        py::arg("abs_tol") = 1e-10, py::arg("rel_tol") = 1e-10, py::arg("order") = 0,
        simulate_doc.c_str());
  // python/npend/analysis.py wraps lyapunov, chaos_indicators and poincare (signatures,
  // docstrings, result classes): they return plain dicts whose keys are the classes' fields.
  m.def("lyapunov", &lyapunov, py::arg("chain"), py::arg("x0"), py::arg("t_end"), py::kw_only(),
        py::arg("dt") = 1e-3, py::arg("stepper") = "gauss6", py::arg("maximal") = false,
        py::arg("exponents") = 0, py::arg("renormalise_every") = 0.1, py::arg("transient") = 0.0,
        py::arg("blocks") = 10, py::arg("atol") = 1e-10, py::arg("rtol") = 1e-10);
  m.def("chaos_indicators", &indicators, py::arg("chain"), py::arg("x0"), py::arg("t_end"),
        py::kw_only(), py::arg("dt") = 0.01, py::arg("vectors") = 2,
        py::arg("sample_interval") = 0.0);
  m.def("poincare", &poincare, py::arg("chain"), py::arg("x0"), py::arg("section"),
        py::arg("t_end"), py::kw_only(), py::arg("dt") = 1e-3, py::arg("stepper") = "gauss6",
        py::arg("direction") = "up", py::arg("max_crossings") = 0, py::arg("unwrapped") = false,
        py::arg("atol") = 1e-10, py::arg("rtol") = 1e-10);
}

}  // namespace npend::python
