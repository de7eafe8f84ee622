"""npend: exact equations of planar n-link pendulum chains, fast generated code for them,
and the analyses of chaos theory on top (equilibria, normal modes, Lyapunov exponents,
Poincare sections, spectra, autocorrelation, delay embedding, chaos maps).

The functions mirror the C++ library and the `npend` command line; arrays go in and come
out as numpy float64 arrays. A state is x = [phi_1..phi_n, p_1..p_n] (rad, kg m^2/s).

    >>> import npend
    >>> chain = npend.Chain(3)                      # the paper's triple pendulum
    >>> t, X = npend.simulate(chain, [0.1, -0.1, 0.1, 0, 0, 0], t_end=10)
    >>> chain.hamiltonian(X).std()                  # energy along the run

Bad input raises ValueError with the command line's message; npend.IntegrationError (a
RuntimeError) when an integration cannot go on; Ctrl-C interrupts long computations.
"""

from ._npend import (  # noqa: F401  (the package's API)
    Chain,
    IntegrationError,
    autocorrelation,
    built_link_counts,
    chaos_indicators,
    choose_delay,
    deflected_state,
    embed,
    energy_from_epsilon,
    equilibria,
    kicked_state,
    lyapunov,
    map,
    map_cells,
    modes,
    poincare,
    simulate,
    spectrum,
)
from ._version import __version__

__all__ = [
    "__version__",
    "Chain",
    "IntegrationError",
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
    "simulate",
    "spectrum",
]
