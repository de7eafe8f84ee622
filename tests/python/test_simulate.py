"""npend.simulate with SciPy's conventions: a Solution that unpacks as (t, X), t_span, atol
and rtol, t_eval from the dense output, every, events located on the dense output, the
energy error, progress and a refusal before a run that would not fit in memory."""

import numpy as np
import pytest

import npend


def test_solution_has_attributes_and_unpacks_as_t_and_X():
    chain = npend.Chain(2)
    sol = npend.simulate(chain, [0.3, -0.2, 0, 0], t_end=1.0, dt=0.01)
    t, X = sol
    assert t is sol.t and X is sol.X
    assert sol.t.shape == (101,) and sol.X.shape == (101, 4)
    assert sol.y.shape == (4, 101) and np.shares_memory(sol.y, sol.X)
    assert sol.status == 0 and sol.success and sol.nsteps == 100
    assert (sol.stepper, sol.dt, sol.atol, sol.rtol, sol.order) == ("gauss6", 0.01, 1e-10,
                                                                     1e-10, 0)
    assert sol.t_events == [] and sol.y_events == []
    assert sol.X.flags.owndata or sol.X.base is not None
    text = repr(sol)
    assert "X=array(shape=(101, 4), dtype=float64)" in text and len(text) < 600


def test_energy_error_is_the_largest_relative_change_of_H():
    chain = npend.Chain(3)
    sol = npend.simulate(chain, [0.9, -0.6, 1.2, 0, 0, 0], t_end=2.0, dt=0.01, stepper="rk4")
    H = chain.hamiltonian(sol.X)
    assert sol.energy_error == pytest.approx(np.max(np.abs(H - H[0]) / abs(H[0])), rel=1e-12)
    assert sol.energy_error > 0


def test_t_span_and_t_end_give_the_same_run():
    chain = npend.Chain(2)
    a = npend.simulate(chain, [0.3, -0.2, 0, 0], t_end=0.5)
    b = npend.simulate(chain, [0.3, -0.2, 0, 0], t_span=(0, 0.5))
    c = npend.simulate(chain, [0.3, -0.2, 0, 0], (0, 0.5))  # solve_ivp's positional t_span
    np.testing.assert_array_equal(a.X, b.X)
    np.testing.assert_array_equal(a.X, c.X)


def test_t_eval_takes_the_states_from_the_dense_output():
    chain = npend.Chain(2)
    x0 = [1.0, -0.5, 0.0, 0.2]
    grid = npend.simulate(chain, x0, t_end=1.0, dt=0.01, stepper="dopri5", atol=1e-12,
                          rtol=1e-12)
    on_grid = npend.simulate(chain, x0, t_end=1.0, dt=0.01, stepper="dopri5", atol=1e-12,
                             rtol=1e-12, t_eval=grid.t[::10])
    np.testing.assert_array_equal(on_grid.t, grid.t[::10])
    np.testing.assert_allclose(on_grid.X, grid.X[::10], rtol=0, atol=1e-11)
    times = [0.1234, 0.5678, 0.9999]
    for stepper in ("dopri5", "taylor", "gauss6", "rkf78"):
        sol = npend.simulate(chain, x0, t_end=1.0, dt=0.01, stepper=stepper, atol=1e-12,
                             rtol=1e-12, t_eval=times)
        for t, x in zip(times, sol.X):
            # an independent run that ends exactly at t
            _, X = npend.simulate(chain, x0, t_end=t, dt=1e-3, stepper="rkf78", atol=1e-13,
                                  rtol=1e-13)
            # gauss6 and rkf78 (steps cut at the grid) between steps of 0.01 s: the cubic
            # Hermite interpolant, O(h^4); dopri5 and taylor: their own dense output
            hermite = stepper in ("gauss6", "rkf78")
            assert np.max(np.abs(x - X[-1])) < (1e-7 if hermite else 1e-10), stepper


