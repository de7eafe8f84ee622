"""npend.Chain: its functions equal the C++ library's (through `npend eval`), match closed
forms written here, and take batches of states; bad input raises ValueError with the command
line's message."""

import math

import numpy as np
import pytest

import npend
from conftest import csv_list, npend_json, run_npend

STATE2 = np.array([0.7, -1.3, 0.4, -0.25])


def eval_json(links, state, *options, time=0.0):
    return npend_json("eval", "--links", links, "--state", csv_list(state), "--time", time,
                      *options)


@pytest.mark.parametrize("options, kwargs", [
    ((), {}),
    (("--masses", "1,2", "--lengths", "0.5,1.5", "--g", "3.7"),
     dict(masses=[1, 2], lengths=[0.5, 1.5], g=3.7)),
    (("--rods", "--stiffness", "0.3", "--rest-angles", "0.1,-0.2", "--damping", "0.05",
      "--pivot", "vertical:0.1:20"),
     dict(rods=True, stiffness=0.3, rest_angles=[0.1, -0.2], damping=0.05,
          pivot="vertical:0.1:20")),
])
def test_functions_equal_the_library(options, kwargs):
    c = npend.Chain(2, **kwargs)
    t = 0.37
    ref = eval_json(2, STATE2, *options, time=t)
    # Same library, same arithmetic: the numbers agree to the last bit (the JSON keeps 17
    # digits).
    assert np.array_equal(c.rhs(STATE2, t), ref["rhs"])
    assert np.array_equal(c.jacobian(STATE2, t), np.array(ref["jacobian"]))
    assert c.hamiltonian(STATE2, t) == ref["hamiltonian"]
    assert np.array_equal(c.mass_matrix(STATE2), np.array(ref["mass_matrix"]))
    assert c.is_physical == bool(options and options[0] == "--rods")


def test_double_pendulum_against_closed_forms():
    """H and the bob positions of the double pendulum, written out here."""
    m1, m2, l1, l2, g = 1.3, 0.6, 0.8, 1.1, 9.81
    c = npend.Chain(2, masses=[m1, m2], lengths=[l1, l2], g=g)
    f1, f2, p1, p2 = STATE2
    delta = f1 - f2
    # T = (m2 l2^2 p1^2 + (m1+m2) l1^2 p2^2 - 2 m2 l1 l2 p1 p2 cos d) / (2 l1^2 l2^2 m2 (m1 + m2 sin^2 d))
    kinetic = (m2 * l2**2 * p1**2 + (m1 + m2) * l1**2 * p2**2
               - 2 * m2 * l1 * l2 * p1 * p2 * math.cos(delta)) / (
                   2 * l1**2 * l2**2 * m2 * (m1 + m2 * math.sin(delta) ** 2))
    potential = -(m1 + m2) * g * l1 * math.cos(f1) - m2 * g * l2 * math.cos(f2)
    potential += (m1 + m2) * g * l1 + m2 * g * l2  # zero at the hanging chain
    assert c.hamiltonian(STATE2) == pytest.approx(kinetic + potential, rel=1e-13)
    bobs = c.positions(STATE2)
    assert bobs.shape == (2, 2)
    assert bobs[0] == pytest.approx([l1 * math.sin(f1), l1 * math.cos(f1)], rel=1e-14)
    assert bobs[1] == pytest.approx(
        [l1 * math.sin(f1) + l2 * math.sin(f2), l1 * math.cos(f1) + l2 * math.cos(f2)], rel=1e-14)


def test_jacobian_against_finite_differences():
    c = npend.Chain(3, masses=[1, 0.5, 2], lengths=[1, 0.7, 0.4])
    x = np.array([0.3, -0.8, 1.9, 0.5, -0.2, 0.1])
    h = 1e-6
    columns = [(c.rhs(x + h * e) - c.rhs(x - h * e)) / (2 * h) for e in np.eye(6)]
    assert c.jacobian(x) == pytest.approx(np.array(columns).T, abs=1e-7)


def test_batches_equal_single_states():
    c = npend.Chain(3)
    rng = np.random.default_rng(3)
    X = rng.uniform(-2, 2, size=(5, 6))
    assert c.rhs(X).shape == (5, 6) and c.rhs(X).dtype == np.float64
    assert c.jacobian(X).shape == (5, 6, 6)
    assert c.hamiltonian(X).shape == (5,)
    assert c.positions(X).shape == (5, 3, 2)
    assert c.velocities(X).shape == (5, 3)
    assert c.mass_matrix(X).shape == (5, 3, 3)
    for k in range(5):
        assert np.array_equal(c.rhs(X)[k], c.rhs(X[k]))
        assert np.array_equal(c.jacobian(X)[k], c.jacobian(X[k]))
        assert c.hamiltonian(X)[k] == c.hamiltonian(X[k])
        assert np.array_equal(c.positions(X)[k], c.positions(X[k]))
    assert isinstance(c.hamiltonian(X[0]), float)
    # Lists and other dtypes are converted.
    assert np.array_equal(c.rhs(list(X[0])), c.rhs(X[0]))
    assert np.array_equal(c.rhs([0, 0, 0, 0, 0, 0]), np.zeros(6))


def test_velocities_invert_state_from_velocities():
    c = npend.Chain(3, rods=True)
    phi, dphi = [0.2, -0.4, 1.0], [0.3, 0.1, -0.7]
    x = c.state_from_velocities(phi, dphi)
    assert c.velocities(x) == pytest.approx(dphi, rel=1e-13)
    assert x[3:] == pytest.approx(c.mass_matrix(x) @ np.array(dphi), rel=1e-13)


