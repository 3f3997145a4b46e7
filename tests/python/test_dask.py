"""splitgrid.dask on a distributed.LocalCluster of two worker processes: the same answers as
one process, each worker reading the .sg file once."""

import numpy as np
import pytest

import splitgrid
from conftest import random_rays, require_module, sphere

da = require_module("dask.array")
distributed = require_module("distributed")
import dask  # noqa: E402
import splitgrid.dask  # noqa: E402


@pytest.fixture(scope="module")
def scene(tmp_path_factory):
    vertices, triangles = sphere(rings=40, segments=80)
    path = tmp_path_factory.mktemp("dask") / "ball.sg"
    splitgrid.build(vertices, triangles).save(path)
    rays = random_rays(np.random.default_rng(4), 60 * 80, vertices).reshape(60, 80, 6)
    return path, rays


@pytest.fixture(scope="module")
def client():
    with distributed.LocalCluster(n_workers=2, threads_per_worker=2, processes=True,
                                  dashboard_address=None) as cluster:
        with distributed.Client(cluster) as client:
            yield client


def test_cast_rays_on_two_workers_equals_one_process(scene, client):
    path, rays = scene
    expected = splitgrid.load(path).cast_rays(rays)
    chunked = da.from_array(rays, chunks=(15, 40, 3))  # the ray axis split too: rejoined
    result = splitgrid.dask.cast_rays(path, chunked)
    assert result["primitive_uvs"].shape == (60, 80, 2)
    (computed,) = dask.compute(result)
    for key, value in expected.items():
        assert computed[key].dtype == value.dtype
        np.testing.assert_array_equal(computed[key], value, err_msg=key)
    # Blocks ran on both workers, and each read the file once.
    loaded = client.run(lambda: len(splitgrid.dask._grids))
    assert sorted(loaded.values()) == [1, 1]


def test_test_occlusions_with_windows_on_two_workers(scene, client):
    path, rays = scene
    tnear = np.random.default_rng(5).uniform(0, 0.5, rays.shape[:-1])
    tfar = tnear + 0.4
    expected = splitgrid.load(path).test_occlusions(rays, tnear=tnear, tfar=tfar)
    result = splitgrid.dask.test_occlusions(
        path, da.from_array(rays.astype(np.float64), chunks=(20, 20, 6)),
        tnear=da.from_array(tnear, chunks=(30, 40)), tfar=tfar)
    np.testing.assert_array_equal(result.compute(), expected)
    assert expected.any() and not expected.all()


def test_bad_rays_are_refused_before_anything_runs(scene):
    path, _ = scene
    with pytest.raises(ValueError, match="rays: expected an array of shape"):
        splitgrid.dask.cast_rays(path, da.zeros((10, 5), chunks=5))
    with pytest.raises(TypeError, match="rays: dtype int64"):
        splitgrid.dask.cast_rays(path, da.zeros((10, 6), dtype=np.int64, chunks=5))
