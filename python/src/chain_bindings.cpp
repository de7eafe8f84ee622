// npend.Chain: a chain's parameters and its generated functions, each taking one state or a
// batch of states as the rows of a 2-D array.
#include <fmt/format.h>
#include <pybind11/stl.h>

#include <functional>
#include <optional>
#include <stdexcept>

#include "bindings.hpp"
#include "npend/excitation.hpp"
#include "npend/spec/chain_spec.hpp"

namespace npend::python {

namespace {

// A per-link list as users give it: None (the default, an empty list), one number for every
// link, or one value per link; chain_spec checks the count as the command line's.
std::vector<double> per_link(const py::handle& value, int links, const char* what) {
  if (value.is_none()) return {};
  const double_array a = as_array(value, what);
  if (a.ndim() > 1)
    throw std::invalid_argument(
        fmt::format("{}: expected a number or a list of {} numbers (one per link)", what, links));
  // An empty list is no value for the links, not the default that None asks for.
  if (a.size() == 0) spec::per_link_values({}, what, links, spec::find_per_link_key(what)->symbol);
  return {a.data(), a.data() + a.size()};
}

// The chain of npend.Chain's arguments: the command line's chain_spec, its messages naming
// the keywords.
chain make_chain(int links, const py::object& masses, const py::object& lengths, double g,
                 const py::object& com, const py::object& inertia, bool rods,
                 const py::object& stiffness, const py::object& rest_angles,
                 const py::object& damping, const py::object& pivot_in,
                 const std::optional<double>& cart, const std::optional<double>& cart_damping) {
  spec::check_links(links, spec::naming::keywords);
  spec::chain_spec s;
  s.links = links;
  s.masses = per_link(masses, links, "masses");
  s.lengths = per_link(lengths, links, "lengths");
  s.g = g;
  s.com = per_link(com, links, "com");
  s.inertia = per_link(inertia, links, "inertia");
  s.rods = rods;
  s.stiffness = per_link(stiffness, links, "stiffness");
  s.rest_angles = per_link(rest_angles, links, "rest_angles");
  s.damping = per_link(damping, links, "damping");
  // None or parameters["pivot"]'s "fixed" for a fixed pivot: that text reads back.
  if (!pivot_in.is_none() && !py::isinstance<py::str>(pivot_in))
    throw py::type_error(
        "pivot: expected None, \"fixed\" or a drive such as "
        "\"vertical:A:OMEGA\", got " +
        std::string(py::repr(pivot_in)));
  const std::string pivot = pivot_in.is_none() ? "" : pivot_in.cast<std::string>();
  s.pivot = pivot == "fixed" ? "" : pivot;
  s.cart = cart;
  s.cart_damping = cart_damping;
  return spec::make_chain(s, spec::naming::keywords);
}

// f(x) of every state in the batch: `out_per_state` values each, written by `fill`.
py::array_t<double> over_states(const chain& c, const py::handle& x, std::size_t out_per_state,
                                std::vector<py::ssize_t> out_shape,
                                const std::function<void(const double* x, double* out)>& fill) {
  const state_batch b = to_states(x, c.state_size(), "x");
  std::vector<double> out(b.count * out_per_state);
  python_interrupt interrupt;
  {
    py::gil_scoped_release no_gil;
    // Ctrl-C reaches a batch of millions of rows: polled every 4096 of them.
    for (std::size_t i = 0; i < b.count; ++i) {
      if (i % 4096 == 4095 && interrupt.stop_requested()) break;
      fill(b.row(i), out.data() + i * out_per_state);
    }
  }
  interrupt.raise_if_interrupted();
  if (!b.single) out_shape.insert(out_shape.begin(), static_cast<py::ssize_t>(b.count));
  return to_numpy(std::move(out), std::move(out_shape));
}

// The coordinates q of a state: the angles, after the cart's position on a cart.
std::span<const double> angles_of(const chain& c, const double* x) {
  return {x, static_cast<std::size_t>(c.coordinates())};
}

py::dict parameters_dict(const chain_parameters& p) {
  py::dict d;
  d["links"] = p.links();
  d["masses"] = p.masses;
  d["lengths"] = p.lengths;
  d["g"] = p.g;
  // A per-link list that was not given reads None, as the constructor's default: the dict
  // passed back as keywords (Chain(**parameters)) builds the same chain.
  const auto given = [](const std::vector<double>& v) {
    return v.empty() ? py::object(py::none()) : py::object(py::cast(v));
  };
  d["com"] = given(p.com);
  d["inertia"] = given(p.inertia);
  d["stiffness"] = given(p.stiffness);
  d["rest_angles"] = given(p.rest_angles);
  d["damping"] = given(p.damping);
  d["pivot"] = p.pivot.describe();
  d["cart"] = p.cart_mass ? py::object(py::float_(*p.cart_mass)) : py::object(py::none());
  d["cart_damping"] = p.cart_mass ? py::object(py::float_(p.cart_damping)) : py::object(py::none());
  return d;
}

// A direction for the excitations: none (their default) or n numbers.
std::vector<double> direction_of(const chain& c, const py::object& direction) {
  if (direction.is_none()) return {};
  return to_vector(direction, static_cast<std::size_t>(c.links()), "direction");
}

void bind_excitations(py::module_& m) {
  m.def("energy_from_epsilon", &energy_from_epsilon, py::arg("chain"), py::arg("epsilon"),
        "E = epsilon m g l (J), the paper's dimensionless energy, for equal masses and lengths.");
  m.def(
      "deflected_state",
      [](const chain& c, double energy, const py::object& direction) {
        return to_numpy(deflected_state(c, energy, direction_of(c, direction)), {c.state_size()});
      },
      py::arg("chain"), py::arg("energy"), py::arg("direction") = py::none(),
      R"(The chain at rest with its angles s * direction (default: all ones), s chosen so
that H = energy (J): the paper's excitation by deflecting the arms.)");
  m.def(
      "kicked_state",
      [](const chain& c, double energy, const py::object& direction) {
        return to_numpy(kicked_state(c, energy, direction_of(c, direction)), {c.state_size()});
      },
      py::arg("chain"), py::arg("energy"), py::arg("direction") = py::none(),
      R"(The hanging chain with momenta s * direction (default: a horizontal kick on the
lowest bob), s chosen so that H = energy (J): the paper's excitation by a kick.)");
}

}  // namespace

void bind_chain(py::module_& m) {
  bind_excitations(m);
  m.def("built_link_counts", &built_link_counts,
        "The link counts whose generated kernels are compiled into this build.");

  py::class_<chain>(m, "Chain", R"(An n-link planar pendulum chain with fixed parameters.

State layout everywhere: x = [phi_1..phi_n, p_1..p_n] (angles in rad from the downward
vertical, canonical momenta in kg m^2/s). Every method takes one state of shape (2n,) or a
batch of k states as the rows of a (k, 2n) array, and then returns one result per row.
With cart=M (kg) the chain hangs from a cart rolling along x (viscous damping cart_damping,
N s/m): x = [x_c, phi_1..phi_n, p_x, p_1..p_n], shape (2n + 2,), and the coordinates
q = [x_c, phi] take the place of phi below.

Per-link parameters take one number for every link or a list of n values. Point masses on
massless rods (the paper's model) unless com/inertia/rods, springs, damping or a moving
pivot ("vertical:A:OMEGA" or "horizontal:A:OMEGA") make it a physical chain.)")
      .def(py::init(&make_chain), py::arg("links"), py::kw_only(), py::arg("masses") = py::none(),
           py::arg("lengths") = py::none(), py::arg("g") = standard_gravity,
           py::arg("com") = py::none(), py::arg("inertia") = py::none(), py::arg("rods") = false,
           py::arg("stiffness") = py::none(), py::arg("rest_angles") = py::none(),
           py::arg("damping") = py::none(), py::arg("pivot") = py::none(),
           py::arg("cart") = py::none(), py::arg("cart_damping") = py::none())
      .def_property_readonly("links", &chain::links)
      .def_property_readonly("state_size", &chain::state_size)
      .def_property_readonly("is_physical", &chain::is_physical)
      .def_property_readonly("has_cart", &chain::has_cart)
      .def_property_readonly(
          "parameters", [](const chain& c) { return parameters_dict(c.parameters()); },
          "The parameters as a dict (masses, lengths, g, com, inertia, stiffness, "
          "rest_angles, damping, pivot, cart, cart_damping)")
      .def(
          "rhs",
          [](const chain& c, const py::handle& x, double t) {
            const auto d = static_cast<std::size_t>(c.state_size());
            return over_states(c, x, d, {static_cast<py::ssize_t>(d)},
                               [&](const double* s, double* out) { c.evaluate_rhs(s, t, out); });
          },
          py::arg("x"), py::arg("t") = 0.0, "Hamilton's equations dx/dt = f(x, t).")
      .def(
          "jacobian",
          [](const chain& c, const py::handle& x, double t) {
            const auto d = static_cast<std::size_t>(c.state_size());
            const auto s = static_cast<py::ssize_t>(d);
            return over_states(c, x, d * d, {s, s}, [&](const double* xs, double* out) {
              c.evaluate_jacobian(xs, t, out);
            });
          },
          py::arg("x"), py::arg("t") = 0.0, "The exact Jacobian df/dx, shape (2n, 2n).")
      .def(
          "hamiltonian",
          [](const chain& c, const py::handle& x, double t) -> py::object {
            const auto d = static_cast<std::size_t>(c.state_size());
            const auto h = over_states(c, x, 1, {}, [&](const double* s, double* out) {
              *out = c.hamiltonian({s, d}, t);
            });
            if (h.ndim() == 0) return py::float_(*h.data());
            return h;
          },
          py::arg("x"), py::arg("t") = 0.0, "The energy H = T + V in J.")
      .def(
          "positions",
          [](const chain& c, const py::handle& x) {
            const auto n = static_cast<std::size_t>(c.points());
            return over_states(c, x, 2 * n, {static_cast<py::ssize_t>(n), 2},
                               [&](const double* s, double* out) {
                                 c.positions(angles_of(c, s), {out, 2 * n});
                               });
          },
          py::arg("x"),
          "The link ends (bobs) relative to the pivot, shape (n, 2): rows (x_i, y_i) in m, "
          "y pointing down; on a cart the cart (x_c, 0) first, shape (n + 1, 2).")
      .def(
          "velocities",
          [](const chain& c, const py::handle& x) {
            const auto n = static_cast<std::size_t>(c.coordinates());
            return over_states(c, x, n, {static_cast<py::ssize_t>(n)},
                               [&](const double* s, double* out) {
                                 c.velocities(angles_of(c, s), {s + n, n}, {out, n});
                               });
          },
          py::arg("x"), "The angular velocities dphi/dt = A(phi)^-1 p, shape (n,).")
      .def(
          "mass_matrix",
          [](const chain& c, const py::handle& x) {
            const auto n = static_cast<std::size_t>(c.coordinates());
            const auto s = static_cast<py::ssize_t>(n);
            return over_states(c, x, n * n, {s, s}, [&](const double* xs, double* out) {
              c.mass_matrix(angles_of(c, xs), {out, n * n});
            });
          },
          py::arg("x"), "The mass matrix A(phi) of T = p^T A^-1 p / 2, shape (n, n).")
      .def(
          "state_from_velocities",
          [](const chain& c, const py::handle& phi, const py::handle& dphi) {
            const auto n = static_cast<std::size_t>(c.coordinates());
            // Angles and velocities side by side as the rows of one batch, (k, 2n) or (2n,).
            const double_array a = as_array(phi, "phi"), v = as_array(dphi, "dphi");
            const bool same_shape = a.ndim() == v.ndim() && a.ndim() >= 1 && a.ndim() <= 2 &&
                                    std::equal(a.shape(), a.shape() + a.ndim(), v.shape());
            if (!same_shape || static_cast<std::size_t>(a.shape(a.ndim() - 1)) != n)
              throw std::invalid_argument(fmt::format(
                  "phi, dphi: expected two arrays of shape ({},) or (k, {}) alike", n, n));
            const auto rows = static_cast<std::size_t>(a.ndim() == 2 ? a.shape(0) : 1);
            std::vector<double> joined(rows * 2 * n);
            for (std::size_t r = 0; r < rows; ++r) {
              std::copy_n(a.data() + r * n, n, joined.begin() + static_cast<long>(2 * r * n));
              std::copy_n(v.data() + r * n, n, joined.begin() + static_cast<long>((2 * r + 1) * n));
            }
            const auto batch = a.ndim() == 2
                                   ? to_numpy(std::move(joined), {static_cast<py::ssize_t>(rows),
                                                                  static_cast<py::ssize_t>(2 * n)})
                                   : to_numpy(std::move(joined), {static_cast<py::ssize_t>(2 * n)});
            return over_states(c, batch, 2 * n, {static_cast<py::ssize_t>(2 * n)},
                               [&](const double* s, double* out) {
                                 const auto x = c.state_from_velocities({s, n}, {s + n, n});
                                 std::copy(x.begin(), x.end(), out);
                               });
          },
          py::arg("phi"), py::arg("dphi"),
          "The state [phi, A(phi) dphi] for angles phi and angular velocities dphi (shape (n,), "
          "or (k, n) each for k states).");
}

}  // namespace npend::python
