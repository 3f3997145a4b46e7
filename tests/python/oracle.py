"""Independent answers for the Python package's tests: brute force over all triangles in double
precision numpy, written here without calling the library.

A float32 structure and a double-precision oracle may disagree about rays that pass within
rounding error of a triangle's edge or of the ends of [tnear, tfar]. So the oracle gives two
answers per ray, with every triangle grown and shrunk by a small margin in its barycentric
coordinates (`margin`) and the window by a relative `t_tolerance`: the closest hit among the
grown triangles (`t_loose`), which no right answer is closer than, and among the shrunk ones
(`t_strict`), which every right answer is at least as close as. A right answer lies between;
a ray missed by the structure must have no strict hit. Away from edges both bounds are the
same, so a wrong triangle, a wrong t or a lost hit is caught.
"""

import numpy as np

MARGIN = 1e-5
T_TOLERANCE = 1e-5


def _intersections(origins, directions, v0, e1, e2):
    """t, u, v (rays x triangles) of each ray's line with each triangle's plane (Moeller and
    Trumbore in float64); NaN where the ray is parallel to the plane."""
    p = np.cross(directions[:, None, :], e2[None, :, :])
    det = np.einsum("rtk,tk->rt", p, e1)
    with np.errstate(divide="ignore", invalid="ignore"):
        inv = 1.0 / det
        s = origins[:, None, :] - v0[None, :, :]
        u = np.einsum("rtk,rtk->rt", s, p) * inv
        q = np.cross(s, e1[None, :, :])
        v = np.einsum("rk,rtk->rt", directions, q) * inv
        t = np.einsum("tk,rtk->rt", e2, q) * inv
    parallel = det == 0
    t[parallel] = np.nan
    return t, u, v


def _prepared(vertices, triangles, rays, tnear, tfar):
    """Rays (n, 6), tnear and tfar (n,) and each triangle's corner and edges, in float64."""
    vertices = np.asarray(vertices, dtype=np.float64)
    triangles = np.asarray(triangles, dtype=np.int64)
    rays = np.asarray(rays, dtype=np.float64).reshape(-1, 6)
    tnear = np.broadcast_to(np.asarray(tnear, dtype=np.float64), (len(rays),))
    tfar = np.broadcast_to(np.asarray(tfar, dtype=np.float64), (len(rays),))
    v0 = vertices[triangles[:, 0]]
    return rays, tnear, tfar, v0, vertices[triangles[:, 1]] - v0, vertices[triangles[:, 2]] - v0


