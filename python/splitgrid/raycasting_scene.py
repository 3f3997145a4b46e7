"""A stand-in for open3d.t.geometry.RaycastingScene, so that code written for Open3D runs
unchanged on the Split Grid.

Open3D 0.16 as Debian 12 packages it answers every ray as a miss (docs/PYTHON.md, "Open3D on
Debian 12"); with ``from splitgrid import RaycastingScene`` the same code gets its hits. Open3D
tensors in give Open3D tensors out; numpy arrays in give numpy arrays out.
"""

import numpy as np

from ._pinhole import create_rays_pinhole
from ._splitgrid import INVALID_ID, build


def _is_open3d(value):
    return type(value).__module__.startswith("open3d")


def _numpy(value):
    return value.numpy() if _is_open3d(value) else np.asarray(value)


def _like(template, array):
    """`array` as the kind of value `template` is: an Open3D tensor or numpy."""
    if _is_open3d(template):
        import open3d
        return open3d.core.Tensor(np.ascontiguousarray(array))
    return array


def _mesh_arrays(mesh):
    """Vertices and triangles of an Open3D TriangleMesh, tensor-based or legacy."""
    if hasattr(mesh, "vertex") and hasattr(mesh, "triangle"):
        return _numpy(mesh.vertex["positions"]), _numpy(mesh.triangle["indices"])
    if hasattr(mesh, "vertices") and hasattr(mesh, "triangles"):
        return np.asarray(mesh.vertices), np.asarray(mesh.triangles)
    raise TypeError(f"add_triangles: expected vertex and triangle arrays or a TriangleMesh, "
                    f"got {type(mesh).__name__}")


