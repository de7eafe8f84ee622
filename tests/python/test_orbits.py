"""npend.periodic_orbit and npend.continue_mode against independent references: the single
pendulum's period from SciPy's complete elliptic integral, the linear frequencies of
npend.modes, a re-integration with another stepper, and a shooting written here with SciPy
on the double pendulum's textbook equations of motion."""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import fsolve
from scipy.special import ellipk

import npend


@pytest.mark.parametrize("amplitude", [0.3, 1.5, 2.5])
def test_the_single_pendulums_period_is_4K_over_omega0(amplitude):
    g, l = 9.81, 0.7
    chain = npend.Chain(1, lengths=l, g=g)
    # The guess: the linear period with its first correction, (1 + a²/16) (the textbook series).
    guess = 2 * math.pi * math.sqrt(l / g) * (1 + amplitude**2 / 16)
    orbit = npend.periodic_orbit(chain, [amplitude, 0.0], guess, steps=2000)
    exact = 4 * ellipk(math.sin(amplitude / 2) ** 2) / math.sqrt(g / l)
    assert orbit.converged and orbit.closure <= 1e-11
    assert orbit.period == pytest.approx(exact, rel=1e-10)
    assert orbit.amplitudes[0] == pytest.approx(amplitude, rel=1e-12)
    assert orbit.multipliers.shape == (0,) and orbit.multipliers.dtype == np.complex128


@pytest.mark.parametrize("amplitude", [0.3, 2.5])
def test_on_taylor_the_single_pendulums_period_is_4K_over_omega0_to_1e_13(amplitude):
    # Taylor's orbit is the flow's to its tolerance, where gauss6's is its map's (1e-10 above
    # at 2000 steps); the shooting's closure is tightened so as not to limit the period.
    g, l = 9.81, 0.7
    chain = npend.Chain(1, lengths=l, g=g)
    guess = 2 * math.pi * math.sqrt(l / g) * (1 + amplitude**2 / 16)
    orbit = npend.periodic_orbit(chain, [amplitude, 0.0], guess, stepper="taylor", tol=1e-13)
    exact = 4 * ellipk(math.sin(amplitude / 2) ** 2) / math.sqrt(g / l)
    assert orbit.converged and orbit.closure <= 1e-13
    assert orbit.period == pytest.approx(exact, rel=1e-13)
    branch = npend.continue_mode(chain, 1, chain.hamiltonian([amplitude, 0.0]), stepper="taylor",
                                 integration_tol=1e-12)
    assert branch.end_reason == "reached energy_max"
    assert branch.period[-1] == pytest.approx(exact, rel=1e-10)
    with pytest.raises(ValueError, match="the taylor tolerance must lie in"):
        npend.periodic_orbit(chain, [amplitude, 0.0], guess, stepper="taylor",
                             integration_tol=1e-3)
    with pytest.raises(ValueError, match="integrates with gauss6, taylor, not rk4"):
        npend.periodic_orbit(chain, [amplitude, 0.0], guess, stepper="rk4")


def test_a_branch_starts_at_its_linear_mode_and_its_orbits_close_under_another_stepper():
    chain = npend.Chain(3, masses=[1, 2, 1.5], lengths=[1, 0.5, 2])
    omegas = npend.modes(chain).frequencies
    for mode in (1, 2, 3):
        branch = npend.continue_mode(chain, mode, 0.5, max_points=12)
        assert branch.linear_frequency == pytest.approx(omegas[mode - 1], rel=1e-12)
        # The first orbit swings to 0.01 rad: its frequency is the linear one to O(0.01²).
        assert branch.frequency[0] / omegas[mode - 1] == pytest.approx(1, abs=1e-3)
        assert branch.amplitudes.shape == (len(branch.energy), 3)
        assert branch.multipliers.shape == (len(branch.energy), 4)
        assert np.all(branch.closure <= 1e-11)
        # The orbit at the branch's end, integrated over one period by dopri5 at tight
        # tolerances, comes back to its start.
        x0, period = branch.x0[-1], branch.period[-1]
        solution = npend.simulate(chain, x0, t_span=(0, period), stepper="dopri5", atol=1e-13,
                                  rtol=1e-13, dt=period / 200)
        assert np.max(np.abs(solution.y[:, -1] - x0)) <= 1e-8
        assert chain.hamiltonian(x0) == pytest.approx(branch.energy[-1], rel=1e-12)
        # Stable orbits of a Hamiltonian flow: multipliers on the unit circle.
        for stable, mu in zip(branch.stable, branch.multipliers):
            if stable:
                assert np.all(np.abs(np.abs(mu) - 1) <= 1e-6)


