"""npend explore's server without a browser: its tiles are `npend map`'s values bit for bit,
its trajectories `npend simulate`'s CSV, bad requests get the command line's own message,
no request reaches a file outside the page, and it stays up and bounded under concurrent,
cancelled and vanishing clients."""

import json
import socket
import threading
import time
import urllib.parse

import numpy as np
import pytest

from conftest import run_npend
from explore_fixture import explore_server, get


def tile_url(base, **params):
    return f"{base}/api/tile?" + urllib.parse.urlencode(params)


def tile_arrays(body, cols, rows):
    values = np.frombuffer(body[: 8 * rows * cols], dtype="<f8").reshape(rows, cols)
    mask = np.frombuffer(body[8 * rows * cols:], dtype=np.uint8).reshape(rows, cols)
    return values, mask


def npend_map(tmp_path, name, *args):
    out = tmp_path / name
    run_npend("map", *args, "--out", out)
    forbidden = out / "forbidden.npy"
    values = np.load(out / "map.npy")
    mask = np.load(forbidden) if forbidden.exists() else np.zeros(values.shape, np.uint8)
    return values, mask


# An asymmetric window, so that a tile turned or mirrored would not match; part of it has too
# little energy to flip (grey, NaN in the values).
FLIP = {"links": "2", "x": "phi1:-1:3:12", "y": "phi2:-3:0.5:10", "t-end": "8"}


def test_a_tile_is_npend_maps_map_bit_for_bit(tmp_path):
    with explore_server("--no-cache") as base:
        status, headers, body = get(tile_url(base, **FLIP))
        assert status == 200
        values, mask = tile_arrays(body, 12, 10)
        legend = json.loads(headers["X-Npend-Legend"])
        command = headers["X-Npend-Command"]
        status, _, lyap_body = get(tile_url(base, **{**FLIP, "quantity": "lyapunov", "t-end": "3"}))
        assert status == 200
        lyapunov, _ = tile_arrays(lyap_body, 12, 10)
    expected, expected_mask = npend_map(tmp_path, "flip", "--links", "2", "--x", FLIP["x"],
                                        "--y", FLIP["y"], "--t-end", "8")
    assert np.array_equal(values, expected, equal_nan=True)
    assert np.array_equal(mask, expected_mask)
    assert mask.any() and not mask.all()  # the window really has both kinds of cell
    assert np.isinf(values).any() and np.isfinite(values).any()
    assert legend["quantity"] == "flip" and legend["logarithmic"] is True
    assert command.startswith("npend map ") and "--x phi1:-1:3:12" in command
    expected, _ = npend_map(tmp_path, "lyapunov", "--links", "2", "--x", FLIP["x"], "--y",
                            FLIP["y"], "--t-end", "3", "--quantity", "lyapunov")
    assert np.array_equal(lyapunov, expected, equal_nan=True)


BAD_MAPS = [
    {"x": "foo:-1:1:8"},
    {"t-end": "-1"},
    {"quantity": "entropy"},
    {"stepper": "euler"},
    {"links": "0"},
    {"masses": "1,-2"},
    {"x": "phi1:1:-1:8"},
    {"t-end": "abc"},
]


@pytest.mark.parametrize("change", BAD_MAPS, ids=lambda c: ",".join(c))
def test_bad_parameters_get_the_command_lines_message(tmp_path, change):
    params = {**FLIP, **change}
    args = []
    for key, value in params.items():
        args += [f"--{key}", value]
    cli = run_npend("map", *args, "--out", tmp_path / "m", expect_success=False)
    assert cli.returncode == 2
    with explore_server("--no-cache") as base:
        status, _, body = get(tile_url(base, **params))
    assert status == 400
    assert body.decode().strip() == cli.stderr.strip()


def test_parameters_outside_the_map_options_are_refused():
    with explore_server("--no-cache") as base:
        for key, value in [("chain", "/etc/passwd"), ("out", "/tmp/x"), ("threads", "64"),
                           ("device", "cuda"), ("bogus", "1")]:
            status, _, body = get(tile_url(base, **FLIP, **{key: value}))
            assert status == 400, key
            assert f"unknown parameter '{key}'" in body.decode()
        status, _, body = get(tile_url(base, **{**FLIP, "x": "phi1:-1:3:257"}))
        assert status == 400 and "at most 256 x 256 cells" in body.decode()


