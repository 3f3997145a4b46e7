#include "ray_queries.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <mutex>
#include <span>
#include <utility>
#include <vector>

#include "batch_query.hpp"
#include "splitgrid/intersections.hpp"
#include "splitgrid/ray_offset.hpp"
#include "splitgrid/traverse.hpp"

namespace sg::python {
namespace {

constexpr float infinity = std::numeric_limits<float>::infinity();

/// Runs `query(mesh, rays, answers)` over the batch in chunks, writing one value per ray into
/// `out` (0 for a miss, as every invalid ray is), then warns about the invalid rays.
template <class Value, class Query>
void each_ray_value(const GridObject& grid, const RayBatch& batch, int threads, Value* out,
                    Query&& query)
{
    const MeshView mesh = grid.mesh();
    run_batch(batch.size(), threads, [&](std::size_t begin, std::size_t end) {
        Ray chunk_rays[chunk_records];
        const std::size_t n = end - begin;
        batch.fill(begin, end, chunk_rays);
        query(mesh, std::span<const Ray>(chunk_rays, n), std::span<Value>(out + begin, n));
        batch.count_invalid(begin, {chunk_rays, n},
                            [&](std::size_t k) { return out[begin + k] == 0; });
    });
    batch.warn_about_invalid_rays();
}

py::dict cast_rays(const GridObject& grid, const py::object& rays, const py::object& tnear,
                   const py::object& tfar, const py::object& threads)
{
    const RayBatch batch(rays, tnear, tfar);
    const int thread_limit = thread_count(threads);
    auto t_hit = batch.rays().new_output<float>();
    auto primitive_ids = batch.rays().new_output<std::uint32_t>();
    auto primitive_uvs = batch.rays().new_output<float>({2});
    auto primitive_normals = batch.rays().new_output<float>({3});
    float* t_out = t_hit.mutable_data();
    std::uint32_t* id_out = primitive_ids.mutable_data();
    float* uv_out = primitive_uvs.mutable_data();
    float* normal_out = primitive_normals.mutable_data();

    const MeshView mesh = grid.mesh();
    run_batch(batch.size(), thread_limit, [&](std::size_t begin, std::size_t end) {
        Ray chunk_rays[chunk_records];
        Hit hits[chunk_records];
        const std::size_t n = end - begin;
        batch.fill(begin, end, chunk_rays);
        intersect(grid.grid(), mesh, std::span<const Ray>(chunk_rays, n), std::span<Hit>(hits, n));
        batch.count_invalid(begin, {chunk_rays, n},
                            [&](std::size_t k) { return !hits[k].is_hit(); });
        for (std::size_t k = 0; k < n; ++k) {
            const std::size_t i = begin + k;
            const Hit& hit = hits[k];
            Vec3f normal{0.0f, 0.0f, 0.0f};
            if (hit.is_hit()) normal = normalize(surface_point(mesh, hit).normal);
            t_out[i] = hit.is_hit() ? hit.t : infinity;
            id_out[i] = hit.triangle;
            uv_out[2 * i] = hit.u;
            uv_out[2 * i + 1] = hit.v;
            normal_out[3 * i] = normal.x;
            normal_out[3 * i + 1] = normal.y;
            normal_out[3 * i + 2] = normal.z;
        }
    });
    batch.warn_about_invalid_rays();

    py::dict result;
    result["t_hit"] = t_hit;
    result["primitive_ids"] = primitive_ids;
    result["primitive_uvs"] = primitive_uvs;
    result["primitive_normals"] = primitive_normals;
    return result;
}

py::array_t<bool> test_occlusions(const GridObject& grid, const py::object& rays,
                                  const py::object& tnear, const py::object& tfar,
                                  const py::object& threads)
{
    const RayBatch batch(rays, tnear, tfar);
    const int thread_limit = thread_count(threads);
    auto occluded_out = batch.rays().new_output<bool>();
    // numpy's bool is one byte holding 0 or 1, what the any-hit kernel writes.
    static_assert(sizeof(bool) == sizeof(std::uint8_t));
    auto* out = reinterpret_cast<std::uint8_t*>(occluded_out.mutable_data());

    each_ray_value(grid, batch, thread_limit, out,
                   [&](const MeshView& mesh, std::span<const Ray> chunk,
                       std::span<std::uint8_t> answers) {
                       occluded(grid.grid(), mesh, chunk, answers);
                   });
    return occluded_out;
}

py::array_t<std::int32_t> count_intersections(const GridObject& grid, const py::object& rays,
                                              const py::object& tnear, const py::object& tfar,
                                              const py::object& threads)
{
    const RayBatch batch(rays, tnear, tfar);
    const int thread_limit = thread_count(threads);
    auto counts = batch.rays().new_output<std::int32_t>();
    std::int32_t* out = counts.mutable_data();
    each_ray_value(grid, batch, thread_limit, out,
                   [&](const MeshView& mesh, std::span<const Ray> chunk,
                       std::span<std::int32_t> answers) {
                       count_intersections(grid.grid(), mesh, chunk, answers);
                   });
    return counts;
}

py::dict list_intersections(const GridObject& grid, const py::object& rays,
                            const py::object& tnear, const py::object& tfar,
                            const py::object& threads)
{
    const RayBatch batch(rays, tnear, tfar);
    const int thread_limit = thread_count(threads);
    const MeshView mesh = grid.mesh();
    // One list per chunk, kept with its first ray; joined in the rays' order once every
    // chunk is done.
    std::vector<std::pair<std::size_t, IntersectionList>> parts;
    std::mutex parts_mutex;
    run_batch(batch.size(), thread_limit, [&](std::size_t begin, std::size_t end) {
        Ray chunk_rays[chunk_records];
        const std::size_t n = end - begin;
        batch.fill(begin, end, chunk_rays);
        IntersectionList part;
        list_intersections(grid.grid(), mesh, std::span<const Ray>(chunk_rays, n), part);
        batch.count_invalid(begin, {chunk_rays, n}, [&](std::size_t k) {
            return part.ray_splits[k] == part.ray_splits[k + 1];
        });
        const std::lock_guard<std::mutex> lock(parts_mutex);
        parts.emplace_back(begin, std::move(part));
    });
    batch.warn_about_invalid_rays();
    std::sort(parts.begin(), parts.end(),
              [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<IntersectionList> ordered;
    ordered.reserve(parts.size());
    for (auto& part : parts) ordered.push_back(std::move(part.second));
    parts.clear();
    const IntersectionList all = concatenate(ordered);
    ordered.clear();

    const auto hits = static_cast<py::ssize_t>(all.hits.size());
    py::array_t<std::int64_t> ray_splits(static_cast<py::ssize_t>(all.ray_splits.size()));
    py::array_t<std::uint32_t> ray_ids(hits);
    py::array_t<float> t_hit(hits);
    py::array_t<std::uint32_t> primitive_ids(hits);
    py::array_t<float> primitive_uvs(std::vector<py::ssize_t>{hits, 2});
    std::int64_t* split_out = ray_splits.mutable_data();
    for (std::size_t k = 0; k < all.ray_splits.size(); ++k)
        split_out[k] = static_cast<std::int64_t>(all.ray_splits[k]);
    std::uint32_t* ray_out = ray_ids.mutable_data();
    float* t_out = t_hit.mutable_data();
    std::uint32_t* id_out = primitive_ids.mutable_data();
    float* uv_out = primitive_uvs.mutable_data();
    for (std::size_t i = 0; i < all.hits.size(); ++i) {
        ray_out[i] = all.ray_ids[i];
        t_out[i] = all.hits[i].t;
        id_out[i] = all.hits[i].triangle;
        uv_out[2 * i] = all.hits[i].u;
        uv_out[2 * i + 1] = all.hits[i].v;
    }
    py::dict result;
    result["ray_splits"] = ray_splits;
    result["ray_ids"] = ray_ids;
    result["t_hit"] = t_hit;
    result["primitive_ids"] = primitive_ids;
    result["primitive_uvs"] = primitive_uvs;
    return result;
}

constexpr const char* cast_rays_doc = R"doc(Closest hit of every ray (Open3D's cast_rays).

Parameters
----------
rays : array_like, float32 or float64, shape (..., 6)
    Origin x, y, z and direction dx, dy, dz of each ray, any leading shape (an
    image's (h, w, 6), a flat (n, 6), one ray (6,)). The direction need not be
    unit length: t is measured in units of its length. float32 C-contiguous rays
    are read in place; float64 is converted chunk by chunk, never copied whole.
tnear, tfar : float or array_like of the rays' leading shape, optional
    Only hits with tnear <= t <= tfar count. Defaults 0 and infinity.
threads : int or None, optional
    oneTBB threads to use: None or 0 for all hardware threads, else at most
    this many.

Returns
-------
dict
    t_hit : float32, shape (...)
        Distance to the closest hit in units of the direction's length; inf on
        a miss.
    primitive_ids : uint32, shape (...)
        Index of the hit triangle in `triangles`; INVALID_ID (0xFFFFFFFF) on a
        miss.
    primitive_uvs : float32, shape (..., 2)
        Barycentric coordinates u, v of the hit: the hit point is
        (1 - u - v) * v0 + u * v1 + v * v2. 0 on a miss.
    primitive_normals : float32, shape (..., 3)
        Unit geometric normal (v1 - v0) x (v2 - v0) of the hit triangle,
        normalised; 0 on a miss.

Warns
-----
InvalidRayWarning
    When rays have a NaN or infinite origin or direction, a zero direction, or
    tnear > tfar: they are answered as misses and counted in the warning.

Notes
-----
The GIL is released while the rays are traced, so other Python threads run, and
several threads may query one SplitGrid at once. Ctrl-C stops a long query with
KeyboardInterrupt.

Examples
--------
>>> rays = np.array([[0.2, 0.1, 1.0, 0.0, 0.0, -1.0]], dtype=np.float32)
>>> grid.cast_rays(rays)["t_hit"]
array([1.], dtype=float32)
)doc";

constexpr const char* test_occlusions_doc =
    R"doc(Whether each ray hits anything (Open3D's test_occlusions).

Stops at the first hit found, so it is faster than cast_rays: for shadow rays and
visibility.

Parameters
----------
rays : array_like, float32 or float64, shape (..., 6)
    Origin and direction of each ray, as for cast_rays.
tnear, tfar : float or array_like of the rays' leading shape, optional
    Only hits with tnear <= t <= tfar count. Defaults 0 and infinity. For a
    shadow ray towards a light at origin + d, pass tfar slightly below 1.
threads : int or None, optional
    oneTBB threads to use: None or 0 for all hardware threads.

Returns
-------
numpy.ndarray of bool, shape (...)
    True where a triangle is hit with t in [tnear, tfar].

Warns
-----
InvalidRayWarning
    When some rays are invalid; they are answered False.
)doc";

constexpr const char* count_intersections_doc =
    R"doc(The number of triangles each ray crosses (Open3D's count_intersections).

Each triangle counts once per ray, however many cells of the grid reference it.
A ray through an edge or a vertex counts what a ray moved off it by an
infinitesimal counts (simulation of simplicity, docs/SPLIT_GRID.md, "Exact edge
functions"): where it crosses the surface through an edge shared by two
triangles, once; where it only grazes the surface, none. So the parity of the
count along a ray from a point tells inside from outside of a closed mesh
exactly, where Open3D's and Embree's counts are off by one at edges.

Parameters
----------
rays : array_like, float32 or float64, shape (..., 6)
    Origin and direction of each ray, as for cast_rays.
tnear, tfar : float or array_like of the rays' leading shape, optional
    Only hits with tnear <= t <= tfar count. Defaults 0 and infinity.
threads : int or None, optional
    oneTBB threads to use: None or 0 for all hardware threads.

Returns
-------
numpy.ndarray of int32, shape (...)

Warns
-----
InvalidRayWarning
    When some rays are invalid; they count 0.
)doc";

constexpr const char* list_intersections_doc =
    R"doc(Every hit along each ray (Open3D's list_intersections).

Each triangle appears once per ray, under the counting rule of
count_intersections. The hits of ray k (its index in the rays flattened in C
order) are entries ray_splits[k]:ray_splits[k + 1] of the other arrays, sorted
by t and, on equal t, by triangle id (Open3D leaves the order unspecified).

Parameters
----------
rays : array_like, float32 or float64, shape (..., 6)
    Origin and direction of each ray, as for cast_rays.
tnear, tfar : float or array_like of the rays' leading shape, optional
    Only hits with tnear <= t <= tfar count. Defaults 0 and infinity.
threads : int or None, optional
    oneTBB threads to use: None or 0 for all hardware threads.

Returns
-------
dict
    ray_splits : int64, shape (R + 1,)
        R the number of rays; ray_splits[0] = 0, ray_splits[R] = the number of
        hits H. (Open3D gives int32.)
    ray_ids : uint32, shape (H,)
        The flat index of the ray of each hit.
    t_hit : float32, shape (H,)
    primitive_ids : uint32, shape (H,)
    primitive_uvs : float32, shape (H, 2)

Raises
------
MemoryError
    When the lists do not fit in memory.
)doc";

}  // namespace

void bind_ray_queries(py::class_<GridObject>& grid_class)
{
    const float inf = infinity;
    grid_class
        .def("cast_rays", &cast_rays, py::arg("rays"), py::kw_only(), py::arg("tnear") = 0.0f,
             py::arg("tfar") = inf, py::arg("threads") = py::none(), cast_rays_doc)
        .def("test_occlusions", &test_occlusions, py::arg("rays"), py::kw_only(),
             py::arg("tnear") = 0.0f, py::arg("tfar") = inf, py::arg("threads") = py::none(),
             test_occlusions_doc)
        .def("count_intersections", &count_intersections, py::arg("rays"), py::kw_only(),
             py::arg("tnear") = 0.0f, py::arg("tfar") = inf, py::arg("threads") = py::none(),
             count_intersections_doc)
        .def("list_intersections", &list_intersections, py::arg("rays"), py::kw_only(),
             py::arg("tnear") = 0.0f, py::arg("tfar") = inf, py::arg("threads") = py::none(),
             list_intersections_doc);
}

}  // namespace sg::python
