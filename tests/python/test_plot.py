"""npend.plot: the animations and figures carry the chain's numbers, computed here
independently (the bobs' positions and H from their closed forms); GIF and MP4 files have
the expected frames; a failure leaves no file behind."""

import math
import os
import shutil
import subprocess
import sys
import tempfile

import numpy as np
import pytest

# The tests draw off screen, with matplotlib's settings and caches in a scratch folder.
os.environ.setdefault("MPLCONFIGDIR", tempfile.mkdtemp(prefix="npend-mpl-"))
matplotlib = pytest.importorskip("matplotlib")
matplotlib.use("Agg")
import matplotlib.animation  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402

import npend  # noqa: E402
import npend.plot  # noqa: E402

G = 9.81

# The tests draw animation frames one by one, which matplotlib does not count as rendering.
pytestmark = pytest.mark.filterwarnings("ignore:Animation was deleted without rendering")


@pytest.fixture(autouse=True)
def close_figures():
    yield
    plt.close("all")


class Solution:
    """A simulation's result as an object with attributes t and X."""

    def __init__(self, t, X):
        self.t, self.X = t, X


def double_pendulum_points(X, lengths=(1.0, 1.0)):
    """The double pendulum's pivot and bobs (x, height up) from the angles, shape (N, 3, 2)."""
    l1, l2 = lengths
    x1, h1 = l1 * np.sin(X[:, 0]), -l1 * np.cos(X[:, 0])
    x2, h2 = x1 + l2 * np.sin(X[:, 1]), h1 - l2 * np.cos(X[:, 1])
    zero = np.zeros(len(X))
    return np.stack([np.stack([zero, zero], 1), np.stack([x1, h1], 1),
                     np.stack([x2, h2], 1)], axis=1)


def artist(ax, label):
    """The animation's artist of that label."""
    (found,) = [a for a in ax.get_children() if a.get_label() == label]
    return found


def drawn_frame(anim, k):
    """Draws frame k and returns the links' points (x, height)."""
    anim._draw_frame(k)
    return np.column_stack(artist(anim._fig.axes[0], "links").get_data())


def pendulum_energy(X, m=1.0, length=1.0):
    """The single pendulum's H = p^2 / (2 m l^2) + m g l (1 - cos phi)."""
    return X[:, 1] ** 2 / (2 * m * length**2) + m * G * length * (1 - np.cos(X[:, 0]))


def test_import_npend_leaves_matplotlib_out():
    """npend: importing the package does not import matplotlib (npend.plot is separate)."""
    code = "import sys, npend; sys.exit('matplotlib' in sys.modules)"
    result = subprocess.run([sys.executable, "-c", code], env=dict(os.environ))
    assert result.returncode == 0


def test_animation_draws_the_chain_at_the_frame_times():
    """animation: frame k shows the double pendulum at t = k speed/fps, its links where the
    closed form puts them, one frame per 1/fps of playback up to the end."""
    chain = npend.Chain(2)
    t, X = npend.simulate(chain, [1.0, 2.0, 0.0, 0.0], t_end=1.0, dt=1e-3)
    for speed in (1.0, 0.5):
        anim = npend.plot.animation(chain, t, X, fps=10, speed=speed)
        frames = list(anim.new_frame_seq())
        expected = math.floor(1.0 * 10 / speed) + 1
        assert len(frames) == expected
        ax = anim._fig.axes[0]
        for k in (0, 3, expected - 1):
            row = int(round(k * speed / 10 / 1e-3))  # the frame falls on this row
            want = double_pendulum_points(X[row:row + 1])[0]
            np.testing.assert_allclose(drawn_frame(anim, k), want, atol=1e-9)
            assert ax.texts[0].get_text() == f"t = {k * speed / 10:.2f} s"
        reach = 1.08 * 2.0
        assert ax.get_xlim() == pytest.approx((-reach, reach))
        assert ax.get_ylim() == pytest.approx((-reach, reach))
        assert ax.get_aspect() == 1.0


def test_animation_plays_in_jupyter():
    """animation: to_jshtml (what Jupyter shows) embeds one image per frame, also after
    plt.close() took the figure from pyplot (so that the inline backend shows no still)."""
    import re

    chain = npend.Chain(2)
    t, X = npend.simulate(chain, [1.0, 2.0, 0.0, 0.0], t_end=0.5)
    anim = npend.plot.animation(chain, t, X, fps=10)
    plt.close()
    html = anim.to_jshtml()
    assert len(re.findall(r"frames\[\d+\] = ", html)) == 6