def test_departures_are_where_the_frequency_is_off_by_the_threshold():
    branch = npend.continue_mode(npend.Chain(2), 2, 2.0, thresholds=[0.01, 0.03, 0.9])
    for shift in (0.01, 0.03):
        orbit = branch.departures[shift]
        assert abs(orbit.frequency / branch.linear_frequency - (1 - shift)) <= 1e-9 * shift
        assert orbit.converged
    assert branch.departures[0.9] is None
    with pytest.raises(ValueError, match="mode: 1..2"):
        npend.continue_mode(npend.Chain(2), 3, 1.0)
    with pytest.raises(ValueError, match="thresholds"):
        npend.continue_mode(npend.Chain(2), 1, 1.0, thresholds=[1.5])
    with pytest.raises(ValueError):
        npend.periodic_orbit(npend.Chain(2, damping=0.1), [0.1, 0.1, 0, 0], 3.0)


# The equal double pendulum (m = l = 1) in its textbook form: angles and angular velocities.
G = 9.81


def textbook(t, y):
    a, b, wa, wb = y
    d = a - b
    den = 3 - math.cos(2 * d)
    acc_a = (-3 * G * math.sin(a) - G * math.sin(a - 2 * b)
             - 2 * math.sin(d) * (wb**2 + wa**2 * math.cos(d))) / den
    acc_b = 2 * math.sin(d) * (2 * wa**2 + 2 * G * math.cos(a) + wb**2 * math.cos(d)) / den
    return [wa, wb, acc_a, acc_b]


def potential(a, b):  # zero when hanging, as npend's H
    return G * (2 * (1 - math.cos(a)) + (1 - math.cos(b)))


def shoot(energy, guess):
    """(a0, b0, T) of the synchronous orbit from rest at (a0, b0) with V = energy: at T/2
    both angular velocities vanish again (the other turning point)."""

    def residual(u):
        a, b, period = u
        half = solve_ivp(textbook, (0, period / 2), [a, b, 0, 0], method="DOP853", rtol=1e-13,
                         atol=1e-13).y[:, -1]
        return [half[2], half[3], potential(a, b) - energy]

    return fsolve(residual, guess, xtol=1e-13)


def test_periods_against_a_scipy_shooting_on_the_textbook_equations():
    chain = npend.Chain(2)
    assert chain.hamiltonian([0.4, -0.3, 0, 0]) == pytest.approx(potential(0.4, -0.3), rel=1e-14)
    for mode in (1, 2):
        branch = npend.continue_mode(chain, mode, 6.0)
        for k in np.linspace(2, len(branch.energy) - 1, 3).astype(int):
            x0 = branch.x0[k]
            a, b, period = shoot(branch.energy[k], [x0[0], x0[1], branch.period[k]])
            assert period == pytest.approx(branch.period[k], rel=1e-9), (mode, k)
            assert max(abs(a - x0[0]), abs(b - x0[1])) <= 1e-8


def test_changes_of_stability_as_the_command_line_finds_them():
    import json

    from conftest import run_npend

    chain = npend.Chain(3)
    branch = npend.continue_mode(chain, 3, 6.0)
    assert len(branch.bifurcations) == 1
    change = branch.bifurcations[0]
    assert change.kind == "branch point" and change.loses_stability
    assert change.stable_side.stable and not change.unstable_side.stable
    assert change.unstable_side.energy - change.stable_side.energy <= 1e-8 * change.energy
    # Stable below, unstable above, as the branch's own orbits say.
    below = branch.energy < change.energy
    assert np.all(branch.stable[below]) and not np.any(branch.stable[~below])
    cli = json.loads(run_npend("orbits", "--links", "3", "--mode", "3", "--energy-max", "6",
                               "--json").stdout)
    [same] = cli["modes"][0]["bifurcations"]
    assert same["kind"] == change.kind and same["energy"] == change.energy
    assert "StabilityChange(...)" in repr(branch)


@pytest.mark.parametrize("turns", [1, -1])
def test_a_rotating_pendulums_period_per_turn_is_2kappa_K_over_omega0(turns):
    # Over the separatrix 2mgl the pendulum turns over: one turn lasts 2 kappa K(kappa^2)/omega0
    # with kappa^2 = 2mgl/E (SciPy's ellipk takes the parameter m = kappa^2).
    g, l, m = 9.81, 0.8, 1.5
    chain = npend.Chain(1, masses=m, lengths=l, g=g)
    energy = 2.5 * 2 * m * g * l
    p = turns * math.sqrt(2 * m * l * l * energy)
    kappa2 = 2 * m * g * l / energy
    exact = 2 * math.sqrt(kappa2) * ellipk(kappa2) / math.sqrt(g / l)
    orbit = npend.periodic_orbit(chain, [0.0, p], 1.05 * exact, phase="poincare",
                                 winding=[turns])
    assert orbit.converged and orbit.closure <= 1e-11
    assert orbit.winding == (turns,)
    assert orbit.period == pytest.approx(exact, rel=1e-10)
    # Multiple shooting finds the same orbit.
    segmented = npend.periodic_orbit(chain, [0.0, p], 1.05 * exact, phase="poincare",
                                     winding=[turns], segments=4)
    assert segmented.converged
    assert segmented.period == pytest.approx(orbit.period, rel=1e-11)
    with pytest.raises(ValueError, match="poincare"):
        npend.periodic_orbit(chain, [0.0, p], exact, winding=[turns])


