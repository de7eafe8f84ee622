"""The results of npend's analyses: small frozen classes whose attributes are numpy arrays
and numbers, printed with their scalars and with their arrays summarised by shape and dtype.

    >>> import numpy as np
    >>> from npend.results import DelayResult, PoincareResult
    >>> DelayResult(found=True, method="T/4", samples=157, seconds=1.57)
    DelayResult(found=True, method='T/4', samples=157, seconds=1.57)
    >>> PoincareResult(t=np.zeros(3), states=np.zeros((3, 4)), t_end=10.0)
    PoincareResult(
        t=array(shape=(3,), dtype=float64),
        states=array(shape=(3, 4), dtype=float64),
        t_end=10.0,
    )
"""

from __future__ import annotations

import dataclasses
from typing import Any, Mapping, Optional

import numpy as np

__all__ = [
    "AutocorrelationResult",
    "DelayResult",
    "Equilibrium",
    "IndicatorsResult",
    "LyapunovResult",
    "MapResult",
    "ModesResult",
    "NNMBranch",
    "PeriodicOrbit",
    "StabilityChange",
    "PoincareResult",
    "Solution",
    "SpectrumResult",
]

# One line while it fits (a dataclass's repr), one field a line beyond.
_REPR_WIDTH = 88


def _summary(value: Any) -> str:
    if isinstance(value, np.ndarray):
        return f"array(shape={value.shape}, dtype={value.dtype})"
    if isinstance(value, _Result):
        return f"{type(value).__name__}(...)"
    if isinstance(value, tuple) and value and all(isinstance(v, _Result) for v in value):
        return "(" + ", ".join(_summary(v) for v in value) + ",)"
    if isinstance(value, Mapping):
        return "{" + ", ".join(f"{k!r}: {_summary(v)}" for k, v in value.items()) + "}"
    return repr(value)


class _Result:
    """What every result class shares: the repr (arrays would print in full in a dataclass's)."""

    def __repr__(self) -> str:
        fields = [f"{f.name}={_summary(getattr(self, f.name))}" for f in dataclasses.fields(self)]
        name = type(self).__name__
        line = f"{name}({', '.join(fields)})"
        if len(line) <= _REPR_WIDTH:
            return line
        return name + "(\n" + "".join(f"    {field},\n" for field in fields) + ")"




@dataclasses.dataclass(frozen=True, repr=False, eq=False)  # == on arrays is no bool
class LyapunovResult(_Result):
    """The Lyapunov exponents of npend.lyapunov.

    Attributes
    ----------
    exponents : ndarray, shape (k,)
        The exponents in 1/s, descending: k = 2n (the spectrum), 1 (maximal) or K.
    sum : float
        Their sum (0 for a Hamiltonian flow's full spectrum).
    pair_sums : ndarray, shape (n,)
        lambda_i + lambda_(2n+1-i), i = 1..n: 0 for a Hamiltonian flow, to round-off with a
        symplectic stepper. Empty unless the full spectrum was asked for.
    standard_error : ndarray, shape (k,)
        Per exponent: the standard deviation of the blocks' exponents / sqrt(blocks) (1/s),
        NaN with fewer than two blocks.
    spread : ndarray, shape (k,)
        Per exponent: max - min of its running value over the last part of the averaging
        time (1/s), the convergence estimate.
    history_t : ndarray, shape (h,)
        The times of the running estimates (s).
    history : ndarray, shape (h, k)
        The running estimates, row i at history_t[i].
    t : float
        Where the integration ended (s).
    averaging_time : float
        The time the exponents average over (t minus the transient, s).
    renormalisations : int
        How many times the tangent vectors were renormalised.
    max_rel_energy_error : float
        The largest |H - H(0)| / |H(0)| at the renormalisations.
    method : str
        "tangent map" (Gauss-Legendre steppers), "Taylor series of the variational
        equations" (taylor) or "variational equations".
    state : ndarray, shape (2n,)
        The final state.
    """

    exponents: np.ndarray
    sum: float
    pair_sums: np.ndarray
    standard_error: np.ndarray
    spread: np.ndarray
    history_t: np.ndarray
    history: np.ndarray
    t: float
    averaging_time: float
    renormalisations: int
    max_rel_energy_error: float
    method: str
    state: np.ndarray


