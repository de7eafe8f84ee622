"""npend.map(out=DIR) runs the map as the command line's tiles: interrupted, it keeps the
finished tiles, and resume=True finishes it with the values of an uninterrupted run."""

import os
import re

import numpy as np
import pytest

import npend

CHAIN = npend.Chain(2)
X, Y = ("phi1", -3.0, 3.0, 24), ("phi2", -3.0, 3.0, 24)
OPTIONS = dict(t_end=20.0, dt=0.01, tile=4)  # 36 tiles


def reference():
    return npend.map(CHAIN, X, Y, t_end=OPTIONS["t_end"], dt=OPTIONS["dt"]).values


def tile_files(folder):
    return sorted(f for f in os.listdir(folder / "tiles") if re.fullmatch(r"tile_\d+\.bin", f))


def test_map_out_values_equal_a_run_without_a_folder(tmp_path):
    r = npend.map(CHAIN, X, Y, out=tmp_path, **OPTIONS)
    np.testing.assert_array_equal(r.values, reference())
    assert len(tile_files(tmp_path)) == 36
    assert r.options["out"] == tmp_path and r.options["tile"] == 4


def test_map_interrupted_keeps_its_tiles_and_resume_finishes_it(tmp_path):
    # Every cell integrated to t_end (about 40 ms a tile on one thread), so that the
    # progress reports, about every 20 ms, see the tiles finish one by one.
    options = dict(OPTIONS, quantity="state", t_end=200.0)

    def stop_after_some_tiles(done, total):
        assert total in (0, 36)  # 0: a report before the first tile finished
        if done >= 6:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt, match="resume=True") as caught:
        npend.map(CHAIN, X, Y, out=tmp_path, progress=stop_after_some_tiles, threads=1,
                  **options)
    kept = tile_files(tmp_path)
    assert 6 <= len(kept) < 36
    assert f"{len(kept)} tiles are in" in str(caught.value)
    # No temporary file of a tile in flight is left behind.
    assert not [f for f in os.listdir(tmp_path / "tiles") if f.startswith(".")]
    before = {f: os.stat(tmp_path / "tiles" / f).st_mtime_ns for f in kept}

    computed = []
    r = npend.map(CHAIN, X, Y, out=tmp_path, resume=True,
                  progress=lambda done, total: computed.append(total), **options)
    np.testing.assert_array_equal(
        r.values, npend.map(CHAIN, X, Y, quantity="state", t_end=200.0, dt=0.01).values)
    # Only the missing tiles were computed; the kept ones were read back untouched.
    assert computed[-1] == 36 - len(kept)
    assert all(os.stat(tmp_path / "tiles" / f).st_mtime_ns == t for f, t in before.items())


def test_map_resume_computes_a_damaged_tile_again(tmp_path):
    npend.map(CHAIN, X, Y, out=tmp_path, **OPTIONS)
    damaged = tmp_path / "tiles" / tile_files(tmp_path)[5]
    data = bytearray(damaged.read_bytes())
    data[-3] ^= 0xFF  # a flipped bit in the last value: the checksum no longer matches
    damaged.write_bytes(bytes(data))
    with pytest.warns(RuntimeWarning, match=f"{damaged.name}.*computed again") as caught:
        r = npend.map(CHAIN, X, Y, out=tmp_path, resume=True, **OPTIONS)
    assert len(caught) == 1
    np.testing.assert_array_equal(r.values, reference())
    cut = tmp_path / "tiles" / tile_files(tmp_path)[7]
    cut.write_bytes(cut.read_bytes()[:20])
    with pytest.warns(RuntimeWarning, match=f"{cut.name}.*computed again"):
        again = npend.map(CHAIN, X, Y, out=tmp_path, resume=True, **OPTIONS)
    np.testing.assert_array_equal(again.values, reference())


def test_map_folder_refusals_name_the_keyword(tmp_path):
    npend.map(CHAIN, X, Y, out=tmp_path, **OPTIONS)
    with pytest.raises(ValueError, match=r"^out: .* this map: finish it with resume=True, or "
                                         r"start afresh with force=True"):
        npend.map(CHAIN, X, Y, out=tmp_path, **OPTIONS)
    with pytest.raises(ValueError, match=r"^resume: .* holds a different map"):
        npend.map(CHAIN, X, ("phi2", -3.0, 3.0, 25), out=tmp_path, resume=True, **OPTIONS)
    with pytest.raises(ValueError, match=r"^out: .* holds another run's tiles.*force=True"):
        npend.map(CHAIN, X, ("phi2", -3.0, 3.0, 25), out=tmp_path, **OPTIONS)
    with pytest.raises(ValueError, match=r"^resume: .* holds no interrupted map"):
        npend.map(CHAIN, X, Y, out=tmp_path / "empty", resume=True, **OPTIONS)
    with pytest.raises(ValueError, match=r"^resume: only with out"):
        npend.map(CHAIN, X, Y, resume=True)
    with pytest.raises(ValueError, match=r"^force: only for a fresh run"):
        npend.map(CHAIN, X, Y, out=tmp_path, resume=True, force=True)
    with pytest.raises(ValueError, match=r"^tile: 1\.\.1024, got 0"):
        npend.map(CHAIN, X, Y, out=tmp_path / "t", tile=0)


def test_map_force_starts_afresh_and_keeps_other_files(tmp_path):
    npend.map(CHAIN, X, Y, out=tmp_path, **OPTIONS)
    (tmp_path / "tiles" / "notes.txt").write_text("mine")
    other_y = ("phi2", -3.0, 3.0, 12)
    r = npend.map(CHAIN, X, other_y, out=tmp_path, force=True, **OPTIONS)
    np.testing.assert_array_equal(
        r.values, npend.map(CHAIN, X, other_y, t_end=20.0, dt=0.01).values)
    assert (tmp_path / "tiles" / "notes.txt").read_text() == "mine"
    assert len(tile_files(tmp_path)) == 18