def raw_get(base, target):
    host, port = base.removeprefix("http://").split(":")
    with socket.create_connection((host, int(port)), timeout=30) as s:
        s.sendall(f"GET {target} HTTP/1.1\r\nHost: {host}\r\nConnection: close\r\n\r\n".encode())
        data = b""
        while chunk := s.recv(65536):
            data += chunk
    return int(data.split(b" ", 2)[1]), data


def test_no_request_reaches_a_file_outside_the_page():
    with explore_server("--no-cache") as base:
        for target in ["/../../../../etc/passwd", "/lib/../../../../etc/passwd",
                       "/%2e%2e/%2e%2e/etc/passwd", "/lib/..%2f..%2f..%2fetc%2fpasswd",
                       "/lib/dygraph.min.js/../../../etc/passwd", "/explore.js%00.html"]:
            status, data = raw_get(base, target)
            assert status in (400, 404), target
            assert b"root:" not in data
        status, data = raw_get(base, "/lib/dygraph.min.js")
        assert status == 200 and b"Dygraph" in data
        status, data = raw_get(base, "/")
        assert status == 200 and b"npend explore" in data


def test_concurrent_clients_get_the_same_values(tmp_path):
    windows = [("phi1:-1:1:6", "phi2:-2:0:6"), ("phi1:1:3:6", "phi2:-2:0:6"),
               ("phi1:-1:1:6", "phi2:0:2:6"), ("phi1:1:3:6", "phi2:0:2:6")]
    results = {}

    def client(k):
        for x, y in windows:
            status, _, body = get(tile_url(base, links="2", x=x, y=y, **{"t-end": "5"},
                                           client=f"c{k}", gen="1"))
            results.setdefault((x, y), []).append((status, body))

    with explore_server("--no-cache", "--threads", "2") as base:
        threads = [threading.Thread(target=client, args=(k,)) for k in range(6)]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
    for (x, y), answers in results.items():
        assert len(answers) == 6
        expected, _ = npend_map(tmp_path, f"{x}{y}".replace(":", "_"), "--links", "2", "--x", x,
                                "--y", y, "--t-end", "5")
        for status, body in answers:
            assert status == 200
            assert np.array_equal(tile_arrays(body, 6, 6)[0], expected, equal_nan=True)


def status_of(base):
    return json.loads(get(f"{base}/api/status")[2])


# A tile that takes minutes on one thread: 256² cells each integrated to 1000 s (about 9 minutes
# here). The state at t_end, not the flip time: the cells of this window flip within seconds and
# stop, so a flip tile of it ends in about 3 s, and on an idle machine before the newer view.
HEAVY = {"links": "2", "x": "phi1:2:3:256", "y": "phi2:2:3:256", "t-end": "1000",
         "quantity": "state"}


def test_a_tile_the_view_left_behind_is_cancelled():
    with explore_server("--no-cache", "--threads", "1") as base:
        answer = {}

        def heavy():
            answer["result"] = get(tile_url(base, **HEAVY, client="page", gen="1"))
            answer["at"] = time.monotonic()

        thread = threading.Thread(target=heavy)
        thread.start()
        time.sleep(1.0)
        asked = time.monotonic()
        status, _, _ = get(tile_url(base, **FLIP, client="page", gen="2"))
        assert status == 200  # the newer view's tile got the only compute slot
        thread.join(timeout=60)
        assert not thread.is_alive()
        assert answer["result"][0] == 409
        assert answer["at"] - asked < 30
        s = status_of(base)
        assert s["tiles_cancelled"] == 1 and s["computing"] == 0


