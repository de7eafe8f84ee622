"""npend.simulate, npend.lyapunov and npend.poincare: the command line's numbers, the
conservation laws, and arrays of the right shape."""

import io

import numpy as np
import pytest

import npend
from conftest import csv_list, npend_json, run_npend

X0 = [0.9, -0.6, 1.2, 0.0, 0.3, -0.1]


def test_simulate_equals_npend_simulate():
    c = npend.Chain(3, masses=[1, 2, 0.5])
    t, X = npend.simulate(c, X0, 0.5, dt=0.01)
    assert t.shape == (51,) and X.shape == (51, 6) and X.dtype == np.float64
    csv = run_npend("simulate", "--links", 3, "--masses", "1,2,0.5", "--phi", csv_list(X0[:3]),
                    "--p", csv_list(X0[3:]), "--t-end", 0.5, "--dt", 0.01).stdout
    table = np.genfromtxt(io.StringIO(csv), delimiter=",", names=True)
    assert np.array_equal(t, table["t"])
    for i in range(3):
        assert np.array_equal(X[:, i], table[f"phi_{i + 1}"])
        assert np.array_equal(X[:, 3 + i], table[f"p_{i + 1}"])
    assert np.array_equal(c.hamiltonian(X), table["H"])


@pytest.mark.parametrize("stepper", ["gauss6", "gauss4", "rk4", "dopri5", "rkf78", "bs",
                                     "rosenbrock4"])
def test_every_stepper_keeps_the_energy(stepper):
    c = npend.Chain(3)
    t, X = npend.simulate(c, X0, 2.0, dt=0.002, stepper=stepper)
    energy = c.hamiltonian(X)
    assert t[-1] == pytest.approx(2.0)
    assert np.max(np.abs(energy - energy[0])) < 1e-6 * abs(energy[0])


def test_simulate_starts_at_t_start_and_can_go_backwards():
    c = npend.Chain(2)
    t, X = npend.simulate(c, X0[:2] + X0[3:5], t_span=(0.5, 1.0), dt=0.01)
    assert t[0] == 0.5 and t[-1] == pytest.approx(1.0) and len(t) == 51
    # Integrating back from the end returns to the start (gauss6 is time-symmetric).
    _, back = npend.simulate(c, X[-1], t_span=(1.0, 0.5), dt=-0.01)
    assert back[-1] == pytest.approx(X[0], abs=1e-10)


def test_lyapunov_equals_npend_lyapunov_and_pairs_up():
    c = npend.Chain(2)
    x0 = [2.0, 1.5, 0.0, 0.0]
    r = npend.lyapunov(c, x0, 20.0, dt=0.005)
    ref = npend_json("lyapunov", "--links", 2, "--phi", "2,1.5", "--t-end", 20, "--dt", 0.005)
    assert np.array_equal(r.exponents, ref["exponents"])
    # A Hamiltonian flow: the exponents come in pairs +-lambda (to round-off with gauss6).
    assert np.max(np.abs(r.pair_sums)) < 1e-10
    assert r.history.shape == (len(r.history_t), 4)
    m = npend.lyapunov(c, x0, 20.0, dt=0.005, maximal=True)
    assert m.exponents.shape == (1,)
    # The K largest: npend lyapunov --exponents K, and with rk4 the first K of the spectrum's
    # frame (Gram-Schmidt leaves the first vectors alone), so the spectrum's first K.
    k = npend.lyapunov(c, x0, 20.0, dt=0.005, stepper="rk4", exponents=2)
    ref = npend_json("lyapunov", "--links", 2, "--phi", "2,1.5", "--t-end", 20, "--dt", 0.005,
                     "--stepper", "rk4", "--exponents", 2)
    assert np.array_equal(k.exponents, ref["exponents"])
    full = npend.lyapunov(c, x0, 20.0, dt=0.005, stepper="rk4")
    assert k.exponents == pytest.approx(full.exponents[:2], rel=1e-6, abs=1e-9)
    with pytest.raises(ValueError, match="maximal and exponents"):
        npend.lyapunov(c, x0, 1.0, maximal=True, exponents=2)


