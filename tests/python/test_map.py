"""npend.map: the numbers of npend map's map.npy, the same for any thread count, and the
energy bound of Heyl's flip map."""

import math
import os

import numpy as np
import pytest

import npend
from conftest import run_npend


def test_map_equals_npend_map(tmp_path):
    c = npend.Chain(2)
    m = npend.map(c, ("phi1", -3, 3, 12), ("phi2", -2.5, 3, 10), t_end=10, dt=0.01,
                  threads=2).values
    assert m.shape == (10, 12) and m.dtype == np.float64
    run_npend("map", "--links", 2, "--x", "phi1:-3:3:12", "--y", "phi2:-2.5:3:10", "--t-end", 10,
              "--dt", 0.01, "--out", tmp_path / "m")
    ref = np.load(tmp_path / "m" / "map.npy")
    assert np.array_equal(m, ref, equal_nan=True)
    one_thread = npend.map(c, ("phi1", -3, 3, 12), ("phi2", -2.5, 3, 10), t_end=10,
                           threads=1).values
    assert np.array_equal(m, one_thread, equal_nan=True)


def test_cells_the_energy_forbids_are_nan():
    # Equal double pendulum from rest: no flip is possible where 2 cos phi1 + cos phi2 > 1
    # (H = g (3 - 2 cos phi1 - cos phi2) below the 2 g m l an upright outer arm needs).
    c = npend.Chain(2)
    phi = np.linspace(-3, 3, 9)
    starts = np.array([[a, b, 0, 0] for b in phi for a in phi])
    times = npend.map_cells(c, starts, t_end=20)
    forbidden = 2 * np.cos(starts[:, 0]) + np.cos(starts[:, 1]) > 1
    assert forbidden.any() and np.array_equal(np.isnan(times), forbidden)
    assert np.isfinite(times[~forbidden]).any()


def test_energy_and_mass_axes(tmp_path):
    # From the hanging double pendulum (l = 1, m1 = 1) the momenta p = s (1, 1) carry the
    # kinetic energy s^2 / (2 m2), so the energy axis must start each cell at s = sqrt(2 m2 E).
    c = npend.Chain(2)
    x_axis, y_axis = ("energy", 0, 30, 6), ("m2", 0.5, 2, 4)
    m = npend.map(c, x_axis, y_axis, quantity="state", component="p1", t_end=2, threads=2).values
    for row, m2 in enumerate(np.linspace(0.5, 2, 4)):
        for col, energy in enumerate(np.linspace(0, 30, 6)):
            s = math.sqrt(2 * m2 * energy)
            want = npend.map_cells(npend.Chain(2, masses=[1, m2]), [0, 0, s, s],
                                   quantity="state", component="p1", t_end=2)
            assert m[row, col] == pytest.approx(float(want), rel=1e-12, abs=1e-12)
    run_npend("map", "--links", 2, "--x", "energy:0:30:6", "--y", "m2:0.5:2:4", "--quantity",
              "state", "--component", "p1", "--t-end", 2, "--out", tmp_path / "m")
    assert np.array_equal(m, np.load(tmp_path / "m" / "map.npy"), equal_nan=True)


def test_state_cells_are_the_simulated_final_state():
    c = npend.Chain(3, masses=[1, 2, 1.5])
    x0 = [0.4, -0.3, 0.2, 0.1, 0, -0.2]
    t, X = npend.simulate(c, x0, t_end=3, dt=0.01, stepper="rk4")
    for k, name in enumerate(["phi1", "phi2", "phi3", "p1", "p2", "p3"]):
        value = npend.map_cells(c, x0, quantity="state", component=name, t_end=3, dt=0.01)
        assert value == pytest.approx(X[-1, k], rel=1e-10, abs=1e-12)


def test_lyapunov_map_cells_are_maximal_exponents():
    c = npend.Chain(2)
    x = np.array([[2.0, 1.5, 0, 0], [0.1, 0.1, 0, 0]])
    values = npend.map_cells(c, x, quantity="lyapunov", t_end=20, dt=0.005)
    for row, value in zip(x, values):
        r = npend.lyapunov(c, row, 20, dt=0.005, stepper="rk4", maximal=True)
        # The cells run on the batch lanes, with SLEEF's sines instead of std::sin's: the
        # same rk4 and renormalisations, equal up to round-off grown over 20 s.
        assert value == pytest.approx(r.exponents[0], rel=1e-9, abs=1e-12)


