"""npend.Chain with the conventions of NumPy and SciPy: solve_ivp's fun(t, y) and jac(t, y),
pickling and copying (so process pools take chains), equality, a repr that rebuilds it,
batches everywhere, one-line type errors, signatures and Python types."""

import copy
import inspect
import pickle
from concurrent.futures import ProcessPoolExecutor

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import npend

# One chain of each kind the constructor builds.
KINDS = [
    dict(links=3, masses=[1, 2, 1.5]),
    dict(links=2, lengths=[1.0, 0.5], g=1.62),
    dict(links=2, rods=True, stiffness=[1.0, 2.0], rest_angles=[0.1, -0.2], damping=0.05),
    dict(links=2, com=[0.3, 0.4], inertia=[0.01, 0.02]),
    dict(links=2, pivot="vertical:0.123456789012345:61.7"),
    dict(links=1, cart=2.0, cart_damping=0.3),
]


@pytest.fixture(params=range(len(KINDS)), ids=lambda i: f"kind{i}")
def chain(request):
    return npend.Chain(**KINDS[request.param])


def test_solve_ivp_with_fun_agrees_with_simulate():
    chain = npend.Chain(3)
    x0 = np.array([0.3, -0.2, 0.25, 0.0, 0.1, 0.0])
    sol = solve_ivp(chain.fun, (0, 5), x0, method="DOP853", rtol=1e-12, atol=1e-12)
    assert sol.status == 0
    t, X = npend.simulate(chain, x0, t_end=5, stepper="rkf78", atol=1e-13, rtol=1e-13)
    assert np.max(np.abs(sol.y[:, -1] - X[-1])) < 1e-9
    vectorized = solve_ivp(chain.fun, (0, 5), x0, method="DOP853", rtol=1e-12, atol=1e-12,
                           vectorized=True)
    np.testing.assert_allclose(vectorized.y[:, -1], sol.y[:, -1], rtol=0, atol=1e-12)


def test_fun_takes_columns_and_time_matters_on_a_moving_pivot():
    chain = npend.Chain(2, pivot="vertical:0.1:30")
    states = np.array([[0.3, -0.2, 0.1, 0.0], [0.1, 0.4, 0.0, -0.3], [1.0, 2.0, 0.5, 0.5]])
    columns = chain.fun(0.7, states.T)
    assert columns.shape == (4, 3)
    for k, x in enumerate(states):
        np.testing.assert_array_equal(columns[:, k], chain.rhs(x, 0.7))
        np.testing.assert_array_equal(chain.fun(0.7, x), chain.rhs(x, 0.7))
    assert not np.array_equal(chain.fun(0.0, states[0]), chain.fun(0.05, states[0]))


def test_jac_is_the_derivative_of_fun(chain):
    rng = np.random.default_rng(3)
    y = rng.uniform(-1, 1, chain.state_size)
    J = chain.jac(0.4, y)
    h = 1e-6
    for j in range(chain.state_size):
        e = np.zeros(chain.state_size)
        e[j] = h
        column = (chain.fun(0.4, y + e) - chain.fun(0.4, y - e)) / (2 * h)
        np.testing.assert_allclose(J[:, j], column, rtol=1e-6, atol=1e-7)


def test_radau_with_the_exact_jacobian_converges_to_the_same_orbit():
    chain = npend.Chain(2, rods=True, damping=0.2)
    x0 = [0.8, -0.4, 0.0, 0.0]
    radau = solve_ivp(chain.fun, (0, 3), x0, method="Radau", jac=chain.jac, rtol=1e-10,
                      atol=1e-10)
    assert radau.status == 0
    _, X = npend.simulate(chain, x0, t_end=3, dt=1e-3)
    assert np.max(np.abs(radau.y[:, -1] - X[-1])) < 1e-7


def test_the_parameters_rebuild_an_equal_chain(chain):
    again = npend.Chain(**chain.parameters)
    assert again == chain and not (again != chain)
    assert hash(again) == hash(chain)
    x = np.linspace(0.1, 0.6, chain.state_size)
    np.testing.assert_array_equal(again.rhs(x, 0.3), chain.rhs(x, 0.3))


