"""The analyses that are not integrations: spectra, autocorrelation and delay vectors
against closed forms; equilibria and normal modes against the paper's formulas and the
command line."""

import inspect
import math
import pydoc

import numpy as np
import pytest

import npend
from conftest import npend_json


def test_spectrum_of_a_sine_peaks_at_its_frequency_and_keeps_parseval():
    dt, omega = 0.01, 3.0
    t = np.arange(4096) * dt
    x = 0.7 * np.sin(omega * t) + 0.2
    r = npend.spectrum(x, dt, window="none")
    assert r.omega.shape == r.power.shape == (2049,)
    assert r.resolution == pytest.approx(2 * math.pi / (4096 * dt))
    peak = r.omega[np.argmax(r.power)]
    assert abs(peak - omega) <= r.resolution
    # Parseval, rectangular window: sum rho d omega is the variance.
    assert np.sum(r.power) * r.resolution == pytest.approx(np.var(x), rel=1e-10)


def test_autocorrelation_of_a_cosine():
    dt, omega, n = 0.01, 2.0, 20000
    t = np.arange(n) * dt
    r = npend.autocorrelation(np.cos(omega * t), dt, max_lag=300, estimator="unbiased")
    assert r.lag.shape == (301,)
    assert r.value == pytest.approx(np.cos(omega * r.lag), abs=2e-3)
    assert r.first_zero == pytest.approx(math.pi / (2 * omega), rel=1e-3)
    with pytest.raises(ValueError, match="estimator"):
        npend.autocorrelation(np.cos(t), dt, estimator="fancy")


def test_embed_stacks_delayed_copies():
    x = np.arange(10.0) ** 2
    v = npend.embed(x, 3, 3)
    assert v.shape == (4, 3)
    # Row i is (x_j, x_(j-tau), x_(j-2 tau)) for j = i + 2 tau, as the paper plots x(t) against x(t - tau).
    assert np.array_equal(v, np.stack([x[6:10], x[3:7], x[0:4]], axis=1))
    d = npend.choose_delay(np.sin(np.arange(2000) * 0.01), 0.01, method="acf-zero")
    assert d.found and d.seconds == pytest.approx(math.pi / 2, abs=0.01)


def test_double_pendulum_modes_against_the_closed_form():
    g = 9.81
    r = npend.modes(npend.Chain(2, g=g))
    # Equal masses and lengths l = 1: omega^2 = g (2 -+ sqrt 2).
    assert r.omega_squared == pytest.approx([g * (2 - math.sqrt(2)), g * (2 + math.sqrt(2))],
                                               rel=1e-13)
    assert r.shapes.shape == (2, 2)
    ref = npend_json("modes", "--links", 2)
    assert np.array_equal(r.frequencies, ref["frequencies"])


def test_equilibria_of_the_double_pendulum():
    m1 = m2 = l1 = l2 = 1.0
    g = 9.81
    found = npend.equilibria(npend.Chain(2))
    assert [list(e.angles) for e in found] == [[0, 0], [0, math.pi], [math.pi, 0],
                                                   [math.pi, math.pi]]
    assert [e.stable for e in found] == [True, False, False, False]
    assert [e.unstable_directions for e in found] == [0, 1, 1, 2]
    # Standing (pi, pi): kappa^2 = g/(2 sqrt(l1 l2)) [M L +- sqrt(M^2 L^2 - 4 M)], M = 1 + m2/m1,
    # L = (l1 + l2)/sqrt(l1 l2) (the paper's 6.5.1).
    big_m, big_l = 1 + m2 / m1, (l1 + l2) / math.sqrt(l1 * l2)
    root = math.sqrt(big_m**2 * big_l**2 - 4 * big_m)
    kappa = sorted(math.sqrt(g / (2 * math.sqrt(l1 * l2)) * (big_m * big_l + s * root))
                   for s in (1, -1))
    standing = found[3].eigenvalues
    assert standing.dtype == np.complex128
    assert sorted(v.real for v in standing if v.real > 0) == pytest.approx(kappa, rel=1e-12)
    assert found[3].energy == pytest.approx(2 * (m1 + m2) * g * l1 + 2 * m2 * g * l2)


def test_results_are_classes_with_attributes():
    dt = 0.01
    x = np.sin(np.arange(2000) * dt)
    s = npend.spectrum(x, dt)
    a = npend.autocorrelation(x, dt, max_lag=10)
    d = npend.choose_delay(x, dt, method="T/4")
    m = npend.modes(npend.Chain(3))
    e = npend.equilibria(npend.Chain(1))
    assert isinstance(s, npend.results.SpectrumResult) and s.power.dtype == np.float64
    assert isinstance(a, npend.results.AutocorrelationResult) and a.first_zero is None
    assert isinstance(d, npend.results.DelayResult) and d.samples * dt == pytest.approx(d.seconds)
    assert isinstance(m, npend.results.ModesResult) and m.mass_matrix.shape == (3, 3)
    assert [type(q).__name__ for q in e] == ["Equilibrium", "Equilibrium"]
    # The repr shows the scalars and summarises the arrays.
    assert repr(d) == (f"DelayResult(found={d.found!r}, method={d.method!r}, "
                       f"samples={d.samples!r}, seconds={d.seconds!r})")
    assert "power=array(shape=(1001,), dtype=float64)" in repr(s)
    assert "first_zero=None" in repr(a)
    with pytest.raises(AttributeError):
        d.seconds = 1.0


def test_every_function_has_a_signature_and_a_numpy_docstring():
    for name in npend.__all__:
        if name in ("Chain", "Event", "IntegrationError", "Solution", "__version__"):
            continue  # classes and data (Chain has its own test, Event its doctest)
        f = getattr(npend, name)
        signature = inspect.signature(f)
        assert signature.return_annotation is not inspect.Signature.empty, name
        assert all(p.annotation is not inspect.Parameter.empty
                   for p in signature.parameters.values()), name
        for section in ("Returns\n    -------", "Examples\n    --------"):
            assert section in f.__doc__, (name, section)
        if signature.parameters:
            assert "Parameters\n    ----------" in f.__doc__, name
    shown = pydoc.render_doc(npend.poincare, renderer=pydoc.plaintext)
    assert "poincare(chain: 'Chain', x0: 'ArrayLike'" in shown


def test_integration_error_is_a_documented_runtime_error():
    assert issubclass(npend.IntegrationError, RuntimeError)
    assert "RuntimeError" in npend.IntegrationError.__doc__
    assert "time" in npend.IntegrationError.__doc__
