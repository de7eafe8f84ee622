"""Figures and animations of npend's results with matplotlib: the chain in motion (an
animation for Jupyter, or a GIF or MP4 file), the bobs' paths, the energy error, Poincare
sections, spectra and chaos maps.

`import npend` does not import this module (nor matplotlib); `import npend.plot` does.

    >>> import npend, npend.plot
    >>> chain = npend.Chain(2)
    >>> t, X = npend.simulate(chain, [2.0, 2.5, 0, 0], t_end=2)
    >>> npend.plot.save_animation(chain, t, X, "double.gif")  # 2 s at 25 frames/s
    'double.gif'
    >>> fig, ax = npend.plot.energy_error(chain, t, X)

A trajectory is given as the arrays `t` (N,) and `X` (N, state size), as `simulate` returns
them, or as one object with attributes `t` and `X` in place of both. Positions are drawn
with the height -y pointing up (the library's y points down), in the lab frame: the pivot
where its drive has moved it, or the cart where it has rolled.

The figure helpers return `(fig, ax)`; given `ax=`, they draw into it (and return its
figure with it).
"""

import importlib.util
import math
import os
import re
import secrets

import matplotlib
import matplotlib.animation as mpl_animation
import matplotlib.colors as mpl_colors
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.collections import LineCollection
from matplotlib.patches import Rectangle

__all__ = [
    "animation",
    "axis_label",
    "chaos_map",
    "energy_error",
    "lab_points",
    "poincare_section",
    "save_animation",
    "spectrum",
    "trajectory",
]

# The colours of the command line's animations: the rods dark grey, the bobs blue, the last
# bob red like its trail; bars where the links carry their mass along their length.
ROD_COLOUR = "#404040"
BAR_COLOUR = "#8a9bb0"
BOB_COLOUR = "#1f77b4"
LAST_BOB_COLOUR = "#d62728"
# Cells without a value (NaN: ruled out by the energy, or failed) in a chaos map.
NAN_COLOUR = "#a0a0a0"
# The command line's limit on an animation's frames.
MAX_FRAMES = 100_000
# Trail samples per frame (as the command line's animations): the trail is drawn through
# the states at these times, so it stays smooth when the chain moves far between frames.
TRAIL_OVERSAMPLING = 4
# Values of the quantities on a log scale drawn no lower than this (a SALI that reached 0).
LOG_FLOOR = 1e-16


# ---------------------------------------------------------------------------------------
# Arguments


def _trajectory_arrays(chain, t, X):
    """t (N,) and X (N, state size) as float64 arrays, from the two arrays or from one
    object with attributes t and X (a simulation's result) passed as `t` with X None."""
    if X is None:
        if hasattr(t, "t") and hasattr(t, "X"):
            t, X = t.t, t.X
        else:
            raise ValueError("X: missing (pass t and X, or one object with attributes t and X)")
    t = np.asarray(t, dtype=float)
    X = np.asarray(X, dtype=float)
    if t.ndim != 1 or t.size < 1:
        raise ValueError(f"t: expected a 1-D array of at least one time, got shape {t.shape}")
    d = chain.state_size
    if X.ndim != 2 or X.shape != (t.size, d):
        raise ValueError(f"X: expected shape ({t.size}, {d}) (a row per time), got {X.shape}")
    if not (np.all(np.isfinite(t)) and np.all(np.isfinite(X))):
        raise ValueError("t, X: the trajectory has values that are not finite")
    steps = np.diff(t)
    if steps.size and not (np.all(steps > 0) or np.all(steps < 0)):
        raise ValueError("t: the times must increase (or decrease) strictly")
    return t, X


def _positive(name, value, allow_zero=False):
    value = float(value)
    if not math.isfinite(value) or value < 0 or (value == 0 and not allow_zero):
        bound = ">= 0" if allow_zero else "> 0"
        raise ValueError(f"{name}: must be a finite number {bound}, got {value}")
    return value


def _axes(ax, **subplot_kw):
    """(fig, ax): a new figure with one axes, or the given axes and its figure."""
    if ax is None:
        fig, ax = plt.subplots(**subplot_kw)
        return fig, ax
    return ax.figure, ax


