"""count_intersections, list_intersections, compute_occupancy, compute_closest_points,
compute_distance and compute_signed_distance: against brute force in double precision (and the
winding number for the side), on generated and real meshes, with rays and points on shared
edges and vertices, every shape, and bad arguments."""

import numpy as np
import pytest

import splitgrid
from conftest import SHARED_SCENES, random_rays, shared_mesh, sphere, triangle_soup
from oracle import all_hits, point_distances, winding_numbers


def closed_box(n=4):
    """The cube [0, n]^3 with each face cut into n x n unit squares of two triangles, wound
    outwards, its vertices shared: rays along its grid lines meet edges and vertices."""
    index = {}
    vertices = []
    triangles = []

    def vertex(p):
        key = tuple(p)
        if key not in index:
            index[key] = len(vertices)
            vertices.append(key)
        return index[key]

    for axis in range(3):
        for side in (0, n):
            u_axis, v_axis = (axis + 1) % 3, (axis + 2) % 3
            for i in range(n):
                for j in range(n):
                    corners = []
                    for di, dj in ((0, 0), (1, 0), (1, 1), (0, 1)):
                        p = [0, 0, 0]
                        p[axis], p[u_axis], p[v_axis] = side, i + di, j + dj
                        corners.append(vertex(p))
                    a, b, c, d = corners
                    quad = [[a, b, c], [a, c, d]] if side == n else [[a, c, b], [a, d, c]]
                    triangles += quad
    return np.array(vertices, dtype=np.float64), np.array(triangles, dtype=np.int64)


@pytest.fixture(scope="module")
def box():
    vertices, triangles = closed_box()
    return vertices, triangles, splitgrid.build(vertices, triangles)


@pytest.fixture(scope="module")
def ball():
    vertices, triangles = sphere(rings=20, segments=40)
    return vertices, triangles, splitgrid.build(vertices, triangles)


def test_the_box_is_wound_outwards(box):
    vertices, triangles, _ = box
    assert np.allclose(winding_numbers(vertices, triangles, [[2.0, 2.0, 2.0], [9.0, 2, 2]]),
                       [1.0, 0.0])


def test_rays_along_the_grid_lines_cross_the_box_once_per_face(box):
    vertices, triangles, grid = box
    # Through every vertex and every edge midpoint of the z = 0 and z = 4 faces, straight up:
    # a vertex has up to 6 triangles around it, an edge 2; each face is crossed exactly once.
    coords = np.arange(0.0, 4.01, 0.5)
    x, y = np.meshgrid(coords[1:-1], coords[1:-1])
    rays = np.column_stack([x.ravel(), y.ravel(), np.full(x.size, -1.0),
                            np.zeros(x.size), np.zeros(x.size), np.ones(x.size)])
    assert np.all(grid.count_intersections(rays) == 2)
    listed = grid.list_intersections(rays)
    assert np.array_equal(np.diff(listed["ray_splits"]), np.full(len(rays), 2))
    assert np.allclose(listed["t_hit"].reshape(-1, 2), [[1.0, 5.0]])
    # From the middle of the box the count is odd, from outside even.
    inside = rays.copy()
    inside[:, 2] = 2.0
    assert np.all(grid.count_intersections(inside) == 1)


def test_counts_and_lists_agree_with_brute_force(ball):
    vertices, triangles, grid = ball
    rays = random_rays(np.random.default_rng(5), 400, vertices)
    sure, possible, t = all_hits(vertices, triangles, rays)
    counts = grid.count_intersections(rays)
    assert counts.dtype == np.int32
    listed = grid.list_intersections(rays)
    splits = listed["ray_splits"]
    assert splits[0] == 0 and splits[-1] == len(listed["t_hit"]) and len(splits) == len(rays) + 1
    assert np.array_equal(np.diff(splits), counts)
    crossed = 0
    for k in range(len(rays)):
        ids = listed["primitive_ids"][splits[k]:splits[k + 1]].astype(np.int64)
        t_k = listed["t_hit"][splits[k]:splits[k + 1]]
        assert np.all(listed["ray_ids"][splits[k]:splits[k + 1]] == k)
        assert len(set(ids)) == len(ids), f"ray {k} lists a triangle twice"
        assert sure[k] <= set(ids) <= possible[k], f"ray {k}: {sorted(ids)} vs {sorted(sure[k])}"
        assert np.all(np.diff(t_k) >= 0), f"ray {k}: hits not sorted by t"
        assert np.allclose(t_k, t[k, ids], rtol=1e-4, atol=1e-6)
        crossed += len(ids)
    assert crossed > 200


def test_tnear_and_tfar_bound_the_counted_hits(box):
    _, _, grid = box
    rays = np.array([[1.5, 1.5, -1.0, 0, 0, 1]] * 4, dtype=np.float32)
    counts = grid.count_intersections(rays, tnear=[0.0, 2.0, 0.0, 0.0], tfar=[np.inf, 9, 3, 0.5])
    assert counts.tolist() == [2, 1, 1, 0]


