"""Files: load and save against sg-build's files, stats() against sg-stats --json,
import_mesh against sg-build, and damaged, truncated or missing files."""

import os
import pathlib
import re
import subprocess
import threading
import warnings

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import splitgrid
from conftest import SHARED_SCENES, run_tool, shared_mesh, sg_stats_json, sphere, tool

HERE = pathlib.Path(__file__).parent
pytestmark = pytest.mark.filterwarnings("ignore::splitgrid.MeshImportWarning")


def assimp_model(relative):
    folder = pathlib.Path(os.environ.get("SG_ASSIMP_MODELS_DIR", "/usr/share/assimp/models"))
    if not (folder / relative).is_file():
        pytest.skip(f"{relative} of assimp-testmodels is absent")
    return folder / relative


ENGINE = "glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb"


@pytest.fixture(scope="module")
def engine():
    return assimp_model(ENGINE)


@pytest.fixture(scope="module")
def engine_sg(tmp_path_factory, engine):
    path = tmp_path_factory.mktemp("sg") / "engine.sg"
    run_tool(tool("sg-build"), engine, "-o", path, "-q")
    return path


def test_a_file_loaded_and_saved_again_is_byte_identical(engine_sg, tmp_path):
    grid = splitgrid.load(engine_sg)
    grid.save(tmp_path / "again.sg")
    assert (tmp_path / "again.sg").read_bytes() == engine_sg.read_bytes()
    # str and PathLike alike.
    grid.save(str(tmp_path / "third.sg"))
    assert (tmp_path / "third.sg").read_bytes() == engine_sg.read_bytes()


def test_stats_is_the_document_of_sg_stats_json(engine_sg):
    assert splitgrid.load(str(engine_sg)).stats() == sg_stats_json(engine_sg)


@pytest.mark.parametrize("flags, params", [
    ([], {}),
    (["--preset", "poster", "--leaf-size", "4", "--resolution-max", "24"],
     {"preset": "poster", "leaf_size": 4, "resolution_max": 24}),
    (["--no-clip-triangles", "--min-cell-width", "0", "--resolution-sigma", "12.5"],
     {"clip_triangles": False, "min_cell_width": 0, "resolution_sigma": 12.5}),
])
def test_a_grid_built_from_import_mesh_is_the_grid_sg_build_builds(engine, tmp_path, flags,
                                                                    params):
    built_by_tool = tmp_path / "tool.sg"
    run_tool(tool("sg-build"), engine, "-o", built_by_tool, "-q", *flags)
    vertices, triangles = splitgrid.import_mesh(engine)
    grid = splitgrid.build(vertices, triangles, source_name=engine.name, **params)
    assert grid.stats()["grid"] == sg_stats_json(built_by_tool)["grid"]
    grid.save(tmp_path / "python.sg")
    assert (tmp_path / "python.sg").read_bytes() == built_by_tool.read_bytes()


@pytest.mark.parametrize("scene", SHARED_SCENES)
def test_real_scenes_import_and_build_as_sg_build_does(scene, tmp_path):
    path = shared_mesh(scene)
    built_by_tool = tmp_path / "tool.sg"
    run_tool(tool("sg-build"), path, "-o", built_by_tool, "-q")
    vertices, triangles = splitgrid.import_mesh(path)
    tool_grid = splitgrid.load(built_by_tool)
    np.testing.assert_array_equal(vertices, tool_grid.vertices)
    np.testing.assert_array_equal(triangles, tool_grid.triangles)
    grid = splitgrid.build(vertices, triangles, source_name=path.name)
    grid.save(tmp_path / "python.sg")
    assert (tmp_path / "python.sg").read_bytes() == built_by_tool.read_bytes()


def test_import_mesh_gives_its_arrays_to_the_caller(engine):
    vertices, triangles = splitgrid.import_mesh(engine)
    assert vertices.dtype == np.float32 and vertices.shape[1] == 3 and vertices.flags.writeable
    assert triangles.dtype == np.uint32 and triangles.shape[1] == 3 and len(triangles) > 1000
    assert triangles.max() < len(vertices)


def sg_build_warnings(path, tmp_path):
    done = subprocess.run([tool("sg-build"), path, "-o", tmp_path / "w.sg"], capture_output=True,
                          text=True)
    assert done.returncode == 0, done.stderr
    return [line[len("warning: "):] for line in done.stderr.splitlines()
            if line.startswith("warning: ")]


@pytest.mark.parametrize("mesh", [HERE.parent / "data" / "nan_and_degenerate.obj",
                                  "tricky/igea_tristrips.ply"])
def test_import_warnings_are_sg_builds_warnings(mesh, tmp_path):
    path = mesh if isinstance(mesh, pathlib.Path) else shared_mesh(mesh)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        splitgrid.import_mesh(path)
    messages = [str(w.message) for w in caught if w.category is splitgrid.MeshImportWarning]
    assert messages, "the file should give warnings"
    assert messages == sg_build_warnings(path, tmp_path)


