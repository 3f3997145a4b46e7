"""Ctrl-C: a long query or build in a child Python process sent SIGINT raises KeyboardInterrupt
within about a second, and the SplitGrid still answers afterwards."""

import contextlib
import os
import select
import signal
import subprocess
import sys
import time

import pytest

# The child: a scene whose rays each test thousands of triangles (large triangles overlapping
# everywhere, which no structure can separate), so that one query of 10^6 rays on one thread
# runs far longer than the test waits.
QUERY_CHILD = """
import sys, time
import numpy as np
import splitgrid
rng = np.random.default_rng(1)
n = 20000
vertices = rng.uniform(-1, 1, size=(3 * n, 3))
grid = splitgrid.build(vertices, np.arange(3 * n).reshape(n, 3))
rays = np.empty((1_000_000, 6), np.float32)
rays[:, :3] = rng.uniform(-2, 2, size=(len(rays), 3))
rays[:, 3:] = -rays[:, :3]
start = time.perf_counter()
sample = grid.cast_rays(rays[:2000], threads=1)
estimate = (time.perf_counter() - start) / 2000 * len(rays)
print(f"ready {estimate:.1f}", flush=True)
try:
    grid.cast_rays(rays, threads=1)
    print("finished", flush=True)
except KeyboardInterrupt:
    print("interrupted", flush=True)
again = grid.cast_rays(rays[:2000], threads=1)
same = all(np.array_equal(again[key], sample[key]) for key in sample)
print("answers after the interrupt:", "same" if same else "different", flush=True)
"""

# The child times one build of a million small triangles on one thread, then starts a second.
BUILD_CHILD = """
import time
import numpy as np
import splitgrid
rng = np.random.default_rng(2)
n = 1_000_000
centers = rng.uniform(-1, 1, size=(n, 1, 3)).astype(np.float32)
vertices = (centers + rng.normal(scale=0.004, size=(n, 3, 3)).astype(np.float32)).reshape(-1, 3)
triangles = np.arange(3 * n).reshape(n, 3)
start = time.perf_counter()
splitgrid.build(vertices, triangles, threads=1)
print(f"ready {time.perf_counter() - start:.3f}", flush=True)
try:
    splitgrid.build(vertices, triangles, threads=1)
    print("finished", flush=True)
except KeyboardInterrupt:
    print("interrupted", flush=True)
print("built afterwards:", len(splitgrid.build(vertices[:3000], triangles[:900])), flush=True)
"""


def read_line(process, timeout):
    """The child's next line, or None after `timeout` seconds."""
    ready, _, _ = select.select([process.stdout], [], [], timeout)
    return process.stdout.readline().strip() if ready else None


@contextlib.contextmanager
def child(code):
    """A Python child running `code`, killed at the end whatever happened."""
    process = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True, env=os.environ.copy())
    try:
        yield process
    finally:
        process.kill()
        process.wait()


def interrupt(process, wait_before=0.5):
    """Sends SIGINT after `wait_before` seconds; returns the next line and its delay."""
    time.sleep(wait_before)
    sent = time.monotonic()
    process.send_signal(signal.SIGINT)
    line = read_line(process, timeout=30)
    return line, time.monotonic() - sent


def test_ctrl_c_stops_a_long_query():
    with child(QUERY_CHILD) as process:
        ready = read_line(process, timeout=300)
        assert ready and ready.startswith("ready"), process.stderr.read()
        estimate = float(ready.split()[1])
        assert estimate > 5, f"the query would take only {estimate} s: not long enough to test"
        line, delay = interrupt(process)
        assert line == "interrupted", f"{line!r}; stderr: {process.stderr.read()}"
        # "Within about a second": rounds are about 0.05 s; the rest is a busy machine's slack.
        assert delay < 3.0, f"KeyboardInterrupt came {delay:.2f} s after SIGINT"
        assert read_line(process, timeout=60) == "answers after the interrupt: same"
        assert process.wait(timeout=60) == 0


def test_ctrl_c_stops_a_long_build():
    """SIGINT a quarter into a build whose length the child measured: the interrupt must come
    from inside the build, well before it would have ended on its own."""
    with child(BUILD_CHILD) as process:
        ready = read_line(process, timeout=300)
        assert ready and ready.startswith("ready"), process.stderr.read()
        build_seconds = float(ready.split()[1])
        line, delay = interrupt(process, wait_before=0.25 * build_seconds)
        assert line == "interrupted", f"{line!r}; stderr: {process.stderr.read()}"
        assert delay < min(3.0, 0.5 * build_seconds), (
            f"KeyboardInterrupt came {delay:.2f} s after SIGINT, in a build of "
            f"{build_seconds:.2f} s: not from inside the build")
        assert read_line(process, timeout=60) == "built afterwards: 900"
        assert process.wait(timeout=60) == 0


def test_an_uncaught_interrupt_ends_python_as_usual():
    code = QUERY_CHILD.replace("except KeyboardInterrupt:", "except ZeroDivisionError:")
    with child(code) as process:
        assert read_line(process, timeout=300).startswith("ready")
        time.sleep(0.5)
        process.send_signal(signal.SIGINT)
        assert process.wait(timeout=30) != 0
        assert "KeyboardInterrupt" in process.stderr.read()