def test_bad_map_input():
    c = npend.Chain(2)
    with pytest.raises(ValueError, match="quantity"):
        npend.map_cells(c, [0, 0, 0, 0], quantity="colour")
    with pytest.raises(ValueError, match="phi7"):
        npend.map(c, ("phi7", 0, 1, 2), ("phi1", 0, 1, 2))
    with pytest.raises(ValueError, match="both are phi1"):
        npend.map(c, ("phi1", 0, 1, 2), ("phi1", 0, 1, 2))
    with pytest.raises(ValueError, match="non-finite"):
        npend.map_cells(c, [[0, math.nan, 0, 0]])
    with pytest.raises(ValueError, match="dt"):
        npend.map_cells(c, [0, 0, 0, 0], dt=-1)
    with pytest.raises(ValueError, match="conserve"):
        npend.map(npend.Chain(2, damping=0.1), ("energy", 0, 1, 2), ("phi1", 0, 1, 2))
    with pytest.raises(ValueError, match="built-in drive"):
        npend.map(c, ("drive-frequency", 1, 2, 2), ("phi1", 0, 1, 2))


def test_thread_counts_beyond_the_bound_are_refused():
    # Tens of thousands of threads crashed the interpreter (the thread library failed); the
    # bound is 4 x the hardware threads, and a negative count is refused as on the command line.
    c = npend.Chain(2)
    bound = 4 * max(1, os.cpu_count() or 1)
    for threads in (100000, bound + 1, -1):
        with pytest.raises(ValueError, match="threads: 0 .every core. or 1.." + str(bound)):
            npend.map(c, ("phi1", 0, 1, 2), ("phi2", 0, 1, 2), t_end=1, threads=threads)
        with pytest.raises(ValueError, match="threads"):
            npend.map_cells(c, [0.5, 0.5, 0, 0], t_end=1, threads=threads)
    m = npend.map(c, ("phi1", 0, 1, 2), ("phi2", 0, 1, 2), t_end=1, threads=bound)
    assert m.values.shape == (2, 2)


def test_axes_that_do_not_increase_or_overflow_are_refused():
    c = npend.Chain(2)
    with pytest.raises(ValueError, match="x: phi1: FROM 1 is above TO 0"):
        npend.map(c, ("phi1", 1, 0, 4), ("phi2", 0, 1, 2))
    with pytest.raises(ValueError, match="y: phi2: FROM = TO = 1 would repeat one value 3 times"):
        npend.map(c, ("phi1", 0, 1, 2), ("phi2", 1, 1, 3))
    with pytest.raises(ValueError, match="too wide"):
        npend.map(c, ("phi1", -1e308, 1e308, 4), ("phi2", 0, 1, 2))


def test_indicator_cells_are_the_indicators_at_t_end():
    c = npend.Chain(2)
    x = np.array([[1.8, 1.8, 0, 0], [0.3, 0.2, 0, 0]])  # chaotic, regular
    # The cells run on the batch lanes (SLEEF's sines): over 3 s the chaotic start's round-off
    # has not grown, so the lanes give the library's indicators to round-off.
    runs = [npend.chaos_indicators(c, row, 3, dt=0.01, vectors=3) for row in x]
    for quantity, pick in [("fli", lambda r: r.fli[-1]), ("megno", lambda r: r.mean_megno[-1]),
                           ("sali", lambda r: r.sali[-1]), ("gali", lambda r: r.gali[-1, -1])]:
        values = npend.map_cells(c, x, quantity=quantity, t_end=3, dt=0.01)
        assert values == pytest.approx([pick(r) for r in runs], rel=1e-9), quantity
    # MEGNO tells the chaotic start (<Y> ~ lambda t / 2) from the regular one (<Y> -> 2).
    megno = npend.map_cells(c, x, quantity="megno", t_end=50)
    assert megno[0] > 10 and megno[1] < 2.5
    with pytest.raises(ValueError, match="GALI_k must be 2..4"):
        npend.map_cells(c, x, quantity="gali", gali_order=5)


