#!/usr/bin/env python3
"""npend from Python against what a SciPy user would write, side by side in one run.

1. One trajectory of the triple pendulum (regular start, t = 10 s): npend.simulate (taylor,
   rkf78) against scipy.integrate.solve_ivp(DOP853) on npend's own right-hand side
   (`chain.fun`) and on a hand-written NumPy right-hand side, over a sweep of tolerances.
   Each run's final-state error is measured against a tight reference (npend taylor at
   1e-15 cross-checked by DOP853 at 1e-14); the ratio is taken at equal error by log-log
   interpolation of npend's time over its sweep.
2. A flip-time map of the equal double pendulum, one thread: npend.map (rk4 lanes) against
   the same rk4 at the same dt vectorised over the cells in NumPy (the double pendulum's
   equations written out, its 2 x 2 mass matrix inverted in closed form, a cell dropped once
   it flips), the flip located by
   linear interpolation in the step (npend locates it with the step's cubic). The cells the
   energy rules out are skipped by both.

Wall times are medians of 7 runs (--quick: 3); the full-size NumPy map runs once. Prints a
Markdown section (or JSON with --json).
Run with PYTHONPATH at the build tree's python folder (bench/run does).
"""
import argparse
import json
import math
import os
import statistics
import subprocess
import sys
import time

import numpy as np
from scipy.integrate import solve_ivp

import npend


def median_time(fn, repeat):
    times, value = [], None
    for _ in range(repeat):
        start = time.perf_counter()
        value = fn()
        times.append(time.perf_counter() - start)
    return statistics.median(times), value


def numpy_rhs(masses, lengths, g):
    """Hamilton's equations of the point-mass chain, written out in NumPy:
    M_ij = mu_ij l_i l_j cos(phi_i - phi_j), mu_ij = sum_{k >= max(i, j)} m_k, omega = M^-1 p,
    dp_k/dt = -omega_k sum_j mu_kj l_k l_j sin(phi_k - phi_j) omega_j - g mu_kk l_k sin phi_k.
    Works on one state (2n,) or on columns (2n, K)."""
    m = np.asarray(masses, float)
    l = np.asarray(lengths, float)
    n = len(m)
    tail = np.cumsum(m[::-1])[::-1]
    mu = tail[np.maximum.outer(np.arange(n), np.arange(n))]
    ll = np.outer(l, l) * mu

    def rhs(t, y):
        phi, p = y[:n], y[n:]
        d = phi[:, None] - phi[None, :]
        if y.ndim == 1:
            omega = np.linalg.solve(ll * np.cos(d), p)
            dp = -omega * ((ll * np.sin(d)) @ omega) - g * tail * l * np.sin(phi)
            return np.concatenate([omega, dp])
        # columns: move the cell axis first for the batched solve
        a = np.moveaxis(ll[:, :, None] * np.cos(d), 2, 0)
        omega = np.linalg.solve(a, p.T[:, :, None])[:, :, 0].T
        s = ll[:, :, None] * np.sin(d)
        dp = -omega * np.einsum("ijk,jk->ik", s, omega) - g * (tail * l)[:, None] * np.sin(phi)
        return np.concatenate([omega, dp])

    return rhs


def double_pendulum_rhs(g):
    """The equal double pendulum (m = l = 1) over columns of states, with the 2 x 2 mass
    matrix inverted in closed form: what a NumPy user writes for a map, no batched solve.
    M = [[2, c], [c, 1]], c = cos(phi1 - phi2); omega = M^-1 p;
    dp1/dt = -omega1 omega2 sin(phi1 - phi2) - 2 g sin phi1,
    dp2/dt = +omega1 omega2 sin(phi1 - phi2) - g sin phi2."""

    def rhs(t, y):
        phi1, phi2, p1, p2 = y
        d = phi1 - phi2
        c, s = np.cos(d), np.sin(d)
        det = 2.0 - c * c
        w1 = (p1 - c * p2) / det
        w2 = (2.0 * p2 - c * p1) / det
        coupling = w1 * w2 * s
        return np.stack([w1, w2, -coupling - 2 * g * np.sin(phi1), coupling - g * np.sin(phi2)])

    return rhs


def interpolated_time(points, error):
    """npend's wall time at `error`, log-log interpolated over its (time, error) sweep; None
    outside the sweep."""
    pts = sorted((e, t) for t, e in points if e > 0)
    for (e0, t0), (e1, t1) in zip(pts, pts[1:]):
        if e0 <= error <= e1:
            w = (math.log(error) - math.log(e0)) / (math.log(e1) - math.log(e0))
            return math.exp(math.log(t0) + w * (math.log(t1) - math.log(t0)))
    return None


