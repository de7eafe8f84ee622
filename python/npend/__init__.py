"""npend: exact equations of planar n-link pendulum chains, fast generated code for them,
and the analyses of chaos theory on top (equilibria, normal modes, Lyapunov exponents,
Poincare sections, spectra, autocorrelation, delay embedding, chaos maps).

The functions mirror the C++ library and the `npend` command line; arrays go in and come
out as numpy float64 arrays, and the analyses return small result classes (npend.results)
whose attributes are those arrays. A state is x = [phi_1..phi_n, p_1..p_n] (rad, kg m^2/s).

    >>> import numpy as np, npend
    >>> chain = npend.Chain(3)                      # the paper's triple pendulum
    >>> x0 = npend.kicked_state(chain, 1.0)         # H = 1 J
    >>> section = npend.poincare(chain, x0, "phi1=0", 20.0)
    >>> section.states.shape[1]
    6
    >>> bool(np.all(np.abs(chain.hamiltonian(section.states) - 1.0) < 1e-9))  # H conserved
    True

Bad input raises ValueError with the command line's message; npend.IntegrationError (a
RuntimeError) when an integration cannot go on; Ctrl-C interrupts long computations.
"""

from ._npend import IntegrationError
from .results import Solution
from .chain import Chain
from .analysis import (
    autocorrelation,
    built_link_counts,
    chaos_indicators,
    choose_delay,
    continue_mode,
    deflected_state,
    embed,
    Event,
    energy_from_epsilon,
    equilibria,
    kicked_state,
    lyapunov,
    map,
    map_cells,
    modes,
    periodic_orbit,
    poincare,
    simulate,
    spectrum,
)
from ._version import __version__

IntegrationError.__doc__ = """An integration that cannot go on: a non-finite state, a step size
that collapsed, or a Newton iteration (implicit steppers) that did not converge.

A subclass of RuntimeError, raised by simulate, lyapunov, poincare and chaos_indicators (a
map's cells give NaN instead). Its `time` attribute is the time (s) where it happened.
"""

__all__ = [
    "__version__",
    "Chain",
    "IntegrationError",
    "autocorrelation",
    "built_link_counts",
    "chaos_indicators",
    "choose_delay",
    "continue_mode",
    "deflected_state",
    "embed",
    "Event",
    "energy_from_epsilon",
    "equilibria",
    "kicked_state",
    "lyapunov",
    "map",
    "map_cells",
    "modes",
    "periodic_orbit",
    "poincare",
    "simulate",
    "Solution",
    "spectrum",
]