def test_drive_axes_match_npend_map(tmp_path):
    # A driven pivot's amplitude and frequency as axes: the numbers of npend map's map.npy,
    # and no cell ruled out by the energy (the drive feeds energy in).
    c = npend.Chain(2, pivot="vertical:0.1:20")
    m = npend.map(c, ("drive-amplitude", 0, 0.3, 4), ("drive-frequency", 10, 40, 3),
                  x0=[1.2, 0, 0, 0], t_end=15, threads=2).values
    run_npend("map", "--links", 2, "--pivot", "vertical:0.1:20", "--phi", "1.2,0",
              "--x", "drive-amplitude:0:0.3:4", "--y", "drive-frequency:10:40:3",
              "--t-end", 15, "--out", tmp_path / "d")
    assert np.array_equal(m, np.load(tmp_path / "d" / "map.npy"), equal_nan=True)
    assert not np.isnan(m).any()
    assert math.isinf(m[0, 0]) and np.isfinite(m).any()


def test_dopri5_maps(tmp_path):
    # dopri5 on the batch lanes: the numbers of `npend map --stepper dopri5`, and the single
    # pendulum's flip time located inside the step, where rk4 reports the end of a step.
    c = npend.Chain(2)
    kw = dict(t_end=10, stepper="dopri5", atol=1e-9, rtol=1e-9, threads=2)
    m = npend.map(c, ("phi1", -3, 3, 8), ("phi2", -2.5, 3, 6), **kw).values
    run_npend("map", "--links", 2, "--x", "phi1:-3:3:8", "--y", "phi2:-2.5:3:6", "--t-end", 10,
              "--stepper", "dopri5", "--abs-tol", 1e-9, "--rel-tol", 1e-9, "--out", tmp_path / "m")
    assert np.array_equal(m, np.load(tmp_path / "m" / "map.npy"), equal_nan=True)
    # One link from the bottom with phi_dot0^2 = 1.5 * 4 g/l: phi_dot^2 = phi_dot0^2 - 2 (g/l)(1 - cos phi),
    # so the time to the top is the integral of dphi / phi_dot from 0 to pi.
    g = 9.81
    rate0 = math.sqrt(1.5 * 4 * g)
    phi = np.linspace(0, math.pi, 200001)
    exact = np.trapz(1 / np.sqrt(rate0 ** 2 - 2 * g * (1 - np.cos(phi))), phi)
    one = npend.Chain(1, g=g)
    located = npend.map_cells(one, [0, rate0], t_end=5, stepper="dopri5", atol=1e-12,
                              rtol=1e-12)
    stepped = npend.map_cells(one, [0, rate0], t_end=5, dt=0.01)
    assert located == pytest.approx(exact, abs=1e-9)
    assert exact <= stepped < exact + 0.01
    # gauss6 on the lanes (fixed-point stage iteration) against simulate's gauss6 (Newton).
    c3 = npend.Chain(3)
    x0 = [0.5, -0.4, 0.3, 0.2, 0.1, -0.1]
    t, X = npend.simulate(c3, x0, t_end=2, dt=0.01, stepper="gauss6")
    for k, name in enumerate(["phi1", "phi2", "phi3", "p1", "p2", "p3"]):
        value = npend.map_cells(c3, x0, quantity="state", component=name, t_end=2, dt=0.01,
                                stepper="gauss6")
        assert value == pytest.approx(X[-1, k], rel=1e-10, abs=1e-12)
    with pytest.raises(ValueError, match="rk4, dopri5, gauss4, gauss6"):
        npend.map_cells(c, [1, 1, 0, 0], stepper="bs")
    with pytest.raises(ValueError, match="integrate with one of rk4, taylor, not dopri5"):
        npend.map_cells(c, [1, 1, 0, 0], quantity="megno", stepper="dopri5")
    with pytest.raises(ValueError, match="stepper"):
        npend.map_cells(c, [1, 1, 0, 0], stepper="euler")


