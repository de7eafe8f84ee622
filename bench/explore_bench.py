#!/usr/bin/env python3
"""npend explore's speed, as a page meets it: the time to the first full view of the default
map (the flip map of the equal double pendulum, 4 x 4 tiles of 64² cells, t-end 100 s), the
time to refine after a zoom by 2 about the centre, and the tiles' throughput against
`npend map` computing the same 256² cells on the same cores (its own compute time, from
map.json: the server's overhead).

The requests go as the page sends them: six connections at a time (a browser's limit per
host), the coarse tiles (16² cells) of a view before its full ones, the centre first. Run on
an otherwise idle machine:

    python3 bench/explore_bench.py [--npend build/npend] [--rounds 3]

Prints a Markdown table of medians over the rounds (each round a fresh server without a disk
cache) for docs/explore.md.
"""
import argparse
import concurrent.futures
import json
import math
import pathlib
import re
import signal
import statistics
import subprocess
import tempfile
import time
import urllib.parse
import urllib.request

PI = math.pi
CELLS, COARSE, DEPTH = 64, 16, 2


def axis(name, lo, hi, cells):
    step = (hi - lo) / cells
    return f"{name}:{lo + step / 2!r}:{hi - step / 2!r}:{cells}"


def view_tiles(zoom, base=(-PI, PI, -PI, PI)):
    """The tiles of the page's view at `zoom` about the centre: (x0, x1, y0, y1) each."""
    level = zoom + DEPTH
    n = 2**level
    w, h = (base[1] - base[0]) / n, (base[3] - base[2]) / n
    half = (base[1] - base[0]) / 2**zoom / 2
    cx, cy = (base[0] + base[1]) / 2, (base[2] + base[3]) / 2
    tiles = []
    for ty in range(n):
        for tx in range(n):
            b = (base[0] + tx * w, base[0] + (tx + 1) * w, base[2] + ty * h, base[2] + (ty + 1) * h)
            if b[1] > cx - half and b[0] < cx + half and b[3] > cy - half and b[2] < cy + half:
                tiles.append(b)
    return sorted(tiles, key=lambda b: math.hypot((b[0] + b[1]) / 2 - cx, (b[2] + b[3]) / 2 - cy))


def fetch(base_url, bounds, cells, generation):
    query = urllib.parse.urlencode({"links": "2", "t-end": "100",
                                    "x": axis("phi1", bounds[0], bounds[1], cells),
                                    "y": axis("phi2", bounds[2], bounds[3], cells),
                                    "client": "bench", "gen": str(generation)})
    with urllib.request.urlopen(f"{base_url}/api/tile?{query}", timeout=600) as r:
        assert r.status == 200
        return len(r.read())


def show_view(base_url, zoom, generation, coarse=True):
    """Seconds until every full tile of the view has arrived."""
    tiles = view_tiles(zoom)
    started = time.perf_counter()
    with concurrent.futures.ThreadPoolExecutor(6) as pool:
        jobs = [pool.submit(fetch, base_url, b, COARSE, generation) for b in tiles] if coarse else []
        jobs += [pool.submit(fetch, base_url, b, CELLS, generation) for b in tiles]
        for j in jobs:
            j.result()
    return time.perf_counter() - started


class server:
    def __init__(self, npend):
        self.process = subprocess.Popen([npend, "explore", "--port", "0", "--no-cache"],
                                        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        port = re.search(r":(\d+)/", self.process.stdout.readline()).group(1)
        self.url = f"http://127.0.0.1:{port}"

    def __enter__(self):
        return self

    def __exit__(self, *_):
        self.process.send_signal(signal.SIGINT)
        self.process.communicate(timeout=60)


def npend_map_seconds(npend):
    """npend map's compute time for the view's 256² cells on every core (map.json)."""
    with tempfile.TemporaryDirectory() as out:
        step = 2 * PI / 256
        subprocess.run([npend, "map", "--links", "2", "--t-end", "100", "--tile", "64",
                        "--x", f"phi1:{-PI + step / 2!r}:{PI - step / 2!r}:256",
                        "--y", f"phi2:{-PI + step / 2!r}:{PI - step / 2!r}:256",
                        "--out", out], check=True, capture_output=True)
        return json.loads((pathlib.Path(out) / "map.json").read_text())["wall_seconds"]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--npend", default="build/npend")
    parser.add_argument("--rounds", type=int, default=3)
    a = parser.parse_args()
    first, zoomed, fine_only, cli = [], [], [], []
    for _ in range(a.rounds):
        with server(a.npend) as s:
            first.append(show_view(s.url, 0, 1))
            zoomed.append(show_view(s.url, 1, 2))
        with server(a.npend) as s:
            fine_only.append(show_view(s.url, 0, 1, coarse=False))
        cli.append(npend_map_seconds(a.npend))
    m = statistics.median
    print("| measure | median (s) | rounds |")
    print("|---|---|---|")
    print(f"| first full view: 16 tiles of 64² (256² cells), coarse 16² first | {m(first):.2f} | "
          f"{', '.join(f'{v:.2f}' for v in first)} |")
    print(f"| refined after a zoom by 2 at the centre: 16 tiles of 64², coarse first | {m(zoomed):.2f} | "
          f"{', '.join(f'{v:.2f}' for v in zoomed)} |")
    print(f"| the same 256² cells as 16 full tiles only | {m(fine_only):.2f} | "
          f"{', '.join(f'{v:.2f}' for v in fine_only)} |")
    print(f"| npend map, the same 256² cells (map.json: wall_seconds) | {m(cli):.2f} | "
          f"{', '.join(f'{v:.2f}' for v in cli)} |")
    print(f"\nserver / npend map on the same cells: {m(fine_only) / m(cli):.3f} "
          f"(cells/s: {256 * 256 / m(fine_only):,.0f} served, {256 * 256 / m(cli):,.0f} npend map)")


if __name__ == "__main__":
    main()