def test_animation_interpolates_between_rows():
    """animation: a frame between two rows shows the state interpolated linearly between
    them (a coarse trajectory of two rows, 1 s apart, at 4 frames per second)."""
    chain = npend.Chain(2)
    t = np.array([0.0, 1.0])
    X = np.array([[0.2, -0.4, 0.0, 0.0], [1.0, 0.6, 0.0, 0.0]])
    anim = npend.plot.animation(chain, t, X, fps=4)
    assert len(list(anim.new_frame_seq())) == 5
    for k in range(5):
        state = X[0] + (X[1] - X[0]) * k / 4
        want = double_pendulum_points(state[None, :])[0]
        np.testing.assert_allclose(drawn_frame(anim, k), want, atol=1e-12)


def test_animation_takes_a_solution_object():
    """animation: an object with attributes t and X draws as its arrays do."""
    chain = npend.Chain(2)
    t, X = npend.simulate(chain, [1.0, 2.0, 0.0, 0.0], t_end=0.5)
    a = npend.plot.animation(chain, t, X, fps=10)
    b = npend.plot.animation(chain, Solution(t, X), fps=10)
    for k in range(6):
        np.testing.assert_array_equal(drawn_frame(a, k), drawn_frame(b, k))


def test_animation_trail_fades_over_its_seconds():
    """animation: the last bob's trail ends at the bob, reaches `trail` seconds back (4
    samples a frame) and fades from opaque to transparent with age."""
    chain = npend.Chain(2)
    t, X = npend.simulate(chain, [1.0, 2.0, 0.0, 0.0], t_end=2.0)
    anim = npend.plot.animation(chain, t, X, fps=10, trail=0.5)
    points = drawn_frame(anim, 15)  # t = 1.5 s
    trail = artist(anim._fig.axes[0], "trail")
    segments = trail.get_segments()
    assert len(segments) == 0.5 * 10 * 4
    np.testing.assert_allclose(segments[-1][1], points[-1], atol=1e-12)
    oldest = double_pendulum_points(X[1000:1001])[0, -1]  # the bob at t = 1.0 s
    np.testing.assert_allclose(segments[0][0], oldest, atol=1e-9)
    alpha = trail.get_colors()[:, 3]
    assert alpha[-1] == pytest.approx(1.0)
    assert np.all(np.diff(alpha) > 0)
    no_trail = npend.plot.animation(chain, t, X, fps=10, trail=0)
    no_trail._draw_frame(15)
    assert len(artist(no_trail._fig.axes[0], "trail").get_segments()) == 0


def test_animation_moves_the_pivot_with_its_drive():
    """animation: a vertically driven pivot is drawn at height a cos(Omega t), the chain
    hanging from it; the view reaches the chain's length plus a."""
    amplitude, omega = 0.2, 15.0
    chain = npend.Chain(2, pivot=f"vertical:{amplitude}:{omega}")
    t, X = npend.simulate(chain, [0.5, 0.3, 0.0, 0.0], t_end=0.5)
    anim = npend.plot.animation(chain, t, X, fps=20)
    for k in (0, 3, 7):
        tk = k / 20
        row = int(round(tk / 1e-3))
        lift = np.array([0.0, amplitude * math.cos(omega * tk)])
        want = double_pendulum_points(X[row:row + 1])[0] + lift
        np.testing.assert_allclose(drawn_frame(anim, k), want, atol=1e-9)
        pivot = np.column_stack(artist(anim._fig.axes[0], "pivot").get_data())
        np.testing.assert_allclose(pivot, [lift], atol=1e-12)
    assert anim._fig.axes[0].get_ylim()[1] == pytest.approx(1.08 * (2.0 + amplitude))