@dataclasses.dataclass(frozen=True, repr=False, eq=False)  # == on arrays is no bool
class PoincareResult(_Result):
    """The crossings of a Poincare section found by npend.poincare.

    Attributes
    ----------
    t : ndarray, shape (k,)
        The crossing times (s), ascending.
    states : ndarray, shape (k, 2n)
        The states at the crossings, row i at t[i].
    t_end : float
        How far the integration went (s): t_end, or less with max_crossings.
    """

    t: np.ndarray
    states: np.ndarray
    t_end: float


@dataclasses.dataclass(frozen=True, repr=False, eq=False)  # == on arrays is no bool
class IndicatorsResult(_Result):
    """The fast chaos indicators of npend.chaos_indicators, one entry per sample.

    Attributes
    ----------
    t : ndarray, shape (s,)
        The sample times (s).
    fli : ndarray, shape (s,)
        The fast Lyapunov indicator.
    megno : ndarray, shape (s,)
        MEGNO Y.
    mean_megno : ndarray, shape (s,)
        Its running mean <Y>.
    sali : ndarray, shape (s,)
        The smaller alignment index.
    gali : ndarray, shape (s, vectors - 1)
        GALI_2..GALI_vectors.
    state : ndarray, shape (2n,)
        The final state.
    """

    t: np.ndarray
    fli: np.ndarray
    megno: np.ndarray
    mean_megno: np.ndarray
    sali: np.ndarray
    gali: np.ndarray
    state: np.ndarray


@dataclasses.dataclass(frozen=True, repr=False, eq=False)  # == on arrays is no bool
class SpectrumResult(_Result):
    """The one-sided spectral density of npend.spectrum.

    Attributes
    ----------
    omega : ndarray, shape (m,)
        The angular frequencies (rad/s), 0 to the Nyquist frequency.
    power : ndarray, shape (m,)
        The spectral density at omega.
    resolution : float
        The spacing of omega (rad/s).
    segment_length : int
        The samples per Welch segment.
    segments : int
        How many segments were averaged.
    """

    omega: np.ndarray
    power: np.ndarray
    resolution: float
    segment_length: int
    segments: int


@dataclasses.dataclass(frozen=True, repr=False, eq=False)  # == on arrays is no bool
class AutocorrelationResult(_Result):
    """The normalised autocorrelation of npend.autocorrelation.

    Attributes
    ----------
    lag : ndarray, shape (L + 1,)
        The lags (s).
    value : ndarray, shape (L + 1,)
        C(lag), C(0) = 1.
    first_zero : float or None
        The first lag where C falls to 0 (s, interpolated between lags), None if it does not.
    first_minimum : float or None
        The first local minimum of C (s, a parabola through three lags), None if none.
    """

    lag: np.ndarray
    value: np.ndarray
    first_zero: Optional[float]
    first_minimum: Optional[float]


@dataclasses.dataclass(frozen=True, repr=False, eq=False)  # == on arrays is no bool
class DelayResult(_Result):
    """The embedding delay chosen by npend.choose_delay.

    Attributes
    ----------
    found : bool
        Whether a method gave a delay.
    method : str
        The method that gave it (auto tries several).
    samples : int
        The delay in samples.
    seconds : float
        The delay in s.
    """

    found: bool
    method: str
    samples: int
    seconds: float


@dataclasses.dataclass(frozen=True, repr=False, eq=False)  # == on arrays is no bool
class Equilibrium(_Result):
    """One equilibrium of npend.equilibria.

    Attributes
    ----------
    angles : ndarray, shape (n,)
        The angles, each 0 or pi (rad).
    energy : float
        H there (J).
    eigenvalues : ndarray of complex, shape (2n,)
        The eigenvalues of the Jacobian there.
    stable : bool
        Whether it is (linearly) stable.
    unstable_directions : int
        How many of its modes grow.
    """

    angles: np.ndarray
    energy: float
    eigenvalues: np.ndarray
    stable: bool
    unstable_directions: int


@dataclasses.dataclass(frozen=True, repr=False, eq=False)  # == on arrays is no bool
class ModesResult(_Result):
    """The normal modes of npend.modes, in ascending omega^2.

    Attributes
    ----------
    omega_squared : ndarray, shape (n,)
        The squared angular frequencies (1/s^2); negative for a growing mode.
    frequencies : ndarray, shape (n,)
        sqrt(omega^2) (rad/s) for the oscillating modes, 0 for the growing ones.
    growth_rates : ndarray, shape (n,)
        sqrt(-omega^2) (1/s) for the growing modes, 0 for the oscillating ones.
    shapes : ndarray, shape (n, n)
        Row k: the shape of mode k.
    mass_matrix : ndarray, shape (n, n)
        The mass matrix at the equilibrium.
    stiffness_matrix : ndarray, shape (n, n)
        The Hessian of the potential there.
    """

    omega_squared: np.ndarray
    frequencies: np.ndarray
    growth_rates: np.ndarray
    shapes: np.ndarray
    mass_matrix: np.ndarray
    stiffness_matrix: np.ndarray