def test_import_errors_name_the_file(tmp_path):
    missing = tmp_path / "missing.obj"
    with pytest.raises(OSError, match=re.escape(str(missing))):
        splitgrid.import_mesh(missing)
    garbage = tmp_path / "garbage.ply"
    garbage.write_bytes(b"ply\nformat binary_little_endian 1.0\nelement vertex 9999999\n" * 3)
    with pytest.raises(ValueError, match=re.escape(str(garbage))):
        splitgrid.import_mesh(garbage)
    points = tmp_path / "points.obj"
    points.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\np 1\nl 1 2\n")
    with pytest.raises(ValueError, match=re.escape(str(points)) + ".*no triangles"):
        splitgrid.import_mesh(points)
    with pytest.raises(TypeError):
        splitgrid.import_mesh(42)


def test_import_mesh_forks_safely_with_tbb_and_python_threads_running(engine):
    """import_mesh forks a child for Assimp: with oneTBB's workers busy in a query and other
    Python threads running at the fork, every import still gives the same mesh."""
    expected_vertices, expected_triangles = splitgrid.import_mesh(engine)
    vertices, triangles = sphere(rings=100, segments=200)
    grid = splitgrid.build(vertices, triangles)
    rays = np.random.default_rng(5).normal(size=(200_000, 6)).astype(np.float32)
    stop = threading.Event()
    errors = []

    def keep_querying():
        try:
            while not stop.is_set():
                grid.cast_rays(rays)
        except Exception as error:  # reported below
            errors.append(error)

    def keep_computing():
        while not stop.is_set():
            np.linalg.svd(np.random.default_rng().normal(size=(60, 60)))

    background = [threading.Thread(target=keep_querying) for _ in range(2)]
    background.append(threading.Thread(target=keep_computing))
    for thread in background:
        thread.start()
    results = []
    try:
        importers = [threading.Thread(target=lambda: results.append(splitgrid.import_mesh(engine)))
                     for _ in range(3)]
        for thread in importers:
            thread.start()
        for thread in importers:
            thread.join(timeout=300)
        for _ in range(2):
            results.append(splitgrid.import_mesh(engine))
    finally:
        stop.set()
        for thread in background:
            thread.join()
    assert not errors, errors
    assert len(results) == 5
    for v, t in results:
        np.testing.assert_array_equal(v, expected_vertices)
        np.testing.assert_array_equal(t, expected_triangles)


@pytest.fixture(scope="module")
def small_sg(tmp_path_factory):
    vertices, triangles = sphere(rings=10, segments=20)
    path = tmp_path_factory.mktemp("small") / "ball.sg"
    splitgrid.build(vertices, triangles, source_name="ball").save(path)
    return path


def test_missing_and_unreadable_files_raise_oserror(tmp_path):
    with pytest.raises(OSError, match=re.escape(str(tmp_path / "none.sg"))):
        splitgrid.load(tmp_path / "none.sg")
    with pytest.raises(OSError):
        splitgrid.load(tmp_path)  # a folder
    grid = splitgrid.build(*sphere(4, 6))
    with pytest.raises(OSError, match=re.escape(str(tmp_path / "no"))):
        grid.save(tmp_path / "no" / "x.sg")
    assert not (tmp_path / "no").exists()


def test_damaged_files_raise_formaterror_naming_the_file(small_sg, tmp_path):
    data = small_sg.read_bytes()
    assert issubclass(splitgrid.FormatError, ValueError)
    damaged = tmp_path / "damaged.sg"
    for size in (0, 7, 64, len(data) // 2, len(data) - 1):
        damaged.write_bytes(data[:size])
        with pytest.raises(splitgrid.FormatError, match=re.escape(str(damaged))):
            splitgrid.load(damaged)
    damaged.write_bytes(data + b"\0" * 8)
    with pytest.raises(splitgrid.FormatError, match=re.escape(str(damaged))):
        splitgrid.load(damaged)
    not_sg = tmp_path / "text.sg"
    not_sg.write_text("hello, this is not a Split Grid\n" * 10)
    with pytest.raises(splitgrid.FormatError, match="text.sg"):
        splitgrid.load(not_sg)


@settings(max_examples=60, deadline=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])
@given(changes=st.lists(st.tuples(st.integers(0, 10**9), st.integers(1, 255)), min_size=1,
                        max_size=4))
def test_random_damage_is_refused_or_harmless(small_sg, tmp_path, changes):
    """Bytes changed anywhere: a FormatError, or (in padding the format ignores) the same
    grid as before. Never a crash, never a different grid."""
    data = bytearray(small_sg.read_bytes())
    for position, flip in changes:
        data[position % len(data)] ^= flip
    damaged = tmp_path / "random.sg"
    damaged.write_bytes(bytes(data))
    try:
        grid = splitgrid.load(damaged)
    except splitgrid.FormatError as error:
        assert str(damaged) in str(error)
        return
    original = splitgrid.load(small_sg)
    assert grid.stats()["grid"] == original.stats()["grid"]
    np.testing.assert_array_equal(grid.vertices, original.vertices)
    np.testing.assert_array_equal(grid.triangles, original.triangles)