def test_every_keeps_every_kth_row():
    chain = npend.Chain(2)
    full = npend.simulate(chain, [0.3, -0.2, 0, 0], t_end=1.0, dt=0.01)
    sparse = npend.simulate(chain, [0.3, -0.2, 0, 0], t_end=1.0, dt=0.01, every=7)
    np.testing.assert_array_equal(sparse.t, full.t[::7])
    np.testing.assert_array_equal(sparse.X, full.X[::7])


def test_an_event_is_located_where_the_function_changes_sign():
    chain = npend.Chain(2)
    x0 = [0.8, -0.3, 0.0, 0.0]

    def phi1(t, y):
        return y[0]

    sol = npend.simulate(chain, x0, t_end=6.0, dt=1e-3, events=phi1)
    # where a fine run's phi1 changes sign, linearly interpolated (error ~ dt^2)
    fine = npend.simulate(chain, x0, t_end=6.0, dt=1e-5, stepper="gauss6")
    s = np.sign(fine.X[:, 0])
    k = np.nonzero(s[:-1] != s[1:])[0]
    crossings = fine.t[k] - fine.X[k, 0] * (fine.t[k + 1] - fine.t[k]) / (
        fine.X[k + 1, 0] - fine.X[k, 0])
    np.testing.assert_allclose(sol.t_events[0], crossings, atol=1e-8)
    np.testing.assert_allclose(sol.y_events[0][:, 0], 0.0, atol=1e-12)
    rising = [sign < 0 for sign in s[k]]

    def phi1_rising(t, y):
        return y[0]

    phi1_rising.direction = 1
    up = npend.simulate(chain, x0, t_end=6.0, dt=1e-3, events=phi1_rising)
    np.testing.assert_allclose(up.t_events[0], crossings[rising], atol=1e-8)


def test_a_terminal_event_ends_the_run_there():
    chain = npend.Chain(1)

    def down(t, y):  # phi falls through 0.05 (released from rest at 0.1)
        return y[0] - 0.05

    down.terminal = True
    sol = npend.simulate(chain, [0.1, 0.0], t_end=5.0, dt=0.01, stepper="rkf78", events=down)
    assert sol.status == 1 and "terminal" in sol.message
    # the small-swing pendulum: phi = 0.1 cos(w t), w = sqrt(g/l); at 0.05: w t = pi/3
    # (the amplitude's correction to the period is ~ 0.1^2/16 of it)
    t_event = sol.t_events[0][0]
    assert t_event == pytest.approx(np.pi / 3 / np.sqrt(9.81), rel=2e-3)
    assert sol.t[-1] <= t_event and sol.t[-1] > t_event - 0.01
    # the rows before the event are the ones an unstopped run has
    full = npend.simulate(chain, [0.1, 0.0], t_end=5.0, dt=0.01, stepper="rkf78")
    np.testing.assert_allclose(sol.X, full.X[: len(sol.t)], atol=1e-12)


def test_an_exception_in_an_event_function_is_raised():
    def broken(t, y):
        raise ZeroDivisionError("inside g")

    with pytest.raises(ZeroDivisionError, match="inside g"):
        npend.simulate(npend.Chain(1), [0.1, 0.0], t_end=1.0, events=broken)


def test_progress_hears_the_simulated_time():
    seen = []
    npend.simulate(npend.Chain(3), [0.5, 0.5, 0.5, 0, 0, 0], t_end=20.0,
                   progress=lambda done, total: seen.append((done, total)))
    assert seen, "a 20 s run of the triple pendulum takes more than one 20 ms poll"
    assert all(total == pytest.approx(20000) for _, total in seen)  # grid points
    assert [d for d, _ in seen] == sorted(d for d, _ in seen)
    assert seen[-1] == (20000, 20000)  # the end is reported


def test_progress_true_draws_a_tqdm_bar(capsys):
    pytest.importorskip("tqdm")
    npend.simulate(npend.Chain(2), [0.5, 0.5, 0, 0], t_end=1.0, progress=True)
    assert "100%" in capsys.readouterr().err


