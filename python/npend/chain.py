"""npend.Chain: a chain's parameters and its generated functions, with the conventions of
NumPy and SciPy: signatures and Python types, `fun(t, y)` and `jac(t, y)` for
scipy.integrate.solve_ivp, pickling and copying, equality by parameters and a repr that
rebuilds the chain.

    >>> import npend
    >>> chain = npend.Chain(3, masses=[1, 2, 1.5])
    >>> chain
    npend.Chain(3, masses=[1.0, 2.0, 1.5])
    >>> npend.Chain(**chain.parameters) == chain
    True
"""

from __future__ import annotations

import numbers
from typing import Any, Dict, Optional, Sequence, Union, cast

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import _npend

__all__ = ["Chain"]

# The constructor's defaults, which repr leaves out.
_STANDARD_GRAVITY = 9.81
_PER_LINK_OPTIONAL = ("com", "inertia", "stiffness", "rest_angles", "damping")


def _number(value: Any, name: str) -> Any:
    """`value` when it is a real number (or None); TypeError naming `name` otherwise, instead
    of pybind11's list of overloads."""
    if value is None or (isinstance(value, numbers.Real) and not isinstance(value, bool)):
        return value
    raise TypeError(f"{name}: expected a number, got {value!r}")


def _rebuild(parameters: Dict[str, Any]) -> "Chain":
    # pickle's and copy's constructor: the parameters dict read back as keywords.
    return Chain(**parameters)