def test_gpu_device_is_refused_by_name_where_it_cannot_run():
    c = npend.Chain(2)
    x = np.array([[2.0, 2.0, 0.0, 0.0]])
    with pytest.raises(ValueError, match="device: 'gpu' is not a device"):
        npend.map_cells(c, x, t_end=1, device="gpu")
    with pytest.raises(ValueError, match="rk4 or dopri5, not gauss6"):
        npend.map(c, ("phi1", -3, 3, 4), ("phi2", -3, 3, 4), stepper="gauss6", t_end=1,
                  device="cuda")
    if "not available" in run_npend("--version").stdout:
        with pytest.raises(RuntimeError, match='device="cuda": CUDA is not usable here'):
            npend.map_cells(c, x, t_end=1, device="cuda")
    else:  # a GPU: the same values as the CPU's on this short, regular run
        assert np.allclose(npend.map_cells(c, x, t_end=1, device="cuda"),
                           npend.map_cells(c, x, t_end=1), rtol=1e-9, equal_nan=True)


def test_map_result_carries_its_axes():
    c = npend.Chain(2)
    m = npend.map(c, ("phi1", -1, 2, 4), ("p2", 0, 0.5, 3), quantity="state", component="phi1",
                  t_end=0.5)
    # The cells' coordinates: count values from FROM to TO, both included, equally spaced.
    assert m.x[0] == -1 and m.x[-1] == 2 and np.diff(m.x) == pytest.approx([1.0] * 3)
    assert m.y[0] == 0 and m.y[-1] == 0.5 and np.diff(m.y) == pytest.approx([0.25] * 2)
    assert (m.x_name, m.y_name, m.quantity) == ("phi1", "p2", "state")
    assert m.options["t_end"] == 0.5 and m.options["component"] == "phi1"
    # Cell (i, j) starts at phi1 = x[j], p2 = y[i]: its own map_cells value.
    want = npend.map_cells(c, [m.x[2], 0, 0, m.y[1]], quantity="state", component="phi1",
                           t_end=0.5)
    assert m.values[1, 2] == pytest.approx(float(want), rel=1e-12, abs=1e-12)
    assert np.asarray(m) is m.values and np.asarray(m, dtype=np.float32).dtype == np.float32
    assert "array(shape=(3, 4), dtype=float64)" in repr(m) and "nan" not in repr(m)
    with pytest.raises(AttributeError):
        m.values = None


def test_map_axes_given_as_lists_just_work():
    c = npend.Chain(2)
    as_tuples = npend.map(c, ("phi1", -3, 3, 5), ("phi2", -3, 3, 4), t_end=2)
    as_lists = npend.map(c, ["phi1", -3, 3, 5], ["phi2", -3.0, 3.0, np.int64(4)], t_end=2)
    assert np.array_equal(as_tuples.values, as_lists.values, equal_nan=True)
    assert np.array_equal(as_tuples.y, as_lists.y)


def test_map_axes_of_the_wrong_type_name_the_axis_and_field():
    c = npend.Chain(2)
    good = ("phi2", 0, 1, 2)
    with pytest.raises(TypeError, match=r"x: count must be an integer, got 64\.5"):
        npend.map(c, ("phi1", -3, 3, 64.5), good)
    with pytest.raises(TypeError, match="x: count must be an integer, got 64.0"):
        npend.map(c, ("phi1", -3, 3, 64.0), good)
    with pytest.raises(TypeError, match="y: from must be a number, got 'a'"):
        npend.map(c, good, ("phi1", "a", 3, 64))
    with pytest.raises(TypeError, match="x: to must be a number, got None"):
        npend.map(c, ("phi1", 0, None, 64), good)
    with pytest.raises(TypeError, match="y: name must be a string"):
        npend.map(c, good, (1, 0, 1, 2))
    with pytest.raises(ValueError, match=r"x: expected \(name, from, to, count\)"):
        npend.map(c, ("phi1", 0, 1), good)
    with pytest.raises(ValueError, match=r"y: expected \(name, from, to, count\)"):
        npend.map(c, good, "phi1:0:1:2")


def test_map_progress_counts_the_cells_up_to_all():
    seen = []
    npend.map(npend.Chain(2), ("phi1", -3, 3, 24), ("phi2", -3, 3, 20), t_end=5.0,
              progress=lambda done, total: seen.append((done, total)))
    assert seen[-1] == (24 * 20, 24 * 20)
    assert all(total == 480 for _, total in seen)
    seen.clear()
    npend.map_cells(npend.Chain(2), np.tile([2.0, 2.0, 0.0, 0.0], (50, 1)), t_end=5.0,
                    progress=lambda done, total: seen.append((done, total)))
    assert seen[-1] == (50, 50)