def test_poincare_equals_npend_poincare_and_lies_on_the_section():
    c = npend.Chain(3)
    x0 = [0.1, -0.1, 0.1, 0, 0, 0]
    r = npend.poincare(c, x0, "phi1=0", 30.0)
    ref = npend_json("poincare", "--links", 3, "--phi", "0.1,-0.1,0.1", "--t-end", 30,
                     "--section", "phi1=0")
    times = [p["t"] for p in ref["points"]]
    assert np.array_equal(r.t, times)
    assert r.states.shape == (len(times), 6)
    assert np.max(np.abs(r.states[:, 0])) < 1e-9
    assert np.all(c.velocities(r.states)[:, 0] > 0)  # "up": phi1 increasing
    energy = c.hamiltonian(r.states)
    assert np.max(np.abs(energy - c.hamiltonian(x0))) < 1e-9


def test_bad_integration_input_raises_value_error():
    c = npend.Chain(2)
    with pytest.raises(ValueError, match="gauss6"):
        npend.simulate(c, [0, 0, 0, 0], 1.0, stepper="euler")
    with pytest.raises(ValueError, match=r"x0 must have shape \(4,\)"):
        npend.simulate(c, [0, 0, 0], 1.0)
    with pytest.raises(ValueError):
        npend.simulate(c, [0, 0, 0, 0], 1.0, dt=0)
    with pytest.raises(ValueError, match="not finite|non-finite"):
        npend.simulate(c, [float("nan"), 0, 0, 0], 1.0)
    with pytest.raises(ValueError, match="section"):
        npend.poincare(c, [0, 0, 0, 0], "phi9=0", 1.0)
    with pytest.raises(ValueError, match="direction"):
        npend.poincare(c, [0, 0, 0, 0], "phi1=0", 1.0, direction="sideways")


def test_chaos_indicators_of_the_single_pendulum():
    """A single pendulum's orbits are 1-tori: MEGNO <Y> -> 2 (the period depends on the
    amplitude, so deviations grow linearly) and GALI_2 = SALI falls like t^-2 up to about
    t = 1000 s. Beyond, the samples every 100 s fall at drifting phases of the orbit, where
    the two vectors' angle differs: Taylor's method at 1e-13 gives the same values there."""
    r = npend.chaos_indicators(npend.Chain(1), [2.0, 0.0], 2000, sample_interval=100)
    assert r.t.shape == (20,) and r.gali.shape == (20, 1)
    assert abs(r.mean_megno[-1] - 2) < 0.05
    # For two unit vectors, GALI_2 = |sin angle| and SALI = 2 sin(angle/2) agree as they -> 0.
    assert np.allclose(r.gali[:, 0], r.sali, rtol=1e-6)
    early = r.t <= 600
    slope = np.polyfit(np.log(r.t[early]), np.log(r.sali[early]), 1)[0]
    assert abs(slope + 2) < 0.2
    with pytest.raises(ValueError, match="vectors"):
        npend.chaos_indicators(npend.Chain(1), [2.0, 0.0], 10, vectors=3)


def test_chaos_indicators_on_taylor_of_the_single_pendulum():
    """On Taylor's method: <Y> -> 2 and SALI ~ t^-2 as on rk4 (above), its values those of
    rk4's run to 1e-3 at t = 2000 s, and rk4's indicators at a fine step over 20 s."""
    c = npend.Chain(1)
    r = npend.chaos_indicators(c, [2.0, 0.0], 2000, sample_interval=100, stepper="taylor",
                               tol=1e-13)
    assert r.t.shape == (20,) and r.t[-1] == 2000.0
    assert abs(r.mean_megno[-1] - 2) < 0.05
    early = r.t <= 600
    slope = np.polyfit(np.log(r.t[early]), np.log(r.sali[early]), 1)[0]
    assert abs(slope + 2) < 0.2
    rk4 = npend.chaos_indicators(c, [2.0, 0.0], 2000, sample_interval=100)
    assert np.allclose(r.sali, rk4.sali, rtol=1e-2)
    fine = npend.chaos_indicators(c, [2.0, 0.0], 20, dt=1e-4, sample_interval=10)
    short = npend.chaos_indicators(c, [2.0, 0.0], 20, sample_interval=10, stepper="taylor",
                                   tol=1e-13)
    assert short.mean_megno == pytest.approx(fine.mean_megno, rel=1e-9)
    assert short.fli == pytest.approx(fine.fli, rel=1e-8)
    with pytest.raises(ValueError, match="integrate with rk4, taylor, not gauss6"):
        npend.chaos_indicators(c, [2.0, 0.0], 10, stepper="gauss6")


