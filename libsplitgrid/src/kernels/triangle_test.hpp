#pragma once

// Traversal kernels, part 4: the triangle tests every structure's leaves call. One triangle at
// a time (TriangleTest::moller_trumbore, and the rare watertight lanes whose edge functions
// need double precision), or up to eight at once with the watertight test, which computes
// for each lane exactly what intersect_triangle computes: the same operations in the same
// order (no FMA contraction), so the batched and the one-at-a-time test return bit-identical
// t, u and v, and every instruction set returns the same hits. The scalar kernels (level 0)
// have no batches: every triangle goes through the one-at-a-time test, the leaves are read one
// reference at a time, and the walks above them do not change.

#ifndef SG_KERNEL_ISA
#error "kernel headers are included by kernels_isa.inc only"
#endif

namespace sg::kernels::SG_KERNEL_ISA {

/// The mesh as the batched test reads it: vertex coordinates and corner indices as flat
/// arrays (Vec3f and Triangle are packed, static_asserts in vec3.hpp and mesh.hpp).
struct MeshArrays {
    MeshView view;
    const float* coords;
    const std::int32_t* corners;
    /// False for meshes whose 3 * id or 3 * vertex index does not fit a signed 32-bit
    /// offset (over 715 million triangles or vertices): they are tested one by one.
    bool batchable;