def closest_hits(vertices, triangles, rays, tnear=0.0, tfar=np.inf, margin=MARGIN,
                 t_tolerance=T_TOLERANCE, batch_pairs=4_000_000):
    """Bounds of the closest hit of each ray of `rays` (n, 6): a dict of float64 arrays
    `t_loose` and `t_strict` (inf where there is none) and `id_strict`, the triangle of the
    strict closest hit (-1 for none)."""
    rays, tnear, tfar, v0, e1, e2 = _prepared(vertices, triangles, rays, tnear, tfar)
    n = len(rays)
    t_loose = np.full(n, np.inf)
    t_strict = np.full(n, np.inf)
    id_strict = np.full(n, -1)
    per_batch = max(1, batch_pairs // max(1, len(triangles)))
    for start in range(0, n, per_batch):
        rows = slice(start, min(n, start + per_batch))
        t, u, v = _intersections(rays[rows, :3], rays[rows, 3:], v0, e1, e2)
        near = tnear[rows, None]
        far = tfar[rows, None]
        scale = np.maximum(1.0, np.abs(t))
        with np.errstate(invalid="ignore"):
            loose = ((u >= -margin) & (v >= -margin) & (u + v <= 1 + margin)
                     & (t >= near - t_tolerance * scale) & (t <= far + t_tolerance * scale))
            strict = ((u >= margin) & (v >= margin) & (u + v <= 1 - margin)
                      & (t >= near + t_tolerance * scale) & (t <= far - t_tolerance * scale))
        t_loose[rows] = np.where(loose, t, np.inf).min(axis=1)
        strict_t = np.where(strict, t, np.inf)
        t_strict[rows] = strict_t.min(axis=1)
        id_strict[rows] = np.where(np.isfinite(t_strict[rows]), strict_t.argmin(axis=1), -1)
    return {"t_loose": t_loose, "t_strict": t_strict, "id_strict": id_strict}


def barycentrics(vertices, triangles, rays, ids):
    """t, u, v and the unit geometric normal (v1 - v0) x (v2 - v0) of each ray's line with
    triangle ids[i], in float64."""
    vertices = np.asarray(vertices, dtype=np.float64)
    tri = np.asarray(triangles, dtype=np.int64)[ids]
    rays = np.asarray(rays, dtype=np.float64).reshape(-1, 6)
    v0 = vertices[tri[:, 0]]
    e1 = vertices[tri[:, 1]] - v0
    e2 = vertices[tri[:, 2]] - v0
    d = rays[:, 3:]
    p = np.cross(d, e2)
    det = np.einsum("ik,ik->i", p, e1)
    s = rays[:, :3] - v0
    q = np.cross(s, e1)
    u = np.einsum("ik,ik->i", s, p) / det
    v = np.einsum("ik,ik->i", d, q) / det
    t = np.einsum("ik,ik->i", e2, q) / det
    normal = np.cross(e1, e2)
    normal /= np.linalg.norm(normal, axis=1, keepdims=True)
    return t, u, v, normal


def _flat(value):
    """tnear or tfar of any leading shape, flat like the rays."""
    return np.ravel(value) if np.ndim(value) else value


def check_cast_rays(vertices, triangles, rays, result, tnear=0.0, tfar=np.inf):
    """Asserts that `result` (SplitGrid.cast_rays' dict, any leading shape) answers `rays`
    as the oracle allows. Returns the number of rays checked that hit something."""
    flat_rays = np.asarray(rays, dtype=np.float64).reshape(-1, 6)
    n = len(flat_rays)
    t_hit = np.asarray(result["t_hit"], dtype=np.float64).reshape(n)
    ids = np.asarray(result["primitive_ids"]).reshape(n)
    uvs = np.asarray(result["primitive_uvs"], dtype=np.float64).reshape(n, 2)
    normals = np.asarray(result["primitive_normals"], dtype=np.float64).reshape(n, 3)
    bounds = closest_hits(vertices, triangles, flat_rays, _flat(tnear), _flat(tfar))
    missed = ids == 0xFFFFFFFF
    # A miss: nothing strictly inside, and the miss reported as Open3D reports it.
    wrong_miss = missed & np.isfinite(bounds["t_strict"])
    assert not wrong_miss.any(), (
        f"{wrong_miss.sum()} of {n} rays missed where the oracle hits, e.g. ray "
        f"{np.flatnonzero(wrong_miss)[0]}: t = {bounds['t_strict'][wrong_miss][0]}")
    assert np.all(np.isinf(t_hit[missed])) and np.all(uvs[missed] == 0) and np.all(
        normals[missed] == 0), "a miss must have t_hit = inf and zero uvs and normals"
    hit = ~missed
    if not hit.any():
        return 0
    scale = np.maximum(1.0, np.abs(t_hit[hit]))
    too_near = t_hit[hit] < bounds["t_loose"][hit] - T_TOLERANCE * scale
    too_far = t_hit[hit] > bounds["t_strict"][hit] + T_TOLERANCE * scale
    assert not too_near.any(), f"{too_near.sum()} hits nearer than any triangle allows"
    assert not too_far.any(), (
        f"{too_far.sum()} hits farther than the oracle's closest, e.g. ray "
        f"{np.flatnonzero(hit)[too_far][0]}")
    # The reported triangle, t, u, v and normal agree with that triangle's own intersection.
    t, u, v, normal = barycentrics(vertices, triangles, flat_rays[hit], ids[hit].astype(np.int64))
    assert np.allclose(t_hit[hit], t, rtol=1e-4, atol=1e-6), "t_hit is not the triangle's t"
    assert np.allclose(uvs[hit, 0], u, atol=1e-4) and np.allclose(uvs[hit, 1], v, atol=1e-4), \
        "primitive_uvs are not the hit's barycentrics"
    assert np.all((u > -MARGIN * 10) & (v > -MARGIN * 10) & (u + v < 1 + MARGIN * 10)), \
        "a reported triangle does not contain its hit"
    assert np.allclose(normals[hit], normal, atol=1e-4), "primitive_normals are wrong"
    return int(hit.sum())


def check_occlusions(vertices, triangles, rays, occluded, tnear=0.0, tfar=np.inf):
    """Asserts that `occluded` (bool, any leading shape) answers `rays` as the oracle allows."""
    flat_rays = np.asarray(rays, dtype=np.float64).reshape(-1, 6)
    occluded = np.asarray(occluded).reshape(-1)
    assert occluded.dtype == bool
    bounds = closest_hits(vertices, triangles, flat_rays, _flat(tnear), _flat(tfar))
    lost = ~occluded & np.isfinite(bounds["t_strict"])
    invented = occluded & np.isinf(bounds["t_loose"])
    assert not lost.any(), f"{lost.sum()} occluded rays answered False"
    assert not invented.any(), f"{invented.sum()} free rays answered True"
    return int(occluded.sum())


def all_hits(vertices, triangles, rays, tnear=0.0, tfar=np.inf, margin=MARGIN,
             t_tolerance=T_TOLERANCE):
    """For each ray of `rays` (n, 6), two sets of triangle ids: those it surely crosses
    (inside the shrunk triangles and window) and those it may cross (inside the grown ones).
    A right list holds every sure one and only possible ones."""
    rays, tnear, tfar, v0, e1, e2 = _prepared(vertices, triangles, rays, tnear, tfar)
    n = len(rays)
    t, u, v = _intersections(rays[:, :3], rays[:, 3:], v0, e1, e2)
    scale = np.maximum(1.0, np.abs(t))
    with np.errstate(invalid="ignore"):
        loose = ((u >= -margin) & (v >= -margin) & (u + v <= 1 + margin)
                 & (t >= tnear[:, None] - t_tolerance * scale)
                 & (t <= tfar[:, None] + t_tolerance * scale))
        sure = ((u >= margin) & (v >= margin) & (u + v <= 1 - margin)
                & (t >= tnear[:, None] + t_tolerance * scale)
                & (t <= tfar[:, None] - t_tolerance * scale))
    return ([set(np.flatnonzero(row)) for row in sure],
            [set(np.flatnonzero(row)) for row in loose], t)


def _segment_distance2(p, a, b):
    """Squared distance from points p (P, 1, 3) to segments a-b (1, T, 3)."""
    ab = b - a
    length2 = np.einsum("...k,...k->...", ab, ab)
    with np.errstate(divide="ignore", invalid="ignore"):
        s = np.clip(np.einsum("...k,...k->...", p - a, ab) / length2, 0.0, 1.0)
    s = np.where(length2 > 0, s, 0.0)
    d = p - (a + s[..., None] * ab)
    return np.einsum("...k,...k->...", d, d)


def point_distances(vertices, triangles, points, batch_pairs=2_000_000):
    """The distance (float64) from each point of `points` (n, 3) to its closest triangle, and
    the set of triangles within a relative 1e-9 of that distance: brute force over every
    triangle, the plane where the projection falls inside, else the nearest edge."""
    vertices = np.asarray(vertices, dtype=np.float64)
    triangles = np.asarray(triangles, dtype=np.int64)
    points = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    a = vertices[triangles[:, 0]][None]
    b = vertices[triangles[:, 1]][None]
    c = vertices[triangles[:, 2]][None]
    normal = np.cross(b - a, c - a)
    area2 = np.einsum("...k,...k->...", normal, normal)
    best = np.empty(len(points))
    nearest = []
    per_batch = max(1, batch_pairs // max(1, len(triangles)))
    for start in range(0, len(points), per_batch):
        p = points[start:start + per_batch, None, :]
        d2 = np.minimum(np.minimum(_segment_distance2(p, a, b), _segment_distance2(p, b, c)),
                        _segment_distance2(p, c, a))
        with np.errstate(divide="ignore", invalid="ignore"):
            # Barycentrics of p's projection: inside when all three sub-areas agree in sign.
            w_a = np.einsum("...k,...k->...", np.cross(c - b, p - b), normal) / area2
            w_b = np.einsum("...k,...k->...", np.cross(a - c, p - c), normal) / area2
            height = np.einsum("...k,...k->...", p - a, normal) ** 2 / area2
        inside = (area2 > 0) & (w_a >= 0) & (w_b >= 0) & (w_a + w_b <= 1)
        d2 = np.where(inside, np.minimum(height, d2), d2)
        d = np.sqrt(d2)
        row_best = d.min(axis=1)
        best[start:start + per_batch] = row_best
        nearest += [set(np.flatnonzero(row <= m * (1 + 1e-9) + 1e-12))
                    for row, m in zip(d, row_best)]
    return best, nearest


def winding_numbers(vertices, triangles, points):
    """The generalised winding number of a closed, consistently wound mesh around each point
    (Van Oosterom and Strackee's solid angle per triangle, float64): 1 inside, 0 outside for
    an outward mesh, away from the surface."""
    vertices = np.asarray(vertices, dtype=np.float64)
    triangles = np.asarray(triangles, dtype=np.int64)
    points = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    a = vertices[triangles[:, 0]][None] - points[:, None]
    b = vertices[triangles[:, 1]][None] - points[:, None]
    c = vertices[triangles[:, 2]][None] - points[:, None]
    la, lb, lc = (np.linalg.norm(x, axis=-1) for x in (a, b, c))
    numerator = np.einsum("...k,...k->...", a, np.cross(b, c))
    denominator = (la * lb * lc + np.einsum("...k,...k->...", a, b) * lc
                   + np.einsum("...k,...k->...", b, c) * la + np.einsum("...k,...k->...", c, a) * lb)
    return (2 * np.arctan2(numerator, denominator)).sum(axis=1) / (4 * np.pi)
