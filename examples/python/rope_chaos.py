#!/usr/bin/env python3
"""How chaotic is a chain of n links on its way to the rope? The paper (section 6.7) expects
the motion to become "maximally random" as n grows at fixed total length. This measures the
largest Lyapunov exponent and the Kolmogorov-Sinai entropy h_KS (the sum of the positive
exponents, Pesin) against n, at fixed total length L, total mass M and energy E.

Each chain has n equal links of length L/n and mass M/n. Each start is the hanging chain
given a kick in a random direction (seeded) with energy E = energy * M g L. The n largest
exponents come from npend.lyapunov (rk4, exponents=n: n tangent vectors, each O(n) per step
on the loop kernels of a long chain). The starts run in parallel threads: the package
releases the GIL. The mean and the standard error over the starts are reported, in units of
sqrt(g/L).

    PYTHONPATH=build/python python3 examples/python/rope_chaos.py --links 2,3,4,5,6 \\
        [--starts 6] [--t-end 200] [--energy 0.5] [--previous OLD.csv] [--out rope_chaos]

Writes OUT.csv (one row per n, with the T and the number of starts it was measured with),
OUT.md (the same table) and OUT.png (the figure). --previous adds the rows of an earlier
run's CSV for link counts not measured now (long chains cost far more per simulated second,
so they are measured apart, with a shorter T).
"""

import argparse
import concurrent.futures
import math
import os
import sys
import tempfile

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.ticker  # noqa: E402
import numpy as np  # noqa: E402

import npend  # noqa: E402

G, LENGTH, MASS = 9.81, 1.0, 1.0


def exponents_of_one_start(links, seed, energy, t_end, dt):
    chain = npend.Chain(links, masses=MASS / links, lengths=LENGTH / links, g=G)
    direction = np.random.default_rng(seed).normal(size=links)
    x0 = npend.kicked_state(chain, energy * MASS * G * LENGTH, direction)
    r = npend.lyapunov(chain, x0, t_end, dt=dt, stepper="rk4", exponents=links)
    return r.exponents, r.max_rel_energy_error


def mean_and_error(values):
    values = np.asarray(values)
    return values.mean(), values.std(ddof=1) / math.sqrt(len(values))


def measure(links, starts, energy, t_end, dt, pool):
    """Per n: lambda_max and h_KS (mean, standard error) in units of sqrt(g/L)."""
    unit = math.sqrt(LENGTH / G)
    runs = list(pool.map(lambda k: exponents_of_one_start(links, 1000 * links + k, energy,
                                                          t_end, dt), range(starts)))
    largest = [e[0] * unit for e, _ in runs]
    # The n largest of the 2n exponents (pairs +-lambda): the positive ones and the zero of
    # the energy direction, whose estimate is close to 0.
    entropy = [np.sum(e[:links]) * unit for e, _ in runs]
    energy_error = max(err for _, err in runs)
    return {"links": links, "lambda_max": mean_and_error(largest),
            "h_ks": mean_and_error(entropy), "max_rel_energy_error": energy_error,
            "t_end": t_end, "starts": starts}


def read_rows(path):
    """The rows of an earlier run's CSV."""
    rows = []
    with open(path) as f:
        header = f.readline().strip().split(",")
        for line in f:
            v = dict(zip(header, line.strip().split(",")))
            rows.append({"links": int(v["links"]),
                         "lambda_max": (float(v["lambda_max"]), float(v["lambda_max_error"])),
                         "h_ks": (float(v["h_ks"]), float(v["h_ks_error"])),
                         "max_rel_energy_error": float(v["max_rel_energy_error"]),
                         "t_end": float(v["t_end"]), "starts": int(v["starts"])})
    return rows


