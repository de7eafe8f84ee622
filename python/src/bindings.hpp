// What the binding files share: numpy conversions, keyword-argument parsing of chains and
// integrators, and the run control that lets Ctrl-C stop a computation running without the GIL.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <atomic>
#include <chrono>
#include <cstddef>
#include <string>
#include <thread>
#include <vector>

#include "npend/chain.hpp"
#include "npend/integrators/integrate.hpp"
#include "npend/run_control.hpp"

namespace npend::python {

namespace py = pybind11;

/// A C-contiguous float64 view of whatever numpy can convert (lists, ints, other dtypes).
using double_array = py::array_t<double, py::array::c_style | py::array::forcecast>;

/// `values` as a float64 array; ValueError naming `what` if numpy cannot convert them.
double_array as_array(const py::handle& values, const char* what);

/// Moves `values` into a numpy array of `shape` without copying: the array owns the vector.
py::array_t<double> to_numpy(std::vector<double>&& values, std::vector<py::ssize_t> shape);

/// A 1-D array of `expected` values (any sequence numpy converts); ValueError naming `what`.
std::vector<double> to_vector(const py::handle& values, std::size_t expected, const char* what);

/// States as the chain functions take them: one state of shape (2n,), or k states as the
/// rows of a (k, 2n) array. ValueError naming `what` and the expected shape otherwise.
struct state_batch {
  double_array array;
  std::size_t count = 0;  ///< k (1 for a single state)
  bool single = true;     ///< shape (2n,) rather than (k, 2n)
  const double* row(std::size_t i) const { return array.data() + i * width; }
  std::size_t width = 0;  ///< 2n
};
state_batch to_states(const py::handle& x, int state_size, const char* what);

/// The integration options shared by simulate, lyapunov and poincare (validated here);
/// `order` is the taylor stepper's (0: from the tolerances), refused for another stepper.
integration_options integration_from(double t_end, double dt, const std::string& stepper,
                                     double t_start, double abs_tol, double rel_tol, int order = 0);

/// The run control of a computation that runs with the GIL released: every 20 ms it takes
/// the GIL back and runs Python's signal handlers, so Ctrl-C (or any handler that raises)
/// asks the computation to stop. Afterwards, with the GIL held, raise_if_interrupted()
/// raises the handler's exception (KeyboardInterrupt) instead of returning a partial result.
/// Signals are only handled on Python's main thread; other threads read the flag.
///
/// With a `progress` callable (not None), the same poll calls progress(done, total) with the
/// computation's latest report (its own units: seconds of simulated time, cells, ...) when
/// it changed; an exception from the callable stops the computation and is raised.
class python_interrupt final : public run_control {
 public:
  explicit python_interrupt(py::object progress = py::none()) : m_progress(std::move(progress)) {}
  void progress(double done, double total) override;
  bool stop_requested() override;
  void raise_if_interrupted() const;
  /// With the GIL held, after the run: passes the last progress report on to Python (the
  /// polls see only some of them), raising what the callable raises.
  void report_last();
  bool interrupted() const { return m_interrupted.load(std::memory_order_relaxed); }

 private:
  void report_to_python();

  py::object m_progress;
  std::atomic<double> m_done{0}, m_total{0};
  double m_reported = -1;
  std::atomic<bool> m_interrupted{false};
  std::thread::id m_owner = std::this_thread::get_id();
  std::chrono::steady_clock::time_point m_last_check = std::chrono::steady_clock::now();
};

void bind_chain(py::module_& m);
void bind_integration(py::module_& m);
void bind_series(py::module_& m);
void bind_stability(py::module_& m);
void bind_orbits(py::module_& m);
void bind_maps(py::module_& m);

}  // namespace npend::python
