"""Open3D's interface: create_rays_pinhole against Open3D's own (which works on Debian 12), and
splitgrid.RaycastingScene running code written for open3d.t.geometry.RaycastingScene."""

import numpy as np
import pytest

import splitgrid
from conftest import require_module, sphere
from oracle import check_cast_rays, check_occlusions

o3d = require_module("open3d")


@pytest.mark.parametrize("fov, center, eye, up, width, height", [
    (90, [0, 0, 2], [2, 3, 0], [0, 1, 0], 4, 3),
    (60, [0.1, -0.2, 0.3], [5, 1, -4], [0, 0, 1], 64, 48),
    (20, [0, 0, 0], [0, 0, -10], [0.3, 1, 0], 31, 17),
])
def test_create_rays_pinhole_is_open3ds(fov, center, eye, up, width, height):
    ours = splitgrid.create_rays_pinhole(fov, center, eye, up, width, height)
    theirs = o3d.t.geometry.RaycastingScene.create_rays_pinhole(
        fov_deg=fov, center=center, eye=eye, up=up, width_px=width, height_px=height).numpy()
    assert ours.dtype == np.float32 and ours.shape == (height, width, 6)
    np.testing.assert_allclose(ours, theirs, rtol=1e-5, atol=1e-5)


def test_create_rays_pinhole_with_matrices_is_open3ds():
    intrinsic = np.array([[400.0, 0, 160], [0, 380, 110], [0, 0, 1]])
    angle = 0.4
    extrinsic = np.eye(4)
    extrinsic[:3, :3] = [[np.cos(angle), 0, np.sin(angle)], [0, 1, 0],
                         [-np.sin(angle), 0, np.cos(angle)]]
    extrinsic[:3, 3] = [0.5, -1.0, 4.0]
    ours = splitgrid.create_rays_pinhole(intrinsic, extrinsic, 320, 240)
    theirs = o3d.t.geometry.RaycastingScene.create_rays_pinhole(
        o3d.core.Tensor(intrinsic), o3d.core.Tensor(extrinsic), 320, 240).numpy()
    np.testing.assert_allclose(ours, theirs, rtol=1e-5, atol=1e-5)


def test_create_rays_pinhole_refuses_bad_cameras():
    with pytest.raises(ValueError, match="fov_deg"):
        splitgrid.create_rays_pinhole(180, [0, 0, 0], [0, 0, 1], [0, 1, 0], 4, 4)
    with pytest.raises(ValueError, match="up: parallel"):
        splitgrid.create_rays_pinhole(60, [0, 0, 0], [0, 1, 0], [0, 1, 0], 4, 4)
    with pytest.raises(ValueError, match="width_px"):
        splitgrid.create_rays_pinhole(60, [0, 0, 0], [0, 0, 1], [0, 1, 0], 0, 4)
    with pytest.raises(ValueError, match="center"):
        splitgrid.create_rays_pinhole(60, [0, 0], [0, 0, 1], [0, 1, 0], 4, 4)
    with pytest.raises(TypeError, match="missing arguments: height_px"):
        splitgrid.create_rays_pinhole(60, [0, 0, 0], [0, 0, 1], [0, 1, 0], 4)


def test_open3d_code_runs_unchanged_on_splitgrid():
    """Open3D's documented example (a box, rays as tensors, results read with .numpy()), with
    only the class replaced."""
    RaycastingScene = splitgrid.RaycastingScene  # instead of o3d.t.geometry.RaycastingScene
    cube = o3d.t.geometry.TriangleMesh.from_legacy(o3d.geometry.TriangleMesh.create_box())
    scene = RaycastingScene()
    cube_id = scene.add_triangles(cube)
    rays = o3d.core.Tensor([[0.5, 0.5, 10, 0, 0, -1], [-1, -1, -1, 0, 0, -1]],
                           dtype=o3d.core.Dtype.Float32)
    ans = scene.cast_rays(rays)
    np.testing.assert_array_equal(ans["t_hit"].numpy(), [9.0, np.inf])
    np.testing.assert_array_equal(ans["geometry_ids"].numpy(), [cube_id, scene.INVALID_ID])
    np.testing.assert_array_equal(ans["primitive_normals"].numpy()[0], [0, 0, 1])
    occluded = scene.test_occlusions(rays, tfar=5.0).numpy()
    np.testing.assert_array_equal(occluded, [False, False])
    image_rays = RaycastingScene.create_rays_pinhole(fov_deg=90, center=[0.5, 0.5, 0.5],
                                                     eye=[-1, 2, 3], up=[0, 1, 0], width_px=32,
                                                     height_px=24)
    image = {key: value.numpy() for key, value in
             scene.cast_rays(o3d.core.Tensor(image_rays)).items()}
    assert image["t_hit"].shape == (24, 32)
    assert check_cast_rays(cube.vertex["positions"].numpy(), cube.triangle["indices"].numpy(),
                           image_rays, image) > 20