# ---------------------------------------------------------------------------------------
# Geometry


def _pivot_positions(chain, t):
    """The pivot r0(t) (m, y down) at the times t, shape (N, 2): its built-in drive
    "vertical:A:OMEGA" (r0 = (0, -A cos OMEGA t)) or "horizontal:A:OMEGA" (A cos OMEGA t, 0)."""
    pivot = chain.parameters["pivot"]
    r0 = np.zeros((len(t), 2))
    if pivot == "fixed":
        return r0
    kind, amplitude, frequency = pivot.split(":")
    drive = float(amplitude) * np.cos(float(frequency) * t)
    if kind == "vertical":
        r0[:, 1] = -drive
    elif kind == "horizontal":
        r0[:, 0] = drive
    else:
        raise ValueError(f"chain: a pivot moving as '{pivot}' cannot be drawn")
    return r0


def _pivot_amplitude(chain):
    pivot = chain.parameters["pivot"]
    return 0.0 if pivot == "fixed" else abs(float(pivot.split(":")[1]))


def lab_points(chain, t, X):
    """The chain's points in the lab frame (m, y down) for each state, shape (N, n + 1, 2):
    point 0 the pivot where its drive has moved it (on a cart the cart), point k the end of
    link k."""
    t = np.asarray(t, dtype=float)
    P = np.asarray(chain.positions(np.atleast_2d(X))).reshape(len(t), -1, 2)
    if chain.has_cart:
        return P  # the cart first, and the bobs where the cart has taken them
    pivot = _pivot_positions(chain, t)[:, None, :]
    return np.concatenate([pivot, pivot + P], axis=1)


def _reach(chain):
    """How far the chain reaches from its pivot's rest position (m): the links at full
    stretch plus the drive's amplitude."""
    return float(np.sum(chain.parameters["lengths"])) + _pivot_amplitude(chain)


def _has_distributed_mass(chain):
    p = chain.parameters
    com, inertia = p["com"] or [], p["inertia"] or []  # None: point masses
    return any(c != length for c, length in zip(com, p["lengths"])) or any(j > 0 for j in inertia)


def _interpolate(t, X, times):
    """The states at `times`, linear between the rows around each time (a row's own state
    where a time falls on it); t increasing or decreasing."""
    if t.size == 1:
        return np.repeat(X, len(times), axis=0)
    if t[0] > t[-1]:
        t, X = t[::-1], X[::-1]
    return np.column_stack([np.interp(times, t, X[:, c]) for c in range(X.shape[1])])


def _frame_times(t, fps, speed):
    """The frames' times in the chain's time: t0 + k speed/fps for every one within the
    trajectory (within 1e-9 of a frame), t0 included, in the direction the times run."""
    duration = abs(t[-1] - t[0])
    last = math.floor(duration * fps / speed + 1e-9)
    if last + 1 > MAX_FRAMES:
        raise ValueError(f"fps, speed: {last + 1} frames is more than the limit of "
                         f"{MAX_FRAMES}; lower fps, raise speed or pass a shorter trajectory")
    return last + 1


# ---------------------------------------------------------------------------------------
# Animations