def trajectory_peers(repeat, tolerances, npend_tolerances):
    chain = npend.Chain(3)
    x0 = np.array([0.3, 0.3, 0.3, 0.0, 0.0, 0.0])
    t_end = 10.0
    reference = npend.simulate(chain, x0, t_end=t_end, dt=t_end, stepper="taylor", atol=1e-15,
                               rtol=1e-15).X[-1]
    check = solve_ivp(chain.fun, (0, t_end), x0, method="DOP853", rtol=3e-14, atol=1e-14).y[:, -1]
    rhs = numpy_rhs([1, 1, 1], [1, 1, 1], 9.81)
    rows = {"reference_check": float(np.max(np.abs(check - reference)))}
    runs = {}

    def record(name, tol, fn):
        seconds, final = median_time(fn, repeat)
        runs.setdefault(name, []).append(
            {"tol": tol, "seconds": seconds, "error": float(np.max(np.abs(final - reference)))})

    for tol in npend_tolerances:
        for stepper in ("taylor", "rkf78"):
            record(f"npend {stepper}", tol, lambda: npend.simulate(
                chain, x0, t_end=t_end, dt=t_end if stepper == "taylor" else 0.1,
                stepper=stepper, atol=tol, rtol=tol).X[-1])
    for tol in tolerances:
        record("solve_ivp DOP853, chain.fun", tol, lambda: solve_ivp(
            chain.fun, (0, t_end), x0, method="DOP853", rtol=tol, atol=tol).y[:, -1])
        record("solve_ivp DOP853, NumPy rhs", tol, lambda: solve_ivp(
            rhs, (0, t_end), x0, method="DOP853", rtol=tol, atol=tol).y[:, -1])
    # npend's best time at each error: the lower envelope of its two steppers
    for name in ("solve_ivp DOP853, chain.fun", "solve_ivp DOP853, NumPy rhs"):
        for r in runs[name]:
            times = [interpolated_time([(s, e) for s, e in
                                        [(x["seconds"], x["error"]) for x in runs[k]]], r["error"])
                     for k in ("npend taylor", "npend rkf78")]
            times = [t for t in times if t is not None]
            r["npend_speedup"] = r["seconds"] / min(times) if times else None
    rows["runs"] = runs
    return rows


def numpy_flip_map(count, t_end, dt):
    """Flip times of the equal double pendulum from rest at (phi1, phi2) on the grid, by RK4
    in NumPy vectorised over the cells; NaN where the energy forbids a flip, inf where none."""
    axis = np.linspace(-3.0, 3.0, count)
    phi1, phi2 = np.meshgrid(axis, axis)
    # The energy of a start at rest allows a flip only where 2 cos phi1 + cos phi2 <= 1
    allowed = 2 * np.cos(phi1) + np.cos(phi2) <= 1
    result = np.full(phi1.shape, np.nan)
    y = np.stack([phi1[allowed], phi2[allowed], np.zeros(allowed.sum()), np.zeros(allowed.sum())])
    flip = np.full(y.shape[1], np.inf)
    active = np.arange(y.shape[1])  # the cells still integrated: a flipped cell is dropped
    rhs = double_pendulum_rhs(9.81)
    steps = int(round(t_end / dt))
    for k in range(steps):
        if active.size == 0:
            break
        k1 = rhs(0, y)
        k2 = rhs(0, y + 0.5 * dt * k1)
        k3 = rhs(0, y + 0.5 * dt * k2)
        k4 = rhs(0, y + dt * k3)
        new = y + dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        over = np.max(np.abs(new[:2]), axis=0) > np.pi
        if over.any():
            before = np.max(np.abs(y[:2, over]), axis=0)
            after = np.max(np.abs(new[:2, over]), axis=0)
            flip[active[over]] = (k + (np.pi - before) / (after - before)) * dt
            new, active = new[:, ~over], active[~over]
        y = new
    result[allowed] = flip
    return result


LANE_ISAS = ("sse2", "avx2", "avx512f")


def npend_flip_map(count, t_end, dt):
    return np.asarray(npend.map(npend.Chain(2), x=("phi1", -3.0, 3.0, count),
                                y=("phi2", -3.0, 3.0, count), quantity="flip", t_end=t_end,
                                dt=dt, stepper="rk4", threads=1))


def npend_map_seconds_on(isa, repeat, count, t_end, dt):
    """npend.map's median time with its lanes on `isa` (NPEND_LANE_ISA, read once per
    process: a child process of this script), or None where this build or CPU lacks it."""
    env = dict(os.environ, NPEND_LANE_ISA=isa)
    out = subprocess.run([sys.executable, __file__, "--npend-map-seconds",
                          json.dumps([repeat, count, t_end, dt])],
                         env=env, capture_output=True, text=True)
    return json.loads(out.stdout) if out.returncode == 0 else None


