"""splitgrid.build: arrays in, parameters, the SplitGrid's arrays, and every kind of bad input."""

import gc
import inspect
import re

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

import splitgrid
from conftest import other_thread_steps_during, sphere
from oracle import check_cast_rays

# The build parameters and their ranges as docs/STATS_JSON.md and `sg-build --help` state them,
# written out here so that the test checks the binding against the documented interface.
COUNT_RANGES = {"resolution_min": (1, 1 << 20), "resolution_max": (2, 1 << 20),
                "leaf_size": (1, 1 << 20), "max_depth": (0, 64)}
REAL_RANGES = {"resolution_sigma": (0.0, 1e9, True), "no_progress_fraction": (0.0, 1.0, True),
               "min_cell_width": (0.0, 1e6, False)}
SWITCHES = ["stop_by_cost", "bounding_planes", "bounding_nodes", "clip_triangles"]


@pytest.fixture(scope="module")
def ball():
    return sphere(rings=12, segments=24)


def test_build_keeps_the_mesh_and_its_views_copy_nothing(ball):
    vertices, triangles = ball[0].copy(), ball[1]
    grid = splitgrid.build(vertices, triangles)
    assert len(grid) == len(triangles)
    assert grid.vertices.dtype == np.float32 and grid.vertices.shape == vertices.shape
    assert grid.triangles.dtype == np.uint32 and grid.triangles.shape == triangles.shape
    np.testing.assert_array_equal(grid.vertices, vertices.astype(np.float32))
    np.testing.assert_array_equal(grid.triangles, triangles)
    # Two reads are views of one buffer, not copies, and they cannot be written.
    assert np.shares_memory(grid.vertices, grid.vertices)
    assert np.shares_memory(grid.triangles, grid.triangles)
    with pytest.raises(ValueError):
        grid.vertices[0, 0] = 1.0
    # The grid keeps its own copy: changing the caller's arrays changes nothing.
    vertices[0] += 100.0
    assert not np.array_equal(grid.vertices[0], vertices[0].astype(np.float32))


def test_a_view_keeps_its_grid_alive(ball):
    vertices, triangles = ball
    view = splitgrid.build(vertices, triangles).vertices
    gc.collect()
    for _ in range(3):
        np.ones(len(vertices) * 3 * 8)  # reuse freed memory, if the grid were gone
    np.testing.assert_array_equal(view, vertices.astype(np.float32))


def test_every_parameter_reaches_the_grid(ball):
    vertices, triangles = ball
    params = {"resolution_min": 3, "resolution_max": 9, "resolution_sigma": 20.5,
              "leaf_size": 5, "max_depth": 7, "no_progress_fraction": 0.75,
              "min_cell_width": 0.5, "stop_by_cost": False, "bounding_planes": False,
              "bounding_nodes": False, "clip_triangles": False}
    grid = splitgrid.build(vertices, triangles, threads=1, **params)
    assert grid.build_parameters == dict(params, threads=0)
    assert grid.stats()["build_config"] == dict(params, threads=0)
    assert grid.stats()["grid"]["max_depth"] <= 7


def test_the_poster_preset_and_flags_over_it(ball):
    vertices, triangles = ball
    poster = splitgrid.build(vertices, triangles, preset="poster").build_parameters
    assert poster["bounding_nodes"] is False and poster["stop_by_cost"] is False
    over = splitgrid.build(vertices, triangles, preset="poster", bounding_nodes=True)
    assert over.build_parameters["bounding_nodes"] is True
    with pytest.raises(ValueError, match="unknown build preset 'fast'"):
        splitgrid.build(vertices, triangles, preset="fast")


def test_the_grid_does_not_depend_on_the_thread_count(ball):
    vertices, triangles = ball
    one = splitgrid.build(vertices, triangles, threads=1).stats()
    two = splitgrid.build(vertices, triangles, threads=2).stats()
    assert one == two


@pytest.mark.parametrize("name", sorted(COUNT_RANGES))
def test_a_count_out_of_range_names_field_value_and_range(ball, name):
    low, high = COUNT_RANGES[name]
    for value in (low - 1, high + 1, -5, 2**40):
        if name == "resolution_max" and value == low - 1:
            value = 1
        message = re.escape(f"BuildConfig.{name} = {value} is out of range [{low}, {high}]")
        with pytest.raises(ValueError, match=message):
            splitgrid.build(*ball, **{name: value})
    with pytest.raises(TypeError, match=f"{name} must be a whole number, not float"):
        splitgrid.build(*ball, **{name: 2.5})
    with pytest.raises(TypeError, match=f"{name} must be a whole number, not bool"):
        splitgrid.build(*ball, **{name: True})
    # numpy integers are whole numbers too.
    grid = splitgrid.build(*ball, **{name: np.int64(max(low, 2))})
    assert grid.build_parameters[name] == max(low, 2)