def write_atomically(path, write):
    folder = os.path.dirname(os.path.abspath(path))
    with tempfile.NamedTemporaryFile("w", dir=folder, delete=False,
                                     suffix=os.path.splitext(path)[1]) as partial:
        name = partial.name
    write(name)
    os.replace(name, path)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--links", default="2,3,4,5,6", help="link counts, comma-separated")
    parser.add_argument("--starts", type=int, default=6, help="random starts per link count")
    parser.add_argument("--t-end", type=float, default=200.0, help="integration time (s)")
    parser.add_argument("--dt", type=float, default=0,
                        help="rk4's step (s); default min(1e-3, 0.02 / n^2) s: shorter links "
                             "swing faster (5e-5 s at n = 20 keeps H to 1e-5)")
    parser.add_argument("--energy", type=float, default=0.5, help="E / (M g L)")
    parser.add_argument("--previous", help="an earlier run's CSV whose rows join the table")
    parser.add_argument("--out", default="rope_chaos", help="output prefix")
    args = parser.parse_args()
    try:
        links = [int(v) for v in args.links.split(",")]
    except ValueError:
        sys.exit(f"rope_chaos: --links: expected comma-separated integers, got {args.links!r}")
    if min(links) < 1:
        sys.exit("rope_chaos: --links: link counts must be at least 1")
    if args.starts < 2:
        sys.exit("rope_chaos: --starts must be at least 2 (for a standard error)")

    rows = []
    with concurrent.futures.ThreadPoolExecutor(max_workers=os.cpu_count()) as pool:
        for n in links:
            dt = args.dt if args.dt > 0 else min(1e-3, 0.02 / n**2)
            rows.append(measure(n, args.starts, args.energy, args.t_end, dt, pool))
            r = rows[-1]
            print(f"n = {n:3d}: lambda_max = {r['lambda_max'][0]:.3f} +- {r['lambda_max'][1]:.3f}, "
                  f"h_KS = {r['h_ks'][0]:.3f} +- {r['h_ks'][1]:.3f} sqrt(g/L) "
                  f"(energy error {r['max_rel_energy_error']:.1e})", flush=True)

    if args.previous:
        try:
            measured = {r["links"] for r in rows}
            rows += [r for r in read_rows(args.previous) if r["links"] not in measured]
        except (OSError, KeyError, ValueError) as e:
            sys.exit(f"rope_chaos: --previous: {args.previous} is not a rope_chaos CSV ({e})")
        rows.sort(key=lambda r: r["links"])
    header = "links,lambda_max,lambda_max_error,h_ks,h_ks_error,max_rel_energy_error,t_end,starts\n"
    lines = [f"{r['links']},{r['lambda_max'][0]:.6g},{r['lambda_max'][1]:.3g},"
             f"{r['h_ks'][0]:.6g},{r['h_ks'][1]:.3g},{r['max_rel_energy_error']:.2g},"
             f"{r['t_end']:g},{r['starts']}\n"
             for r in rows]
    write_atomically(args.out + ".csv", lambda p: open(p, "w").write(header + "".join(lines)))
    table = ["| n | λ_max √(L/g) | h_KS √(L/g) | h_KS / n | max rel. energy error | T (s) | starts |",
             "|---:|---:|---:|---:|---:|---:|---:|"]
    for r in rows:
        table.append(f"| {r['links']} | {r['lambda_max'][0]:.3f} ± {r['lambda_max'][1]:.3f} | "
                     f"{r['h_ks'][0]:.3f} ± {r['h_ks'][1]:.3f} | "
                     f"{r['h_ks'][0] / r['links']:.3f} | {r['max_rel_energy_error']:.1e} | "
                     f"{r['t_end']:g} | {r['starts']} |")
    write_atomically(args.out + ".md", lambda p: open(p, "w").write("\n".join(table) + "\n"))

    figure, axis = plt.subplots(figsize=(7, 4.5), constrained_layout=True)
    link_counts = [r["links"] for r in rows]
    for key, label in [("lambda_max", r"$\lambda_{\max}$"), ("h_ks", r"$h_{KS}$")]:
        axis.errorbar(link_counts, [r[key][0] for r in rows], yerr=[r[key][1] for r in rows], marker="o",
                      capsize=3, label=label)
    axis.set(xscale="log", yscale="log", xlabel="links n (fixed total length, mass, energy)",
             ylabel=r"rate in units of $\sqrt{g/L}$",
             title=f"E = {args.energy} M g L, random kicks; T and starts per n in the table")
    axis.set_xticks(link_counts, [str(v) for v in link_counts])
    axis.xaxis.set_minor_locator(matplotlib.ticker.NullLocator())
    axis.legend()
    write_atomically(args.out + ".png", lambda p: figure.savefig(p, dpi=100))
    print(f"wrote {args.out}.csv, {args.out}.md, {args.out}.png")


if __name__ == "__main__":
    main()