def test_occupancy_and_signed_distance_follow_the_winding_number(ball):
    vertices, triangles, grid = ball
    rng = np.random.default_rng(8)
    points = rng.uniform(-1.3, 1.3, size=(1500, 3)).astype(np.float32)
    winding = winding_numbers(vertices, triangles, points)
    distance, _ = point_distances(vertices, triangles, points)
    clear = distance > 1e-4  # the exact band is 2^-17 of the box; no point lies that near
    assert clear.sum() > 1400
    occupancy = grid.compute_occupancy(points)
    assert occupancy.dtype == np.float32
    assert np.array_equal(occupancy[clear], np.round(winding[clear]).astype(np.float32))
    signed = grid.compute_signed_distance(points)
    expected = np.where(np.round(winding) == 1, -distance, distance)
    assert np.allclose(signed[clear], expected[clear], rtol=1e-5, atol=1e-6)


def test_occupancy_is_exact_on_the_boxs_grid_points(box):
    vertices, triangles, grid = box
    # Points on a half-unit lattice inside and around the box, off the surface: their rays run
    # along the box's grid lines and through its vertices.
    coords = np.arange(-0.5, 4.51, 0.5)
    p = np.stack(np.meshgrid(coords, coords, coords, indexing="ij"), axis=-1).reshape(-1, 3)
    on_surface = np.any((p == 0) | (p == 4), axis=1) & np.all((p >= 0) & (p <= 4), axis=1)
    p = p[~on_surface]
    expected = np.all((p > 0) & (p < 4), axis=1).astype(np.float32)
    assert np.array_equal(grid.compute_occupancy(p), expected)
    assert np.array_equal(grid.compute_occupancy(p, nsamples=5), expected)


def check_closest(vertices, triangles, points, result):
    distance, nearest = point_distances(vertices, triangles, points)
    ids = result["primitive_ids"].astype(np.int64)
    got = np.linalg.norm(result["points"].astype(np.float64) - points, axis=1)
    assert np.allclose(got, distance, rtol=1e-5, atol=1e-6)
    wrong = [k for k in range(len(points)) if ids[k] not in nearest[k]]
    assert not wrong, f"{len(wrong)} points got a triangle that is not closest, e.g. {wrong[0]}"
    tied = [k for k in range(len(points)) if len(nearest[k]) > 1]
    for k in tied:  # equal distances: the smallest id
        assert ids[k] == min(nearest[k]), f"point {k}: {ids[k]} of {sorted(nearest[k])}"
    # The closest point is the triangle's point at the reported barycentrics.
    tri = np.asarray(vertices, dtype=np.float64)[np.asarray(triangles)[ids]]
    u, v = result["primitive_uvs"][:, 0:1], result["primitive_uvs"][:, 1:2]
    at = (1 - u - v) * tri[:, 0] + u * tri[:, 1] + v * tri[:, 2]
    assert np.allclose(at, result["points"], atol=1e-5)
    normal = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    normal /= np.linalg.norm(normal, axis=1, keepdims=True)
    assert np.allclose(result["primitive_normals"], normal, atol=1e-5)
    return len(tied)


def test_closest_points_agree_with_brute_force_near_far_and_on_the_mesh():
    rng = np.random.default_rng(9)
    vertices, triangles = triangle_soup(rng, count=300)
    vertices = vertices.astype(np.float32)
    grid = splitgrid.build(vertices, triangles)
    far = rng.uniform(-30, 30, size=(300, 3))
    on_vertices = vertices[rng.integers(0, len(vertices), 100)]
    midpoints = (vertices[triangles[:60, 0]] + vertices[triangles[:60, 1]]) / 2
    points = np.concatenate([far, on_vertices, midpoints]).astype(np.float32)
    check_closest(vertices, triangles, points, grid.compute_closest_points(points))
    assert np.allclose(grid.compute_distance(points),
                       point_distances(vertices, triangles, points)[0], rtol=1e-5, atol=1e-6)


def test_a_point_equally_near_several_faces_gets_the_smallest_id(box):
    vertices, triangles, grid = box
    points = np.array([[2.0, 2.0, 2.0], [0.5, 0.5, 0.5], [2.0, 2.0, 6.0], [-1.0, -1.0, -1.0]],
                      dtype=np.float32)
    assert check_closest(vertices, triangles, points, grid.compute_closest_points(points)) >= 3


@pytest.mark.parametrize("name", SHARED_SCENES[:2])
def test_real_scenes_distances_agree_with_brute_force(name):
    vertices, triangles = splitgrid.import_mesh(shared_mesh(name))
    grid = splitgrid.build(vertices, triangles)
    rng = np.random.default_rng(12)
    lower, upper = vertices.min(axis=0), vertices.max(axis=0)
    box_points = rng.uniform(lower, upper, size=(60, 3))
    near = vertices[rng.integers(0, len(vertices), 60)] + rng.normal(
        scale=1e-3 * np.linalg.norm(upper - lower), size=(60, 3))
    points = np.concatenate([box_points, near]).astype(np.float32)
    check_closest(vertices, triangles, points, grid.compute_closest_points(points))


