#!/usr/bin/env python3
"""The SciPy peer of `npend map`: the flip time of the equal double pendulum from rest, one
cell after another with scipy.integrate.solve_ivp in a Python loop — how users compute Heyl's
fractal without npend.

Times a random sample of the cells of a COUNT x COUNT grid over (phi1, phi2) in [-3.14, 3.14]
that the energy does not rule out (2 cos phi1 + cos phi2 <= 1 for point masses; npend skips the
others without integrating, and so does this loop), and extrapolates the mean time per cell to
all of them. The right-hand side is the double pendulum's closed-form Hamiltonian equations,
checked first against `npend eval --json` at random states when --npend is given.

Prints one JSON object: the sample, the seconds per cell, the extrapolated seconds for the map.
Run by bench/run; alone: bench/scipy_flip_peer.py --npend build/npend --sample 40.
"""
import argparse
import json
import math
import random
import subprocess
import sys
import time

import numpy as np
from scipy.integrate import solve_ivp

M, L, G = 1.0, 1.0, 9.81  # both links: 1 kg, 1 m


def rhs(_t, y):
    """Hamilton's equations of the point-mass double pendulum (m1 = m2 = M, l1 = l2 = L),
    from H = N / (2 m2 l1^2 l2^2 D) + V with D = m1 + m2 sin^2(phi1 - phi2) and
    N = m2 l2^2 p1^2 + (m1 + m2) l1^2 p2^2 - 2 m2 l1 l2 p1 p2 cos(phi1 - phi2)."""
    a, b, p1, p2 = y
    delta = a - b
    s, c = math.sin(delta), math.cos(delta)
    d = M + M * s * s
    da = (L * p1 - L * p2 * c) / (L ** 3 * d)
    db = (L * 2 * M * p2 - L * M * p1 * c) / (L ** 3 * M * d)
    c1 = p1 * p2 * s / (L * L * d)
    n = L * L * M * p1 * p1 + L * L * 2 * M * p2 * p2 - 2 * L * L * M * p1 * p2 * c
    c2 = n * 2 * s * c / (2 * L ** 4 * d * d)
    return [da, db, -2 * M * G * L * math.sin(a) - c1 + c2, -M * G * L * math.sin(b) + c1 - c2]


def check_against_npend(npend, rng):
    """The closed form must be the chain npend derives: its rhs at 5 random states."""
    for _ in range(5):
        y = [rng.uniform(-3, 3) for _ in range(4)]
        out = subprocess.run([npend, "eval", "--links", "2", "--state",
                              ",".join(repr(v) for v in y), "--json"],
                             check=True, capture_output=True, text=True).stdout
        want = json.loads(out)["rhs"]
        got = rhs(0, y)
        if max(abs(g - w) for g, w in zip(got, want)) > 1e-12 * max(1, max(map(abs, want))):
            sys.exit(f"scipy_flip_peer: the closed form differs from npend eval at {y}")


def flip_event(k):
    def event(_t, y):
        return abs(y[k]) - math.pi
    event.terminal = True
    return event


def flip_time(phi1, phi2, t_end, rtol, atol):
    """solve_ivp (RK45) from rest at (phi1, phi2) until an arm passes the upright position."""
    result = solve_ivp(rhs, (0, t_end), [phi1, phi2, 0.0, 0.0], method="RK45", rtol=rtol,
                       atol=atol, events=[flip_event(0), flip_event(1)])
    times = [e[0] for e in result.t_events if len(e) > 0]
    return min(times) if times else math.inf


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--count", type=int, default=256, help="grid side (default 256)")
    parser.add_argument("--t-end", type=float, default=1000, help="s (default 1000)")
    parser.add_argument("--sample", type=int, default=40, help="cells timed (default 40)")
    parser.add_argument("--rtol", type=float, default=1e-9)
    parser.add_argument("--atol", type=float, default=1e-9)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--npend", help="an npend binary to check the right-hand side against")
    args = parser.parse_args()
    if args.count < 2 or args.sample < 1 or not args.t_end > 0:
        sys.exit("scipy_flip_peer: need --count >= 2, --sample >= 1, --t-end > 0")
    rng = random.Random(args.seed)
    if args.npend:
        check_against_npend(args.npend, rng)
    grid = np.linspace(-3.14, 3.14, args.count)
    allowed = [(a, b) for b in grid for a in grid if 2 * math.cos(a) + math.cos(b) <= 1]
    sample = rng.sample(allowed, min(args.sample, len(allowed)))
    start = time.perf_counter()
    flipped = sum(math.isfinite(flip_time(a, b, args.t_end, args.rtol, args.atol))
                  for a, b in sample)
    seconds = time.perf_counter() - start
    per_cell = seconds / len(sample)
    print(json.dumps({"grid": args.count, "t_end": args.t_end, "method": "RK45",
                      "rtol": args.rtol, "atol": args.atol, "cells_integrated": len(allowed),
                      "sample": len(sample), "sample_flipped": flipped,
                      "sample_seconds": seconds, "seconds_per_cell": per_cell,
                      "extrapolated_seconds": per_cell * len(allowed)}))


if __name__ == "__main__":
    main()