class Chain(_npend.Chain):
    """An n-link planar pendulum chain with fixed parameters.

    The state is x = [phi_1..phi_n, p_1..p_n]: angles in rad from the downward vertical,
    canonical momenta in kg m^2/s. With `cart`, x = [x_c, phi_1..phi_n, p_x, p_1..p_n] and
    the coordinates q = [x_c, phi] take the place of phi. Every method taking states takes
    one state of shape (2n,) or k states as the rows of a (k, 2n) array, and then returns
    one result per row; the loop runs in C++ without the GIL, and Ctrl-C stops it.

    Parameters
    ----------
    links : int
        The number of links n (any n; the built link counts run generated kernels).
    masses, lengths : float or sequence of float, optional
        Per link, in kg and m; one number for every link. Default 1 kg and 1 m.
    g : float
        Gravitational acceleration in m/s^2 (default 9.81).
    com, inertia : float or sequence of float, optional
        Rigid links: the centre of mass c_i (m down the link) and the moment of inertia J_i
        (kg m^2) about it.
    rods : bool
        Uniform rods (c = l/2, J = m l^2/12); not with com or inertia.
    stiffness, rest_angles, damping : float or sequence of float, optional
        Joint springs k_j (N m/rad) with their rest angles (rad), viscous damping b_j
        (N m s/rad).
    pivot : str, optional
        None or "fixed" for a fixed pivot, "vertical:A:OMEGA" or "horizontal:A:OMEGA" for
        a pivot shaken with amplitude A (m) at angular frequency OMEGA (rad/s).
    cart, cart_damping : float, optional
        The chain hangs from a cart of this mass (kg) rolling along x, damped by
        cart_damping (N s/m).

    Raises
    ------
    TypeError
        links not an integer, or a number that is not one.
    ValueError
        A parameter out of range, with the command line's message naming the keyword.

    Examples
    --------
    >>> import numpy as np, npend
    >>> c = npend.Chain(2)
    >>> c.links, c.state_size, c.is_physical
    (2, 4, False)
    >>> print(f"{c.hamiltonian([np.pi, np.pi, 0, 0]):.2f}")  # both arms up: 6 m g l
    58.86
    """

    def __init__(
        self,
        links: int,
        *,
        masses: Optional[ArrayLike] = None,
        lengths: Optional[ArrayLike] = None,
        g: float = _STANDARD_GRAVITY,
        com: Optional[ArrayLike] = None,
        inertia: Optional[ArrayLike] = None,
        rods: bool = False,
        stiffness: Optional[ArrayLike] = None,
        rest_angles: Optional[ArrayLike] = None,
        damping: Optional[ArrayLike] = None,
        pivot: Optional[str] = None,
        cart: Optional[float] = None,
        cart_damping: Optional[float] = None,
    ) -> None:
        """Builds the chain (the parameters are the class's)."""
        if isinstance(links, bool) or not isinstance(links, numbers.Integral):
            raise TypeError(f"links: expected an integer, got {links!r}")
        if not isinstance(rods, (bool, np.bool_)):
            raise TypeError(f"rods: expected True or False, got {rods!r}")
        super().__init__(
            int(links), masses=masses, lengths=lengths, g=_number(g, "g"), com=com,
            inertia=inertia, rods=bool(rods), stiffness=stiffness, rest_angles=rest_angles,
            damping=damping, pivot=pivot, cart=_number(cart, "cart"),
            cart_damping=_number(cart_damping, "cart_damping"))

    # --- SciPy's conventions -------------------------------------------------------------

    def fun(self, t: float, y: ArrayLike) -> NDArray[np.float64]:
        """Hamilton's equations as scipy.integrate.solve_ivp calls them: dy/dt = f(t, y).

        Parameters
        ----------
        t : float
            Time in s (it matters for a moving pivot).
        y : array_like, shape (2n,) or (2n, k)
            One state, or k states as columns (solve_ivp's `vectorized=True`).

        Returns
        -------
        ndarray, shape of y

        Examples
        --------
        >>> import numpy as np, npend
        >>> from scipy.integrate import solve_ivp
        >>> chain = npend.Chain(2)
        >>> x0 = [0.3, -0.2, 0.0, 0.0]
        >>> sol = solve_ivp(chain.fun, (0, 5), x0, method="DOP853", rtol=1e-12, atol=1e-12)
        >>> t, X = npend.simulate(chain, x0, t_end=5)
        >>> bool(np.max(np.abs(sol.y[:, -1] - X[-1])) < 1e-9)
        True
        """
        y = np.asarray(y, dtype=float)
        if y.ndim == 2:
            return self.rhs(y.T, t).T
        return self.rhs(y, t)

    def jac(self, t: float, y: ArrayLike) -> NDArray[np.float64]:
        """The exact Jacobian df/dy at (t, y), shape (2n, 2n), as solve_ivp's `jac=` takes it
        (for the implicit methods Radau, BDF and LSODA).

        Examples
        --------
        >>> import numpy as np, npend
        >>> from scipy.integrate import solve_ivp
        >>> chain = npend.Chain(2)
        >>> sol = solve_ivp(chain.fun, (0, 1), [0.3, -0.2, 0, 0], method="Radau",
        ...                 jac=chain.jac, rtol=1e-10, atol=1e-10)
        >>> sol.status
        0
        """
        y = np.asarray(y, dtype=float)
        if y.ndim != 1:
            raise ValueError(f"y: expected one state of shape ({self.state_size},), "
                             f"got shape {y.shape}")
        return self.jacobian(y, t)

    # --- The chain's functions, with their Python signatures ------------------------------

    def rhs(self, x: ArrayLike, t: float = 0.0) -> NDArray[np.float64]:
        """Hamilton's equations dx/dt = f(x, t), shape (2n,) per state (odeint's argument
        order; `fun` has SciPy's)."""
        return super().rhs(x, _number(t, "t"))

    def jacobian(self, x: ArrayLike, t: float = 0.0) -> NDArray[np.float64]:
        """The exact Jacobian df/dx, shape (2n, 2n) per state."""
        return super().jacobian(x, _number(t, "t"))

    def hamiltonian(self, x: ArrayLike, t: float = 0.0) -> Union[float, NDArray[np.float64]]:
        """The energy H = T + V in J: a float for one state, shape (k,) for k states."""
        return cast(Union[float, NDArray[np.float64]], super().hamiltonian(x, _number(t, "t")))

    def positions(self, x: ArrayLike) -> NDArray[np.float64]:
        """The link ends (bobs) relative to the pivot, shape (n, 2) per state: rows
        (x_i, y_i) in m, y pointing down; on a cart the cart (x_c, 0) first, (n + 1, 2)."""
        return super().positions(x)

    def velocities(self, x: ArrayLike) -> NDArray[np.float64]:
        """The velocities dq/dt = A(q)^-1 p of the coordinates, shape (n,) per state."""
        return super().velocities(x)

    def mass_matrix(self, x: ArrayLike) -> NDArray[np.float64]:
        """The mass matrix A(q) of T = p^T A^-1 p / 2, shape (n, n) per state."""
        return super().mass_matrix(x)

    def state_from_velocities(self, phi: ArrayLike, dphi: ArrayLike) -> NDArray[np.float64]:
        """The state [q, A(q) dq/dt] from coordinates and their velocities: shape (n,) each
        for one state (2n,), or (k, n) each for k states (k, 2n).

        Examples
        --------
        >>> import npend
        >>> npend.Chain(1).state_from_velocities([0.0], [2.0])  # p = m l^2 dphi
        array([0., 2.])
        """
        return super().state_from_velocities(phi, dphi)

    # --- Python's protocols -------------------------------------------------------------

    def __reduce__(self):
        return (_rebuild, (self.parameters,))

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, _npend.Chain):
            return NotImplemented
        return self.parameters == other.parameters

    def __hash__(self) -> int:
        # A chain's parameters never change, so equal chains may share dict keys.
        return hash(repr(self))

    def __repr__(self) -> str:
        p = self.parameters
        keywords = [str(p["links"])]

        def show(name: str, values: Sequence[float]) -> None:
            keywords.append(f"{name}=[{', '.join(repr(float(v)) for v in values)}]")

        for name in ("masses", "lengths"):
            if any(v != 1.0 for v in p[name]):
                show(name, p[name])
        if p["g"] != _STANDARD_GRAVITY:
            keywords.append(f"g={p['g']!r}")
        for name in _PER_LINK_OPTIONAL:
            if p[name] is not None:
                show(name, p[name])
        if p["pivot"] != "fixed":
            keywords.append(f"pivot={p['pivot']!r}")
        if p["cart"] is not None:
            keywords.append(f"cart={p['cart']!r}")
            if p["cart_damping"]:
                keywords.append(f"cart_damping={p['cart_damping']!r}")
        return f"npend.Chain({', '.join(keywords)})"


Chain.__module__ = "npend"
