"""npend.simulate's output grid ends at t_end itself, as the command line's: a shorter last
step when t_end is not a multiple of dt."""

import numpy as np
import pytest

import npend

from conftest import run_npend


@pytest.mark.parametrize("stepper", ["gauss6", "rk4", "dopri5"])
def test_grid_ends_at_t_end_after_a_shorter_last_step(stepper):
    chain = npend.Chain(2)
    x0 = [0.4, -0.2, 0.0, 0.1]
    t, X = npend.simulate(chain, x0, t_end=1.0, dt=0.03, stepper=stepper)
    np.testing.assert_array_equal(t, [0.03 * k for k in range(34)] + [1.0])
    # The last row is the state at t = 1: a run on a grid that lands on 1.0 agrees.
    _, fine = npend.simulate(chain, x0, t_end=1.0, dt=1e-3, stepper="gauss6")
    assert np.max(np.abs(X[-1] - fine[-1])) < (1e-5 if stepper == "rk4" else 1e-8)


def test_a_float32_t_end_gives_every_grid_point_and_t_end():
    t, _ = npend.simulate(npend.Chain(1), [0.1, 0.0], t_end=np.float32(0.01), dt=1e-3)
    assert len(t) == 11
    assert t[-1] == float(np.float32(0.01))


def test_the_command_line_ends_its_grid_at_t_end_too():
    csv = run_npend("simulate", "-n", "2", "--phi", "0.4,-0.2", "--t-end", "1", "--dt", "0.3").stdout
    times = [float(line.split(",")[0]) for line in csv.splitlines()[1:]]
    assert times == [0.0, 0.3, 0.6, 0.3 * 3, 1.0]
