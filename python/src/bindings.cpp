// The helpers the binding files share (bindings.hpp).
#include "bindings.hpp"

#include <fmt/format.h>

#include <stdexcept>

#include "npend/integrators/stepper_kind.hpp"

namespace npend::python {

py::array_t<double> to_numpy(std::vector<double>&& values, std::vector<py::ssize_t> shape) {
  auto* owned = new std::vector<double>(std::move(values));
  py::capsule free_when_done(owned, [](void* p) { delete static_cast<std::vector<double>*>(p); });
  return py::array_t<double>(std::move(shape), owned->data(), free_when_done);
}

namespace {

std::string shape_text(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) s += fmt::format("{}{}", i ? ", " : "", a.shape(i));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

}  // namespace

double_array as_array(const py::handle& values, const char* what) {
  // ensure() returns a null array (its error cleared) for what numpy cannot convert.
  double_array a = double_array::ensure(values);
  if (!a) throw std::invalid_argument(fmt::format("{} must be an array of numbers", what));
  return a;
}

std::vector<double> to_vector(const py::handle& values, std::size_t expected, const char* what) {
  const double_array a = as_array(values, what);
  if (a.ndim() != 1 || static_cast<std::size_t>(a.shape(0)) != expected)
    throw std::invalid_argument(
        fmt::format("{} must have shape ({},); got {}", what, expected, shape_text(a)));
  return {a.data(), a.data() + expected};
}

state_batch to_states(const py::handle& x, int state_size, const char* what) {
  state_batch b;
  b.array = as_array(x, what);
  b.width = static_cast<std::size_t>(state_size);
  const auto width = static_cast<py::ssize_t>(state_size);
  if (b.array.ndim() == 1 && b.array.shape(0) == width) {
    b.count = 1;
    return b;
  }
  if (b.array.ndim() == 2 && b.array.shape(1) == width) {
    b.count = static_cast<std::size_t>(b.array.shape(0));
    b.single = false;
    return b;
  }
  throw std::invalid_argument(fmt::format("{} must have shape ({},) or (k, {}); got {}", what,
                                          state_size, state_size, shape_text(b.array)));
}

integration_options integration_from(double t_end, double dt, const std::string& stepper,
                                     double t_start, double abs_tol, double rel_tol, int order) {
  integration_options o;
  o.stepper = parse_stepper_kind(stepper);
  o.t_start = t_start;
  o.t_end = t_end;
  o.dt = dt;
  o.abs_tol = abs_tol;
  o.rel_tol = rel_tol;
  o.taylor_order = order;
  if (order != 0 && o.stepper != stepper_kind::taylor)
    throw std::invalid_argument(
        fmt::format("order: only the taylor stepper takes an order, not {}", stepper));
  o.validate();
  return o;
}

bool python_interrupt::stop_requested() {
  if (interrupted()) return true;
  // Worker threads (a map's OpenMP team) only read the flag: the thread that made this
  // control is the one that called from Python, and only there can signal handlers run.
  if (std::this_thread::get_id() != m_owner) return false;
  const auto now = std::chrono::steady_clock::now();
  if (now - m_last_check < std::chrono::milliseconds(20)) return false;
  m_last_check = now;
  py::gil_scoped_acquire gil;
  if (PyErr_CheckSignals() != 0) m_interrupted.store(true, std::memory_order_relaxed);
  if (!interrupted()) report_to_python();
  return interrupted();
}

void python_interrupt::progress(double done, double total) {
  // Any thread may report (a map's team); only the owner's poll passes it on to Python.
  m_done.store(done, std::memory_order_relaxed);
  m_total.store(total, std::memory_order_relaxed);
}

void python_interrupt::report_last() {
  report_to_python();
  raise_if_interrupted();
}

void python_interrupt::report_to_python() {
  const double done = m_done.load(std::memory_order_relaxed);
  if (m_progress.is_none() || done == m_reported) return;
  m_reported = done;
  try {
    m_progress(done, m_total.load(std::memory_order_relaxed));
  } catch (py::error_already_set& e) {
    e.restore();  // raised by raise_if_interrupted, as a signal handler's exception is
    m_interrupted.store(true, std::memory_order_relaxed);
  }
}

void python_interrupt::raise_if_interrupted() const {
  if (interrupted()) throw py::error_already_set();
}

}  // namespace npend::python