    explicit MeshArrays(const MeshView& mesh) noexcept
        : view(mesh), coords(reinterpret_cast<const float*>(mesh.vertices.data())),
          corners(reinterpret_cast<const std::int32_t*>(mesh.triangles.data())),
          batchable(mesh.triangles.size() < max_batchable && mesh.vertices.size() < max_batchable),
          last_vertex(mesh.vertices.empty() ? coords : coords + 3 * (mesh.vertices.size() - 1))
    {
        if (!mesh.vertices.empty()) std::memcpy(last_row, last_vertex, 3 * sizeof(float));
    }
    /// The last vertex's coordinates: the only vertex whose 16-byte row (load_corners) would
    /// reach past the array; load_corners reads `last_row`, a copy of it, instead.
    const float* last_vertex;
    float last_row[4] = {};
    static constexpr std::size_t max_batchable = 0x7FFFFFFF / 3;
};

#if SG_KERNEL_ISA_LEVEL >= 2
/// intersect_triangle's margin of its early out, lane by lane: |x| 2^-20 + FLT_MIN. (A
/// function, not a lambda: GCC compiles lambdas without the target region's instruction set.)
[[nodiscard]] inline vfloat early_out_margin(vfloat x) noexcept
{
    return abs(x) * splat(0x1p-20f) + splat(0x1p-126f);
}
#endif

#if SG_KERNEL_ISA_LEVEL >= 3
/// The corners of the triangles id[l], transposed: corner[c][k] holds, lane by lane, coordinate
/// k of corner c. Corner indices are read one by one, each vertex as one 16-byte row (its
/// three coordinates and the next vertex's first; the last vertex, which has no next, from a
/// copy chosen by address, which GCC compiles without a branch), and eight rows become three
/// vectors in eleven shuffles. The twelve gathers this replaces (three of corner indices, nine
/// of coordinates) made every leaf visit wait for two gathers in a row. With these loads every
/// structure traced faster, shadow rays most (docs/notebook/trace.md, "Triangles loaded as
/// rows, not gathered").
[[gnu::always_inline]] inline void load_corners(const MeshArrays& mesh, vint id,
                                                vfloat (&corner)[3][3]) noexcept
{
    for (int c = 0; c < 3; ++c) {
        __m128 row[lane_count];
        for (int l = 0; l < lane_count; ++l) {
            const float* v = mesh.coords + 3 * mesh.corners[3 * id[l] + c];
            row[l] = _mm_loadu_ps(v < mesh.last_vertex ? v : mesh.last_row);
        }
        const __m256 r0 = _mm256_set_m128(row[4], row[0]), r1 = _mm256_set_m128(row[5], row[1]);
        const __m256 r2 = _mm256_set_m128(row[6], row[2]), r3 = _mm256_set_m128(row[7], row[3]);
        const __m256 xy01 = _mm256_unpacklo_ps(r0, r1), xy23 = _mm256_unpacklo_ps(r2, r3);
        const __m256 zw01 = _mm256_unpackhi_ps(r0, r1), zw23 = _mm256_unpackhi_ps(r2, r3);
        corner[c][0] = vfloat(_mm256_shuffle_ps(xy01, xy23, 0x44));
        corner[c][1] = vfloat(_mm256_shuffle_ps(xy01, xy23, 0xEE));
        corner[c][2] = vfloat(_mm256_shuffle_ps(zw01, zw23, 0x44));
    }
}
#endif

/// One triangle with `test` over [t_min, t_max]; intersect_triangle's contract.
template <TriangleTest test>
[[nodiscard]] inline bool test_one(const KernelRay& ray, const MeshView& mesh, std::uint32_t tri,
                                   float t_min, float t_max, float& t, float& u,
                                   float& v) noexcept
{
    const Vec3f a = mesh.vertex(tri, 0), b = mesh.vertex(tri, 1), c = mesh.vertex(tri, 2);
    if constexpr (test == TriangleTest::watertight)
        return intersect_triangle(ray.shear, a, b, c, t_min, t_max, t, u, v);
    else if constexpr (test == TriangleTest::watertight_no_tie_break)
        return intersect_triangle_no_tie_break(ray.shear, a, b, c, t_min, t_max, t, u, v);
    else
        return intersect_triangle_moller_trumbore(ray.origin_vec, ray.direction_vec, a, b, c,
                                                  t_min, t_max, t, u, v);
}

#if SG_KERNEL_ISA_LEVEL >= 2
/// Tests the triangles id[l] of the lanes l set in `lanes` (at least one) over
/// [search.t_min(), search.best_t()] and offers each hit to `search` in lane order (which
/// breaks ties on t by triangle id). Lanes not set must still hold a valid id.
/// True if a hit was kept.
template <TriangleTest test, class Search>
inline bool test_lanes(const KernelRay& ray, const MeshArrays& mesh, vint id, std::uint32_t lanes,
                       Search& search) noexcept
{
    search.count_triangles(static_cast<std::uint32_t>(__builtin_popcount(lanes)));
    bool kept = false;
    // The test without the tie-break differs from the watertight one only where an edge
    // function is within rounding of zero, the lanes the batched test hands to test_one.
    if (test == TriangleTest::moller_trumbore || !mesh.batchable) {
        for (std::uint32_t todo = lanes; todo != 0; todo &= todo - 1) {
            const auto tri = static_cast<std::uint32_t>(id[__builtin_ctz(todo)]);
            float t, u, v;
            if (test_one<test>(ray, mesh.view, tri, search.t_min(), search.best_t(), t, u, v) &&
                search.offer(t, tri, u, v)) {
                kept = true;
                if (search.done()) return true;
            }
        }
        return kept;
    }

    const WatertightRay& r = ray.shear;
    const vfloat ox = splat(r.origin[r.kx]), oy = splat(r.origin[r.ky]), oz = splat(r.origin[r.kz]);
    // A = a - origin, per permuted axis, as intersect_triangle forms it.
#if SG_KERNEL_ISA_LEVEL >= 3
    vfloat corner[3][3];
    load_corners(mesh, id, corner);
    const vfloat Akx = corner[0][r.kx] - ox, Aky = corner[0][r.ky] - oy, Akz = corner[0][r.kz] - oz;
    const vfloat Bkx = corner[1][r.kx] - ox, Bky = corner[1][r.ky] - oy, Bkz = corner[1][r.kz] - oz;
    const vfloat Ckx = corner[2][r.kx] - ox, Cky = corner[2][r.ky] - oy, Ckz = corner[2][r.kz] - oz;
#else
    const vint id3 = id * 3;
    const vint a3 = gather(mesh.corners, id3) * 3;
    const vint b3 = gather(mesh.corners, id3 + 1) * 3;
    const vint c3 = gather(mesh.corners, id3 + 2) * 3;
    const float* p = mesh.coords;
    const vfloat Akx = gather(p, a3 + r.kx) - ox, Aky = gather(p, a3 + r.ky) - oy,
                 Akz = gather(p, a3 + r.kz) - oz;
    const vfloat Bkx = gather(p, b3 + r.kx) - ox, Bky = gather(p, b3 + r.ky) - oy,
                 Bkz = gather(p, b3 + r.kz) - oz;
    const vfloat Ckx = gather(p, c3 + r.kx) - ox, Cky = gather(p, c3 + r.ky) - oy,
                 Ckz = gather(p, c3 + r.kz) - oz;
#endif
    const vfloat sx = splat(r.sx), sy = splat(r.sy), sz = splat(r.sz);
    const vfloat Ax = Akx - sx * Akz, Ay = Aky - sy * Akz;
    const vfloat Bx = Bkx - sx * Bkz, By = Bky - sy * Bkz;
    const vfloat Cx = Ckx - sx * Ckz, Cy = Cky - sy * Ckz;
    const vfloat U = Cx * By - Cy * Bx;
    const vfloat V = Ax * Cy - Ay * Cx;
    const vfloat W = Bx * Ay - By * Ax;
    const vfloat zero = splat(0.0f);
    const vint below_u = U < zero, below_v = V < zero, below_w = W < zero;
    const vint above_u = U > zero, above_v = V > zero, above_w = W > zero;
    const vint mixed = (below_u | below_v | below_w) & (above_u | above_v | above_w);
    const vfloat det = U + V + W;
    const vfloat Az = sz * Akz, Bz = sz * Bkz, Cz = sz * Ckz;
    const vfloat T = U * Az + V * Bz + W * Cz;
    // intersect_triangle's early out, the same comparisons lane by lane.
    const vfloat lo = splat(search.t_min()) * det, hi = splat(search.best_t()) * det;
    const vint positive = det > zero;
    const vint outside = (positive & ((T < lo - early_out_margin(lo)) | (T > hi + early_out_margin(hi)))) |
                         (~positive & ((T > lo + early_out_margin(lo)) | (T < hi - early_out_margin(hi))));
    const vfloat inv_det = splat(1.0f) / det;
    const vfloat t = T * inv_det;
    const vint pass = ~mixed & (det != zero) & ((T - T) == zero) & ~outside &
                      (t >= splat(search.t_min())) & (t <= splat(search.best_t()));
    // Lanes with an edge function neither below nor above zero (zero, or NaN) take
    // intersect_triangle's exact path, one by one, below (detail::edge_sign_is_uncertain).
    const std::uint32_t exact =
        lane_bits(~(below_u | above_u) | ~(below_v | above_v) | ~(below_w | above_w)) & lanes;
    std::uint32_t todo = (lane_bits(pass) & lanes) | exact;
    if (todo == 0) return false;
    const vfloat u = V * inv_det, v = W * inv_det;
    for (; todo != 0; todo &= todo - 1) {
        const int l = __builtin_ctz(todo);
        const auto tri = static_cast<std::uint32_t>(id[l]);
        float tl = t[l], ul = u[l], vl = v[l];
        if ((exact >> l) & 1u) {
            if (!test_one<test>(ray, mesh.view, tri, search.t_min(), search.best_t(), tl, ul, vl))
                continue;
        } else if (!(tl <= search.best_t())) {
            continue;  // a lane before this one was closer
        }
        if (search.offer(tl, tri, ul, vl)) {
            kept = true;
            if (search.done()) return true;
        }
    }
    return kept;
}

/// Reads `count` triangle ids at `ids` (`ids_end` the end of their array) `lane_count` at a
/// time, loading whole vectors where the array holds them, so no loop runs per id: calls
/// `visit(id, n)` with the next batch in lanes 0 .. n - 1 and the other lanes holding a copy
/// of lane 0, until the ids end or `visit` returns true. `visit` is a class, not a lambda
/// (see for_each_leaf_batch).
template <class Visit>
[[gnu::always_inline]] inline void for_each_id_batch(const std::uint32_t* ids, std::uint32_t count,
                                                     const std::uint32_t* ids_end,
                                                     Visit& visit) noexcept
{
    const vint lane_index = {0, 1, 2, 3, 4, 5, 6, 7};
    for (;;) {
        const std::uint32_t n = std::min<std::uint32_t>(count, lane_count);
        vint id = load_ids(ids, n, ids_end);
        id = (lane_index < static_cast<std::int32_t>(n)) ? id : splat(id[0]);
        if (visit(id, n)) return;
        if (count <= lane_count) return;
        count -= lane_count;
        ids += lane_count;
    }
}

/// Hands `visit` the batch's first n lanes, n ending at the first lane set in `last_bits`
/// (none set: the leaf goes on after the batch, all `available` lanes), the other lanes a
/// copy of lane 0. Returns what `visit` returns.
template <class Visit>
[[gnu::always_inline]] inline bool visit_leaf_batch(Visit& visit, vint id, std::uint32_t last_bits,
                                                    std::uint32_t available) noexcept
{
    const vint lane_index = {0, 1, 2, 3, 4, 5, 6, 7};
    const std::uint32_t n = last_bits != 0 ? static_cast<std::uint32_t>(__builtin_ctz(last_bits)) + 1
                                           : available;
    return visit((lane_index < static_cast<std::int32_t>(n)) ? id : splat(id[0]), n);
}

/// Reads one Split Grid leaf, the words from `leaf` on (leaf_words.hpp; `end` is the end of
/// the word array), `lane_count` references at a time: calls `visit(id, n)` with the ids of
/// the next batch in lanes 0 .. n - 1 and the other lanes holding a copy of lane 0, until the
/// leaf ends or `visit` returns true. The leaf's length comes from the lane mask of the last
/// bits, so no loop runs per reference. `visit` is a class, not a lambda: GCC compiles
/// lambdas without the instruction set of the target region they are written in.
template <class Visit>
[[gnu::always_inline]] inline void for_each_leaf_batch(const std::uint16_t* leaf,
                                                       const std::uint16_t* end,
                                                       Visit& visit) noexcept
{
    // The leaf has its two head words and ends at a marked reference: the kernels run only
    // on grids that passed check_invariants. Past the head, the loads stop at the array's end
    // all the same.
    const std::uint32_t head = leaf_pair(leaf);
    if ((head & leaf_code::wide_bit) == 0) {
        // Lane 0 is the head: its upper word keeps only the head's last bit (bit 15 of that
        // word), so its offset is 0; lanes 1 .. 7 are the words after the head.
        const vint base = splat(static_cast<std::int32_t>(head & leaf_code::id_mask));
        vint keep = {static_cast<std::int32_t>(leaf_code::narrow_last_bit), -1, -1, -1, -1, -1, -1, -1};
        for (const std::uint16_t* w = leaf + 1;; w += lane_count) {
            const auto available =
                static_cast<std::uint32_t>(std::min<std::ptrdiff_t>(end - w, lane_count));
            const vint raw = load_words(w, available, end) & keep;
            keep = splat(std::int32_t{-1});
            const std::uint32_t last_bits =
                lane_bits((raw & static_cast<std::int32_t>(leaf_code::narrow_last_bit)) != 0) &
                ((1u << available) - 1u);
            const vint id = base + (raw & static_cast<std::int32_t>(leaf_code::narrow_offset_mask));
            if (visit_leaf_batch(visit, id, last_bits, available)) return;
            if (last_bits != 0 || available < lane_count) return;
        }
    }
    // Wide: word pairs from the head on, the last bit the sign bit.
    for (const std::uint16_t* w = leaf;; w += 2 * lane_count) {
        const auto available =
            static_cast<std::uint32_t>(std::min<std::ptrdiff_t>((end - w) / 2, lane_count));
        const vint raw = load_pairs(w, available, end);
        const std::uint32_t last_bits = lane_bits(raw < 0) & ((1u << available) - 1u);
        const vint id = raw & static_cast<std::int32_t>(leaf_code::id_mask);
        if (visit_leaf_batch(visit, id, last_bits, available)) return;
        if (last_bits != 0 || available < lane_count) return;
    }
}

#else
/// Tests triangle `tri` over [search.t_min(), search.best_t()] and offers a hit to `search`:
/// the scalar kernels' test_lanes, one triangle at a time. True if the hit was kept.
template <TriangleTest test, class Search>
inline bool test_triangle(const KernelRay& ray, const MeshArrays& mesh, std::uint32_t tri,
                          Search& search) noexcept
{
    search.count_triangles(1);
    float t, u, v;
    return test_one<test>(ray, mesh.view, tri, search.t_min(), search.best_t(), t, u, v) &&
           search.offer(t, tri, u, v);
}

/// The scalar kernels' for_each_id_batch: a batch is one id, `visit(id)` is called for each
/// of ids[0, count) until it returns true.
template <class Visit>
inline void for_each_id_batch(const std::uint32_t* ids, std::uint32_t count,
                              const std::uint32_t* /*ids_end*/, Visit& visit) noexcept
{
    for (std::uint32_t i = 0; i < count; ++i)
        if (visit(ids[i])) return;
}

/// The scalar kernels' for_each_leaf_batch: `visit(id)` for each reference of the Split Grid
/// leaf at `leaf` (read_leaf, leaf_words.hpp), until it returns true.
template <class Visit>
inline void for_each_leaf_batch(const std::uint16_t* leaf, const std::uint16_t* end,
                                Visit& visit) noexcept
{
    bool stopped = false;
    (void)read_leaf(std::span<const std::uint16_t>(leaf, end), 0, [&](std::uint32_t id) {
        if (!stopped) stopped = visit(id);
    });
}
#endif

/// The ray's side of for_each_leaf_batch: tests the batch's ids that `mailbox` has not seen,
/// and stops the leaf once an any-hit query is done.
template <TriangleTest test, class Search, class Box>
class RayLeafBatch {
public:
    RayLeafBatch(const KernelRay& ray, const MeshArrays& mesh, Search& search, Box& mailbox) noexcept
        : ray_(ray), mesh_(mesh), search_(search), mailbox_(mailbox)
    {
    }
#if SG_KERNEL_ISA_LEVEL >= 2
    bool operator()(vint id, std::uint32_t n) noexcept
    {
        const std::uint32_t fresh = mailbox_.filter(id, (1u << n) - 1u);
        if (fresh == 0 || !test_lanes<test>(ray_, mesh_, id, fresh, search_)) return false;
        kept = true;
        return search_.done();
    }
#else
    bool operator()(std::uint32_t id) noexcept
    {
        if (!mailbox_.is_fresh(id) || !test_triangle<test>(ray_, mesh_, id, search_)) return false;
        kept = true;
        return search_.done();
    }
#endif
    bool kept = false;  ///< a hit was kept

private:
    const KernelRay& ray_;
    const MeshArrays& mesh_;
    Search& search_;
    Box& mailbox_;
};

/// Tests one leaf of `count` triangle ids at `ids` (the BVH's, kd-tree's and uniform grid's
/// leaves; for_each_id_batch), skipping those `mailbox` has seen. True if a hit was kept.
template <TriangleTest test, class Search, class Box>
inline bool test_id_leaf(const KernelRay& ray, const MeshArrays& mesh, Search& search, Box& mailbox,
                         const std::uint32_t* ids, std::uint32_t count,
                         const std::uint32_t* ids_end) noexcept
{
    RayLeafBatch<test, Search, Box> batch(ray, mesh, search, mailbox);
    for_each_id_batch(ids, count, ids_end, batch);
    return batch.kept;
}

/// Tests one Split Grid leaf (for_each_leaf_batch), skipping the references `mailbox` has
/// seen. True if a hit was kept.
template <TriangleTest test, class Search, class Box>
inline bool test_packed_leaf(const KernelRay& ray, const MeshArrays& mesh, Search& search,
                             Box& mailbox, const std::uint16_t* leaf,
                             const std::uint16_t* end) noexcept
{
    RayLeafBatch<test, Search, Box> batch(ray, mesh, search, mailbox);
    for_each_leaf_batch(leaf, end, batch);
    return batch.kept;
}

}  // namespace sg::kernels::SG_KERNEL_ISA
