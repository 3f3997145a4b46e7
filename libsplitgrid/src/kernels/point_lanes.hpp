#pragma once

// Traversal kernels, part 9: the point queries' triangle test, eight triangles at a time. Each lane
// computes in double exactly what points::closest_on_triangle computes for its distance (the
// same operations in the same order, no contraction), so a batched walk keeps the same best
// triangle as a scalar one would, and brute force agrees bit for bit. The scalar kernels
// (level 0) measure one triangle at a time with PointSearch::offer (point_search.hpp), as
// brute force does.

#ifndef SG_KERNEL_ISA
#error "kernel headers are included by kernels_isa.inc only"
#endif

namespace sg::kernels::SG_KERNEL_ISA {

#if SG_KERNEL_ISA_LEVEL >= 2
/// Three coordinates of eight points, in double.
struct Lanes3d {
    vdouble x, y, z;
};

[[nodiscard]] inline Lanes3d operator-(const Lanes3d& a, const Lanes3d& b) noexcept
{
    return {a.x - b.x, a.y - b.y, a.z - b.z};
}
[[nodiscard]] inline vdouble dot(const Lanes3d& a, const Lanes3d& b) noexcept
{
    return a.x * b.x + a.y * b.y + a.z * b.z;
}
[[nodiscard]] inline Lanes3d cross(const Lanes3d& a, const Lanes3d& b) noexcept
{
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
[[nodiscard]] inline Lanes3d select(vlong mask, const Lanes3d& a, const Lanes3d& b) noexcept
{
    return {mask ? a.x : b.x, mask ? a.y : b.y, mask ? a.z : b.z};
}

/// Lane by lane, whether corner a comes before corner b in (x, y, z) order (as floats; the
/// lanes' float coordinates `af`, `bf`).
[[nodiscard]] inline vlong lexicographically_before(const vfloat (&af)[3], const vfloat (&bf)[3]) noexcept
{
    const vint x_differs = af[0] != bf[0], y_differs = af[1] != bf[1];
    const vint before = x_differs ? vint(af[0] < bf[0]) : y_differs ? vint(af[1] < bf[1]) : vint(af[2] < bf[2]);
    return widen(before);
}

/// points::closest_on_edge's squared distance, lane by lane, for the edge between corners i
/// and j (float corners `cf`, the same in double `cd`).
[[nodiscard, gnu::always_inline]] inline vdouble edge_distance2(const Lanes3d& q, const vfloat (&cf)[3][3],
                                            const Lanes3d (&cd)[3], int i, int j) noexcept
{
    const vlong swap = lexicographically_before(cf[j], cf[i]);
    const Lanes3d p = select(swap, cd[j], cd[i]);
    const Lanes3d end = select(swap, cd[i], cd[j]);
    const Lanes3d e = end - p;
    const vdouble len2 = dot(e, e);
    const vdouble zero = splat(0.0), one = splat(1.0);
    const vdouble along = dot(q - p, e) / len2;
    // std::clamp(along, 0, 1): below 0 gives 0, above 1 gives 1, else (NaN too) itself.
    const vdouble clamped = along < zero ? zero : one < along ? one : along;
    const vdouble s = len2 > zero ? clamped : zero;
    const Lanes3d inner{p.x + e.x * s, p.y + e.y * s, p.z + e.z * s};
    const Lanes3d point = select(s <= zero, p, select(s >= one, end, inner));
    const Lanes3d d = q - point;
    return dot(d, d);
}

/// points::closest_on_triangle's squared distance from q to each lane's triangle.
[[nodiscard, gnu::always_inline]] inline vdouble triangle_distance2(const Lanes3d& q, const vfloat (&cf)[3][3]) noexcept
{
    Lanes3d cd[3];
    for (int c = 0; c < 3; ++c) cd[c] = {widen(cf[c][0]), widen(cf[c][1]), widen(cf[c][2])};
    const Lanes3d n = cross(cd[1] - cd[0], cd[2] - cd[0]);
    const vdouble n2 = dot(n, n);
    const vdouble wa = dot(n, cross(cd[2] - cd[1], q - cd[1]));
    const vdouble wb = dot(n, cross(cd[0] - cd[2], q - cd[2]));
    const vdouble wc = dot(n, cross(cd[1] - cd[0], q - cd[0]));
    const vdouble zero = splat(0.0);
    const vlong inside = (n2 > zero) & (wa > zero) & (wb > zero) & (wc > zero);
    const vdouble height = dot(n, q - cd[0]);
    const vdouble plane = height * height / n2;
    vdouble best = edge_distance2(q, cf, cd, 0, 1);
    const vdouble e12 = edge_distance2(q, cf, cd, 1, 2);
    best = e12 < best ? e12 : best;
    const vdouble e20 = edge_distance2(q, cf, cd, 2, 0);
    best = e20 < best ? e20 : best;
    return inside ? plane : best;
}

/// The corners of the triangles id[l]: corner[c][k] holds, lane by lane, coordinate k of
/// corner c.
[[gnu::always_inline]] inline void gather_corners(const MeshArrays& mesh, vint id,
                                                  vfloat (&corner)[3][3]) noexcept
{
#if SG_KERNEL_ISA_LEVEL >= 3
    load_corners(mesh, id, corner);
#else
    const vint id3 = id * 3;
    for (int c = 0; c < 3; ++c) {
        const vint v3 = gather(mesh.corners, id3 + c) * 3;
        for (int k = 0; k < 3; ++k) corner[c][k] = gather(mesh.coords, v3 + k);
    }
#endif
}

/// Measures the triangles id[l] of the lanes set in `lanes` (at least one; lanes not set must
/// still hold a valid id) and offers each to `search` in lane order.
inline void test_point_lanes(points::PointSearch& search, const MeshArrays& mesh, vint id,
                             std::uint32_t lanes) noexcept
{
    if (!mesh.batchable) {
        for (std::uint32_t todo = lanes; todo != 0; todo &= todo - 1)
            search.offer(mesh.view, static_cast<std::uint32_t>(id[__builtin_ctz(todo)]));
        return;
    }
    vfloat corner[3][3];
    gather_corners(mesh, id, corner);
    const points::Vec3d p = search.point();
    const Lanes3d q{splat(p.x), splat(p.y), splat(p.z)};
    const vdouble d2 = triangle_distance2(q, corner);
    const std::uint32_t near = lane_bits(narrow(d2 <= splat(search.bound2()))) & lanes;
    for (std::uint32_t todo = near; todo != 0; todo &= todo - 1) {
        const int l = __builtin_ctz(todo);
        search.offer_distance(mesh.view, static_cast<std::uint32_t>(id[l]), d2[l]);
    }
}
#endif

/// The point's side of for_each_id_batch and for_each_leaf_batch: measures the batch's ids
/// that `mailbox` has not seen.
template <class Box>
class PointBatch {
public:
    PointBatch(points::PointSearch& search, const MeshArrays& mesh, Box& mailbox) noexcept
        : search_(search), mesh_(mesh), mailbox_(mailbox)
    {
    }
#if SG_KERNEL_ISA_LEVEL >= 2
    bool operator()(vint id, std::uint32_t n) noexcept
    {
        const std::uint32_t fresh = mailbox_.filter(id, (1u << n) - 1u);
        if (fresh != 0) test_point_lanes(search_, mesh_, id, fresh);
        return false;
    }
#else
    bool operator()(std::uint32_t id) noexcept
    {
        if (mailbox_.is_fresh(id)) search_.offer(mesh_.view, id);
        return false;
    }
#endif

private:
    points::PointSearch& search_;
    const MeshArrays& mesh_;
    Box& mailbox_;
};

/// The ids[0, count) (`ids_end` the end of their array), eight at a time, skipping those
/// `mailbox` has seen.
template <class Box>
inline void test_point_ids(points::PointSearch& search, const MeshArrays& mesh, Box& mailbox,
                           const std::uint32_t* ids, std::uint32_t count,
                           const std::uint32_t* ids_end) noexcept
{
    PointBatch<Box> batch(search, mesh, mailbox);
    for_each_id_batch(ids, count, ids_end, batch);
}

}  // namespace sg::kernels::SG_KERNEL_ISA
