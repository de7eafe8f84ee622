#!/usr/bin/env python3
"""The work-precision diagram of npend_bench_work_precision's CSV: the error of the final
state against the wall time, log-log, one line per stepper (its settings in order), one panel
per case.

    python3 bench/integrators/plot_work_precision.py POINTS.csv OUT.png
"""

import argparse
import csv
import math

import matplotlib

matplotlib.use("Agg")  # files only, no display needed
import matplotlib.lines  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402

# Below double's resolution an error can come out as 0; it is drawn at this floor.
ERROR_FLOOR = 1e-17


def read_points(path):
    """{case: {stepper: [(ms, error, setting label)]}}, in the order of the file."""
    cases = {}
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            points = cases.setdefault(row["case"], {}).setdefault(row["stepper"], [])
            points.append((float(row["ms"]), max(float(row["error"]), ERROR_FLOOR),
                           f"{row['setting']} = {float(row['value']):g}"))
    return cases


def plot(cases, out):
    columns = 2 if len(cases) > 1 else 1
    rows = math.ceil(len(cases) / columns)
    fig, axes = plt.subplots(rows, columns, figsize=(6.2 * columns, 4.6 * rows), squeeze=False)
    steppers = list(dict.fromkeys(s for case in cases.values() for s in case))
    colours = {s: f"C{i}" for i, s in enumerate(steppers)}
    for ax, (name, by_stepper) in zip(axes.flat, cases.items()):
        for stepper, points in by_stepper.items():
            taylor = stepper == "taylor"
            ax.loglog([p[0] for p in points], [p[1] for p in points], marker="o",
                      markersize=5 if taylor else 3.5, linewidth=2.2 if taylor else 1.2,
                      color=colours[stepper], label=stepper, zorder=3 if taylor else 2)
        ax.set_title(name, fontsize=10)
        ax.set_xlabel("wall time per integration (ms, one thread)")
        ax.set_ylabel("max |x(T) − x_ref(T)|")
        ax.grid(True, which="major", alpha=0.35)
    for ax in list(axes.flat)[len(cases):]:
        ax.set_visible(False)
    handles = [matplotlib.lines.Line2D([], [], color=colours[s], marker="o",
                                       linewidth=2.2 if s == "taylor" else 1.2, label=s)
               for s in steppers]
    handles.append(matplotlib.lines.Line2D([], [], linestyle="none", label="heyoka: not built"))
    fig.legend(handles=handles, loc="lower center", ncol=len(handles), frameon=False)
    fig.suptitle("Work-precision: npend's steppers against a long double Taylor reference")
    fig.tight_layout(rect=(0, 0.05, 1, 0.97))
    fig.savefig(out, dpi=110)


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("csv", help="npend_bench_work_precision --csv output")
    parser.add_argument("png", help="the figure to write")
    args = parser.parse_args()
    plot(read_points(args.csv), args.png)


if __name__ == "__main__":
    main()