def test_animation_draws_the_cart_where_it_rolls():
    """animation: on a cart the cart (a rectangle) is centred on x_c, the chain hangs from
    it, and the view follows the cart's range."""
    chain = npend.Chain(1, cart=1.0)
    t, X = npend.simulate(chain, [0.0, 1.0, 0.5, 0.0], t_end=1.0)
    anim = npend.plot.animation(chain, t, X, fps=10)
    ax = anim._fig.axes[0]
    cart = artist(ax, "cart")
    for k in (0, 5, 10):
        row = int(round(k / 10 / 1e-3))
        xc, phi = X[row, 0], X[row, 1]
        want = [[xc, 0.0], [xc + math.sin(phi), -math.cos(phi)]]
        np.testing.assert_allclose(drawn_frame(anim, k), want, atol=1e-9)
        centre = cart.get_x() + cart.get_width() / 2
        assert centre == pytest.approx(xc, abs=1e-9)
    assert ax.get_xlim() == pytest.approx((X[:, 0].min() - 1.08, X[:, 0].max() + 1.08))


def test_animation_refuses_bad_arguments():
    """animation: bad arguments raise ValueError naming them."""
    chain = npend.Chain(2)
    t, X = npend.simulate(chain, [1.0, 2.0, 0.0, 0.0], t_end=0.1)
    with pytest.raises(ValueError, match="^X: expected shape"):
        npend.plot.animation(chain, t, X[:, :3])
    with pytest.raises(ValueError, match="^X: expected shape"):
        npend.plot.animation(chain, t[:-1], X)
    with pytest.raises(ValueError, match="^fps:"):
        npend.plot.animation(chain, t, X, fps=0)
    with pytest.raises(ValueError, match="^trail:"):
        npend.plot.animation(chain, t, X, trail=-1)
    with pytest.raises(ValueError, match="^speed:"):
        npend.plot.animation(chain, t, X, speed=float("nan"))
    with pytest.raises(ValueError, match="^X: missing"):
        npend.plot.animation(chain, t)


def gif_frames(path):
    from PIL import Image

    with Image.open(path) as image:
        return image.n_frames


def test_save_animation_writes_a_gif_of_every_frame(tmp_path):
    """save_animation: a GIF of 1.2 s at 10 frames per second has 13 frames; nothing but
    the file is left in its folder."""
    pytest.importorskip("PIL")
    chain = npend.Chain(2)
    t, X = npend.simulate(chain, [1.0, 2.0, 0.0, 0.0], t_end=1.2)
    out = tmp_path / "double.gif"
    npend.plot.save_animation(chain, Solution(t, X), None, out, fps=10, dpi=20)
    assert gif_frames(out) == 13
    assert os.listdir(tmp_path) == ["double.gif"]
    umask = os.umask(0o022)
    os.umask(umask)
    assert os.stat(out).st_mode & 0o777 == 0o666 & ~umask  # as any new file


@pytest.mark.skipif(shutil.which("ffmpeg") is None or shutil.which("ffprobe") is None,
                    reason="ffmpeg is not installed")
def test_save_animation_writes_an_mp4(tmp_path):
    """save_animation: an MP4 of 1 s at 20 frames per second has 21 frames (ffprobe)."""
    chain = npend.Chain(2)
    t, X = npend.simulate(chain, [1.0, 2.0, 0.0, 0.0], t_end=1.0)
    out = tmp_path / "double.MP4"
    npend.plot.save_animation(chain, t, X, str(out), fps=20, dpi=30)
    probe = subprocess.run(
        ["ffprobe", "-v", "error", "-count_frames", "-select_streams", "v:0",
         "-show_entries", "stream=nb_read_frames", "-of", "csv=p=0", str(out)],
        capture_output=True, text=True, check=True)
    assert int(probe.stdout.strip()) == 21
    assert os.listdir(tmp_path) == ["double.MP4"]


def test_save_animation_refuses_other_suffixes(tmp_path):
    """save_animation: an output that is not .gif or .mp4 raises ValueError naming it, and
    writes nothing."""
    chain = npend.Chain(2)
    t, X = npend.simulate(chain, [1.0, 2.0, 0.0, 0.0], t_end=0.2)
    for name in ("double.png", "double", ".gif"):
        out = str(tmp_path / name)
        with pytest.raises(ValueError, match=f"^out: '{out}' must be a file name ending in"):
            npend.plot.save_animation(chain, t, X, out)
    with pytest.raises(ValueError, match="^fps: a GIF"):
        npend.plot.save_animation(chain, t, X, tmp_path / "fast.gif", fps=60)
    assert os.listdir(tmp_path) == []