def animation(chain, t, X=None, *, fps=25, trail=2.0, speed=1.0, ax=None):
    """An animation of the chain's motion: the links (bars where they carry their mass
    along their length), the bobs, the pivot (or the cart and its rail), the last bob's
    fading trail and the time.

    chain: the npend.Chain the trajectory belongs to.
    t, X: the trajectory, shapes (N,) and (N, chain.state_size), or one object with
        attributes t and X as `t`.
    fps: frames per second of playback. Frame k shows the chain at t0 + k speed/fps, for
        every such time within the trajectory; its state is interpolated linearly between
        the two rows of X around that time (a row itself where the time falls on one), so
        rows closer than the frame step (simulate's dt) make a faithful animation.
    trail: seconds (of the chain's time) of the last bob's path drawn behind it; 0: none.
    speed: seconds of the chain's time per second of playback.
    ax: axes to draw into (default: a new 6.4 x 6.4 inch figure).

    Returns a matplotlib.animation.FuncAnimation; keep a reference to it while it plays.
    Its artists are labelled "links", "bobs", "last bob", "pivot" (or "cart" and "rail")
    and "trail".
    In Jupyter: IPython.display.HTML(anim.to_jshtml()). Raises ValueError for a bad
    argument, naming it."""
    t, X = _trajectory_arrays(chain, t, X)
    fps = _positive("fps", fps)
    trail = _positive("trail", trail, allow_zero=True)
    speed = _positive("speed", speed)
    frames = _frame_times(t, fps, speed)
    direction = 1.0 if t.size == 1 or t[-1] >= t[0] else -1.0

    # The states every 1/TRAIL_OVERSAMPLING of a frame: frame k is sample k * oversampling.
    step = direction * speed / (fps * TRAIL_OVERSAMPLING)
    samples = (frames - 1) * TRAIL_OVERSAMPLING + 1
    times = t[0] + step * np.arange(samples)
    points = lab_points(chain, times, _interpolate(t, X, times))
    points[:, :, 1] *= -1  # the height, up

    fig, ax = _axes(ax, figsize=(6.4, 6.4))
    reach = 1.08 * _reach(chain)
    if chain.has_cart:
        ax.set_xlim(X[:, 0].min() - reach, X[:, 0].max() + reach)  # x_c's range
        ax.axhline(0.0, color="#b0b0b0", linewidth=1, zorder=0, label="rail")
    else:
        ax.set_xlim(-reach, reach)
    ax.set_ylim(-reach, reach)
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("height \u2212y (m)")

    bars = _has_distributed_mass(chain)
    trail_line = LineCollection([], linewidths=1.5, zorder=1, label="trail")
    ax.add_collection(trail_line)
    (links,) = ax.plot([], [], "-", color=BAR_COLOUR if bars else ROD_COLOUR,
                       linewidth=6 if bars else 2, solid_capstyle="round", zorder=2,
                       label="links")
    (bobs,) = ax.plot([], [], "o", color=ROD_COLOUR if bars else BOB_COLOUR,
                      markersize=4 if bars else 8, zorder=3, label="bobs")
    (last_bob,) = ax.plot([], [], "o", color=LAST_BOB_COLOUR, markersize=6 if bars else 8,
                          zorder=4, label="last bob")
    if chain.has_cart:
        width, height = 0.16 * reach, 0.08 * reach
        pivot = Rectangle((0, 0), width, height, facecolor="#606060", zorder=3, label="cart")
        ax.add_patch(pivot)
    else:
        (pivot,) = ax.plot([], [], "s", color="black", markersize=5, zorder=4, label="pivot")
    clock = ax.text(0.02, 0.96, "", transform=ax.transAxes, ha="left", va="top")
    red = mpl_colors.to_rgb(LAST_BOB_COLOUR)

    def draw(k):
        j = k * TRAIL_OVERSAMPLING
        p = points[j]
        links.set_data(p[:, 0], p[:, 1])
        bobs.set_data(p[1:, 0], p[1:, 1])
        last_bob.set_data(p[-1:, 0], p[-1:, 1])
        if chain.has_cart:
            pivot.set_xy((p[0, 0] - width / 2, p[0, 1] - height / 2))
        else:
            pivot.set_data(p[:1, 0], p[:1, 1])
        if trail > 0 and j > 0:
            first = max(0, j - int(math.floor(trail / abs(step) + 1e-9)))
            path = points[first:j + 1, -1, :]
            segments = np.stack([path[:-1], path[1:]], axis=1)
            # Each segment's age (s) at its newer end; it fades to nothing at `trail`.
            age = (j - np.arange(first + 1, j + 1)) * abs(step)
            alpha = np.clip(1.0 - age / trail, 0.0, 1.0)
            trail_line.set_segments(segments)
            trail_line.set_color([(*red, a) for a in alpha])
        else:
            trail_line.set_segments([])
        clock.set_text(f"t = {times[j]:.2f} s")
        return [trail_line, links, bobs, last_bob, pivot, clock]

    draw(0)
    return mpl_animation.FuncAnimation(fig, draw, frames=frames, interval=1000.0 / fps,
                                       blit=False, repeat=True)


