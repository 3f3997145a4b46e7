"""Shared fixtures of the Python package's tests: generated meshes and rays, the shared real
scenes (tests skip cleanly when ../shared/meshes is absent) and the command-line tools."""

import importlib
import json
import os
import pathlib
import struct
import subprocess
import sys
import threading

import numpy as np
import pytest

sys.path.insert(0, str(pathlib.Path(__file__).parent))

# Real scenes small enough for a brute-force oracle in a test, from ../shared/meshes.
SHARED_SCENES = ["models/teapot.obj", "scanned/bunny_npm.obj", "gltf/smallpine/scene.gltf",
                 "scanned/stanford_dragon_vrip_res4.ply"]


def require_module(name):
    """Imports an optional test dependency (Dask, Open3D); skips without it, except in CI
    (CI=true), where scripts/test.sh installs it and a skip would hide its tests."""
    try:
        return importlib.import_module(name)
    except ImportError as error:
        if os.environ.get("CI") == "true":
            pytest.fail(f"{name} is missing in CI: {error}", pytrace=False)
        pytest.skip(f"{name} is not installed (scripts/test.sh installs it)",
                    allow_module_level=True)


def shared_meshes_dir():
    folder = os.environ.get("SG_SHARED_MESHES_DIR", "")
    return pathlib.Path(folder) if folder and pathlib.Path(folder).is_dir() else None


def shared_mesh(relative):
    """Path of a real scene, or skip the test when the shared scenes are absent."""
    folder = shared_meshes_dir()
    if folder is None or not (folder / relative).is_file():
        pytest.skip(f"../shared/meshes/{relative} is absent (SG_SHARED_MESHES_DIR)")
    return folder / relative


def tool(name):
    """Path of a command-line tool (sg-build, sg-stats, sg-trace, sg-bench), or skip without
    it."""
    variable = {"sg-build": "SG_BUILD_EXE", "sg-stats": "SG_STATS_EXE",
                "sg-trace": "SG_TRACE_EXE", "sg-bench": "SG_BENCH_EXE"}[name]
    path = os.environ.get(variable, "")
    if not path or not os.path.isfile(path):
        pytest.skip(f"{name} is not built ({variable} unset)")
    return path


def run_tool(*args):
    """Runs a tool, returns its stdout; fails the test with its stderr on a non-zero exit."""
    done = subprocess.run([str(a) for a in args], capture_output=True, text=True)
    assert done.returncode == 0, f"{args[0]} exited {done.returncode}: {done.stderr}"
    return done.stdout


def sg_stats_json(path):
    return json.loads(run_tool(tool("sg-stats"), path, "--json"))


def other_thread_steps_during(work):
    """How many times another Python thread ran a loop step while `work()` ran: thousands when
    `work` releases the GIL, a handful (the interpreter's switch interval) when it holds it."""
    steps = []
    done = threading.Event()

    def step():
        while not done.is_set():
            steps.append(1)

    counter = threading.Thread(target=step)
    counter.start()
    try:
        before = len(steps)
        work()
        return len(steps) - before
    finally:
        done.set()
        counter.join()


def write_ray_file(path, rays, tnear=0.0, tfar=np.inf):
    """A ray file of docs/FORMAT.md ("SGRAY001", uint64 count, 8 float32 per ray), written here
    from the format's description."""
    rays = np.asarray(rays, dtype=np.float32).reshape(-1, 6)
    records = np.empty((len(rays), 8), dtype="<f4")
    records[:, :6] = rays
    records[:, 6] = tnear
    records[:, 7] = tfar
    with open(path, "wb") as out:
        out.write(b"SGRAY001" + struct.pack("<Q", len(rays)) + records.tobytes())


def read_hit_file(path):
    """A hit file ("SGHIT001", uint64 count, per ray uint32 id and float32 t, u, v)."""
    data = pathlib.Path(path).read_bytes()
    assert data[:8] == b"SGHIT001"
    (count,) = struct.unpack("<Q", data[8:16])
    records = np.frombuffer(data[16:], dtype=np.dtype([("id", "<u4"), ("t", "<f4"),
                                                       ("u", "<f4"), ("v", "<f4")]))
    assert len(records) == count
    return records


def sphere(rings=24, segments=48, radius=1.0, center=(0.0, 0.0, 0.0)):
    """A closed UV sphere with shared vertices: float64 (N, 3), int64 (M, 3)."""
    theta = np.linspace(0, np.pi, rings + 1)[1:-1]
    phi = np.linspace(0, 2 * np.pi, segments, endpoint=False)
    t, p = np.meshgrid(theta, phi, indexing="ij")
    body = np.stack([np.sin(t) * np.cos(p), np.cos(t), np.sin(t) * np.sin(p)], axis=-1)
    vertices = np.concatenate([[[0, 1, 0]], body.reshape(-1, 3), [[0, -1, 0]]]) * radius
    vertices += center
    triangles = []
    ring = lambda r, s: 1 + r * segments + s % segments  # noqa: E731
    for s in range(segments):
        triangles.append([0, ring(0, s + 1), ring(0, s)])
        triangles.append([len(vertices) - 1, ring(rings - 2, s), ring(rings - 2, s + 1)])
    for r in range(rings - 2):
        for s in range(segments):
            triangles.append([ring(r, s), ring(r, s + 1), ring(r + 1, s)])
            triangles.append([ring(r + 1, s), ring(r, s + 1), ring(r + 1, s + 1)])
    return vertices, np.array(triangles, dtype=np.int64)


def triangle_soup(rng, count=300, extent=10.0, size=1.5):
    """Random triangles of random sizes in a box: float64 (3 * count, 3), int64 (count, 3)."""
    centers = rng.uniform(-extent, extent, size=(count, 1, 3))
    vertices = (centers + rng.normal(scale=size, size=(count, 3, 3))).reshape(-1, 3)
    return vertices, np.arange(3 * count, dtype=np.int64).reshape(count, 3)


def random_rays(rng, count, vertices, spread=1.5):
    """Rays from points around the mesh's box towards random points inside it, so most hit."""
    lower, upper = vertices.min(axis=0), vertices.max(axis=0)
    # Origins off a flat scene's plane too, so that rays do not graze it.
    middle = (lower + upper) / 2
    half = (upper - lower) / 2 * spread + 0.1 * np.linalg.norm(upper - lower)
    origins = middle + rng.uniform(-1, 1, size=(count, 3)) * half
    targets = middle + rng.uniform(-0.5, 0.5, size=(count, 3)) * (upper - lower)
    return np.concatenate([origins, targets - origins], axis=1).astype(np.float32)


@pytest.fixture
def rng():
    return np.random.default_rng(20240611)


@pytest.fixture
def soup(rng):
    return triangle_soup(rng)