def test_save_animation_leaves_nothing_after_a_failure(tmp_path, monkeypatch):
    """save_animation: a writer failing at the third frame leaves no new file and no
    temporary one, and an existing file as it was."""
    pytest.importorskip("PIL")
    chain = npend.Chain(2)
    t, X = npend.simulate(chain, [1.0, 2.0, 0.0, 0.0], t_end=1.0)
    grab = matplotlib.animation.PillowWriter.grab_frame
    grabbed = []

    def failing_grab(self, **kwargs):
        grabbed.append(1)
        if len(grabbed) == 3:
            raise OSError("disk full")
        return grab(self, **kwargs)

    monkeypatch.setattr(matplotlib.animation.PillowWriter, "grab_frame", failing_grab)
    with pytest.raises(OSError, match="disk full"):
        npend.plot.save_animation(chain, t, X, tmp_path / "new.gif", fps=10, dpi=20)
    assert os.listdir(tmp_path) == []
    old = tmp_path / "old.gif"
    old.write_bytes(b"the previous animation")
    grabbed.clear()
    with pytest.raises(OSError, match="disk full"):
        npend.plot.save_animation(chain, t, X, old, fps=10, dpi=20)
    assert os.listdir(tmp_path) == ["old.gif"]
    assert old.read_bytes() == b"the previous animation"


def test_trajectory_draws_the_bobs_paths():
    """trajectory: one line per bob along its closed-form path (height up), the pivot
    marked, axes in m with equal scales; a Solution object draws the same."""
    chain = npend.Chain(2)
    t, X = npend.simulate(chain, [1.0, 2.0, 0.0, 0.0], t_end=2.0)
    fig, ax = npend.plot.trajectory(chain, t, X)
    want = double_pendulum_points(X)
    for k in (1, 2):
        np.testing.assert_allclose(np.column_stack(ax.lines[k - 1].get_data()), want[:, k],
                                   atol=1e-12)
        assert ax.lines[k - 1].get_label() == f"bob {k}"
    assert ax.lines[2].get_label() == "pivot"
    assert ax.get_xlabel() == "x (m)" and ax.get_ylabel().endswith("(m)")
    assert ax.get_aspect() == 1.0
    _, other = plt.subplots()
    fig2, ax2 = npend.plot.trajectory(chain, Solution(t, X), ax=other)
    assert ax2 is other and fig2 is other.figure
    np.testing.assert_array_equal(ax2.lines[1].get_xydata(), ax.lines[1].get_xydata())


def test_trajectory_follows_a_horizontal_drive():
    """trajectory: with a horizontally driven pivot the paths are in the lab frame and the
    pivot's path x = a cos(Omega t) is drawn."""
    amplitude, omega = 0.1, 10.0
    chain = npend.Chain(1, pivot=f"horizontal:{amplitude}:{omega}")
    t, X = npend.simulate(chain, [0.3, 0.0], t_end=1.0)
    _, ax = npend.plot.trajectory(chain, t, X)
    drive = amplitude * np.cos(omega * t)
    np.testing.assert_allclose(ax.lines[0].get_xdata(), drive + np.sin(X[:, 0]), atol=1e-12)
    np.testing.assert_allclose(ax.lines[0].get_ydata(), -np.cos(X[:, 0]), atol=1e-12)
    np.testing.assert_allclose(ax.lines[1].get_xdata(), drive, atol=1e-12)
    assert ax.lines[1].get_label() == "pivot"


def test_energy_error_plots_the_relative_change_of_h():
    """energy_error: the curve is |H - H0| / |H0| from the single pendulum's closed-form H,
    against t, on a log scale."""
    chain = npend.Chain(1)
    t, X = npend.simulate(chain, [2.0, 0.0], t_end=5.0, dt=0.01, stepper="rk4")
    H = pendulum_energy(X)
    want = np.abs(H - H[0]) / abs(H[0])
    assert want.max() > 1e-9  # rk4 at this step drifts measurably
    fig, ax = npend.plot.energy_error(chain, t, X)
    np.testing.assert_array_equal(ax.lines[0].get_xdata(), t)
    np.testing.assert_allclose(ax.lines[0].get_ydata(), want, rtol=1e-6, atol=1e-15)
    assert ax.get_yscale() == "log"
    assert ax.get_xlabel() == "t (s)" and "relative" in ax.get_ylabel()
    _, ax2 = npend.plot.energy_error(chain, Solution(t, X))
    np.testing.assert_array_equal(ax2.lines[0].get_ydata(), ax.lines[0].get_ydata())


