"""cast_rays and test_occlusions: against the brute-force oracle, against sg-trace, for every
shape, dtype and layout of rays, with tnear and tfar, invalid rays, bad arguments and threads."""

import re
import threading
import tracemalloc
import warnings

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

import splitgrid
from conftest import (SHARED_SCENES, other_thread_steps_during, random_rays, read_hit_file,
                      run_tool, shared_mesh, sphere, tool, triangle_soup, write_ray_file)
from oracle import check_cast_rays, check_occlusions


def generated_scene(name):
    rng = np.random.default_rng(7)
    if name == "soup":
        return triangle_soup(rng, count=400)
    if name == "sphere":
        return sphere(rings=30, segments=60)
    if name == "flat":  # every triangle in the plane z = 0: a flat root box
        xy = rng.uniform(-5, 5, size=(600, 2))
        return np.column_stack([xy, np.zeros(600)]), rng.integers(0, 600, size=(300, 3))
    if name == "grid":  # a regular grid of quads: rays through shared edges and vertices
        n = 16
        x, y = np.meshgrid(np.arange(n + 1.0), np.arange(n + 1.0))
        vertices = np.column_stack([x.ravel(), y.ravel(), np.zeros(x.size)])
        quads = [(j * (n + 1) + i, j * (n + 1) + i + 1, (j + 1) * (n + 1) + i)
                 for j in range(n) for i in range(n)]
        quads += [(j * (n + 1) + i + 1, (j + 1) * (n + 1) + i + 1, (j + 1) * (n + 1) + i)
                  for j in range(n) for i in range(n)]
        return vertices, np.array(quads)
    raise ValueError(name)


GENERATED = ["soup", "sphere", "flat", "grid"]


@pytest.fixture(scope="module", params=GENERATED)
def scene(request):
    vertices, triangles = generated_scene(request.param)
    return vertices, triangles, splitgrid.build(vertices, triangles)


def scene_rays(vertices, count=2000, seed=3):
    rays = random_rays(np.random.default_rng(seed), count, np.asarray(vertices))
    # A few rays straight down the axes, through the grid's shared edges and vertices.
    lower, upper = np.min(vertices, axis=0), np.max(vertices, axis=0)
    xs = np.linspace(lower[0], upper[0], 9)
    ys = np.linspace(lower[1], upper[1], 9)
    axis_rays = [[x, y, upper[2] + 1, 0, 0, -1] for x in xs for y in ys]
    return np.concatenate([rays, np.array(axis_rays, dtype=np.float32)])


def test_cast_rays_agrees_with_the_oracle(scene):
    vertices, triangles, grid = scene
    rays = scene_rays(vertices)
    hits = check_cast_rays(grid.vertices, triangles, rays, grid.cast_rays(rays))
    assert hits > len(rays) // 4


def test_test_occlusions_agrees_with_the_oracle(scene):
    vertices, triangles, grid = scene
    rays = scene_rays(vertices, seed=4)
    assert check_occlusions(grid.vertices, triangles, rays, grid.test_occlusions(rays)) > 0


@pytest.mark.parametrize("name", SHARED_SCENES)
def test_real_scenes_agree_with_the_oracle(name):
    vertices, triangles = splitgrid.import_mesh(shared_mesh(name))
    grid = splitgrid.build(vertices, triangles)
    rays = random_rays(np.random.default_rng(11), 300, vertices)
    assert check_cast_rays(vertices, triangles, rays, grid.cast_rays(rays)) > 30
    check_occlusions(vertices, triangles, rays, grid.test_occlusions(rays))
    camera = splitgrid.create_rays_pinhole(50, vertices.mean(axis=0), vertices.max(axis=0) * 2.5,
                                           [0, 1, 0], 24, 16)
    check_cast_rays(vertices, triangles, camera, grid.cast_rays(camera))


