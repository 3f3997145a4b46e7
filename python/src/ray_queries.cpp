#include "ray_queries.hpp"

#include <cmath>
#include <cstdint>
#include <limits>
#include <span>

#include "batch_query.hpp"
#include "splitgrid/ray_offset.hpp"
#include "splitgrid/traverse.hpp"

namespace sg::python {
namespace {

constexpr float infinity = std::numeric_limits<float>::infinity();

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

    const MeshView mesh = grid.mesh();
    run_batch(batch.size(), thread_limit, [&](std::size_t begin, std::size_t end) {
        Ray chunk_rays[chunk_records];
        const std::size_t n = end - begin;
        batch.fill(begin, end, chunk_rays);
        occluded(grid.grid(), mesh, std::span<const Ray>(chunk_rays, n),
                 std::span<std::uint8_t>(out + begin, n));
        batch.count_invalid(begin, {chunk_rays, n},
                            [&](std::size_t k) { return out[begin + k] == 0; });
    });
    batch.warn_about_invalid_rays();
    return occluded_out;
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

}  // namespace

void bind_ray_queries(py::class_<GridObject>& grid_class)
{
    const float inf = infinity;
    grid_class
        .def("cast_rays", &cast_rays, py::arg("rays"), py::kw_only(), py::arg("tnear") = 0.0f,
             py::arg("tfar") = inf, py::arg("threads") = py::none(), cast_rays_doc)
        .def("test_occlusions", &test_occlusions, py::arg("rays"), py::kw_only(),
             py::arg("tnear") = 0.0f, py::arg("tfar") = inf, py::arg("threads") = py::none(),
             test_occlusions_doc);
}

}  // namespace sg::python