def test_several_geometries_have_their_own_ids():
    box = o3d.geometry.TriangleMesh.create_box()
    ball_vertices, ball_triangles = sphere(rings=16, segments=32, radius=0.4,
                                           center=(3.0, 0.5, 0.5))
    scene = splitgrid.RaycastingScene(nthreads=1)
    assert scene.add_triangles(box) == 0
    assert scene.add_triangles(ball_vertices.astype(np.float32),
                               ball_triangles.astype(np.uint32)) == 1
    rng = np.random.default_rng(3)
    targets = np.concatenate([rng.uniform(0, 1, (300, 3)),
                              rng.uniform(2.6, 3.4, (300, 3)) * [1, 0.4, 0.4] + [0, 0.3, 0.3]])
    origins = rng.uniform(-3, 6, (600, 3))
    rays = np.concatenate([origins, targets - origins], axis=1).astype(np.float32)
    ans = scene.cast_rays(rays)
    # The oracle over both meshes as one, ids mapped back to each geometry's own.
    box_vertices, box_triangles = np.asarray(box.vertices), np.asarray(box.triangles)
    vertices = np.concatenate([box_vertices, ball_vertices]).astype(np.float32)
    triangles = np.concatenate([box_triangles, ball_triangles + len(box_vertices)])
    hit = ans["primitive_ids"] != splitgrid.INVALID_ID
    global_ids = ans["primitive_ids"].astype(np.int64)
    global_ids[hit & (ans["geometry_ids"] == 1)] += len(box_triangles)
    combined = dict(ans, primitive_ids=np.where(hit, global_ids, splitgrid.INVALID_ID))
    check_cast_rays(vertices, triangles, rays, combined)
    assert set(np.unique(ans["geometry_ids"][hit])) == {0, 1}
    check_occlusions(vertices, triangles, rays, scene.test_occlusions(rays))


def test_an_empty_scene_answers_misses():
    scene = splitgrid.RaycastingScene()
    ans = scene.cast_rays(np.array([[0, 0, 0, 1, 0, 0]], np.float32))
    assert np.isinf(ans["t_hit"][0]) and ans["geometry_ids"][0] == splitgrid.INVALID_ID


def test_open3ds_counting_and_point_examples_run_unchanged():
    """Open3D's documented count_intersections example (rays into its unit box), and its
    point queries, with only the class replaced."""
    cube = o3d.t.geometry.TriangleMesh.from_legacy(o3d.geometry.TriangleMesh.create_box())
    scene = splitgrid.RaycastingScene()
    scene.add_triangles(cube)
    rays = o3d.core.Tensor([[0.5, 0.5, -1, 0, 0, 1], [0.5, 0.5, 0.5, 0, 0, 1],
                            [10, 10, 10, 1, 0, 0]], dtype=o3d.core.Dtype.Float32)
    np.testing.assert_array_equal(scene.count_intersections(rays).numpy(), [2, 1, 0])
    listed = scene.list_intersections(rays)
    np.testing.assert_array_equal(listed["ray_splits"].numpy(), [0, 2, 3, 3])
    np.testing.assert_allclose(listed["t_hit"].numpy(), [1.0, 2.0, 0.5])
    query = o3d.core.Tensor([[0.5, 0.5, 0.5], [2.0, 0.5, 0.5]], dtype=o3d.core.Dtype.Float32)
    np.testing.assert_allclose(scene.compute_distance(query).numpy(), [0.5, 1.0])
    np.testing.assert_allclose(scene.compute_signed_distance(query).numpy(), [-0.5, 1.0])
    np.testing.assert_array_equal(scene.compute_occupancy(query).numpy(), [1.0, 0.0])
    closest = scene.compute_closest_points(query)
    np.testing.assert_allclose(closest["points"].numpy()[1], [1.0, 0.5, 0.5])
    np.testing.assert_array_equal(closest["geometry_ids"].numpy(), [0, 0])


def test_distances_agree_with_open3ds():
    """Open3D 0.16's closest point query works on Debian 12: a second, independent answer."""
    vertices, triangles = sphere(rings=24, segments=48)
    vertices = vertices.astype(np.float32)
    theirs = o3d.t.geometry.RaycastingScene()
    theirs.add_triangles(o3d.core.Tensor(vertices), o3d.core.Tensor(triangles.astype(np.uint32)))
    grid = splitgrid.build(vertices, triangles)
    points = np.random.default_rng(4).uniform(-2, 2, size=(3000, 3)).astype(np.float32)
    expected = theirs.compute_distance(o3d.core.Tensor(points)).numpy()
    np.testing.assert_allclose(grid.compute_distance(points), expected, rtol=1e-5, atol=1e-6)
    closest = theirs.compute_closest_points(o3d.core.Tensor(points))["points"].numpy()
    ours = grid.compute_closest_points(points)["points"]
    # Where two triangles are equally near, the two may pick different points at the same
    # distance (ours: the smallest triangle id).
    differ = np.abs(ours - closest).max(axis=1) > 1e-5
    assert differ.mean() < 0.01
    np.testing.assert_allclose(np.linalg.norm(ours[differ] - points[differ], axis=1),
                               np.linalg.norm(closest[differ] - points[differ], axis=1),
                               rtol=1e-5)