def _writer(out, suffix, fps):
    """The matplotlib writer for a .gif or .mp4, or RuntimeError saying what to install."""
    if suffix == ".gif":
        if importlib.util.find_spec("PIL") is not None:  # PillowWriter's encoder
            return mpl_animation.PillowWriter(fps=fps)
        if mpl_animation.ImageMagickWriter.isAvailable():
            return mpl_animation.ImageMagickWriter(fps=fps)
        raise RuntimeError(f"out: writing '{out}' needs Pillow (Debian: apt-get install "
                           "python3-pil) or ImageMagick")
    if not mpl_animation.FFMpegWriter.isAvailable():
        raise RuntimeError(f"out: writing '{out}' needs ffmpeg (Debian: apt-get install "
                           "ffmpeg), or write a .gif")
    return mpl_animation.FFMpegWriter(fps=fps)


def _temporary_sibling(folder, stem, suffix):
    """Creates an empty file of a new name in `folder` and returns its path. It keeps the
    suffix (the writers choose the format by it) and, unlike tempfile.mkstemp's private
    0600, gets the permissions of any new file (0666 less the umask), which it keeps when
    renamed into place."""
    while True:
        partial = os.path.join(folder, f".{stem}.{secrets.token_hex(4)}.partial{suffix}")
        try:
            os.close(os.open(partial, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666))
            return partial
        except FileExistsError:
            continue


def save_animation(chain, t, X, out, *, fps=25, trail=2.0, speed=1.0, dpi=100):
    """Writes the animation of `animation(chain, t, X, ...)` to `out`: an animated GIF
    (out ending in .gif; matplotlib's PillowWriter) or an H.264 MP4 (.mp4; ffmpeg).

    X may be None with an object with attributes t and X as `t`. fps: at most 50 for a GIF
    (its frame delays are whole hundredths of a second, and players slow down delays below
    2/100 s). dpi: pixels per inch of the 6.4 x 6.4 inch figure (100: 640 x 640 pixels).

    The file is written next to `out` under a temporary name and renamed into place when
    complete, so a failure (or Ctrl-C) leaves no half-written file, and an existing `out`
    as it was. Returns out. Raises ValueError naming `out` for another suffix (and any
    other bad argument, naming it), RuntimeError when the encoder is missing."""
    path = os.fspath(out)
    name = os.path.basename(path)
    stem, suffix = os.path.splitext(name)
    suffix = suffix.lower()
    if suffix not in (".gif", ".mp4") or not stem:
        raise ValueError(f"out: '{path}' must be a file name ending in .gif or .mp4")
    fps = _positive("fps", fps)
    if suffix == ".gif" and fps > 50:
        raise ValueError(f"fps: a GIF's frame delay is whole hundredths of a second and "
                         f"players slow down delays below 2/100 s: at most 50 for a GIF, got "
                         f"{fps} (write an .mp4 for more)")
    dpi = _positive("dpi", dpi)
    writer = _writer(path, suffix, fps)
    fig, ax = plt.subplots(figsize=(6.4, 6.4))
    try:
        anim = animation(chain, t, X, fps=fps, trail=trail, speed=speed, ax=ax)
    except BaseException:
        plt.close(fig)
        raise
    folder = os.path.dirname(os.path.abspath(path))
    partial = _temporary_sibling(folder, stem, suffix)
    try:
        anim.save(partial, writer=writer, dpi=dpi)
        os.replace(partial, path)
    except BaseException:
        if os.path.exists(partial):
            os.remove(partial)
        raise
    finally:
        plt.close(fig)
    return out


# ---------------------------------------------------------------------------------------
# Figures