def test_tnear_and_tfar_as_numbers_and_arrays(scene):
    vertices, triangles, grid = scene
    rays = scene_rays(vertices, count=1500, seed=5)
    window = np.random.default_rng(6).uniform(0.0, 1.2, size=(len(rays), 2))
    tnear, tfar = window.min(axis=1), window.max(axis=1)
    check_cast_rays(grid.vertices, triangles, rays, grid.cast_rays(rays, tnear=tnear, tfar=tfar),
                    tnear=tnear, tfar=tfar)
    check_occlusions(grid.vertices, triangles, rays,
                     grid.test_occlusions(rays, tnear=tnear, tfar=tfar), tnear=tnear, tfar=tfar)
    check_cast_rays(grid.vertices, triangles, rays, grid.cast_rays(rays, tnear=0.3, tfar=0.9),
                    tnear=0.3, tfar=0.9)
    # float32, integer and 0-d arrays are taken as well.
    as_float32 = grid.cast_rays(rays, tnear=tnear.astype(np.float32), tfar=np.array(2))
    check_cast_rays(grid.vertices, triangles, rays, as_float32,
                    tnear=tnear.astype(np.float32), tfar=2.0)


@pytest.mark.parametrize("leading", [(), (1,), (7,), (3, 5), (2, 3, 4), (0,), (4, 0), (2, 1, 3, 1)])
def test_any_leading_shape_is_kept_in_every_output(leading):
    vertices, triangles = generated_scene("sphere")
    grid = splitgrid.build(vertices, triangles)
    count = int(np.prod(leading, dtype=np.int64))
    flat = scene_rays(vertices, count=max(count, 1))[:count]
    rays = flat.reshape(leading + (6,))
    result = grid.cast_rays(rays)
    expected = grid.cast_rays(flat)
    shapes = {"t_hit": leading, "primitive_ids": leading, "primitive_uvs": leading + (2,),
              "primitive_normals": leading + (3,)}
    for key, shape in shapes.items():
        assert result[key].shape == shape, key
        assert result[key].flags.c_contiguous
        np.testing.assert_array_equal(result[key].reshape(expected[key].shape), expected[key])
    assert result["primitive_ids"].dtype == np.uint32 and result["t_hit"].dtype == np.float32
    occluded = grid.test_occlusions(rays)
    assert occluded.shape == leading and occluded.dtype == bool
    np.testing.assert_array_equal(occluded.reshape(-1), grid.test_occlusions(flat))


def test_every_layout_and_float64_give_the_float32_answers():
    vertices, triangles = generated_scene("soup")
    grid = splitgrid.build(vertices, triangles)
    rays64 = scene_rays(vertices).astype(np.float64) + 1e-9  # not exactly float32
    reference = grid.cast_rays(rays64.astype(np.float32))
    variants = {
        "float64": rays64,
        "list": rays64.tolist(),
        "fortran": np.asfortranarray(rays64.astype(np.float32)),
        "strided": np.repeat(rays64.astype(np.float32), 2, axis=0)[::2],
        "big-endian": rays64.astype(">f4"),
        "transposed": np.ascontiguousarray(rays64.astype(np.float32).T).T,
    }
    for name, rays in variants.items():
        result = grid.cast_rays(rays)
        for key in reference:
            np.testing.assert_array_equal(result[key], reference[key], err_msg=name)
        np.testing.assert_array_equal(grid.test_occlusions(rays),
                                      grid.test_occlusions(rays64.astype(np.float32)), err_msg=name)


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_rays_are_not_copied_and_results_written_in_place(dtype):
    """The only arrays a query allocates are its outputs: no full copy of the rays in numpy
    (float64 rays are converted chunk by chunk)."""
    vertices, triangles = generated_scene("sphere")
    grid = splitgrid.build(vertices, triangles)
    rays = np.tile(scene_rays(vertices, count=1000), (400, 1)).astype(dtype)
    n = len(rays)
    output_bytes = n * (4 + 4 + 8 + 12)
    grid.cast_rays(rays[:10])
    tracemalloc.start()
    try:
        result = grid.cast_rays(rays)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < output_bytes + (1 << 20), f"peak {peak} bytes for {output_bytes} of outputs"
    del result