def test_repr_shows_the_parameters_and_rebuilds_the_chain(chain):
    text = repr(chain)
    assert text.startswith(f"npend.Chain({chain.links}")
    assert eval(text, {"npend": npend}) == chain


def test_repr_leaves_the_defaults_out():
    assert repr(npend.Chain(3)) == "npend.Chain(3)"
    assert repr(npend.Chain(3, masses=[1, 2, 1.5])) == "npend.Chain(3, masses=[1.0, 2.0, 1.5])"


def test_chains_differ_by_any_parameter():
    assert npend.Chain(2) != npend.Chain(2, g=9.8)
    assert npend.Chain(2) != npend.Chain(3)
    assert npend.Chain(2) != npend.Chain(2, damping=0.1)
    assert npend.Chain(2) != "npend.Chain(2)"


def test_pickle_copy_and_deepcopy(chain):
    for clone in (pickle.loads(pickle.dumps(chain)), copy.copy(chain), copy.deepcopy(chain)):
        assert type(clone) is npend.Chain
        assert clone == chain


def energy_of_hanging_deflection(chain):
    x = np.zeros(chain.state_size)
    x[chain.state_size // 2 - 1] = 0.5  # the last coordinate deflected by 0.5 rad
    return chain.hamiltonian(x)


def test_a_process_pool_takes_chains():
    chains = [npend.Chain(n, masses=2.0) for n in (1, 2, 3)]
    with ProcessPoolExecutor(2) as pool:
        energies = list(pool.map(energy_of_hanging_deflection, chains))
    # The last bob (2 kg) raised by l (1 - cos 0.5) with every link above it hanging.
    np.testing.assert_allclose(energies, 2.0 * 9.81 * (1 - np.cos(0.5)), rtol=1e-14)


def test_pivot_none_is_a_fixed_pivot():
    assert npend.Chain(2, pivot=None) == npend.Chain(2, pivot="fixed") == npend.Chain(2)
    assert npend.Chain(2, pivot=None).parameters["pivot"] == "fixed"


def test_state_from_velocities_takes_batches():
    chain = npend.Chain(3, masses=[1, 2, 1.5], lengths=[1, 0.5, 0.8])
    rng = np.random.default_rng(5)
    phi, dphi = rng.uniform(-2, 2, (7, 3)), rng.uniform(-1, 1, (7, 3))
    batch = chain.state_from_velocities(phi, dphi)
    assert batch.shape == (7, 6)
    for k in range(7):
        np.testing.assert_array_equal(batch[k], chain.state_from_velocities(phi[k], dphi[k]))
        # p = A(phi) dphi, from the mass matrix
        np.testing.assert_allclose(batch[k, 3:], chain.mass_matrix(batch[k]) @ dphi[k],
                                   rtol=1e-14)
    with pytest.raises(ValueError, match="phi, dphi"):
        chain.state_from_velocities(phi, dphi[:3])


@pytest.mark.parametrize("call, message", [
    (lambda: npend.Chain(3.0), "links: expected an integer, got 3.0"),
    (lambda: npend.Chain("3"), "links: expected an integer, got '3'"),
    (lambda: npend.Chain(2, g="9.81"), "g: expected a number, got '9.81'"),
    (lambda: npend.Chain(2, cart="1"), "cart: expected a number"),
    (lambda: npend.Chain(2, rods="yes"), "rods: expected True or False"),
    (lambda: npend.Chain(2, pivot=3), "pivot: expected None"),
    (lambda: npend.Chain(2).rhs([0, 0, 0, 0], "t"), "t: expected a number"),
])
def test_common_mistakes_give_one_line(call, message):
    with pytest.raises(TypeError) as error:
        call()
    assert message in str(error.value)
    assert "\n" not in str(error.value)


def test_every_method_has_a_signature_and_python_types():
    for name, member in inspect.getmembers(npend.Chain):
        if name.startswith("_") and name != "__init__":
            continue
        if callable(member):
            inspect.signature(member)  # raises for a function without one
            doc = inspect.getdoc(member) or ""
            for cpp in ("handle", "npend::", "_npend"):
                assert cpp not in doc, (name, cpp)
    assert npend.Chain.__module__ == "npend"