def trajectory(chain, t, X=None, *, ax=None):
    """The bobs' paths in the plane (lab frame, height -y up, equal scales), one line per
    bob (labelled "bob k"), the pivot's path (or the cart's) in grey where it moves, else a
    black square at the pivot. t, X as for `animation`. Returns (fig, ax); the bobs' lines
    are ax.lines[0..n-1]."""
    t, X = _trajectory_arrays(chain, t, X)
    points = lab_points(chain, t, X)
    fig, ax = _axes(ax)
    n = points.shape[1] - 1
    for k in range(1, n + 1):
        ax.plot(points[:, k, 0], -points[:, k, 1], linewidth=0.8, label=f"bob {k}")
    moving = chain.has_cart or chain.parameters["pivot"] != "fixed"
    if moving:
        ax.plot(points[:, 0, 0], -points[:, 0, 1], color="grey", linewidth=1.5,
                label="cart" if chain.has_cart else "pivot")
    else:
        ax.plot([0.0], [0.0], "s", color="black", markersize=5, label="pivot")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("height \u2212y (m)")
    ax.legend(loc="best", fontsize="small")
    return fig, ax


def _energies(chain, t, X):
    """H(x_k, t_k) (J) for each row: one call for a fixed pivot, row by row where the drive
    makes H depend on t."""
    if chain.parameters["pivot"] == "fixed":
        return np.atleast_1d(chain.hamiltonian(X))
    return np.array([chain.hamiltonian(x, float(tk)) for tk, x in zip(t, X)])


def energy_error(chain, t, X=None, *, ax=None):
    """The relative energy error |H(t) - H0| / |H0| against t on a log scale, H0 the first
    row's energy; the absolute |H - H0| (J) where H0 = 0 (the chain hanging at rest). Where
    damping or a drive change the energy, this is its change, not an error. Rows where the
    error is exactly 0 (the first) are not drawn on the log scale. t, X as for `animation`.
    Returns (fig, ax); the curve is ax.lines[0]."""
    t, X = _trajectory_arrays(chain, t, X)
    H = _energies(chain, t, X)
    fig, ax = _axes(ax)
    change = np.abs(H - H[0])
    if H[0] != 0:
        ax.plot(t, change / abs(H[0]))
        ax.set_ylabel("relative energy error |H - H$_0$| / |H$_0$|")
    else:
        ax.plot(t, change)
        ax.set_ylabel("energy error |H - H$_0$| (J)")
    ax.set_yscale("log", nonpositive="mask")
    ax.set_xlabel("t (s)")
    return fig, ax


def _coordinate(index, size, chain):
    """A coordinate of the state (an index, or a name phiK / pK) as (index, axis label)."""
    cart = chain is not None and chain.has_cart
    n = (size - 2) // 2 if cart else size // 2
    names = (["$x_c$ (m)"] if cart else []) + [axis_label(f"phi{k}") for k in range(1, n + 1)]
    names += (["$p_x$ (kg m/s)"] if cart else []) + [axis_label(f"p{k}") for k in range(1, n + 1)]
    offset = 1 if cart else 0
    if isinstance(index, str):
        match = re.fullmatch(r"(phi|p)([1-9][0-9]*)", index)
        if not match or int(match.group(2)) > n:
            raise ValueError(f"coordinate: '{index}' is not phi1..phi{n} or p1..p{n}")
        k = int(match.group(2)) - 1
        index = offset + k if match.group(1) == "phi" else size // 2 + offset + k
    index = int(index)
    if not 0 <= index < size:
        raise ValueError(f"coordinate: index {index} is outside 0..{size - 1}")
    return index, names[index]


