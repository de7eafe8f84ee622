"""npend explore started for a test: the server of this build on a free port, stopped with
Ctrl-C (SIGINT) at the end, when it must say so and exit with 130 as every command does."""

import re
import signal
import subprocess
import urllib.error
import urllib.request
from contextlib import contextmanager

from conftest import npend_binary


@contextmanager
def explore_server(*args):
    process = subprocess.Popen([npend_binary(), "explore", "--port", "0", *map(str, args)],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        line = process.stdout.readline()
        match = re.search(r"http://127\.0\.0\.1:(\d+)/", line)
        assert match, f"no address in {line!r}; stderr: {process.stderr.read()}"
        yield f"http://127.0.0.1:{match.group(1)}"
    finally:
        process.send_signal(signal.SIGINT)
        try:
            _, err = process.communicate(timeout=30)
        except subprocess.TimeoutExpired:
            process.kill()
            raise AssertionError("npend explore did not stop within 30 s of SIGINT")
    assert process.returncode == 130, err
    assert err.strip().endswith("npend explore: stopped"), err


def get(url, timeout=300):
    """(status, headers, body bytes) of a GET, errors included."""
    try:
        with urllib.request.urlopen(url, timeout=timeout) as response:
            return response.status, response.headers, response.read()
    except urllib.error.HTTPError as e:
        return e.code, e.headers, e.read()
