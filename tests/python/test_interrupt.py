"""Long computations release the GIL (other Python threads run meanwhile) and stop with
KeyboardInterrupt when Ctrl-C arrives, instead of running to the end."""

import _thread
import signal
import threading
import time

import numpy as np
import pytest

import npend


def interrupt_after(seconds):
    """Delivers SIGINT to the main thread after `seconds`, like Ctrl-C at the terminal."""
    timer = threading.Timer(seconds, lambda: _thread.interrupt_main(signal.SIGINT))
    timer.start()
    return timer


@pytest.mark.parametrize("long_run", [
    lambda: npend.simulate(npend.Chain(6), [1.0] * 6 + [0.0] * 6, 1e4, dt=1e-3),
    lambda: npend.lyapunov(npend.Chain(4), [1.0] * 4 + [0.0] * 4, 1e5),
    lambda: npend.map(npend.Chain(2), ("phi1", -3, 3, 400), ("phi2", -3, 3, 400), t_end=1e4),
], ids=["simulate", "lyapunov", "map"])
def test_ctrl_c_stops_a_long_run(long_run):
    started = time.monotonic()
    timer = interrupt_after(0.5)
    with pytest.raises(KeyboardInterrupt):
        long_run()  # each would take many minutes
    timer.join()
    assert time.monotonic() - started < 30


def test_other_threads_run_during_a_computation():
    ticks = []
    stop = threading.Event()

    def tick():
        while not stop.is_set():
            ticks.append(time.monotonic())
            time.sleep(0.01)

    ticker = threading.Thread(target=tick)
    c = npend.Chain(3)
    started = time.monotonic()
    ticker.start()
    npend.simulate(c, [1.0, 1.0, 1.0, 0, 0, 0], 600.0, dt=1e-3)  # about a second
    finished = time.monotonic()
    stop.set()
    ticker.join()
    during = [t for t in ticks if started + 0.1 < t < finished - 0.1]
    # The ticker ran while simulate did: about one tick per 10 ms.
    assert finished - started > 0.5
    assert len(during) > 0.3 * (finished - started - 0.2) / 0.01
    assert np.isfinite(c.hamiltonian([1.0, 1.0, 1.0, 0, 0, 0]))


def test_ctrl_c_stops_a_batch_of_chain_states():
    # A batch method on millions of rows polls Ctrl-C between rows: interrupted at a fifth of
    # its run, it stops long before the batch's end. Without the poll the KeyboardInterrupt
    # would still come, but only after the whole batch, so the time tells the two apart.
    c = npend.Chain(10)
    rows = np.random.default_rng(1).uniform(-1.0, 1.0, (1_500_000, c.state_size))
    started = time.monotonic()
    c.hamiltonian(rows)
    whole = time.monotonic() - started
    started = time.monotonic()
    timer = interrupt_after(0.2 * whole)
    with pytest.raises(KeyboardInterrupt):
        c.hamiltonian(rows)
    stopped_after = time.monotonic() - started
    timer.join()
    assert stopped_after < 0.7 * whole