@dataclasses.dataclass(frozen=True, repr=False, eq=False)  # == on arrays is no bool
class PeriodicOrbit(_Result):
    """A periodic orbit of npend.periodic_orbit (or a point of an NNMBranch).

    Attributes
    ----------
    converged : bool
        Whether the shooting reached its tolerance.
    x0 : ndarray, shape (2n,)
        The start, on the orbit.
    period : float
        T (s).
    frequency : float
        2 pi / T (rad/s).
    energy : float
        H(x0) (J).
    closure : float
        max |phi(T; x0) - x0| of the last integration.
    iterations : int
        The Newton corrections taken.
    amplitudes : ndarray, shape (n,)
        max |phi_i| over the orbit (rad).
    multipliers : ndarray of complex, shape (2n - 2,)
        The Floquet multipliers by descending modulus, without the trivial pair at +1.
    max_multiplier : float
        The largest |multiplier| (1 when there are none).
    stable : bool
        Every multiplier has |mu| <= 1 + 1e-6.
    winding : tuple of int
        Whole turns of each angle per period (all 0 for an oscillation; empty for the orbits
        of a branch).
    """

    converged: bool
    x0: np.ndarray
    period: float
    frequency: float
    energy: float
    closure: float
    iterations: int
    amplitudes: np.ndarray
    multipliers: np.ndarray
    max_multiplier: float
    stable: bool
    winding: tuple = ()


@dataclasses.dataclass(frozen=True, repr=False, eq=False)
class StabilityChange(_Result):
    """Where a branch's orbits lose or regain stability, bracketed to 1e-8 in energy.

    Attributes
    ----------
    kind : str
        How the Floquet multipliers leave the unit circle on the unstable side: "branch
        point" (a real pair through +1), "period doubling" (through -1) or "complex pair"
        (a quartet: a Krein collision).
    energy : float
        The bracket's midpoint (J).
    loses_stability : bool
        Stable below the energy and unstable above (False: the reverse).
    stable_side, unstable_side : PeriodicOrbit
        The orbits at the bracket's ends.
    family : tuple of PeriodicOrbit
        With ``continue_mode(..., branches=True)``: the orbits of the family born here
        (branch switching), by the order of its continuation up to energy_max; empty
        otherwise, and for a complex pair.
    """

    kind: str
    energy: float
    loses_stability: bool
    stable_side: PeriodicOrbit
    unstable_side: PeriodicOrbit
    family: tuple = ()


@dataclasses.dataclass(frozen=True, repr=False, eq=False)  # == on arrays is no bool
class NNMBranch(_Result):
    """A nonlinear normal mode of npend.continue_mode: its periodic orbits by energy.

    Attributes
    ----------
    mode : int
        The linear mode it continues (1 = the slowest).
    linear_frequency : float
        omega_k of the linear mode (rad/s).
    shape : ndarray, shape (n,)
        The linear mode's shape.
    energy, period, frequency : ndarray, shape (k,)
        Each orbit's H (J), T (s) and 2 pi / T (rad/s), by increasing energy.
    amplitudes : ndarray, shape (k, n)
        Each orbit's max |phi_i| (rad).
    x0 : ndarray, shape (k, 2n)
        Each orbit's start (a turning point: p = 0).
    multipliers : ndarray of complex, shape (k, 2n - 2)
        Each orbit's Floquet multipliers by descending modulus, without the trivial pair.
    max_multiplier : ndarray, shape (k,)
        Each orbit's largest |multiplier|.
    stable : ndarray of bool, shape (k,)
        Whether each orbit is stable.
    closure : ndarray, shape (k,)
        Each orbit's closure.
    end_reason : str
        Why the branch ended ("reached energy_max", ...).
    departures : dict
        For each threshold (a relative shift such as 0.01), the PeriodicOrbit where
        |omega / omega_k - 1| reaches it, or None where the branch does not get there.
    bifurcations : tuple of StabilityChange
        Where the orbits lose or regain stability, by increasing energy.
    folds : tuple of (int, float)
        Where the energy along the branch turns back: the index of the orbit before the turn
        and the turn's energy (J) from a parabola through three orbits.
    """

    mode: int
    linear_frequency: float
    shape: np.ndarray
    energy: np.ndarray
    period: np.ndarray
    frequency: np.ndarray
    amplitudes: np.ndarray
    x0: np.ndarray
    multipliers: np.ndarray
    max_multiplier: np.ndarray
    stable: np.ndarray
    closure: np.ndarray
    end_reason: str
    departures: dict
    bifurcations: tuple
    folds: tuple = ()