def test_energy_error_is_absolute_from_zero_energy():
    """energy_error: from H0 = 0 (the chain at rest hanging) the curve is |H - H0| in J."""
    chain = npend.Chain(1)
    t = np.array([0.0, 1.0, 2.0])
    X = np.array([[0.0, 0.0], [0.1, 0.0], [0.0, 0.2]])
    _, ax = npend.plot.energy_error(chain, t, X)
    np.testing.assert_allclose(ax.lines[0].get_ydata(), pendulum_energy(X), rtol=1e-12)
    assert ax.get_ylabel().endswith("(J)")


def test_energy_error_takes_the_drive_time():
    """energy_error: under a vertical drive H depends on t, row by row: a pendulum held at
    rest at phi has H = m (g - a_y(t)) l (1 - cos phi), a_y = A Omega^2 cos(Omega t) the
    pivot's downward acceleration (the pivot-frame energy of docs/model.md)."""
    amplitude, omega, phi = 0.1, 2.0, 0.4
    chain = npend.Chain(1, pivot=f"vertical:{amplitude}:{omega}")
    t = np.array([0.0, 1.0, 2.5])
    X = np.array([[phi, 0.0]] * 3)
    H = (G - amplitude * omega**2 * np.cos(omega * t)) * (1 - math.cos(phi))
    _, ax = npend.plot.energy_error(chain, t, X)
    np.testing.assert_allclose(ax.lines[0].get_ydata(), np.abs(H - H[0]) / abs(H[0]),
                               rtol=1e-12)


def test_poincare_section_scatters_two_coordinates():
    """poincare_section: the points are the chosen columns of the section's states, by index
    or name, labelled with their units; the poincare result itself is taken."""
    chain = npend.Chain(3)
    x0 = npend.deflected_state(chain, npend.energy_from_epsilon(chain, 0.5), [1, -1, 1])
    section = npend.poincare(chain, x0, "phi1=0", 30.0)
    states = section.states
    assert len(states) > 5
    _, ax = npend.plot.poincare_section(states, 2, 5)
    np.testing.assert_array_equal(ax.collections[0].get_offsets(), states[:, [2, 5]])
    assert "varphi_{3}" in ax.get_xlabel() and ax.get_xlabel().endswith("(rad)")
    assert "p_{3}" in ax.get_ylabel() and "kg m" in ax.get_ylabel()
    _, by_name = npend.plot.poincare_section(section, "phi3", "p3")
    np.testing.assert_array_equal(by_name.collections[0].get_offsets(), states[:, [2, 5]])
    cart = npend.Chain(2, cart=1.0)
    _, on_cart = npend.plot.poincare_section(np.zeros((4, 6)), "p2", 0, chain=cart)
    assert "p_{2}" in on_cart.get_xlabel() and on_cart.get_ylabel() == "$x_c$ (m)"
    with pytest.raises(ValueError, match="^coordinate:"):
        npend.plot.poincare_section(states, 0, 6)
    with pytest.raises(ValueError, match="^coordinate:"):
        npend.plot.poincare_section(states, "phi4", "p1")


def test_spectrum_plots_log_power_against_omega():
    """spectrum: the curve is npend.spectrum's power against omega (rad/s), log scale;
    its result passed alone draws the same."""
    dt = 0.01
    x = np.sin(3.0 * np.arange(4096) * dt)
    s = npend.spectrum(x, dt)
    _, ax = npend.plot.spectrum(s.omega, s.power)
    np.testing.assert_array_equal(ax.lines[0].get_xdata(), s.omega)
    np.testing.assert_array_equal(ax.lines[0].get_ydata(), s.power)
    assert ax.get_yscale() == "log" and ax.get_xlabel().endswith("(rad/s)")
    omega_peak = ax.lines[0].get_xdata()[np.argmax(ax.lines[0].get_ydata())]
    assert omega_peak == pytest.approx(3.0, abs=s.resolution)
    _, alone = npend.plot.spectrum(s)
    np.testing.assert_array_equal(alone.lines[0].get_ydata(), s.power)