def test_invalid_rays_are_counted_misses():
    vertices, triangles = generated_scene("sphere")
    grid = splitgrid.build(vertices, triangles)
    rays = np.tile(np.array([0, 0, 5, 0, 0, -1], np.float32), (2, 3, 1))
    rays[0, 1, 0] = np.nan
    rays[1, 0, 3:] = 0
    rays[1, 2, 4] = np.inf
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = grid.cast_rays(rays)
    assert len(caught) == 1 and caught[0].category is splitgrid.InvalidRayWarning
    assert re.search(r"rays: 3 of 6 rays are invalid .* the first is ray \(0, 1\)",
                     str(caught[0].message)), str(caught[0].message)
    invalid = np.zeros((2, 3), bool)
    invalid[0, 1] = invalid[1, 0] = invalid[1, 2] = True
    assert np.all(result["primitive_ids"][invalid] == splitgrid.INVALID_ID)
    assert np.all(np.isinf(result["t_hit"][invalid]))
    assert np.all(result["t_hit"][~invalid] == pytest.approx(4.0))
    # Ray 4 is valid but for its window: tnear > tfar.
    with pytest.warns(splitgrid.InvalidRayWarning, match="4 of 6 rays are invalid"):
        occluded = grid.test_occlusions(rays.reshape(-1, 6), tnear=np.array([0, 0, 0, 0, 3, 0.]),
                                        tfar=np.array([1, 9, 9, 9, 1, 9.]))
    np.testing.assert_array_equal(occluded, [False, False, True, False, False, False])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(splitgrid.InvalidRayWarning):
            grid.cast_rays(rays)


BAD_RAYS = [
    (np.zeros((4, 6), np.int64), {}, TypeError, "rays: dtype int64 is not supported"),
    (np.zeros((4, 6), np.float16), {}, TypeError, "rays: dtype float16"),
    (np.zeros((4, 6), np.complex64), {}, TypeError, "rays: dtype complex64"),
    (np.zeros((4, 5), np.float32), {}, ValueError,
     r"rays: expected an array of shape \(\.\.\., 6\), got shape \(4, 5\)"),
    (np.float32(1.0), {}, ValueError,
     r"rays: expected an array of shape \(\.\.\., 6\), got shape \(\)"),
    ("rays", {}, TypeError, "rays: dtype <U4"),
    (None, {}, TypeError, "rays: dtype object"),
    (np.zeros((4, 6), np.float32), {"tnear": np.zeros(3)}, ValueError,
     r"tnear: expected a number or an array of rays' leading shape \(4,\), got shape \(3,\)"),
    (np.zeros((2, 2, 6), np.float32), {"tfar": np.zeros((4,))}, ValueError,
     r"tfar: expected .* \(2, 2\), got shape \(4,\)"),
    (np.zeros((4, 6), np.float32), {"tnear": "near"}, TypeError, "tnear: dtype <U4"),
    (np.zeros((4, 6), np.float32), {"threads": -2}, ValueError, "threads = -2 is out of range"),
    (np.zeros((4, 6), np.float32), {"threads": "2"}, TypeError, "threads must be None or a whole"),
]


@pytest.mark.parametrize("rays, arguments, error, message", BAD_RAYS)
def test_bad_ray_arguments_raise_naming_the_argument(rays, arguments, error, message):
    grid = splitgrid.build(*generated_scene("sphere"))
    with pytest.raises(error, match=message):
        grid.cast_rays(rays, **arguments)
    with pytest.raises(error, match=message):
        grid.test_occlusions(rays, **arguments)


@pytest.fixture(scope="module")
def small_grid():
    vertices, triangles = generated_scene("soup")
    return vertices, triangles, splitgrid.build(vertices, triangles)


@settings(max_examples=200, deadline=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])
# Values in steps of 1e-3: a direction of denormals is a zero direction to every query
# (ray.hpp) but not to the double-precision oracle.
@given(rays=hnp.arrays(np.float64, hnp.array_shapes(min_dims=0, max_dims=4, min_side=0,
                                                    max_side=7),
                       elements=st.floats(-30, 30).map(lambda x: round(x, 3)) | st.sampled_from(
                           [0.0, np.nan, np.inf, -np.inf])),
       dtype=st.sampled_from([np.float32, np.float64, ">f4", np.int32]),
       tnear=st.sampled_from([0.0, -1.0, 2.0, np.nan, "array"]))
def test_random_ray_arrays_raise_or_are_answered_right(small_grid, rays, dtype, tnear):
    vertices, triangles, grid = small_grid
    with np.errstate(invalid="ignore"):
        rays = rays.astype(dtype)
    if tnear == "array":
        tnear = np.full(rays.shape[:-1] if rays.ndim else (), 0.5)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", splitgrid.InvalidRayWarning)
        try:
            result = grid.cast_rays(rays, tnear=tnear)
        except (TypeError, ValueError) as error:
            assert re.match(r"(rays|tnear)", str(error)), str(error)
            return
    assert rays.dtype.kind == "f" and rays.shape[-1] == 6
    assert result["t_hit"].shape == rays.shape[:-1]
    flat = rays.reshape(-1, 6).astype(np.float32)
    valid = (np.all(np.isfinite(flat), axis=1) & np.any(flat[:, 3:] != 0, axis=1)
             & np.isfinite(np.broadcast_to(tnear, rays.shape[:-1]).reshape(-1)))
    ids = result["primitive_ids"].reshape(-1)
    assert np.all(ids[~valid] == splitgrid.INVALID_ID)
    subset = {key: value.reshape((len(flat),) + value.shape[rays.ndim - 1:])[valid]
              for key, value in result.items()}
    near = np.broadcast_to(tnear, rays.shape[:-1]).reshape(-1)[valid]
    check_cast_rays(grid.vertices, triangles, flat[valid], subset, tnear=near)


