"""The analyses of npend: start states, Lyapunov exponents, Poincare sections, chaos
indicators, time series, stability and chaos maps.

Each function calls the compiled module npend._npend, which runs the C++ library's code (the
command line's), and returns numpy arrays or a result class of npend.results. Bad input
raises ValueError with the command line's message, naming the keyword; an integration that
cannot go on raises npend.IntegrationError; Ctrl-C raises KeyboardInterrupt.
"""

from __future__ import annotations

import operator
from numbers import Real
import math
import os
import re
from typing import TYPE_CHECKING, Any, Callable, List, Optional, Sequence, Tuple, Union

import numpy as np

from . import _npend
from .chain import _number
from .results import (
    AutocorrelationResult,
    DelayResult,
    Equilibrium,
    IndicatorsResult,
    LyapunovResult,
    MapResult,
    ModesResult,
    NNMBranch,
    PeriodicOrbit,
    PoincareResult,
    StabilityChange,
    Solution,
    SpectrumResult,
)

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

    from .chain import Chain

__all__ = [
    "simulate",
    "autocorrelation",
    "built_link_counts",
    "chaos_indicators",
    "choose_delay",
    "deflected_state",
    "embed",
    "energy_from_epsilon",
    "equilibria",
    "kicked_state",
    "lyapunov",
    "map",
    "map_cells",
    "modes",
    "poincare",
    "spectrum",
]


# Start states


def built_link_counts() -> List[int]:
    """The link counts whose generated kernels are compiled into this build.

    Returns
    -------
    list of int
        Ascending; a Chain takes only these link counts.

    Examples
    --------
    >>> import npend
    >>> 3 in npend.built_link_counts()
    True
    """
    return _npend.built_link_counts()


def energy_from_epsilon(chain: Chain, epsilon: float) -> float:
    """The paper's dimensionless energy epsilon as an energy: E = epsilon m g l.

    Parameters
    ----------
    chain : Chain
        A chain with equal masses m and equal lengths l.
    epsilon : float
        The dimensionless energy (the paper's weak start is 0.01, its strong one 1.5).

    Returns
    -------
    float
        E in J.

    Raises
    ------
    ValueError
        If the chain's masses or lengths differ.

    Examples
    --------
    >>> import npend
    >>> print(f"{npend.energy_from_epsilon(npend.Chain(3, masses=2.0), 1.5):.3f}")  # 1.5*2*9.81
    29.430
    """
    return _npend.energy_from_epsilon(chain, epsilon)


def deflected_state(
    chain: Chain, energy: float, direction: Optional[ArrayLike] = None
) -> np.ndarray:
    """The chain at rest with its angles s * direction, s > 0 chosen so that H = energy.

    This is the paper's excitation by deflecting the arms.

    Parameters
    ----------
    chain : Chain
        The chain.
    energy : float
        H of the state (J), at least 0 and below what the direction allows.
    direction : array_like, shape (n,), optional
        The direction of the angles; default all ones.

    Returns
    -------
    ndarray, shape (2n,)
        The state [phi, p], p = 0.

    Raises
    ------
    ValueError
        For a direction of another shape, a negative energy or one the direction cannot reach.

    Examples
    --------
    >>> import npend
    >>> chain = npend.Chain(3)
    >>> x = npend.deflected_state(chain, 2.0)
    >>> print(f"{chain.hamiltonian(x):.9f}", x[3:], bool(x[0] == x[1] == x[2] > 0))
    2.000000000 [0. 0. 0.] True
    """
    return _npend.deflected_state(chain, energy, direction)


def kicked_state(
    chain: Chain, energy: float, direction: Optional[ArrayLike] = None
) -> np.ndarray:
    """The hanging chain with momenta s * direction, s > 0 chosen so that H = energy.

    This is the paper's excitation by a kick.

    Parameters
    ----------
    chain : Chain
        The chain.
    energy : float
        H of the state (J), at least 0.
    direction : array_like, shape (n,), optional
        The direction of the momenta; default a horizontal kick on the lowest bob.

    Returns
    -------
    ndarray, shape (2n,)
        The state [phi, p], phi = 0.

    Raises
    ------
    ValueError
        For a direction of another shape or a negative energy.

    Examples
    --------
    >>> import npend
    >>> chain = npend.Chain(2)
    >>> x = npend.kicked_state(chain, 1.0, direction=[1.0, 0.0])
    >>> print(f"{chain.hamiltonian(x):.9f}", x[:2], x[3])
    1.000000000 [0. 0.] 0.0
    """
    return _npend.kicked_state(chain, energy, direction)


# Integrations


# --- Integration ------------------------------------------------------------------------

# A run whose output would take more than this share of the memory available is refused
# before it starts (it would otherwise grow until MemoryError, or the machine swaps).
_MEMORY_SHARE = 0.5