def pixel(fig, ax, x, y):
    """The RGB colour drawn at data point (x, y)."""
    fig.canvas.draw()
    buffer = np.asarray(fig.canvas.buffer_rgba())
    px, py = ax.transData.transform((x, y))
    return tuple(buffer[buffer.shape[0] - 1 - int(py), int(px), :3])


def test_chaos_map_draws_the_grid_with_its_extents():
    """chaos_map: the double pendulum's flip map, each cell centred on its grid point, NaN
    exactly where 2 cos phi1 + cos phi2 > 1 (no flip possible) drawn grey, the flip times
    on a log colour bar, axes labelled in rad."""
    chain = npend.Chain(2)
    x, y = ("phi1", -3.0, 3.0, 13), ("phi2", -2.0, 2.0, 9)
    result = npend.map(chain, x, y, t_end=3.0)
    values = result.values
    phi1, phi2 = np.meshgrid(np.linspace(-3, 3, 13), np.linspace(-2, 2, 9))
    forbidden = 2 * np.cos(phi1) + np.cos(phi2) > 1
    np.testing.assert_array_equal(np.isnan(values), forbidden)
    fig, ax = npend.plot.chaos_map(values, x, y, quantity="flip")
    image = ax.images[0]
    assert image.get_extent() == pytest.approx([-3.25, 3.25, -2.25, 2.25])
    assert image.origin == "lower"
    shown = image.get_array()
    finite = np.isfinite(values)
    np.testing.assert_array_equal(shown[finite], values[finite])
    assert isinstance(image.norm, matplotlib.colors.LogNorm)
    assert ax.get_xlabel() == r"$\varphi_{1}$ (rad)" and ax.get_ylabel() == r"$\varphi_{2}$ (rad)"
    assert fig.axes[-1].get_ylabel() == r"$t_\mathrm{flip}$ (s)"
    grey = (0xa0, 0xa0, 0xa0)
    for i, j in zip(*np.nonzero(forbidden)):
        assert pixel(fig, ax, phi1[i, j], phi2[i, j]) == grey
    for i, j in zip(*np.nonzero(finite)):
        assert pixel(fig, ax, phi1[i, j], phi2[i, j]) != grey
    # The map's result alone carries its axes and quantity.
    _, alone = npend.plot.chaos_map(result)
    assert alone.images[0].get_extent() == pytest.approx([-3.25, 3.25, -2.25, 2.25])
    assert alone.get_xlabel() == ax.get_xlabel()


def test_chaos_map_shows_no_flip_white_and_names_units():
    """chaos_map: +inf cells (no flip by t_end) are white; parameter axes carry their units;
    a linear quantity has a linear colour bar; the counts must match the values."""
    values = np.array([[1.0, np.inf, 4.0], [np.nan, 2.0, np.inf]])
    x, y = ("energy", 0.0, 10.0, 3), ("m2", 0.5, 1.5, 2)
    fig, ax = npend.plot.chaos_map(values, x, y)
    assert ax.images[0].get_extent() == pytest.approx([-2.5, 12.5, 0.0, 2.0])
    assert pixel(fig, ax, 5.0, 0.5) == (255, 255, 255)
    assert pixel(fig, ax, 10.0, 1.5) == (255, 255, 255)
    assert pixel(fig, ax, 0.0, 1.5) == (0xa0, 0xa0, 0xa0)
    assert ax.get_xlabel() == "$E$ (J)" and ax.get_ylabel() == "$m_{2}$ (kg)"
    _, lyap = npend.plot.chaos_map(values, x, y, quantity="lyapunov")
    assert type(lyap.images[0].norm) is matplotlib.colors.Normalize
    _, state = npend.plot.chaos_map(values, x, y, quantity="state", component="p2")
    assert state.figure.axes[-1].get_ylabel() == "$p_{2}$ (kg m$^2$/s)"
    with pytest.raises(ValueError, match="^x: 4 values, but the map has 3"):
        npend.plot.chaos_map(values, ("energy", 0, 1, 4), y)
    with pytest.raises(ValueError, match="^quantity:"):
        npend.plot.chaos_map(values, x, y, quantity="entropy")