class RaycastingScene:
    """A scene of triangle meshes answering rays, with Open3D's RaycastingScene interface.

    Each add_triangles() call adds one geometry and returns its id; the Split Grid of all
    geometries is built at the first query after a change. Results carry ``geometry_ids``
    and primitive ids counted within each geometry, as Open3D's do.

    Parameters
    ----------
    nthreads : int, optional
        Threads for building the grid, 0 for all hardware threads.
    """

    INVALID_ID = INVALID_ID

    def __init__(self, nthreads=0):
        self._nthreads = nthreads
        self._vertices = []
        self._triangles = []
        self._grid = None
        self._first_triangle = np.zeros(1, dtype=np.int64)

    def add_triangles(self, vertex_positions, triangle_indices=None):
        """Adds a mesh: ``(vertices (N, 3) float32, triangles (M, 3) uint32)`` as arrays or
        Open3D tensors, or one ``open3d.t.geometry.TriangleMesh`` (or a legacy one). Returns
        the geometry id."""
        if triangle_indices is None:
            vertices, triangles = _mesh_arrays(vertex_positions)
        else:
            vertices, triangles = _numpy(vertex_positions), _numpy(triangle_indices)
        if vertices.ndim != 2 or vertices.shape[1] != 3:
            raise ValueError(f"vertex_positions: expected shape (N, 3), got {vertices.shape}")
        if triangles.ndim != 2 or triangles.shape[1] != 3:
            raise ValueError(f"triangle_indices: expected shape (M, 3), got {triangles.shape}")
        if triangles.size and (triangles.min() < 0 or triangles.max() >= len(vertices)):
            raise ValueError(f"triangle_indices: an index is outside [0, {len(vertices)})")
        offset = sum(len(v) for v in self._vertices)
        self._vertices.append(np.asarray(vertices, dtype=np.float32))
        self._triangles.append(np.asarray(triangles, dtype=np.int64) + offset)
        self._first_triangle = np.cumsum([0] + [len(t) for t in self._triangles])
        self._grid = None
        return len(self._triangles) - 1

    def _scene(self):
        if self._grid is None and self._first_triangle[-1] > 0:
            self._grid = build(np.concatenate(self._vertices), np.concatenate(self._triangles),
                               threads=self._nthreads)
        return self._grid

    def cast_rays(self, rays, nthreads=0):
        """Closest hits: a dict of t_hit, geometry_ids, primitive_ids, primitive_uvs and
        primitive_normals (SplitGrid.cast_rays, plus the geometry of each hit)."""
        plain = _numpy(rays)
        grid = self._scene()
        if grid is None:
            shape = plain.shape[:-1]
            result = {"t_hit": np.full(shape, np.inf, np.float32),
                      "primitive_ids": np.full(shape, INVALID_ID, np.uint32),
                      "primitive_uvs": np.zeros(shape + (2,), np.float32),
                      "primitive_normals": np.zeros(shape + (3,), np.float32)}
        else:
            result = grid.cast_rays(plain, threads=nthreads)
        result["geometry_ids"] = self._geometry_of(result["primitive_ids"])
        return {key: _like(rays, value) for key, value in result.items()}

    def test_occlusions(self, rays, tnear=0.0, tfar=np.inf, nthreads=0):
        """Whether anything is hit with t in [tnear, tfar] along each ray (bool, the rays'
        leading shape)."""
        plain = _numpy(rays)
        grid = self._scene()
        if grid is None:
            return _like(rays, np.zeros(plain.shape[:-1], dtype=bool))
        return _like(rays, grid.test_occlusions(plain, tnear=tnear, tfar=tfar, threads=nthreads))

    def _geometry_of(self, ids):
        """Geometry ids of the triangle ids `ids` (modified in place to count within their
        geometry), INVALID_ID where there is none."""
        hit = ids != INVALID_ID
        geometry = np.full(ids.shape, INVALID_ID, dtype=np.uint32)
        geometry[hit] = np.searchsorted(self._first_triangle, ids[hit], side="right") - 1
        ids[hit] -= self._first_triangle[geometry[hit]].astype(np.uint32)
        return geometry

    def count_intersections(self, rays, nthreads=0):
        """The number of triangles each ray crosses (int32, the rays' leading shape);
        SplitGrid.count_intersections, exact at shared edges and vertices."""
        plain = _numpy(rays)
        grid = self._scene()
        if grid is None:
            return _like(rays, np.zeros(plain.shape[:-1], dtype=np.int32))
        return _like(rays, grid.count_intersections(plain, threads=nthreads))

    def list_intersections(self, rays, nthreads=0):
        """Every hit of every ray: ray_splits, ray_ids, geometry_ids, primitive_ids,
        primitive_uvs and t_hit (SplitGrid.list_intersections, plus each hit's geometry)."""
        plain = _numpy(rays)
        grid = self._scene()
        if grid is None:
            count = int(np.prod(plain.shape[:-1]))
            result = {"ray_splits": np.zeros(count + 1, np.int64),
                      "ray_ids": np.zeros(0, np.uint32), "t_hit": np.zeros(0, np.float32),
                      "primitive_ids": np.zeros(0, np.uint32),
                      "primitive_uvs": np.zeros((0, 2), np.float32)}
        else:
            result = grid.list_intersections(plain, threads=nthreads)
        result["geometry_ids"] = self._geometry_of(result["primitive_ids"])
        return {key: _like(rays, value) for key, value in result.items()}

    def _points_query(self, query_points, answer, empty):
        plain = _numpy(query_points)
        grid = self._scene()
        if grid is None:
            return _like(query_points, np.full(plain.shape[:-1], empty, dtype=np.float32))
        return _like(query_points, answer(grid, plain))

    def compute_closest_points(self, query_points, nthreads=0):
        """The closest point on the scene to each point: points, geometry_ids,
        primitive_ids, primitive_uvs, primitive_normals (SplitGrid.compute_closest_points)."""
        plain = _numpy(query_points)
        grid = self._scene()
        if grid is None:
            raise ValueError("compute_closest_points: the scene has no triangles")
        result = grid.compute_closest_points(plain, threads=nthreads)
        result["geometry_ids"] = self._geometry_of(result["primitive_ids"])
        return {key: _like(query_points, value) for key, value in result.items()}

    def compute_distance(self, query_points, nthreads=0):
        """The distance from each point to the scene (float32; inf for an empty scene)."""
        return self._points_query(query_points,
                                  lambda g, p: g.compute_distance(p, threads=nthreads), np.inf)

    def compute_signed_distance(self, query_points, nthreads=0, nsamples=1):
        """The distance, negative inside the closed scene; the side is exact
        (SplitGrid.compute_signed_distance)."""
        return self._points_query(
            query_points,
            lambda g, p: g.compute_signed_distance(p, nsamples=nsamples, threads=nthreads),
            np.inf)

    def compute_occupancy(self, query_points, nthreads=0, nsamples=1):
        """1.0 inside the closed scene, 0.0 outside (float32); exact
        (SplitGrid.compute_occupancy)."""
        return self._points_query(
            query_points,
            lambda g, p: g.compute_occupancy(p, nsamples=nsamples, threads=nthreads), 0.0)

    create_rays_pinhole = staticmethod(create_rays_pinhole)