def sine_nanoseconds():
    """NumPy's np.sin per element on 10^4 doubles: the part of the NumPy map that SIMD
    dispatch (NumPy's own, to AVX-512 where the CPU has it) speeds up as it does npend's."""
    x = np.linspace(-3.0, 3.0, 10_000)
    y = np.empty_like(x)
    seconds, _ = median_time(lambda: [np.sin(x, out=y) for _ in range(200)], 7)
    return seconds / (200 * x.size) * 1e9


def map_peers(repeat, count, t_end, dt):
    npend_s, values = median_time(lambda: npend_flip_map(count, t_end, dt), repeat)
    # NumPy takes minutes at full size: one run (its spread is small next to the ratio)
    numpy_s, ref = median_time(lambda: numpy_flip_map(count, t_end, dt), 1 if count > 64 else 3)
    both = np.isfinite(values) & np.isfinite(ref)
    by_isa = {isa: npend_map_seconds_on(isa, repeat, count, t_end, dt) for isa in LANE_ISAS}
    return {"count": count, "t_end": t_end, "dt": dt, "npend_seconds": npend_s,
            "numpy_seconds": numpy_s, "speedup": numpy_s / npend_s,
            "lane_isa_seconds": {isa: t for isa, t in by_isa.items() if t is not None},
            "numpy_sine_ns": sine_nanoseconds(),
            "cells_flipping_both": int(both.sum()),
            "flip_times_within_1e-2": int(np.sum(np.abs(values[both] - ref[both]) < 1e-2)),
            "npend_flips": int(np.isfinite(values).sum()), "numpy_flips": int(np.isfinite(ref).sum())}


def markdown(result):
    lines = ["| run | tolerance | wall ms (median) | final-state error | npend faster at equal error |",
             "|---|---|---|---|---|"]
    for name, runs in result["trajectory"]["runs"].items():
        for r in runs:
            speed = r.get("npend_speedup")
            lines.append(f"| {name} | {r['tol']:.0e} | {1e3 * r['seconds']:.2f} | {r['error']:.1e} | "
                         + (f"{speed:.1f}×" if speed else "—") + " |")
    m = result["map"]
    lines += ["", f"Flip map {m['count']}² of the equal double pendulum, t_end = {m['t_end']} s, "
              f"rk4 dt = {m['dt']}, one thread: npend.map {m['npend_seconds']:.2f} s, NumPy "
              f"vectorised rk4 {m['numpy_seconds']:.2f} s: npend {m['speedup']:.1f}× faster. "
              f"{m['flip_times_within_1e-2']} of the {m['cells_flipping_both']} cells that flip "
              "in both agree to 1e-2 s (chaotic cells part by round-off).",
              "", "npend.map with its lanes on each ISA (NPEND_LANE_ISA; the default takes the "
              "widest the CPU has): " + ", ".join(
                  f"{isa} {t:.2f} s ({m['numpy_seconds'] / t:.1f}× NumPy)"
                  for isa, t in m["lane_isa_seconds"].items()) + ". "
              f"NumPy's np.sin takes {m['numpy_sine_ns']:.2f} ns an element here: where NumPy "
              "runs its sines and cosines on AVX-512 too, they cost it about what SLEEF's cost "
              "the lanes, and npend's lead is in the rest of the step."]
    return "\n".join(lines)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="a 32² map to t = 10 s, 3 repeats")
    parser.add_argument("--json", action="store_true",
                        help="print JSON (with the Markdown as its key 'markdown')")
    parser.add_argument("--npend-map-seconds", metavar="JSON", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.npend_map_seconds:  # the child of npend_map_seconds_on
        repeat, count, t_end, dt = json.loads(args.npend_map_seconds)
        print(json.dumps(median_time(lambda: npend_flip_map(count, t_end, dt), repeat)[0]))
        return 0
    repeat = 3 if args.quick else 7
    result = {"trajectory": trajectory_peers(repeat, [1e-6, 1e-8, 1e-10, 1e-12],
                                             [1e-4, 1e-6, 1e-8, 1e-10, 1e-12, 1e-14]),
              "map": map_peers(repeat, 32 if args.quick else 128, 10.0 if args.quick else 100.0,
                               0.01)}
    if args.json:
        result["markdown"] = markdown(result)
    print(json.dumps(result, indent=1) if args.json else markdown(result))


if __name__ == "__main__":
    sys.exit(main())