@pytest.mark.parametrize("name", sorted(REAL_RANGES))
def test_a_real_out_of_range_names_field_value_and_range(ball, name):
    low, high, open_low = REAL_RANGES[name]
    for value in (low - 1.0, high * 2):
        shown = f"{value:g}"
        bracket = "(" if open_low else "["
        message = re.escape(f"BuildConfig.{name} = {shown} is out of range {bracket}")
        with pytest.raises(ValueError, match=message):
            splitgrid.build(*ball, **{name: value})
    with pytest.raises(ValueError, match=f"BuildConfig.{name} must be a finite number"):
        splitgrid.build(*ball, **{name: float("nan")})
    with pytest.raises(TypeError, match=f"{name} must be a real number, not str"):
        splitgrid.build(*ball, **{name: "1"})


@pytest.mark.parametrize("name", SWITCHES)
def test_a_switch_takes_only_a_bool(ball, name):
    with pytest.raises(TypeError, match=f"{name} must be True or False, not int"):
        splitgrid.build(*ball, **{name: 1})
    assert splitgrid.build(*ball, **{name: np.bool_(False)}).build_parameters[name] is False


def test_at_most_relations_and_unknown_names(ball):
    with pytest.raises(ValueError, match=re.escape(
            "BuildConfig.resolution_min = 20 is above BuildConfig.resolution_max = 16")):
        splitgrid.build(*ball, resolution_min=20)
    with pytest.raises(TypeError, match="unexpected keyword argument 'leaf_sise'.*leaf_size"):
        splitgrid.build(*ball, leaf_sise=4)
    with pytest.raises(TypeError, match="unexpected keyword argument 'leaf-size'"):
        splitgrid.build(*ball, **{"leaf-size": 3})
    for bad in (-1, 1025):
        with pytest.raises(ValueError, match=f"threads = {bad} is out of range"):
            splitgrid.build(*ball, threads=bad)
    with pytest.raises(TypeError, match="threads must be None or a whole number"):
        splitgrid.build(*ball, threads=1.5)


def test_float64_vertices_are_rounded_once_and_huge_ones_refused(ball):
    vertices, triangles = ball
    grid = splitgrid.build(vertices.astype(np.float64), triangles)
    np.testing.assert_array_equal(grid.vertices, vertices.astype(np.float32))
    huge = vertices.copy()
    huge[3, 1] = 1e300
    with pytest.raises(ValueError, match=re.escape("vertices[3, 1] = 1e+300 is outside "
                                                   "float32's range")):
        splitgrid.build(huge, triangles)


@pytest.mark.parametrize("dtype", [np.int8, np.uint8, np.int16, np.uint16, np.int32, np.uint32,
                                   np.int64, np.uint64, ">i4", "<u8"])
def test_triangles_of_every_integer_dtype_give_the_same_grid(dtype):
    vertices, triangles = sphere(rings=6, segments=8)
    reference = splitgrid.build(vertices, triangles).stats()
    assert splitgrid.build(vertices, triangles.astype(dtype)).stats() == reference
    # Strided (every other row of a bigger array) and Fortran-ordered arrays too.
    doubled = np.repeat(triangles.astype(dtype), 2, axis=0)[::2]
    assert splitgrid.build(vertices, doubled).stats() == reference
    assert splitgrid.build(np.asfortranarray(vertices), np.asfortranarray(
        triangles.astype(dtype))).stats() == reference


BAD_INPUTS = [
    # (vertices, triangles, exception, message)
    (np.zeros((3, 3), np.int32), [[0, 1, 2]], TypeError, "vertices: dtype int32 is not supported"),
    (np.zeros((3, 3), np.float16), [[0, 1, 2]], TypeError, "vertices: dtype float16"),
    (np.zeros((3, 2)), [[0, 1, 2]], ValueError,
     r"vertices: expected shape \(N, 3\), got shape \(3, 2\)"),
    (np.zeros(9), [[0, 1, 2]], ValueError, r"vertices: expected shape \(N, 3\), got shape \(9,\)"),
    (np.eye(3), np.array([[0, 1, 2]], np.float32), TypeError, "triangles: dtype float32"),
    (np.eye(3), np.array([[True, False, True]]), TypeError, "triangles: dtype bool"),
    (np.eye(3), [0, 1, 2], ValueError, r"triangles: expected shape \(M, 3\), got shape \(3,\)"),
    (np.eye(3), np.zeros((0, 3), np.int32), ValueError, "triangles: the mesh has no triangles"),
    (np.eye(3), [[0, 1, -1]], ValueError, r"triangles\[0, 2\] = -1 is negative"),
    (np.eye(3), [[0, 1, 2], [0, 3, 1]], ValueError,
     r"triangles\[1, 1\] = 3 is not a vertex index: there are 3 vertices"),
    (np.zeros((0, 3)), [[0, 0, 0]], ValueError, "there are 0 vertices"),
    (np.array([[0, 0, 0], [1, 0, np.nan], [0, 1, 0]]), [[0, 1, 2]], ValueError,
     r"vertices: vertex 1 \(of triangle 0\) has a NaN or infinite coordinate"),
    (np.array([[0, 0, 0], [1, 0, 0], [0, np.inf, 0]]), [[0, 1, 2]], ValueError,
     "vertices: vertex 2"),
    ("not an array", [[0, 1, 2]], TypeError, "vertices: dtype <U12"),
    (None, [[0, 1, 2]], TypeError, "vertices: dtype object"),
]