def test_an_exception_in_the_progress_callable_stops_the_run():
    def impatient(done, total):
        raise RuntimeError("enough")

    with pytest.raises(RuntimeError, match="enough"):
        npend.simulate(npend.Chain(3), [0.5, 0.5, 0.5, 0, 0, 0], t_end=20.0, progress=impatient)


def test_a_run_that_would_not_fit_in_memory_is_refused_before_it_starts():
    with pytest.raises(ValueError, match="every=K"):
        npend.simulate(npend.Chain(2), [0.1, 0, 0, 0], t_end=1e12)


@pytest.mark.parametrize("kwargs, message", [
    (dict(t_end=1.0, t_span=(0, 1)), "t_end, t_span"),
    (dict(), "t_end, t_span"),
    (dict(t_end=1.0, t_eval=[0.5, 2.0]), "t_eval: the times must lie within"),
    (dict(t_end=1.0, t_eval=[0.5, 0.2]), "t_eval: the times must be sorted"),
    (dict(t_end=1.0, every=0), "every"),
    (dict(t_end=1.0, every=2, t_eval=[0.5]), "every: not with t_eval"),
    (dict(t_span=(0, 1, 2)), "t_span: expected (t0, t1)"),
])
def test_bad_input_names_the_keyword(kwargs, message):
    with pytest.raises(ValueError) as error:
        npend.simulate(npend.Chain(1), [0.1, 0.0], **kwargs)
    assert message in str(error.value)


def test_the_tolerances_have_scipys_names():
    with pytest.raises(TypeError, match="abs_tol"):
        npend.simulate(npend.Chain(1), [0.1, 0.0], t_end=1.0, abs_tol=1e-9)


def test_nfev_counts_the_right_hand_side_as_a_python_counter_does():
    chain = npend.Chain(2)
    x0 = [0.3, -0.2, 0, 0]
    # rk4 takes four evaluations a step: 100 steps.
    sol = npend.simulate(chain, x0, t_end=1.0, dt=0.01, stepper="rk4")
    assert (sol.nsteps, sol.nfev, sol.njev) == (100, 400, 0)
    # SciPy's RK45 on chain.fun, counted by a wrapper, against SciPy's own nfev: the same
    # meaning of the name.
    solve_ivp = pytest.importorskip("scipy.integrate").solve_ivp
    calls = []

    def counted(t, y):
        calls.append(t)
        return chain.fun(t, y)

    ref = solve_ivp(counted, (0, 1), x0, method="RK45", rtol=1e-8, atol=1e-10)
    assert ref.nfev == len(calls)
    # dopri5 is the same method as RK45 (first same as last): 1 + 6 per attempted step.
    sol = npend.simulate(chain, x0, t_end=1.0, dt=0.01, stepper="dopri5", atol=1e-10,
                         rtol=1e-8)
    assert (sol.nfev - 1) % 6 == 0 and (sol.nfev - 1) // 6 >= sol.nsteps
    # rosenbrock4 evaluates the Jacobian once per attempted step.
    sol = npend.simulate(chain, x0, t_end=1.0, stepper="rosenbrock4", atol=1e-8, rtol=1e-8)
    assert sol.njev >= sol.nsteps > 0