def test_parameters_round_trip():
    c = npend.Chain(2, masses=2.0, lengths=[1, 3], g=1.62)
    p = c.parameters
    assert p["masses"] == [2.0, 2.0] and p["lengths"] == [1.0, 3.0] and p["g"] == 1.62
    assert p["pivot"] == "fixed" and c.links == 2 and c.state_size == 4
    assert npend.Chain(2, pivot="horizontal:0.2:5").parameters["pivot"].startswith("horizontal")


def cli_error(*args):
    r = run_npend(*args, expect_success=False)
    assert r.returncode != 0
    return r.stderr.strip().split("error: ", 1)[1]


def test_bad_input_raises_value_error_with_the_cli_message():
    with pytest.raises(ValueError) as e:
        npend.Chain(3, masses=[1, 2])
    expected = cli_error("eval", "--links", 3, "--masses", "1,2", "--state", "0,0,0,0,0,0")
    assert str(e.value) == expected.replace("--masses", "masses")

    with pytest.raises(ValueError) as e:
        npend.Chain(2, pivot="sideways:1:2")
    expected = cli_error("eval", "--links", 2, "--pivot", "sideways:1:2", "--state", "0,0,0,0")
    assert str(e.value) == expected.replace("--pivot", "pivot")

    # The command line's rules, spelt with the keywords: rest angles need springs.
    with pytest.raises(ValueError) as e:
        npend.Chain(2, rest_angles=0.1)
    expected = cli_error("eval", "--links", 2, "--rest-angles", "0.1", "--state", "0,0,0,0")
    assert str(e.value) == expected.replace("--rest-angles", "rest_angles").replace(
        "--stiffness", "stiffness")

    with pytest.raises(ValueError, match=r"x must have shape \(4,\) or \(k, 4\); got \(3,\)"):
        npend.Chain(2).rhs([1, 2, 3])
    with pytest.raises(ValueError, match="got \\(2, 5\\)"):
        npend.Chain(2).hamiltonian(np.zeros((2, 5)))
    with pytest.raises(ValueError, match="must be an array of numbers"):
        npend.Chain(2).rhs(["a", "b", "c", "d"])
    with pytest.raises(ValueError, match="links: must be at least 1, got 0"):
        npend.Chain(0)
    with pytest.raises(ValueError, match="NPEND_LINKS"):
        npend.Chain(max(npend.built_link_counts()) + 1, damping=0.1)
    with pytest.raises(ValueError, match="mass"):
        npend.Chain(2, masses=[1, -1])


def test_chain_on_a_cart_against_closed_forms():
    """The cart-pole (point mass m on a massless rod l over a cart M), written out here."""
    m, l, M, g, b = 0.8, 1.3, 2.5, 9.81, 0.4
    c = npend.Chain(1, masses=m, lengths=l, g=g, cart=M, cart_damping=b)
    assert c.has_cart and c.is_physical and c.state_size == 4
    assert c.parameters["cart"] == M and c.parameters["cart_damping"] == b
    xc, phi, px, pphi = 0.2, 0.5, 0.3, -0.1
    x = np.array([xc, phi, px, pphi])
    # A = [[M + m, m l cos phi], [m l cos phi, m l^2]]; T = p^T A^-1 p / 2, V = m g l (1 - cos phi).
    A = np.array([[M + m, m * l * math.cos(phi)], [m * l * math.cos(phi), m * l * l]])
    assert c.mass_matrix(x) == pytest.approx(A, rel=1e-14)
    rates = np.linalg.solve(A, [px, pphi])
    assert c.velocities(x) == pytest.approx(rates, rel=1e-13)
    energy = 0.5 * np.dot([px, pphi], rates) + m * g * l * (1 - math.cos(phi))
    assert c.hamiltonian(x) == pytest.approx(energy, rel=1e-13)
    # Nothing depends on x_c; the cart's damping force -b xdot is its generalised force.
    f = c.rhs(x)
    assert f[:2] == pytest.approx(rates, rel=1e-13)
    assert f[2] == pytest.approx(-b * rates[0], rel=1e-13)
    bobs = c.positions(x)
    assert bobs.shape == (2, 2)
    assert bobs[0] == pytest.approx([xc, 0.0], abs=1e-15)
    assert bobs[1] == pytest.approx([xc + l * math.sin(phi), l * math.cos(phi)], rel=1e-14)
    with pytest.raises(ValueError, match="cart: the cart.s mass must be a positive finite number .kg., got -1"):
        npend.Chain(1, cart=-1.0)
    with pytest.raises(ValueError, match="cart_damping: the cart.s damping needs a cart"):
        npend.Chain(1, cart_damping=0.5)


def test_analyses_of_a_fixed_pivot_refuse_a_cart():
    """The 0/pi equilibria and their modes belong to a fixed pivot: a cart gets a message."""
    c = npend.Chain(2, cart=1.0)
    with pytest.raises(ValueError, match="normal_modes: the chain is on a cart"):
        npend.modes(c)
    with pytest.raises(ValueError, match="find_equilibria: the chain is on a cart"):
        npend.equilibria(c)
    with pytest.raises(ValueError, match="flip: the chain is on a cart"):
        npend.map_cells(c, [0, 0.1, 0.2, 0, 0, 0], t_end=1.0)
