"""Ray queries over dask arrays: rays beyond one process, or one machine.

Each block of rays is answered by SplitGrid.cast_rays or test_occlusions in the worker that
holds it; every worker process loads the ``.sg`` file once (the first block it gets) and keeps
it for the blocks that follow. The file must be readable at the same path on every worker (a
shared or copied folder: docs/PYTHON.md, "Beyond one machine").

    import dask.array as da, splitgrid.dask
    rays = da.from_array(rays_numpy, chunks=(250_000, 6))
    hits = splitgrid.dask.cast_rays("scene.sg", rays)
    t_hit = hits["t_hit"].compute()          # on the active scheduler or distributed.Client
"""

import os
import threading

import dask.array as da
import numpy as np

from ._splitgrid import load

_grids = {}
_grids_lock = threading.Lock()


def _grid(path):
    """The SplitGrid of `path`, read once per process (again if the file changes)."""
    status = os.stat(path)
    key = (os.path.abspath(path), status.st_mtime_ns, status.st_size)
    with _grids_lock:
        grid = _grids.get(key)
        if grid is None:
            grid = _grids[key] = load(path)
        return grid


def _cast_block(rays, tnear, tfar, *, sg_path, threads):
    result = _grid(sg_path).cast_rays(rays, tnear=tnear, tfar=tfar, threads=threads)
    return (result["t_hit"], result["primitive_ids"], result["primitive_uvs"],
            result["primitive_normals"])


def _occlusion_block(rays, tnear, tfar, *, sg_path, threads):
    return _grid(sg_path).test_occlusions(rays, tnear=tnear, tfar=tfar, threads=threads)


def _ray_arguments(rays, tnear, tfar):
    rays = da.asarray(rays)
    if rays.ndim < 1 or rays.shape[-1] != 6:
        raise ValueError(f"rays: expected an array of shape (..., 6), got shape {rays.shape}")
    if rays.dtype.kind != "f" or rays.dtype.itemsize not in (4, 8):
        raise TypeError(f"rays: dtype {rays.dtype} is not supported; give float32 or float64")
    # A block must hold whole rays: the last axis in one chunk.
    if len(rays.chunks[-1]) != 1:
        rays = rays.rechunk({rays.ndim - 1: 6})
    windows = []
    for name, value in (("tnear", tnear), ("tfar", tfar)):
        value = da.asarray(value, dtype=np.float64)
        if value.ndim != 0:
            if value.shape != rays.shape[:-1]:
                raise ValueError(f"{name}: expected a number or an array of rays' leading shape "
                                 f"{rays.shape[:-1]}, got shape {value.shape}")
            value = value.rechunk(rays.chunks[:-1])  # block by block with the rays
        windows.append(value)
    return (rays, *windows)


def cast_rays(sg_path, rays, *, tnear=0.0, tfar=np.inf, threads=None):
    """SplitGrid.cast_rays over a dask array of rays.

    Parameters
    ----------
    sg_path : str or os.PathLike
        The .sg file, readable at this path by every worker.
    rays : dask.array.Array or array_like, float32 or float64, shape (..., 6)
        Any chunks along the leading axes; the last axis is made one chunk.
    tnear, tfar : float or array_like of the rays' leading shape, optional
    threads : int or None, optional
        oneTBB threads per block (None: all of the worker's machine).

    Returns
    -------
    dict of dask.array.Array
        t_hit (...), primitive_ids (...), primitive_uvs (..., 2), primitive_normals
        (..., 3), as SplitGrid.cast_rays returns them, chunked as the rays. Computing
        several of them together traces each block once.
    """
    rays, tnear, tfar = _ray_arguments(rays, tnear, tfar)
    outputs = da.apply_gufunc(
        _cast_block, "(r),(),()->(),(),(u),(n)", rays, tnear, tfar,
        output_dtypes=[np.float32, np.uint32, np.float32, np.float32],
        output_sizes={"u": 2, "n": 3}, sg_path=os.fspath(sg_path), threads=threads)
    names = ("t_hit", "primitive_ids", "primitive_uvs", "primitive_normals")
    return dict(zip(names, outputs))


def test_occlusions(sg_path, rays, *, tnear=0.0, tfar=np.inf, threads=None):
    """SplitGrid.test_occlusions over a dask array of rays: a dask array of bool of the rays'
    leading shape. Parameters as for cast_rays."""
    rays, tnear, tfar = _ray_arguments(rays, tnear, tfar)
    return da.apply_gufunc(_occlusion_block, "(r),(),()->()", rays, tnear, tfar,
                           output_dtypes=bool, sg_path=os.fspath(sg_path), threads=threads)


# pytest would take a module-level function named test_* in an imported module for a test.
test_occlusions.__test__ = False