def _memory_available() -> float:
    """Bytes of memory available now (Linux's MemAvailable; all physical memory elsewhere)."""
    try:
        with open("/proc/meminfo") as meminfo:
            for line in meminfo:
                if line.startswith("MemAvailable:"):
                    return float(line.split()[1]) * 1024
    except OSError:
        pass
    return float(os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES"))


def _time_span(t_end: Any, t_span: Any) -> Tuple[float, float]:
    if isinstance(t_end, (tuple, list)):  # simulate(chain, x0, (0, 10)): SciPy's t_span
        t_end, t_span = t_span, t_end
        if t_end is not None:
            raise ValueError("t_span: given twice (as the third argument and as t_span=)")
    if (t_end is None) == (t_span is None):
        raise ValueError("t_end, t_span: give one of them (t_end=T, or t_span=(t0, t1))")
    if t_span is None:
        return 0.0, _real(t_end, "t_end")
    try:
        t0, t1 = t_span
    except (TypeError, ValueError):
        raise ValueError(f"t_span: expected (t0, t1), got {t_span!r}") from None
    return _real(t0, "t_span"), _real(t1, "t_span")


def _real(value: Any, what: str) -> float:
    if value is None:
        raise TypeError(f"{what}: expected a number, got None")
    return float(_number(value, what))


def _progress_callback(progress: Any) -> Tuple[Optional[Callable[[float, float], None]],
                                               Callable[[], None]]:
    """The callable the C++ run reports to (done, total), and what closes it afterwards:
    None (no report), True (a tqdm bar, python3-tqdm), or the user's callable."""
    if progress is None or progress is False:
        return None, lambda: None
    if progress is True:
        try:
            from tqdm.auto import tqdm
        except ImportError:
            raise ValueError("progress: True needs tqdm (python3-tqdm); or pass a callable "
                             "progress(done, total)") from None
        bar = tqdm(total=1.0, unit="", bar_format="{l_bar}{bar}| {elapsed}<{remaining}")

        def report(done: float, total: float) -> None:
            bar.total = total
            bar.n = done
            bar.refresh()

        def close() -> None:
            if bar.total:
                bar.n = bar.total
            bar.close()

        return report, close
    if callable(progress):
        return progress, lambda: None
    raise TypeError(f"progress: expected None, True or a callable progress(done, total), "
                    f"got {progress!r}")


def _output_rows(t0: float, t1: float, dt: float, every: int, t_eval: Any) -> float:
    if t_eval is not None:
        return float(len(t_eval))
    # The library's grid (it also says what is wrong with t0, t1 or dt).
    return math.ceil(_npend.output_points(t0, t1, dt) / every)


class Event:
    """A named event of npend.simulate, with SciPy's ``terminal`` and ``direction``.

    Parameters
    ----------
    spec : str
        "flip" (an arm passes the upright position, max |phi_k| - pi rising through 0),
        "flipK" (arm K), or a section as npend.poincare takes it: "phi1=0", "p2=0.5",
        "phi1=phi2" (the angles' sections on the circle, every 2 pi).
    terminal : bool, optional
        True ends the run at the event.
    direction : float, optional
        > 0: only where g = w.x - c (max |phi_k| - pi for a flip) rises through 0; < 0: only
        where it falls; 0: both.

    Examples
    --------
    The time of the first flip of the double pendulum from phi = (1.5, 1.5), with the run
    ended there (the last row of the grid is the last before it):

    >>> import npend
    >>> sol = npend.simulate(npend.Chain(2), [1.5, 1.5, 0, 0], 20.0, dt=0.01, stepper="rk4",
    ...                      events=npend.Event("flip", terminal=True, direction=1))
    >>> sol.status, round(float(sol.t_events[0][0]), 4), round(float(sol.t[-1]), 2)
    (1, 10.2084, 10.2)
    """

    def __init__(self, spec: str, *, terminal: bool = False, direction: float = 0.0) -> None:
        if not isinstance(spec, str):
            raise TypeError(f"spec: expected an event name such as 'flip' or 'phi1=0', got {spec!r}")
        self.spec = spec
        self.terminal = bool(terminal)
        self.direction = float(direction)

    def __repr__(self) -> str:
        return (f"npend.Event({self.spec!r}, terminal={self.terminal}, "
                f"direction={self.direction:g})")


_EventLike = Union[Callable[..., float], str, Event]


def simulate(
    chain: Chain,
    x0: ArrayLike,
    t_end: Union[float, Tuple[float, float], None] = None,
    *,
    t_span: Optional[Tuple[float, float]] = None,
    dt: float = 1e-3,
    stepper: str = "gauss6",
    atol: float = 1e-10,
    rtol: float = 1e-10,
    order: int = 0,
    t_eval: Optional[ArrayLike] = None,
    every: int = 1,
    events: Union[_EventLike, Sequence[_EventLike], None] = None,
    progress: Any = None,
    dense_output: bool = False,
) -> Solution:
    """Integrates Hamilton's equations from x0, as ``npend simulate`` does.

    Parameters
    ----------
    chain : Chain
        The chain.
    x0 : array_like, shape (2n,)
        The start state [phi, p].
    t_end : float, or (t0, t1)
        The end of the run (from t = 0); a pair is taken as t_span.
    t_span : (float, float), optional
        The run from t0 to t1, as SciPy's solve_ivp (t1 < t0 with dt < 0: backwards).
    dt : float, optional
        The output grid t0 + k dt, which ends at t1 itself (a shorter last step when t1 is
        not a multiple of dt); the step of the fixed-step steppers (rk4, gauss4, gauss6),
        the first trial step of the adaptive ones.
    stepper : str, optional
        gauss6 (default), gauss4, rk4, dopri5, rkf78, bs, rosenbrock4 or taylor.
    atol, rtol : float, optional
        The tolerances of the adaptive steppers (|err_i| <= atol + rtol |x_i|).
    order : int, optional
        The taylor stepper's order, 2..60 (0: from the tolerances); refused for the others.
    t_eval : array_like, optional
        Output at these times only (sorted in the run's direction, within the span), taken
        from the stepper's dense output (see the library's integration_step: the stepper's
        own interpolant, or a cubic Hermite one for rk4, rkf78 and the Gauss steppers), not
        by shortening the steps.
    every : int, optional
        Keep every k-th grid row (not with t_eval).
    events : callable, str, Event, or a list of them, optional
        g(t, y) -> float, as SciPy's: an event is where g crosses zero, located on the dense
        output to rounding in t. Attributes read from the function: ``terminal`` (True ends
        the run there) and ``direction`` (> 0: only rising, < 0: only falling crossings).
        A string names an event computed without calling Python: "flip" (an arm passes
        the upright position, |phi_k| = pi; "flipK": arm K) or a section as for
        npend.poincare ("phi1=0", "p2=0.5", "phi1=phi2"; sections of angles on the circle);
        npend.Event(name, terminal=..., direction=...) gives one its attributes.
    progress : None, True or callable, optional
        True shows a tqdm bar; a callable hears progress(done, total), the output steps
        done of all of them, about every 20 ms and at the end.
    dense_output : bool, optional
        Keep the stepper's dense output over every step as Solution.sol, a callable
        sol(t) as SciPy's (up to the terminal event where one ended the run). Its memory is
        counted in the refusal above for the fixed-step steppers; an adaptive stepper's
        steps are not known before the run.

    Returns
    -------
    Solution
        t, X (and y = X.T), status, events, energy error, nfev, sol and the options;
        unpacks as ``t, X``.

    Raises
    ------
    ValueError
        For bad input, naming the keyword; also when the output would take more than half
        of the memory available (use every= or t_eval=).
    IntegrationError
        When the integration cannot go on.

    Examples
    --------
    A small swing of the single pendulum, and its turning points as events (p = 0 falling
    through zero), half a period 2 pi sqrt(l/g) / 2 = 1.003 s apart:

    >>> import numpy as np, npend
    >>> chain = npend.Chain(1)
    >>> def turning(t, y):
    ...     return y[1]
    >>> turning.direction = -1
    >>> sol = npend.simulate(chain, [0.0, 0.05], t_span=(0, 5), events=turning)
    >>> sol.t.shape, sol.X.shape, sol.status
    ((5001,), (5001, 2), 0)
    >>> print(np.round(np.diff(sol.t_events[0]), 4))
    [2.0061 2.0061]
    >>> t, X = sol  # unpacks as (t, X)

    With dense_output=True, sol.sol(t) gives the state at any time of the run:

    >>> sol = npend.simulate(chain, [0.0, 0.05], t_span=(0, 5), dense_output=True)
    >>> sol.sol(0.25).shape, sol.sol([0.25, 0.5]).shape
    ((2,), (2, 2))
    >>> bool(np.allclose(sol.sol(sol.t[::1000]), sol.X[::1000].T, rtol=1e-13, atol=1e-15))
    True
    """
    t0, t1 = _time_span(t_end, t_span)
    if isinstance(every, bool) or not isinstance(every, (int, np.integer)) or every < 1:
        raise ValueError(f"every: expected an integer of 1 or more, got {every!r}")
    direction = 1.0 if t1 >= t0 else -1.0
    if t_eval is not None:
        if every != 1:
            raise ValueError("every: not with t_eval (the output is at t_eval's times)")
        t_eval = np.asarray(t_eval, dtype=float).ravel()
        if not np.all(np.isfinite(t_eval)):
            raise ValueError("t_eval: the times must be finite")
        if np.any(direction * np.diff(t_eval) < 0):
            raise ValueError("t_eval: the times must be sorted in the run's direction")
        if t_eval.size and (min(t_eval[0], t_eval[-1]) < min(t0, t1)
                            or max(t_eval[0], t_eval[-1]) > max(t0, t1)):
            raise ValueError(f"t_eval: the times must lie within the span [{t0}, {t1}]")
    if events is None:
        events = []
    elif callable(events) or isinstance(events, (str, Event)):
        events = [events]
    for g in events:
        if not (callable(g) or isinstance(g, (str, Event))):
            raise TypeError(
                f"events: expected functions g(t, y), event names or npend.Event, got {g!r}")
    rows = _output_rows(t0, t1, _real(dt, "dt"), int(every), t_eval)
    need = rows * (chain.state_size + 1) * 8
    if dense_output and stepper in ("rk4", "gauss4", "gauss6"):
        # The fixed steps are the grid's; each keeps 4 states of its cubic dense output.
        need += _output_rows(t0, t1, _real(dt, "dt"), 1, None) * 4 * chain.state_size * 8
    available = _memory_available()
    if need > _MEMORY_SHARE * available:
        raise ValueError(
            f"t_end: the output would take {need / 1e9:.3g} GB ({rows:.3g} rows), more than "
            f"half of the {available / 1e9:.3g} GB available: keep fewer rows with every=K, "
            f"or ask for t_eval=[...]")
    report, close = _progress_callback(progress)
    try:
        d = _npend.simulate(chain, x0, t0, t1, dt, stepper, atol, rtol, order, int(every),
                            t_eval, list(events), report, bool(dense_output))
    finally:
        close()
    terminated = d.pop("terminated")
    return Solution(
        status=1 if terminated else 0,
        message="a terminal event ended the run" if terminated else "the run reached t_end",
        stepper=stepper, dt=float(dt), atol=float(atol), rtol=float(rtol), order=int(order),
        **d)


def lyapunov(
    chain: Chain,
    x0: ArrayLike,
    t_end: float,
    *,
    dt: float = 1e-3,
    stepper: str = "gauss6",
    maximal: bool = False,
    exponents: int = 0,
    renormalise_every: float = 0.1,
    transient: float = 0.0,
    blocks: int = 10,
    atol: float = 1e-10,
    rtol: float = 1e-10,
) -> LyapunovResult:
    """Lyapunov exponents of the trajectory from x0 by Benettin's method, as ``npend lyapunov``.

    The full spectrum of 2n exponents, the largest alone (maximal=True) or the K largest
    (exponents=K: K tangent vectors, O(n) each per step on a long chain's loop kernels).

    Parameters
    ----------
    chain : Chain
        The chain.
    x0 : array_like, shape (2n,)
        The start state.
    t_end : float
        The end of the integration (s).
    dt : float, optional
        The step (s).
    stepper : str, optional
        A stepper as for npend.simulate that integrates the variational equations; the
        Gauss-Legendre ones (gauss6, gauss4) carry the tangent vectors by their exact
        tangent map, an adaptive one (taylor among them: the Taylor series of the state and
        the vectors) steps under atol and rtol between renormalisations; rosenbrock4 is
        refused.
    maximal : bool, optional
        Only the largest exponent.
    exponents : int, optional
        K > 0: the K largest exponents; 0: all 2n (or the largest with maximal).
    renormalise_every : float, optional
        The interval between the tangent vectors' re-orthonormalisations (s).
    transient : float, optional
        The time integrated before the averaging starts (s).
    blocks : int, optional
        The blocks the averaging time is cut into for the standard error (at least 2).
    atol, rtol : float, optional
        The absolute and relative tolerances of an adaptive stepper.

    Returns
    -------
    LyapunovResult
        The exponents (1/s, descending), their errors and running estimates, the final state.

    Raises
    ------
    ValueError
        For bad input, also for maximal=True with exponents.
    IntegrationError
        When the integration cannot go on.

    Examples
    --------
    >>> import numpy as np, npend
    >>> r = npend.lyapunov(npend.Chain(2), [2.0, 1.5, 0.0, 0.0], 20.0, dt=0.005)
    >>> r.exponents.shape, bool(np.all(np.diff(r.exponents) <= 0))
    ((4,), True)
    >>> bool(np.all(np.abs(r.pair_sums) < 1e-10))  # a Hamiltonian flow: pairs +-lambda
    True
    """
    d = _npend.lyapunov(
        chain, x0, t_end, dt=dt, stepper=stepper, maximal=maximal, exponents=exponents,
        renormalise_every=renormalise_every, transient=transient, blocks=blocks, atol=atol,
        rtol=rtol)
    return LyapunovResult(**d)


def poincare(
    chain: Chain,
    x0: ArrayLike,
    section: str,
    t_end: float,
    *,
    dt: float = 1e-3,
    stepper: str = "gauss6",
    direction: str = "up",
    max_crossings: int = 0,
    unwrapped: bool = False,
    atol: float = 1e-10,
    rtol: float = 1e-10,
) -> PoincareResult:
    """The crossings of a Poincare section by the trajectory from x0, as ``npend poincare``.

    Parameters
    ----------
    chain : Chain
        The chain.
    x0 : array_like, shape (2n,)
        The start state.
    section : str
        The section as on the command line: "phi1=0", "p2=0.5", "phi2=phi3".
    t_end : float
        The end of the integration (s).
    dt : float, optional
        The step (s); an adaptive stepper's first trial step.
    stepper : str, optional
        A stepper as for npend.simulate.
    direction : {"up", "down", "both"}, optional
        The crossings counted: the section's coordinate increasing, decreasing, or both.
    max_crossings : int, optional
        Stop after this many crossings (0: run to t_end).
    unwrapped : bool, optional
        Compare the angles as they are, not modulo 2 pi.
    atol, rtol : float, optional
        The absolute and relative tolerances of an adaptive stepper.

    Returns
    -------
    PoincareResult
        The crossing times, the states there, and how far the integration went.

    Raises
    ------
    ValueError
        For bad input: a section, direction or stepper that does not parse, a bad x0.
    IntegrationError
        When the integration cannot go on.

    Examples
    --------
    A small swing of the single pendulum crosses phi1 = 0 upwards once a period,
    2 pi sqrt(l/g) = 2.006 s:

    >>> import numpy as np, npend
    >>> r = npend.poincare(npend.Chain(1), [0.01, 0.0], "phi1=0", 10.0)
    >>> print(np.round(np.diff(r.t), 3), r.states.shape)
    [2.006 2.006 2.006 2.006] (5, 2)
    """
    d = _npend.poincare(
        chain, x0, section, t_end, dt=dt, stepper=stepper, direction=direction,
        max_crossings=max_crossings, unwrapped=unwrapped, atol=atol, rtol=rtol)
    return PoincareResult(**d)


def chaos_indicators(
    chain: Chain,
    x0: ArrayLike,
    t_end: float,
    *,
    dt: float = 0.01,
    vectors: int = 2,
    sample_interval: float = 0.0,
    stepper: str = "rk4",
    tol: float = 1e-12,
) -> IndicatorsResult:
    """The fast chaos indicators of the trajectory from x0: FLI, MEGNO, SALI and GALI.

    The trajectory and `vectors` deviation vectors run with rk4 at dt, or with Taylor's
    method at the tolerance `tol` (``stepper="taylor"``); the vectors are renormalised after
    every step. On a torus <Y> -> 2 and SALI stays away from 0; on a
    chaotic orbit <Y> ~ lambda_1 t / 2 and SALI ~ exp(-(lambda_1 - lambda_2) t).

    Parameters
    ----------
    chain : Chain
        The chain.
    x0 : array_like, shape (2n,)
        The start state.
    t_end : float
        The end of the integration (s).
    dt : float, optional
        The rk4 step (s); taylor's first trial step.
    vectors : int, optional
        The deviation vectors, 2..2n.
    sample_interval : float, optional
        The time between samples (s); 0: one sample at t_end.
    stepper : {"rk4", "taylor"}, optional
        rk4's fixed steps, or Taylor's adaptive steps (its steps land on the samples; MEGNO's
        integrals by quadrature over each step's polynomials, FLI's maximum located within
        the steps).
    tol : float, optional
        taylor: the absolute and relative tolerance of its steps, in (0, 1e-6].

    Returns
    -------
    IndicatorsResult
        The indicators over the samples and the final state.

    Raises
    ------
    ValueError
        For bad input, such as more vectors than 2n.
    IntegrationError
        When the integration cannot go on.

    Examples
    --------
    A single pendulum's orbit is a torus, so <Y> tends to 2:

    >>> import npend
    >>> r = npend.chaos_indicators(npend.Chain(1), [2.0, 0.0], 2000.0, sample_interval=100.0)
    >>> print(r.t.shape, r.gali.shape, f"{r.mean_megno[-1]:.1f}")
    (20,) (20, 1) 2.0
    """
    d = _npend.chaos_indicators(
        chain, x0, t_end, dt=dt, vectors=vectors, sample_interval=sample_interval,
        stepper=stepper, tol=tol)
    return IndicatorsResult(**d)


# Time series


def spectrum(
    x: ArrayLike,
    dt: float,
    *,
    window: str = "hann",
    segment_length: int = 0,
    overlap: float = 0.5,
) -> SpectrumResult:
    """The one-sided spectral density of x_j = x(j dt) (paper 6.6.2), as ``npend spectrum``.

    Parameters
    ----------
    x : array_like, shape (N,)
        The samples.
    dt : float
        The sampling interval (s).
    window : {"hann", "none", "hamming", "blackman"}, optional
        The window; with "none", sum(power) * resolution is the variance of x (Parseval).
    segment_length : int, optional
        Welch segments of this many samples; 0: one segment of all N.
    overlap : float, optional
        The segments' overlap, a fraction in [0, 1).

    Returns
    -------
    SpectrumResult
        omega (rad/s), power, resolution, segment_length, segments.

    Raises
    ------
    ValueError
        For x not 1-D, an unknown window or bad segments.

    Examples
    --------
    >>> import numpy as np, npend
    >>> dt = 0.01
    >>> r = npend.spectrum(np.sin(3.0 * dt * np.arange(4096)), dt)
    >>> r.power.shape, bool(abs(r.omega[np.argmax(r.power)] - 3.0) <= r.resolution)
    ((2049,), True)
    """
    return SpectrumResult(**_npend.spectrum(
        x, dt, window=window, segment_length=segment_length, overlap=overlap))


def autocorrelation(
    x: ArrayLike,
    dt: float,
    *,
    max_lag: int = 0,
    estimator: str = "biased",
) -> AutocorrelationResult:
    """The normalised autocorrelation C(tau) of x_j = x(j dt), as ``npend autocorrelation``.

    Parameters
    ----------
    x : array_like, shape (N,)
        The samples.
    dt : float
        The sampling interval (s).
    max_lag : int, optional
        The largest lag in samples; 0: all, N - 1.
    estimator : {"biased", "unbiased"}, optional
        Divide the sums by N (biased) or by the number of terms.

    Returns
    -------
    AutocorrelationResult
        lag (s), value (C(0) = 1), first_zero and first_minimum (s, or None).

    Raises
    ------
    ValueError
        For x not 1-D, an unknown estimator or a lag beyond the samples.

    Examples
    --------
    C of cos(2 t) is cos(2 tau), first zero at pi/4:

    >>> import numpy as np, npend
    >>> r = npend.autocorrelation(np.cos(2.0 * 0.001 * np.arange(100000)), 0.001, max_lag=2000)
    >>> print(r.lag.shape, f"{r.first_zero:.3f}")
    (2001,) 0.785
    """
    return AutocorrelationResult(**_npend.autocorrelation(
        x, dt, max_lag=max_lag, estimator=estimator))


def embed(x: ArrayLike, delay: int, dimension: int) -> np.ndarray:
    """The delay vectors of a series: rows (x_j, x_(j-delay), ..., x_(j-(dimension-1) delay)).

    Parameters
    ----------
    x : array_like, shape (N,)
        The samples.
    delay : int
        The delay in samples, at least 1.
    dimension : int
        The embedding dimension m, at least 1.

    Returns
    -------
    ndarray, shape (N - (m-1) delay, m)
        Row i ends at sample j = i + (m-1) delay and reaches back from there.

    Raises
    ------
    ValueError
        For a delay or dimension of 0, or N <= (m-1) delay.

    Examples
    --------
    >>> import numpy as np, npend
    >>> print(npend.embed(np.arange(6.0), 2, 3))
    [[4. 2. 0.]
     [5. 3. 1.]]
    """
    return _npend.embed(x, delay, dimension)


def choose_delay(x: ArrayLike, dt: float, *, method: str = "auto") -> DelayResult:
    """The embedding delay of a series, chosen as ``npend embed`` chooses it.

    Parameters
    ----------
    x : array_like, shape (N,)
        The samples, N >= 4.
    dt : float
        The sampling interval (s).
    method : {"auto", "T/4", "acf-zero", "acf-min", "ami"}, optional
        A quarter of the dominant period, the autocorrelation's first zero or minimum, the
        first minimum of the average mutual information; auto tries ami, then the others.

    Returns
    -------
    DelayResult
        found, the method that gave the delay, the delay in samples and in s.

    Raises
    ------
    ValueError
        For x not 1-D, too short or constant, or an unknown method.

    Examples
    --------
    A quarter period of sin(t) is pi/2:

    >>> import numpy as np, npend
    >>> d = npend.choose_delay(np.sin(0.01 * np.arange(10000)), 0.01, method="T/4")
    >>> print(d.found, d.method, f"{d.seconds:.2f}")
    True T/4 1.57
    """
    return DelayResult(**_npend.choose_delay(x, dt, method=method))


# Stability


def equilibria(chain: Chain) -> List[Equilibrium]:
    """The 2^n equilibria phi_i in {0, pi}, p = 0, as ``npend equilibria``.

    Parameters
    ----------
    chain : Chain
        The chain.

    Returns
    -------
    list of Equilibrium
        Ordered as binary numbers, phi_n's 0 or pi the last digit: hanging first.

    Examples
    --------
    The double pendulum hangs stably; standing upright it has two unstable directions:

    >>> import npend
    >>> found = npend.equilibria(npend.Chain(2))
    >>> [(e.stable, e.unstable_directions) for e in found]
    [(True, 0), (False, 1), (False, 1), (False, 2)]
    >>> print(f"{found[3].energy:.2f}")  # 2 (m1 + m2) g l1 + 2 m2 g l2
    58.86
    """
    return [Equilibrium(**e) for e in _npend.equilibria(chain)]


def modes(chain: Chain, angles: Optional[ArrayLike] = None) -> ModesResult:
    """The normal modes about an equilibrium, as ``npend modes``.

    Parameters
    ----------
    chain : Chain
        The chain.
    angles : array_like, shape (n,), optional
        The equilibrium's angles (each 0 or pi); default the hanging chain.

    Returns
    -------
    ModesResult
        The modes in ascending omega^2: frequencies, growth rates, shapes and the matrices.

    Raises
    ------
    ValueError
        For angles of another shape or not an equilibrium.

    Examples
    --------
    The double pendulum's omega^2 = g (2 -+ sqrt 2):

    >>> import numpy as np, npend
    >>> print(np.round(npend.modes(npend.Chain(2)).omega_squared, 3))
    [ 5.747 33.493]
    """
    return ModesResult(**_npend.modes(chain, angles))


# Chaos maps


def _axis(spec: Any, what: str) -> tuple:
    """An axis (name, from, to, count) as the binding takes it; a TypeError or ValueError
    naming the axis and the field otherwise (the binding's own message names neither)."""
    if isinstance(spec, str) or not isinstance(spec, Sequence) or len(spec) != 4:
        raise ValueError(
            f"{what}: expected (name, from, to, count), e.g. ('phi1', -3.14, 3.14, 256)"
            f", got {spec!r}")
    name, start, stop, count = spec
    if not isinstance(name, str):
        raise TypeError(f"{what}: name must be a string such as 'phi1', got {name!r}")
    for field, value in (("from", start), ("to", stop)):
        if isinstance(value, bool) or not isinstance(value, Real):
            raise TypeError(f"{what}: {field} must be a number, got {value!r}")
    if isinstance(count, bool):
        raise TypeError(f"{what}: count must be an integer, got {count!r}")
    try:
        count = operator.index(count)
    except TypeError:
        raise TypeError(f"{what}: count must be an integer, got {count!r}") from None
    return (name, float(start), float(stop), count)


def map(
    chain: Chain,
    x: Sequence,
    y: Sequence,
    *,
    quantity: str = "flip",
    t_end: float = 100.0,
    dt: float = 0.01,
    flip_link: int = 0,
    gali_order: int = 0,
    component: str = "phi1",
    x0: Optional[ArrayLike] = None,
    velocities: Optional[ArrayLike] = None,
    stepper: str = "rk4",
    atol: float = 1e-10,
    rtol: float = 1e-10,
    threads: int = 0,
    device: str = "cpu",
    progress: Any = None,
    out: Union[str, "os.PathLike[str]", None] = None,
    resume: bool = False,
    force: bool = False,
    tile: int = 16,
) -> MapResult:
    """A chaos map over a grid of starts or parameters, as ``npend map``.

    Parameters
    ----------
    chain : Chain
        The chain.
    x, y : sequence (name, from, to, count)
        The axes (a tuple or a list): count values from `from` to `to`, both included. name
        is a start coordinate (phi1..phin, p1..pn, or dphi1..dphin with `velocities`),
        "energy" (the start's momenta scaled to that energy, J), or a parameter of the
        chain (m1..mn, l1..ln, g, k1..kn and b1..bn: the joints' stiffness and damping,
        drive-amplitude and drive-frequency of a chain whose pivot has a built-in drive).
    quantity : {"flip", "lyapunov", "fli", "megno", "sali", "gali", "state"}, optional
        What each cell holds: the time to the first flip of an arm (or of arm flip_link; +inf
        if none by t_end, located inside its step), the largest Lyapunov exponent (rk4), an
        indicator of chaos_indicators at t_end ("megno": <Y>; "gali": GALI_k, k =
        gali_order, 0: n + 1), or coordinate `component` at t_end (angles not wrapped).
    t_end : float, optional
        The end of each cell's integration (s).
    dt : float, optional
        The step (s); dopri5's first trial step.
    flip_link : int, optional
        The arm whose flip counts (1..n); 0: any.
    gali_order : int, optional
        k of GALI_k for quantity "gali" (0: n + 1).
    component : str, optional
        The coordinate of quantity "state": phi1..phin or p1..pn.
    x0 : array_like, shape (2n,), optional
        The rest of each start (default 0).
    velocities : array_like, shape (n,), optional
        The start's angular velocities instead of x0's momenta.
    stepper : {"rk4", "dopri5", "gauss4", "gauss6", "taylor"}, optional
        rk4 steps dt; dopri5 (flip, lyapunov, state) steps adaptively under atol and rtol;
        gauss4 and gauss6 (flip, lyapunov, state) are symplectic with steps dt; taylor (the
        chaos indicators only) runs chaos_indicators on Taylor's method, cell by cell, at
        atol = rtol.
    atol, rtol : float, optional
        dopri5's absolute and relative tolerances; taylor's one tolerance (equal).
    threads : int, optional
        The OpenMP threads (0: every core); the values do not depend on it.
    device : {"cpu", "cuda"}, optional
        "cuda" computes the cells on a GPU (rk4 or dopri5) as ``npend map --device cuda``.
    progress : None, True or callable, optional
        True shows a tqdm bar; a callable hears progress(cells done, cells) about every
        20 ms and at the end (not on the GPU); with `out`, progress(tiles done, tiles).
    out : str or os.PathLike, optional
        A folder for the run, as ``npend map --out``: the grid is cut into tiles of
        tile x tile cells, each written to out/tiles/ as soon as it is done, with
        out/tiles/run.json saying which map they belong to. Ctrl-C (KeyboardInterrupt) keeps
        the finished tiles, and the same call with resume=True computes only the others.
        The tiles stay afterwards, so such a call also returns a finished map at once from
        them. The values are those of a run without `out`, bit for bit.
    resume : bool, optional
        Finish the run in `out` (its run.json must describe the same map).
    force : bool, optional
        Start afresh in an `out` that holds tiles, removing npend's own files from
        out/tiles/ (other files stay).
    tile : int, optional
        Cells per tile side with `out` (1..1024); part of the run's identity.

    Returns
    -------
    MapResult
        values of shape (len(y), len(x)), row 0 at the first y value, the same numbers as
        ``npend map``'s map.npy; NaN where the energy rules a cell out or its integration
        failed. np.asarray(result) gives values.

    Raises
    ------
    TypeError
        For an axis whose name is not a string, a bound not a number or a count not an
        integer (the message names the axis and the field).
    ValueError
        For other bad input: an unknown axis or quantity, a count outside 1..16384, an
        `out` that holds an unfinished run (resume or force it) or another map's tiles, a
        resume=True whose `out` holds no run or another map's, ...
    KeyboardInterrupt
        On Ctrl-C; with `out`, its message says how many tiles are done.
    RuntimeError
        For device="cuda" where no GPU, CUDA driver or NVRTC is found.

    Examples
    --------
    Where 2 cos phi1 + cos phi2 > 1 the double pendulum's energy rules a flip out:

    >>> import numpy as np, npend
    >>> r = npend.map(npend.Chain(2), ("phi1", -1, 1, 3), ("phi2", 0, 0.5, 2), t_end=1.0)
    >>> print(r.x, r.y, np.asarray(r).shape, bool(np.isnan(r.values).all()))
    [-1.  0.  1.] [0.  0.5] (2, 3) True
    >>> r  # doctest: +ELLIPSIS
    MapResult(
        values=array(shape=(2, 3), dtype=float64),
        x=array(shape=(3,), dtype=float64),
        y=array(shape=(2,), dtype=float64),
        x_name='phi1',
        y_name='phi2',
        quantity='flip',
        options={'t_end': 1.0, 'dt': 0.01, ...},
    )
    """
    x_axis, y_axis = _axis(x, "x"), _axis(y, "y")
    options = dict(
        t_end=t_end, dt=dt, flip_link=flip_link, gali_order=gali_order, component=component,
        x0=x0, velocities=velocities, stepper=stepper, atol=atol, rtol=rtol, threads=threads,
        device=device)
    folder = dict(out=out, resume=resume, force=force, tile=tile)
    report, close = _progress_callback(progress)
    try:
        d = _npend.map(chain, x_axis, y_axis, quantity=quantity, progress=report, **options,
                       **folder)
    except KeyboardInterrupt as interrupt:
        if out is None:
            raise
        tiles = os.path.join(os.fspath(out), "tiles")
        done = len([f for f in os.listdir(tiles) if re.fullmatch(r"tile_\d+\.bin", f)])
        raise KeyboardInterrupt(
            f"npend.map: interrupted; {done} tiles are in {tiles}: the same call with "
            "resume=True finishes the map") from interrupt
    finally:
        close()
    if out is not None:
        options.update(folder)
    return MapResult(values=d["values"], x=d["x"], y=d["y"], x_name=x_axis[0],
                     y_name=y_axis[0], quantity=quantity, options=options)


def map_cells(
    chain: Chain,
    x: ArrayLike,
    *,
    quantity: str = "flip",
    t_end: float = 100.0,
    dt: float = 0.01,
    flip_link: int = 0,
    gali_order: int = 0,
    component: str = "phi1",
    stepper: str = "rk4",
    atol: float = 1e-10,
    rtol: float = 1e-10,
    threads: int = 0,
    device: str = "cpu",
    progress: Any = None,
) -> np.ndarray:
    """One map value per start state, computed as ``npend map`` computes its cells.

    Parameters
    ----------
    chain : Chain
        The chain.
    x : array_like, shape (2n,) or (k, 2n)
        The start states, one per row.
    quantity, t_end, dt, flip_link, gali_order, component, stepper, atol, rtol, threads, device, progress
        As for npend.map.

    Returns
    -------
    float64 ndarray, shape () or (k,)
        The cells' values: a 0-d array for one state.

    Raises
    ------
    ValueError
        For bad input, such as a non-finite start.
    RuntimeError
        For device="cuda" where no GPU, CUDA driver or NVRTC is found.

    Examples
    --------
    Starts of too little energy for a flip, and a start at rest, which stays there:

    >>> import npend
    >>> chain = npend.Chain(2)
    >>> print(npend.map_cells(chain, [[0.1, 0.1, 0.0, 0.0], [0.2, 0.0, 0.0, 0.0]], t_end=1.0))
    [nan nan]
    >>> print(npend.map_cells(chain, [0.0] * 4, quantity="state", component="p2", t_end=1.0))
    0.0
    """
    report, close = _progress_callback(progress)
    try:
        return _npend.map_cells(
            chain, x, quantity=quantity, t_end=t_end, dt=dt, flip_link=flip_link,
            gali_order=gali_order, component=component, stepper=stepper, atol=atol,
            rtol=rtol, threads=threads, device=device, progress=report)
    finally:
        close()


def periodic_orbit(
    chain: Chain,
    x0: ArrayLike,
    period: float,
    *,
    energy: Optional[float] = None,
    phase: str = "turning_point",
    steps: int = 400,
    tol: float = 1e-11,
    max_iterations: int = 20,
    segments: int = 1,
    winding: Optional[Sequence[int]] = None,
    stepper: str = "gauss6",
    integration_tol: float = 1e-14,
) -> PeriodicOrbit:
    """The periodic orbit near a guess, by shooting with the exact monodromy matrix.

    Newton's method on phi(T; x0) = x0 with a phase condition and the energy fixed, the flow
    being the Gauss-Legendre (order 6) map of `steps` steps over the period with its exact
    tangent map, or Taylor's method with the Taylor series of the variational equations. The
    conserved energy makes the square system singular; each correction is the least-squares
    solution of all its rows.

    Parameters
    ----------
    chain : Chain
        An undamped chain on a fixed pivot.
    x0 : array_like, shape (2n,)
        The guess of the start.
    period : float
        The guess of the period T (s).
    energy : float, optional
        The energy H the orbit keeps (J); None: the guess's.
    phase : {"turning_point", "poincare"}, optional
        turning_point: the start has p = 0 (every angle at its extreme, the natural choice for
        nonlinear normal modes); poincare: the start lies on the plane through the guess
        normal to the flow (any orbit).
    steps : int, optional
        gauss6: Gauss-Legendre steps over the period (at least 2); the orbit is that map's,
        whose period differs from the flow's by about steps**-6.
    tol : float, optional
        Converged when max |phi(T) - x0| <= tol and |H(x0) - E| <= tol max(1, |E|).
    max_iterations : int, optional
        The most Newton corrections.
    segments : int, optional
        Multiple shooting: the period cut into this many segments, each integrated from its
        own start and matched to the next, for strongly unstable orbits (1: single shooting).
    winding : sequence of int, optional
        A rotating orbit: whole turns of each angle per period (phi(T) = phi(0) + 2 pi
        winding); needs ``phase="poincare"``. None: an oscillation.
    stepper : {"gauss6", "taylor"}, optional
        How the shooting crosses the period (as ``npend orbit --stepper``): gauss6's `steps`
        fixed steps, or taylor's adaptive steps, whose orbit is the flow's to about
        `integration_tol`.
    integration_tol : float, optional
        taylor: the absolute and relative tolerance of its steps, in (0, 1e-6].

    Returns
    -------
    PeriodicOrbit
        The orbit, its period, amplitudes and Floquet multipliers; `converged` says whether
        the tolerance was reached.

    Raises
    ------
    ValueError
        For a damped or driven chain, a chain on a cart, or bad parameters.

    Examples
    --------
    >>> import math, npend
    >>> chain = npend.Chain(1)                      # l = 1 m, g = 9.81 m/s^2
    >>> orbit = npend.periodic_orbit(chain, [2.0, 0.0], 2.5)
    >>> K = 2.0874382317296236                      # K(k), k = sin(1): scipy.special.ellipk(k**2)
    >>> exact = 4 * K / math.sqrt(9.81)              # the period 4 K(k)/omega0
    >>> orbit.converged, abs(orbit.period / exact - 1) < 1e-6
    (True, True)
    """
    return _orbit(_npend.periodic_orbit(
        chain, x0, period, energy=energy, phase=phase, steps=steps, tol=tol,
        max_iterations=max_iterations, segments=segments,
        winding=None if winding is None else [int(w) for w in winding], stepper=stepper,
        integration_tol=integration_tol))


def _orbit(d: dict) -> PeriodicOrbit:
    d["multipliers"] = np.asarray(d["multipliers"], dtype=np.complex128)
    return PeriodicOrbit(**d)


def continue_mode(
    chain: Chain,
    mode: int,
    energy_max: float,
    *,
    start_amplitude: float = 0.01,
    steps: int = 400,
    max_points: int = 200,
    thresholds: Sequence[float] = (0.01, 0.05),
    segments: int = 1,
    continuation: str = "arclength",
    branches: bool = False,
    stepper: str = "gauss6",
    integration_tol: float = 1e-14,
) -> NNMBranch:
    """A nonlinear normal mode: linear mode `mode` continued in energy as periodic orbits.

    As ``npend orbits``: the first orbit starts from the mode shape scaled to
    `start_amplitude` (rad, the largest angle); the family is followed by pseudo-arclength
    (each orbit on the plane normal to the secant of the last two in (start, period), the
    energy free, so it turns round folds in energy) or by steps in the energy, with step-size
    control, up to `energy_max`; for each threshold the orbit where |omega / omega_k - 1|
    reaches it is located by regula falsi in the energy.

    Parameters
    ----------
    chain : Chain
        An undamped chain on a fixed pivot.
    mode : int
        Which linear mode of the hanging chain, 1 = the slowest (as ``--mode``).
    energy_max : float
        Continue up to this energy (J).
    start_amplitude : float, optional
        The first orbit's largest angle (rad).
    steps : int, optional
        Gauss-Legendre steps per period of each orbit.
    max_points : int, optional
        At most this many orbits.
    thresholds : sequence of float, optional
        Relative frequency departures to locate (0.01 = 1 %).
    segments : int, optional
        Multiple shooting of each orbit (as ``--segments``), to follow strongly unstable
        orbits further.
    continuation : {"arclength", "natural"}, optional
        Pseudo-arclength (the default) or steps in the energy.
    branches : bool, optional
        Branch switching (as ``--branches``): each bifurcation's `family` holds the orbits of
        the family born there, continued up to `energy_max`.
    stepper : {"gauss6", "taylor"}, optional
        How each shooting crosses the period, as for npend.periodic_orbit.
    integration_tol : float, optional
        taylor: the absolute and relative tolerance of its steps, in (0, 1e-6].

    Returns
    -------
    NNMBranch
        The orbits' energies, periods, frequencies, amplitudes, multipliers and stability,
        why the branch ended, the departures and the changes of stability (bifurcations).

    Raises
    ------
    ValueError
        For a damped or driven chain, a mode out of range or an energy_max below the first
        orbit's energy.

    Examples
    --------
    >>> import npend
    >>> branch = npend.continue_mode(npend.Chain(3), 3, 1.0)
    >>> round(branch.linear_frequency, 4), branch.end_reason
    (7.8552, 'reached energy_max')
    >>> departure = branch.departures[0.01]             # where omega is 1 % below omega_3
    >>> round(float(departure.frequency / branch.linear_frequency), 6)
    0.99
    """
    d = _npend.continue_mode(chain, mode, energy_max, start_amplitude=start_amplitude,
                             steps=steps, max_points=max_points, thresholds=list(thresholds),
                             segments=segments, continuation=continuation,
                             branches=branches, stepper=stepper,
                             integration_tol=integration_tol)
    n = len(d["shape"])
    d["multipliers"] = np.asarray(d["multipliers"], dtype=np.complex128).reshape(
        len(d["energy"]), 2 * n - 2)
    d["departures"] = {shift: None if orbit is None else _orbit(orbit)
                       for shift, orbit in d["departures"].items()}
    d["bifurcations"] = tuple(
        StabilityChange(kind=b["kind"], energy=b["energy"], loses_stability=b["loses_stability"],
                        stable_side=_orbit(b["stable_side"]),
                        unstable_side=_orbit(b["unstable_side"]),
                        family=tuple(_orbit(p) for p in b["family"]))
        for b in d["bifurcations"])
    return NNMBranch(**d)