def test_max_distance_leaves_far_points_without_an_answer(ball):
    _, _, grid = ball
    points = np.array([[0.0, 0.0, 0.0], [0.0, 0.0, 5.0], [0.0, 0.0, 1.05]], dtype=np.float32)
    result = grid.compute_closest_points(points, max_distance=0.5)
    assert result["primitive_ids"].tolist()[:2] == [splitgrid.INVALID_ID] * 2
    assert result["primitive_ids"][2] != splitgrid.INVALID_ID
    assert np.all(np.isnan(result["points"][:2]))
    distance = grid.compute_distance(points, max_distance=0.5)
    assert np.isinf(distance[:2]).all() and 0.04 < distance[2] < 0.06
    assert np.isinf(grid.compute_signed_distance(points, max_distance=0.5)[:2]).all()


def test_shapes_dtypes_and_non_finite_points(ball):
    _, _, grid = ball
    points = np.random.default_rng(1).uniform(-1, 1, size=(4, 5, 3))  # float64
    assert grid.compute_distance(points).shape == (4, 5)
    assert grid.compute_occupancy(points).shape == (4, 5)
    assert grid.compute_signed_distance(points).dtype == np.float32
    result = grid.compute_closest_points(points)
    assert result["points"].shape == (4, 5, 3) and result["primitive_uvs"].shape == (4, 5, 2)
    assert grid.compute_distance(np.zeros(3)).shape == ()
    assert grid.count_intersections(np.zeros((2, 3, 6)) + [0, 0, 5, 0, 0, -1]).tolist() == \
        [[2, 2, 2], [2, 2, 2]]
    bad = np.array([[np.nan, 0, 0], [0, np.inf, 0]], dtype=np.float32)
    assert np.isnan(grid.compute_distance(bad)).all()
    assert np.isnan(grid.compute_occupancy(bad)).all()
    assert np.isnan(grid.compute_signed_distance(bad)).all()
    assert (grid.compute_closest_points(bad)["primitive_ids"] == splitgrid.INVALID_ID).all()


def test_answers_do_not_depend_on_the_thread_count(ball):
    _, _, grid = ball
    points = np.random.default_rng(2).uniform(-1.5, 1.5, size=(5000, 3)).astype(np.float32)
    rays = random_rays(np.random.default_rng(3), 3000, grid.vertices)
    assert np.array_equal(grid.compute_signed_distance(points, threads=1),
                          grid.compute_signed_distance(points, threads=2))
    one, two = grid.list_intersections(rays, threads=1), grid.list_intersections(rays, threads=2)
    for key in one:
        assert np.array_equal(one[key], two[key]), key


@pytest.mark.parametrize("call, message", [
    (lambda g: g.compute_occupancy(np.zeros((2, 3)), nsamples=2), "nsamples = 2"),
    (lambda g: g.compute_signed_distance(np.zeros((2, 3)), nsamples=0), "nsamples = 0"),
    (lambda g: g.compute_distance(np.zeros((2, 3)), max_distance=0), "max_distance"),
    (lambda g: g.compute_distance(np.zeros((2, 4))), r"points: expected an array of shape \(\.\.\., 3\)"),
    (lambda g: g.count_intersections(np.zeros((2, 3))), r"rays: expected an array of shape"),
    (lambda g: g.compute_closest_points(np.zeros((2, 3), dtype=np.int32)), "dtype int32"),
])
def test_bad_arguments_are_refused_with_a_message(ball, call, message):
    _, _, grid = ball
    with pytest.raises((ValueError, TypeError), match=message):
        call(grid)


def test_invalid_rays_count_nothing_and_warn(ball):
    _, _, grid = ball
    rays = np.array([[0, 0, 5, 0, 0, -1], [0, 0, 5, 0, 0, 0]], dtype=np.float32)
    with pytest.warns(splitgrid.InvalidRayWarning):
        assert grid.count_intersections(rays).tolist() == [2, 0]
    with pytest.warns(splitgrid.InvalidRayWarning):
        assert grid.list_intersections(rays)["ray_splits"].tolist() == [0, 2, 2]


def test_an_open_mesh_warns_once_per_side_query_and_a_closed_one_does_not(ball):
    import warnings
    vertices, triangles, grid = ball
    points = np.zeros((3, 3), dtype=np.float32)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        grid.compute_occupancy(points)
        grid.compute_signed_distance(points)
    half = splitgrid.build(vertices, triangles[: len(triangles) // 2])  # a bowl: open edges
    expected = half.stats()["edges"]["open_edges"]
    assert expected > 0
    for query in (half.compute_occupancy, half.compute_signed_distance):
        with pytest.warns(splitgrid.OpenMeshWarning, match=f"{expected} open edges") as caught:
            query(points)
        assert len(caught) == 1
