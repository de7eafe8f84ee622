// The compiled part of the `npend` Python package (npend._npend); python/npend/__init__.py
// re-exports it. Errors: std::invalid_argument (bad input, with the library's and the
// command line's messages) becomes ValueError, npend::integration_error becomes
// npend.IntegrationError (a RuntimeError carrying the time), Ctrl-C KeyboardInterrupt.
#include "bindings.hpp"
#include "npend/integrators/integration_error.hpp"

PYBIND11_MODULE(_npend, m) {
  namespace py = pybind11;
  m.doc() = "Exact equations of planar n-link pendulum chains and the analyses of chaos";
  static py::exception<npend::integration_error> integration_error(m, "IntegrationError",
                                                                   PyExc_RuntimeError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const npend::integration_error& e) {
      py::object error = py::reinterpret_borrow<py::object>(integration_error)(e.what());
      error.attr("time") = e.time();
      PyErr_SetObject(integration_error.ptr(), error.ptr());
    }
  });
  npend::python::bind_chain(m);
  npend::python::bind_integration(m);
  npend::python::bind_series(m);
  npend::python::bind_stability(m);
  npend::python::bind_orbits(m);
  npend::python::bind_maps(m);
}