def test_poincare_takes_scipys_tolerance_names():
    # An adaptive stepper under atol/rtol: the crossings lie on the section and keep H; the
    # library's names abs_tol/rel_tol are not a second spelling.
    c = npend.Chain(2)
    x0 = [0.5, -0.3, 0, 0]
    r = npend.poincare(c, x0, "phi1=0", 20.0, stepper="dopri5", atol=1e-12, rtol=1e-12)
    assert len(r.t) >= 5 and r.t_end == 20.0
    assert np.max(np.abs(r.states[:, 0])) < 1e-9
    assert np.max(np.abs(c.hamiltonian(r.states) - c.hamiltonian(x0))) < 1e-9
    with pytest.raises(TypeError, match="abs_tol"):
        npend.poincare(c, x0, "phi1=0", 1.0, abs_tol=1e-9)


def test_lyapunov_result_is_a_frozen_class_with_a_short_repr():
    r = npend.lyapunov(npend.Chain(1), [1.0, 0.0], 5.0, dt=0.01)
    assert isinstance(r, npend.results.LyapunovResult)
    # A single pendulum's flow keeps volume: the two exponents sum to 0.
    assert r.sum == pytest.approx(0, abs=1e-10) and r.exponents.shape == (2,)
    assert r.history.shape == (len(r.history_t), 2) and r.state.shape == (2,)
    text = repr(r)
    assert "exponents=array(shape=(2,), dtype=float64)" in text and f"t={r.t!r}" in text
    with pytest.raises(AttributeError):
        r.t = 0.0


def test_lyapunov_takes_the_tolerances_of_an_adaptive_stepper():
    # dopri5 under atol/rtol: the numbers of npend lyapunov --abs-tol/--rel-tol, and looser
    # tolerances change them (the keywords reach the stepper).
    c = npend.Chain(2)
    x0 = [1.0, 0.5, 0.0, 0.0]
    r = npend.lyapunov(c, x0, 5.0, dt=0.01, stepper="dopri5", atol=1e-6, rtol=1e-6)
    ref = npend_json("lyapunov", "--links", 2, "--phi", "1,0.5", "--t-end", 5, "--dt", 0.01,
                     "--stepper", "dopri5", "--abs-tol", 1e-6, "--rel-tol", 1e-6)
    assert np.array_equal(r.exponents, ref["exponents"])
    tight = npend.lyapunov(c, x0, 5.0, dt=0.01, stepper="dopri5")
    assert not np.array_equal(r.exponents, tight.exponents)
    assert r.exponents == pytest.approx(tight.exponents, abs=1e-3)
    # taylor: the Taylor series of the variational equations, under the same keywords.
    t = npend.lyapunov(c, x0, 5.0, dt=0.01, stepper="taylor", atol=1e-12, rtol=1e-12)
    ref = npend_json("lyapunov", "--links", 2, "--phi", "1,0.5", "--t-end", 5, "--dt", 0.01,
                     "--stepper", "taylor", "--abs-tol", 1e-12, "--rel-tol", 1e-12)
    assert t.method == "Taylor series of the variational equations"
    assert np.array_equal(t.exponents, ref["exponents"])
    assert t.exponents == pytest.approx(tight.exponents, abs=1e-6)