def test_the_server_survives_a_client_that_vanishes_mid_tile(tmp_path):
    with explore_server("--no-cache", "--threads", "1") as base:
        host, port = base.removeprefix("http://").split(":")
        query = urllib.parse.urlencode({**FLIP, "t-end": "30", "x": "phi1:-1:3:40"})
        with socket.create_connection((host, int(port))) as s:
            s.sendall(f"GET /api/tile?{query} HTTP/1.1\r\nHost: {host}\r\n\r\n".encode())
            time.sleep(0.2)
        # The vanished client's tile finishes and is kept; the server goes on serving.
        status, _, body = get(tile_url(base, **FLIP))
        assert status == 200
        expected, _ = npend_map(tmp_path, "m", "--links", "2", "--x", FLIP["x"], "--y", FLIP["y"],
                                "--t-end", "8")
        assert np.array_equal(tile_arrays(body, 12, 10)[0], expected, equal_nan=True)
        deadline = time.monotonic() + 120
        while status_of(base)["computing"] > 0 and time.monotonic() < deadline:
            time.sleep(0.2)
        assert status_of(base)["tiles_computed"] == 2


def test_memory_stays_within_its_limit_while_zooming_deep():
    with explore_server("--no-cache", "--memory", "1") as base:
        # 40 tiles of 64² cells (37 kB each, 1.5 MB together), ever deeper into one corner.
        for z in range(40):
            w = 4.0 / 2**z
            x = f"phi1:{-1 + w / 128}:{-1 + w - w / 128}:64"
            y = f"phi2:{0.5 - w + w / 128}:{0.5 - w / 128}:64"
            status, _, _ = get(tile_url(base, links="2", x=x, y=y, **{"t-end": "0.05"}))
            assert status == 200
        s = status_of(base)
    assert s["tiles_computed"] == 40
    assert s["memory_cache_bytes"] <= 1 << 20
    assert 0 < s["memory_cache_tiles"] < 40


def test_tiles_on_disk_serve_the_next_server(tmp_path):
    cache = tmp_path / "cache"
    with explore_server("--cache", cache) as base:
        _, _, first = get(tile_url(base, **FLIP))
    assert len(list(cache.glob("*.tile"))) == 1
    with explore_server("--cache", cache) as base:
        _, _, again = get(tile_url(base, **FLIP))
        assert status_of(base)["tiles_computed"] == 0
    assert again == first


def test_the_trajectory_is_npend_simulates_csv():
    params = {"links": "3", "phi": "1.2,-0.4,0.3", "p": "0,0.5,0", "t-end": "2", "dt": "0.01",
              "stepper": "rk4", "every": "3", "masses": "1,2,1.5"}
    with explore_server("--no-cache") as base:
        status, headers, body = get(f"{base}/api/trajectory.csv?" + urllib.parse.urlencode(params))
        bad = get(f"{base}/api/trajectory.csv?" + urllib.parse.urlencode({**params, "dt": "0"}))
    args = []
    for key, value in params.items():
        args += [f"--{key}", value]
    assert status == 200
    assert body.decode() == run_npend("simulate", *args).stdout
    assert headers["X-Npend-Command"].startswith("npend simulate ")
    cli = run_npend("simulate", *args[:-8], "--dt", "0", "--stepper", "rk4", "--every", "3",
                    "--masses", "1,2,1.5", expect_success=False)
    assert bad[0] == 400 and bad[2].decode().strip() == cli.stderr.strip()


def test_a_starts_lyapunov_exponent_and_section():
    import npend

    params = {"links": "2", "phi": "1.5,1.5", "p": "0,0", "t-end": "50", "dt": "0.01",
              "stepper": "rk4"}
    with explore_server("--no-cache") as base:
        status, _, body = get(f"{base}/api/start?" + urllib.parse.urlencode(params))
    assert status == 200
    answer = json.loads(body)
    chain = npend.Chain(2)
    result = npend.lyapunov(chain, [1.5, 1.5, 0, 0], t_end=50, dt=0.01, stepper="rk4",
                            maximal=True)
    assert answer["lyapunov"] == pytest.approx(result.exponents[0], rel=1e-12)
    # Every point of the section φ1 = 0 lies on the start's energy surface: with φ1 = 0 and
    # (φ2, p2) given, H = E fixes p1 by a quadratic, which must have a real root.
    energy = chain.hamiltonian([1.5, 1.5, 0, 0])
    assert len(answer["section"]["points"]) > 5
    for phi2, p2 in answer["section"]["points"]:
        roots = [p1 for p1 in np.linspace(-30, 30, 6001)
                 if chain.hamiltonian([0, phi2, p1, p2]) <= energy]
        assert roots, (phi2, p2)