def poincare_section(points, i, j, *, chain=None, ax=None, **scatter):
    """A Poincare section: coordinate j against coordinate i of the section's states.

    points: the states at the crossings, shape (k, 2n) (npend.poincare's "states"), or the
        poincare result itself (npend.PoincareResult).
    i, j: the coordinates, as indices into the state (0..2n-1) or names ("phi3", "p3").
    chain: needed only on a cart, for the labels of its state [x_c, phi, p_x, p].
    scatter: passed to ax.scatter (default: points of size 1).
    Returns (fig, ax); the points are ax.collections[0]."""
    if hasattr(points, "states"):
        points = points.states
    points = np.asarray(points, dtype=float)
    if points.ndim != 2:
        raise ValueError(f"points: expected shape (k, state size), got {points.shape}")
    if chain is not None and points.shape[1] != chain.state_size:
        raise ValueError(f"points: expected {chain.state_size} columns (the chain's state), "
                         f"got {points.shape[1]}")
    i, xlabel = _coordinate(i, points.shape[1], chain)
    j, ylabel = _coordinate(j, points.shape[1], chain)
    fig, ax = _axes(ax)
    scatter.setdefault("s", 1)
    ax.scatter(points[:, i], points[:, j], **scatter)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(f"Poincare section: {len(points)} points")
    return fig, ax


def spectrum(omega, power=None, *, ax=None):
    """The spectral density rho(omega) on a log scale against the angular frequency omega
    (rad/s), as npend.spectrum gives them (its result may be passed alone, as `omega`).
    Zero power is not drawn on the log scale. Returns (fig, ax); the curve is ax.lines[0]."""
    if power is None:
        if hasattr(omega, "omega") and hasattr(omega, "power"):
            omega, power = omega.omega, omega.power
        else:
            raise ValueError("power: missing (pass omega and power, or a spectrum result)")
    omega = np.asarray(omega, dtype=float)
    power = np.asarray(power, dtype=float)
    if omega.ndim != 1 or power.shape != omega.shape:
        raise ValueError(f"omega, power: expected two 1-D arrays of one length, got shapes "
                         f"{omega.shape} and {power.shape}")
    fig, ax = _axes(ax)
    ax.plot(omega, power)
    ax.set_yscale("log", nonpositive="mask")
    ax.set_xlabel(r"$\omega$ (rad/s)")
    ax.set_ylabel(r"spectral density $\rho(\omega)$")
    return fig, ax


def axis_label(name):
    """The label with units of a map axis or coordinate named as in npend.map
    (phi2, p1, dphi1, energy, m2, l1, g, k1, b1, drive-amplitude, drive-frequency)."""
    fixed = {"energy": "$E$ (J)", "g": "$g$ (m/s$^2$)", "drive-amplitude": "$a$ (m)",
             "drive-frequency": r"$\Omega$ (rad/s)"}
    if name in fixed:
        return fixed[name]
    per_link = {"phi": (r"\varphi", "rad"), "dphi": (r"\dot\varphi", "rad/s"),
                "p": ("p", "kg m$^2$/s"), "m": ("m", "kg"), "l": ("l", "m"),
                "k": ("k", "N m/rad"), "b": ("b", "N m s/rad")}
    match = re.fullmatch(r"([a-z]+)([1-9][0-9]*)", name)
    if match and match.group(1) in per_link:
        symbol, unit = per_link[match.group(1)]
        return f"${symbol}_{{{match.group(2)}}}$ ({unit})"
    return name


# Per quantity of npend.map: the colour bar's label, whether its scale is logarithmic, and
# the title (as the command line's map.png).
_QUANTITIES = {
    "flip": (r"$t_\mathrm{flip}$ (s)", True, "Time to the first flip; white: no flip"),
    "lyapunov": (r"$\lambda_1$ (1/s)", False, "Maximal Lyapunov exponent"),
    "fli": ("FLI", False, "Fast Lyapunov indicator"),
    "megno": (r"$\langle Y \rangle$", False, "MEGNO (2: regular, growing: chaotic)"),
    "sali": ("SALI", True, "SALI (0: chaotic); below 1e-16 shown as 1e-16"),
    "gali": ("GALI", True, "GALI (0: chaotic); below 1e-16 shown as 1e-16"),
    "state": (None, False, "Final state"),
}


def _map_axis(axis, count, name):
    try:
        label, start, stop, n = axis
        start, stop, n = float(start), float(stop), int(n)
    except (TypeError, ValueError):
        raise ValueError(f"{name}: expected (name, from, to, count) as given to npend.map, "
                         f"got {axis!r}") from None
    if n != count:
        raise ValueError(f"{name}: {n} values, but the map has {count} along it")
    half = (stop - start) / (n - 1) / 2 if n > 1 else 0.5
    return str(label), start - half, stop + half