def test_arclength_and_natural_continuation_trace_the_same_family():
    chain = npend.Chain(2)
    arc = npend.continue_mode(chain, 2, 5.0, thresholds=[0.01])
    natural = npend.continue_mode(chain, 2, 5.0, thresholds=[0.01], continuation="natural")
    assert arc.end_reason == natural.end_reason == "reached energy_max"
    assert arc.folds == ()
    # The same departure, located on either branch, to the locator's tolerance.
    assert arc.departures[0.01].energy == pytest.approx(natural.departures[0.01].energy, rel=1e-8)
    # Every arclength orbit's period lies on the natural branch's period-energy curve.
    inside = (arc.energy >= natural.energy[0]) & (arc.energy <= natural.energy[-1])
    between = np.interp(arc.energy[inside], natural.energy, natural.period)
    assert np.allclose(arc.period[inside], between, rtol=2e-3)
    with pytest.raises(ValueError, match="arclength or natural"):
        npend.continue_mode(chain, 1, 1.0, continuation="bogus")


def test_branch_switching_returns_the_family_born_at_each_branch_point():
    chain = npend.Chain(3)
    branch = npend.continue_mode(chain, 3, 6.0, thresholds=[0.01], branches=True)
    (change,) = branch.bifurcations
    assert change.kind == "branch point"
    family = change.family
    assert len(family) > 5
    # Born at the bifurcation with its period, stable where the old family is not.
    assert family[0].energy == pytest.approx(change.energy, rel=1e-3)
    assert family[0].period == pytest.approx(change.stable_side.period, rel=1e-5)
    assert family[0].stable and not change.unstable_side.stable
    # Each orbit closes again under SciPy's DOP853 on npend's right-hand side.
    last = family[-1]
    assert last.energy == pytest.approx(6.0, rel=1e-12)
    back = solve_ivp(lambda t, x: chain.fun(t, x), (0, last.period), last.x0, method="DOP853",
                     rtol=1e-13, atol=1e-13)
    assert np.max(np.abs(back.y[:, -1] - last.x0)) < 1e-8
    assert npend.continue_mode(chain, 3, 6.0, thresholds=[0.01]).bifurcations[0].family == ()


# The equal triple pendulum (m = l = 1) from its Lagrangian, written here: with
# mu_ij = the mass below the later of joints i and j, M_ij = mu_ij cos(a_i - a_j) and
# M a'' = -sum_j mu_ij sin(a_i - a_j) a_j'^2 - mu_ii g sin(a_i).
def triple_lagrangian(t, y):
    a, w = np.asarray(y[:3]), np.asarray(y[3:])
    mu = np.array([[3 - max(i, j) for j in range(3)] for i in range(3)], dtype=float)
    d = a[:, None] - a[None, :]
    mass = mu * np.cos(d)
    force = -(mu * np.sin(d)) @ (w**2) - np.diag(mu) * G * np.sin(a)
    return np.concatenate([w, np.linalg.solve(mass, force)])


def triple_potential(a):
    return G * sum((3 - i) * (1 - math.cos(a[i])) for i in range(3))


def triple_shoot(energy, guess):
    """(a0, T) of the synchronous orbit from rest at a0 with V = energy: at T/2 every angular
    velocity vanishes again."""

    def residual(u):
        a, period = u[:3], u[3]
        half = solve_ivp(triple_lagrangian, (0, period / 2), list(a) + [0, 0, 0],
                         method="DOP853", rtol=1e-13, atol=1e-13).y[:, -1]
        return list(half[3:]) + [triple_potential(a) - energy]

    return fsolve(residual, guess, xtol=1e-13)


def test_triple_pendulum_periods_against_a_scipy_shooting_on_its_lagrangian():
    chain = npend.Chain(3)
    assert chain.hamiltonian([0.4, -0.3, 0.2, 0, 0, 0]) == pytest.approx(
        triple_potential([0.4, -0.3, 0.2]), rel=1e-14)
    for mode in (1, 2, 3):
        branch = npend.continue_mode(chain, mode, 6.0, thresholds=[0.01])
        for k in np.linspace(2, len(branch.energy) - 1, 3).astype(int):
            x0 = branch.x0[k]
            u = triple_shoot(branch.energy[k], list(x0[:3]) + [branch.period[k]])
            assert u[3] == pytest.approx(branch.period[k], rel=1e-9), (mode, k)
            assert np.max(np.abs(u[:3] - x0[:3])) <= 1e-8
