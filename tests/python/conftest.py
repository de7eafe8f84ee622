"""What the Python tests share: the `npend` command line of the same build, whose results
the module's must equal (both call the same C++ library)."""

import json
import os
import subprocess

import pytest


def npend_binary():
    path = os.environ.get("NPEND_BINARY")
    if not path or not os.path.exists(path):
        pytest.fail("NPEND_BINARY must name the npend binary of this build (CTest sets it)")
    return path


def run_npend(*args, expect_success=True):
    """Runs `npend ARGS...`; returns the CompletedProcess (text output)."""
    result = subprocess.run([npend_binary(), *map(str, args)], capture_output=True, text=True,
                            timeout=300)
    if expect_success and result.returncode != 0:
        pytest.fail(f"npend {' '.join(map(str, args))} failed:\n{result.stderr}")
    return result


def npend_json(*args):
    """Runs `npend ARGS... --json` and parses what it prints."""
    return json.loads(run_npend(*args, "--json").stdout)


def csv_list(values):
    return ",".join(repr(float(v)) for v in values)