def chaos_map(values, x=None, y=None, *, quantity="flip", component="phi1", ax=None,
              cmap="viridis"):
    """A chaos map as the command line's map.png: the values as an image with a colour bar,
    each cell centred on its grid point, row 0 at the first y value.

    values: npend.map's result (npend.MapResult: its axes, quantity and component are used,
        and x, y, quantity and component are not given), or an array of shape
        (y count, x count) with x and y.
    x, y: the axes as given to npend.map, (name, from, to, count); the image spans from - d/2
        to to + d/2 (d the grid step), and the axes are labelled with their units.
    quantity: npend.map's quantity (flip, lyapunov, fli, megno, sali, gali, state): the
        colour bar's label and scale (log for flip times, SALI and GALI).
    component: for quantity="state", the coordinate the values are (phi1, p2, ...).
    NaN cells (ruled out by the energy, or failed) are grey, +inf (no flip by t_end) white.
    Returns (fig, ax); the image is ax.images[0], its colour bar fig.axes[-1]."""
    if hasattr(values, "x_name"):  # a MapResult carries its axes
        result = values
        x = (result.x_name, result.x[0], result.x[-1], len(result.x))
        y = (result.y_name, result.y[0], result.y[-1], len(result.y))
        quantity = result.quantity
        component = result.options.get("component", component)
        values = result.values
    if x is None or y is None:
        raise ValueError("x, y: give the axes (name, from, to, count) with an array of values")
    if quantity not in _QUANTITIES:
        raise ValueError(f"quantity: '{quantity}' is not one of {', '.join(_QUANTITIES)}")
    values = np.asarray(values, dtype=float)
    if values.ndim != 2:
        raise ValueError(f"values: expected shape (y count, x count), got {values.shape}")
    x_name, left, right = _map_axis(x, values.shape[1], "x")
    y_name, bottom, top = _map_axis(y, values.shape[0], "y")
    label, logarithmic, title = _QUANTITIES[quantity]
    if quantity == "state":
        label = axis_label(component)
        title = f"{component} at the end"

    finite = values[np.isfinite(values)]
    if logarithmic:
        positive = finite[finite > 0]
        low = max(positive.min(), LOG_FLOOR) if positive.size else 1.0
        high = positive.max() if positive.size else 10.0
        shown = np.where(np.isfinite(values) & (values < low), low, values)
        if high <= low:
            high = low * 10
        norm = mpl_colors.LogNorm(vmin=low, vmax=high)
    else:
        low = finite.min() if finite.size else 0.0
        high = finite.max() if finite.size else 1.0
        if high <= low:
            low, high = low - 0.5, high + 0.5
        shown = values
        norm = mpl_colors.Normalize(vmin=low, vmax=high)
    # imshow takes +inf for a missing value (grey): it gets a stand-in above the colour
    # bar's top, drawn in the colour map's `over` colour, white.
    shown = np.where(np.isposinf(shown), high * 10 if logarithmic else high + (high - low), shown)
    # (matplotlib 3.6 sets the registry up at import; mypy cannot see it there)
    colours = matplotlib.colormaps[cmap].with_extremes(  # type: ignore[attr-defined]
        bad=NAN_COLOUR, over="white")
    if np.isnan(values).any():
        title += "; grey: no value (NaN)"

    fig, ax = _axes(ax)
    angles = x_name.startswith("phi") and y_name.startswith("phi")
    image = ax.imshow(shown, origin="lower", extent=(left, right, bottom, top),
                      cmap=colours, norm=norm, interpolation="nearest",
                      aspect="equal" if angles else "auto")
    if not angles:
        ax.set_box_aspect(1)
    fig.colorbar(image, ax=ax, label=label,
                 extend="max" if np.isposinf(values).any() else "neither")
    ax.set_xlabel(axis_label(x_name))
    ax.set_ylabel(axis_label(y_name))
    ax.set_title(title)
    return fig, ax