@dataclasses.dataclass(frozen=True, repr=False, eq=False)  # == on arrays is no bool
class MapResult(_Result):
    """A chaos map of npend.map, with its axes; np.asarray(result) is `values`.

    Attributes
    ----------
    values : ndarray, shape (len(y), len(x))
        The map, row i at y[i], column j at x[j]: the same numbers as npend map's map.npy.
    x, y : ndarray
        The axes' values, each from `from` to `to`, both included.
    x_name, y_name : str
        The axes' names ("phi1", "energy", "m2", ...).
    quantity : str
        What the cells hold ("flip", "lyapunov", "fli", ...).
    options : dict
        The other options the map was computed with (t_end, dt, stepper, ...).
    """

    values: np.ndarray
    x: np.ndarray
    y: np.ndarray
    x_name: str
    y_name: str
    quantity: str
    options: Mapping[str, Any]

    def __array__(self, dtype=None, copy=None):
        if copy:
            return np.array(self.values, dtype=dtype, copy=True)
        return np.asarray(self.values, dtype=dtype)


@dataclasses.dataclass(frozen=True, repr=False, eq=False)  # == on arrays is no bool
class Solution(_Result):
    """A trajectory of npend.simulate. It unpacks as ``t, X = npend.simulate(...)``.

    Attributes
    ----------
    t : ndarray, shape (N,)
        The output times (s): the grid t_start + k dt up to t_end (every `every`-th), or
        t_eval; up to the terminal event where one ended the run.
    X : ndarray, shape (N, 2n)
        Row k the state at t[k].
    status : int
        0: the run reached t_end; 1: a terminal event ended it. (A failed integration raises
        npend.IntegrationError instead of returning.)
    message : str
        What `status` says, in words.
    nsteps : int
        The steps the stepper took (accepted steps for an adaptive one).
    nfev : int
        The evaluations of the right-hand side (SciPy's name): the stepper's stages, the
        Newton iterations of gauss4 and gauss6, and the end-point derivatives of the cubic
        Hermite dense output where `t_eval` or `events` read it. 0 for taylor, which
        expands the solution with the generated Taylor kernels once per step instead.
    njev : int
        The evaluations of the Jacobian: rosenbrock4's, once per attempted step, and
        gauss4's and gauss6's where their simplified Newton iteration renews it.
    t_events, y_events : list of ndarray
        Per event function: the times (k,) and states (k, 2n) where it fired, in order.
    energy_error : float
        The largest |H(t) - H(t_start)| / |H(t_start)| over the output (absolute, in J, when
        H(t_start) = 0). A measure of the stepper's error for a conservative chain; for a
        damped or driven one, H changes physically.
    stepper : str
    dt, atol, rtol : float
    order : int
        The options the run used.
    sol : DenseOutput or None
        With dense_output=True, the continuous solution: sol(t) is the state at t (shape
        (2n,)), or at an array of m times (shape (2n, m)), anywhere in the run's span, as
        SciPy's OdeSolution. It is the stepper's own dense output (the cubic Hermite
        interpolant for rk4, rkf78, gauss4 and gauss6), kept step by step. None otherwise.

    Notes
    -----
    `y` is X.T, SciPy's layout (a view, not a copy).
    """

    t: np.ndarray
    X: np.ndarray
    status: int
    message: str
    nsteps: int
    nfev: int
    njev: int
    t_events: list
    y_events: list
    energy_error: float
    stepper: str
    dt: float
    atol: float
    rtol: float
    order: int
    sol: Any = None

    @property
    def y(self) -> np.ndarray:
        return self.X.T

    @property
    def success(self) -> bool:
        """True: the run ended at t_end or at a terminal event (as SciPy's)."""
        return self.status >= 0

    def __iter__(self):
        return iter((self.t, self.X))