def test_answers_are_sg_traces_answers(tmp_path):
    """The same .sg and rays through sg-trace: the same triangle, t, u and v, bit for bit
    (the same kernels); test_occlusions as sg-trace --any-hit."""
    vertices, triangles = generated_scene("soup")
    path = tmp_path / "soup.sg"
    splitgrid.build(vertices, triangles).save(path)
    grid = splitgrid.load(path)
    rays = scene_rays(vertices, count=5000, seed=9)
    tnear = np.random.default_rng(10).uniform(0, 0.2, len(rays)).astype(np.float32)
    tfar = np.where(np.arange(len(rays)) % 3 == 0, np.float32(0.8), np.float32(np.inf))
    write_ray_file(tmp_path / "rays.bin", rays, tnear, tfar)
    run_tool(tool("sg-trace"), path, "--rays", tmp_path / "rays.bin", "-o", tmp_path / "hits.bin",
             "-q")
    hits = read_hit_file(tmp_path / "hits.bin")
    result = grid.cast_rays(rays, tnear=tnear, tfar=tfar)
    np.testing.assert_array_equal(result["primitive_ids"], hits["id"])
    hit = hits["id"] != splitgrid.INVALID_ID
    assert hit.sum() > 1000
    np.testing.assert_array_equal(result["t_hit"][hit], hits["t"][hit])
    np.testing.assert_array_equal(result["primitive_uvs"][hit, 0], hits["u"][hit])
    np.testing.assert_array_equal(result["primitive_uvs"][hit, 1], hits["v"][hit])
    run_tool(tool("sg-trace"), path, "--rays", tmp_path / "rays.bin", "-o", tmp_path / "any.bin",
             "--any-hit", "-q")
    any_hits = read_hit_file(tmp_path / "any.bin")
    np.testing.assert_array_equal(grid.test_occlusions(rays, tnear=tnear, tfar=tfar),
                                  any_hits["id"] != splitgrid.INVALID_ID)


def test_the_thread_count_does_not_change_the_answers(small_grid):
    vertices, _, grid = small_grid
    rays = scene_rays(vertices, count=20000)
    reference = grid.cast_rays(rays, threads=1)
    for threads in (2, 3, 0, None):
        result = grid.cast_rays(rays, threads=threads)
        for key in reference:
            np.testing.assert_array_equal(result[key], reference[key])


def test_several_python_threads_query_one_grid_at_once(small_grid):
    vertices, triangles, grid = small_grid
    ray_sets = [scene_rays(vertices, count=30000, seed=seed) for seed in range(6)]
    expected = [grid.cast_rays(rays, threads=1) for rays in ray_sets]
    expected_occluded = [grid.test_occlusions(rays, threads=1) for rays in ray_sets]
    failures = []

    def query(k):
        for _ in range(3):
            result = grid.cast_rays(ray_sets[k], threads=2)
            occluded = grid.test_occlusions(ray_sets[k])
            if not all(np.array_equal(result[key], expected[k][key]) for key in result):
                failures.append(k)
            if not np.array_equal(occluded, expected_occluded[k]):
                failures.append(k)

    threads = [threading.Thread(target=query, args=(k,)) for k in range(len(ray_sets))]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert not failures
    check_cast_rays(grid.vertices, triangles, ray_sets[0][:500],
                    {key: value[:500] for key, value in expected[0].items()})


def test_queries_release_the_gil():
    vertices, triangles = sphere(rings=60, segments=120)
    grid = splitgrid.build(vertices, triangles)
    rays = np.tile(scene_rays(vertices, count=10000), (100, 1))
    steps = other_thread_steps_during(lambda: grid.cast_rays(rays, threads=1))
    assert steps > 1000, f"the other thread ran only {steps} times during the query"