def test_dense_output_is_the_steppers_own_dense_output_at_any_time():
    chain = npend.Chain(3)
    x0 = [0.3, 0.3, 0.3, 0, 0, 0]
    times = np.linspace(0.0123, 4.98, 37)  # off the grid
    reference = npend.simulate(chain, x0, t_end=5.0, stepper="taylor", atol=1e-15, rtol=1e-15,
                               t_eval=times)
    for stepper, tol, off in [("dopri5", 1e-10, 1e-7), ("taylor", 1e-12, 1e-10),
                              ("rosenbrock4", 1e-8, 1e-5), ("gauss6", 1e-10, 1e-10)]:
        sol = npend.simulate(chain, x0, t_end=5.0, stepper=stepper, atol=tol, rtol=tol,
                             dense_output=True)
        # The same run's t_eval reads the same steps' dense output directly: sol keeps it.
        same_run = npend.simulate(chain, x0, t_end=5.0, stepper=stepper, atol=tol, rtol=tol,
                                  t_eval=times)
        np.testing.assert_allclose(sol.sol(times), same_run.X.T, rtol=0, atol=1e-13,
                                   err_msg=stepper)
        np.testing.assert_allclose(sol.sol(sol.t), sol.X.T, rtol=0, atol=1e-13,
                                   err_msg=stepper)
        # Against a tight reference, to the stepper's accuracy.
        assert np.max(np.abs(sol.sol(times) - reference.X.T)) < off, stepper
        assert (sol.sol.t_min, sol.sol.t_max) == (0.0, 5.0)
        assert sol.sol(2.5).shape == (6,) and sol.sol(times).shape == (6, times.size)
    with pytest.raises(ValueError, match="^t: 5.5 is outside the solution's span"):
        sol.sol(5.5)
    assert npend.simulate(chain, x0, t_end=1.0).sol is None


def test_dense_output_ends_at_a_terminal_event_and_runs_backwards():
    chain = npend.Chain(1)

    def turning(t, y):
        return y[1]

    turning.terminal = True
    turning.direction = -1
    sol = npend.simulate(chain, [0.0, 0.05], t_end=5.0, events=turning, dense_output=True)
    assert sol.sol.t_max == sol.t_events[0][0]
    np.testing.assert_allclose(sol.sol(sol.t_events[0][0]), sol.y_events[0][0], atol=1e-14)
    back = npend.simulate(chain, [0.0, 0.05], t_span=(0.0, -1.0), dt=-1e-3, dense_output=True)
    assert (back.sol.t_min, back.sol.t_max) == (-1.0, 0.0)
    np.testing.assert_allclose(back.sol(back.t), back.X.T, rtol=0, atol=1e-14)


def test_named_events_flip_and_sections():
    chain = npend.Chain(2)
    x0 = [1.5, 1.5, 0.0, 0.0]
    # The first flip, as the maps compute it (rk4 at the same step, its cubic Hermite
    # interpolant), ends the run.
    sol = npend.simulate(chain, x0, 20.0, dt=0.01, stepper="rk4",
                         events=npend.Event("flip", terminal=True, direction=1))
    flip = npend.map_cells(chain, np.array([x0]), t_end=20.0, dt=0.01)[0]
    assert sol.status == 1 and sol.t_events[0].size == 1
    assert sol.t_events[0][0] == pytest.approx(flip, abs=1e-9)
    assert np.max(np.abs(sol.y_events[0][0][:2])) == pytest.approx(np.pi, abs=1e-9)
    # A section as a string: the same crossings as npend.poincare's.
    section = npend.simulate(chain, [0.4, -0.3, 0.0, 0.0], 30.0, events=npend.Event(
        "phi1=0", direction=1))
    reference = npend.poincare(chain, [0.4, -0.3, 0.0, 0.0], "phi1=0", 30.0, direction="up")
    assert section.t_events[0].size == reference.t.size > 10
    np.testing.assert_allclose(section.t_events[0], reference.t, rtol=0, atol=1e-9)
    # On the circle: a rotating pendulum passes phi = 0 (mod 2 pi) once a turn, and the
    # wrap of the angle at pi is no crossing.
    one = npend.Chain(1)
    turns = npend.simulate(one, [0.0, 8.0], 10.0, events="phi1=0")
    phi = turns.y_events[0][:, 0]
    assert phi.size == int(turns.X[-1, 0] // (2 * np.pi))
    np.testing.assert_allclose(np.sin(phi), 0, atol=1e-9)
    assert np.all(np.cos(phi) > 0)
    with pytest.raises(ValueError, match="flip1..flip2"):
        npend.simulate(chain, x0, 1.0, events="flip3")
    with pytest.raises(ValueError, match="events"):
        npend.simulate(chain, x0, 1.0, events="phi9=0")
    assert repr(npend.Event("p2=0.5")) == "npend.Event('p2=0.5', terminal=False, direction=0)"
