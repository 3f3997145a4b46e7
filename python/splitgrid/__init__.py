"""The Split Grid ray-tracing acceleration structure, from Python.

numpy arrays in, numpy arrays out, with the names and shapes of Open3D's
``RaycastingScene``::

    import numpy as np, splitgrid
    vertices, triangles = splitgrid.import_mesh("bunny.obj")
    grid = splitgrid.build(vertices, triangles)
    rays = splitgrid.create_rays_pinhole(60, center=[0, 0.1, 0], eye=[0, 0.1, 0.3],
                                         up=[0, 1, 0], width_px=640, height_px=480)
    depth = grid.cast_rays(rays)["t_hit"]            # (480, 640) float32, inf on a miss

The package:

- ``build(vertices, triangles, *, preset, threads, **params)`` and ``load(path)``
  make a ``SplitGrid``; ``SplitGrid.save(path)`` writes a ``.sg`` file.
- ``SplitGrid.cast_rays``, ``test_occlusions``, ``count_intersections`` and
  ``list_intersections`` answer rays of any leading shape ``(..., 6)``;
  ``create_rays_pinhole`` makes a camera's rays.
- ``SplitGrid.compute_closest_points``, ``compute_distance``,
  ``compute_signed_distance`` and ``compute_occupancy`` answer points
  ``(..., 3)``; the side of a point is exact, never a vote.
- ``import_mesh(path)`` reads any mesh file as ``sg-build`` reads it.
- ``RaycastingScene`` runs code written for Open3D's class unchanged.
- ``splitgrid.dask`` (imported on its own) traces dask arrays of rays on a
  cluster.

docs/PYTHON.md documents every function with shapes and dtypes.
"""

from ._splitgrid import (
    INVALID_ID,
    FormatError,
    InvalidRayWarning,
    MeshImportWarning,
    OpenMeshWarning,
    SplitGrid,
    __version__,
    build,
    import_mesh,
    kernel_isa,
    load,
)
from ._pinhole import create_rays_pinhole
from .raycasting_scene import RaycastingScene

__all__ = [
    "INVALID_ID",
    "FormatError",
    "InvalidRayWarning",
    "MeshImportWarning",
    "OpenMeshWarning",
    "RaycastingScene",
    "SplitGrid",
    "build",
    "create_rays_pinhole",
    "import_mesh",
    "kernel_isa",
    "load",
]