@pytest.mark.parametrize("vertices, triangles, error, message", BAD_INPUTS)
def test_bad_meshes_raise_an_error_naming_the_argument(vertices, triangles, error, message):
    with pytest.raises(error, match=message):
        splitgrid.build(vertices, triangles)


def test_an_unused_nan_vertex_is_harmless():
    vertices = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [np.nan, 0, 0]])
    grid = splitgrid.build(vertices, [[0, 1, 2]])
    hit = grid.cast_rays(np.array([0.2, 0.2, 1, 0, 0, -1], np.float32))
    assert hit["primitive_ids"] == 0 and hit["t_hit"] == 1.0


SHAPES = hnp.array_shapes(min_dims=1, max_dims=3, min_side=0, max_side=5)


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
# Coordinates in steps of 1e-3: the float32 ray test covers coordinates of 1e-18 to 1e18
# (ray.hpp), and a random step of 1e-300 is outside that range, not a finding.
@given(vertices=hnp.arrays(np.float64, SHAPES, elements=st.floats(-1e3, 1e3).map(
           lambda x: round(x, 3)) | st.sampled_from([np.nan, np.inf, 0.0])),
       vertex_dtype=st.sampled_from([np.float32, np.float64, ">f8", np.int64, np.float16]),
       triangles=hnp.arrays(np.int64, SHAPES, elements=st.integers(-3, 6)),
       triangle_dtype=st.sampled_from([np.int8, np.int64, np.uint32, ">i2", np.float64, np.bool_]))
def test_random_shapes_dtypes_and_values_raise_or_build_a_right_grid(vertices, vertex_dtype,
                                                                     triangles, triangle_dtype):
    """Whatever arrives, build() either refuses it with a TypeError or ValueError that names
    the argument, or builds a grid whose answers the oracle accepts: never a crash."""
    with np.errstate(invalid="ignore", over="ignore"):
        vertices = vertices.astype(vertex_dtype)
        triangles = triangles.astype(triangle_dtype)
    try:
        grid = splitgrid.build(vertices, triangles)
    except (TypeError, ValueError) as error:
        assert re.match(r"(vertices|triangles)", str(error)), str(error)
        return
    assert vertices.dtype.kind == "f" and vertices.itemsize in (4, 8) and vertices.ndim == 2
    assert triangles.ndim == 2 and triangles.shape[1] == 3 and len(triangles) > 0
    assert triangles.min() >= 0 and triangles.max() < len(vertices)
    assert np.all(np.isfinite(vertices[np.unique(triangles)]))
    rays = np.random.default_rng(1).normal(size=(64, 6)).astype(np.float32)
    rays[:, 3:] = -rays[:, :3] * 2
    check_cast_rays(vertices.astype(np.float32), triangles, rays, grid.cast_rays(rays))


def test_build_releases_the_gil():
    vertices, triangles = sphere(rings=120, segments=240)
    steps = other_thread_steps_during(lambda: splitgrid.build(vertices, triangles, threads=1))
    assert steps > 1000, f"the other thread ran only {steps} times during the build"


def test_help_shows_numpy_style_docstrings():
    for function in (splitgrid.build, splitgrid.load, splitgrid.import_mesh,
                     splitgrid.SplitGrid.cast_rays, splitgrid.SplitGrid.test_occlusions,
                     splitgrid.create_rays_pinhole, splitgrid.SplitGrid.save):
        doc = inspect.getdoc(function)
        assert "Parameters\n----------" in doc, function.__name__
    assert "(..., 6)" in splitgrid.SplitGrid.cast_rays.__doc__
    assert "primitive_normals : float32, shape (..., 3)" in splitgrid.SplitGrid.cast_rays.__doc__
