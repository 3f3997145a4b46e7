#include "point_queries.hpp"

#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "batch_query.hpp"
#include "splitgrid/closest_point.hpp"
#include "splitgrid/mesh_order.hpp"
#include "splitgrid/occupancy.hpp"
#include "splitgrid/ray_offset.hpp"

namespace sg::python {
namespace {

constexpr float infinity = std::numeric_limits<float>::infinity();

/// The query points of a point query, read once as floats, and the order to answer them in:
/// along a Morton curve over the mesh's box, so that the points one thread answers one after
/// the other lie near each other (docs/notebook/points.md, "Points in Morton order").
class PointBatch {
public:
    explicit PointBatch(const py::handle& points) : records_(points, "points", 3)
    {
        points_.resize(records_.size());
        for (std::size_t i = 0; i < points_.size(); ++i) records_.read(i, &points_[i].x);
    }

    [[nodiscard]] const RecordArray& records() const noexcept { return records_; }
    [[nodiscard]] std::size_t size() const noexcept { return points_.size(); }

    /// Computes the order (with the GIL released: a sort of every point).
    void order_for(const MeshView& mesh)
    {
        const py::gil_scoped_release release;
        order_ = morton_order(std::span<const Vec3f>(points_), bounds(mesh));
    }

    /// Points order[begin, end) into `out`; their indices into `index`.
    void fill(std::size_t begin, std::size_t end, Vec3f* out, std::uint32_t* index) const noexcept
    {
        for (std::size_t k = begin; k < end; ++k) {
            index[k - begin] = order_[k];
            out[k - begin] = points_[order_[k]];
        }
    }

private:
    RecordArray records_;
    std::vector<Vec3f> points_;
    std::vector<std::uint32_t> order_;
};

/// nsamples as compute_occupancy takes it: a whole number, odd and at least 1.
std::uint32_t sample_count(const py::object& nsamples)
{
    if (py::isinstance<py::bool_>(nsamples) || PyIndex_Check(nsamples.ptr()) == 0)
        throw py::type_error("nsamples must be an odd whole number, not " +
                             py::str(py::type::of(nsamples).attr("__name__")).cast<std::string>());
    const long long value = nsamples.cast<long long>();
    if (value < 1 || value % 2 == 0 || value > 1'000'000)
        throw py::value_error("nsamples = " + std::to_string(value) +
                              " must be odd and in [1, 999999]: the majority of an odd number of "
                              "rays decides");
    return static_cast<std::uint32_t>(value);
}

/// max_distance as a float: a positive number or infinity.
float distance_limit(double max_distance)
{
    if (!(max_distance > 0.0))
        throw py::value_error("max_distance = " + py::str(py::float_(max_distance)).cast<std::string>() +
                              " must be positive (infinity for no limit)");
    return static_cast<float>(max_distance);
}

/// Runs `query(mesh, points, answers)` over the batch in chunks, in the batch's order, and
/// hands each answer to `emit(i, answer)`, i the point's flat index.
template <class Answer, class Query, class Emit>
void each_point_answer(const GridObject& grid, PointBatch& batch, int threads, Query&& query,
                       Emit&& emit)
{
    const MeshView mesh = grid.mesh();
    batch.order_for(mesh);
    run_batch(batch.size(), threads, [&](std::size_t begin, std::size_t end) {
        Vec3f points[chunk_records];
        std::uint32_t index[chunk_records];
        Answer answers[chunk_records];
        const std::size_t n = end - begin;
        batch.fill(begin, end, points, index);
        query(mesh, std::span<const Vec3f>(points, n), std::span<Answer>(answers, n));
        for (std::size_t k = 0; k < n; ++k) emit(index[k], answers[k]);
    });
}

/// Runs the closest point search over the batch and hands each answer to `emit(i, answer)`.
template <class Emit>
void each_closest_point(const GridObject& grid, PointBatch& batch, int threads,
                        float max_distance, Emit&& emit)
{
    each_point_answer<ClosestPoint>(
        grid, batch, threads,
        [&](const MeshView& mesh, std::span<const Vec3f> points, std::span<ClosestPoint> out) {
            closest_points(grid.grid(), mesh, points, out, max_distance);
        },
        emit);
}

/// A float per point, from `query(mesh, points, answers)`, as an array of the points' shape.
template <class Query>
py::array_t<float> each_point_value(const GridObject& grid, PointBatch& batch, int threads,
                                    Query&& query)
{
    auto values = batch.records().new_output<float>();
    float* out = values.mutable_data();
    each_point_answer<float>(grid, batch, threads, query,
                             [&](std::size_t i, float value) { out[i] = value; });
    return values;
}

py::dict compute_closest_points(const GridObject& grid, const py::object& points,
                                double max_distance, const py::object& threads)
{
    PointBatch batch(points);
    const float limit = distance_limit(max_distance);
    const int thread_limit = thread_count(threads);
    auto closest = batch.records().new_output<float>({3});
    auto primitive_ids = batch.records().new_output<std::uint32_t>();
    auto primitive_uvs = batch.records().new_output<float>({2});
    auto primitive_normals = batch.records().new_output<float>({3});
    float* point_out = closest.mutable_data();
    std::uint32_t* id_out = primitive_ids.mutable_data();
    float* uv_out = primitive_uvs.mutable_data();
    float* normal_out = primitive_normals.mutable_data();
    const MeshView mesh = grid.mesh();
    each_closest_point(grid, batch, thread_limit, limit,
                       [&](std::size_t i, const ClosestPoint& answer) {
                           const float nan = std::numeric_limits<float>::quiet_NaN();
                           Vec3f normal{0.0f, 0.0f, 0.0f};
                           Vec3f at{nan, nan, nan};
                           if (answer.is_hit()) {
                               Hit hit;
                               hit.triangle = answer.triangle;
                               normal = normalize(surface_point(mesh, hit).normal);
                               at = answer.point;
                           }
                           point_out[3 * i] = at.x;
                           point_out[3 * i + 1] = at.y;
                           point_out[3 * i + 2] = at.z;
                           id_out[i] = answer.triangle;
                           uv_out[2 * i] = answer.u;
                           uv_out[2 * i + 1] = answer.v;
                           normal_out[3 * i] = normal.x;
                           normal_out[3 * i + 1] = normal.y;
                           normal_out[3 * i + 2] = normal.z;
                       });
    py::dict result;
    result["points"] = closest;
    result["primitive_ids"] = primitive_ids;
    result["primitive_uvs"] = primitive_uvs;
    result["primitive_normals"] = primitive_normals;
    return result;
}

py::array_t<float> compute_distance(const GridObject& grid, const py::object& points,
                                    double max_distance, const py::object& threads)
{
    PointBatch batch(points);
    const float limit = distance_limit(max_distance);
    const int thread_limit = thread_count(threads);
    auto distance = batch.records().new_output<float>();
    float* out = distance.mutable_data();
    each_closest_point(grid, batch, thread_limit, limit,
                       [&](std::size_t i, const ClosestPoint& answer) { out[i] = answer.distance; });
    return distance;
}

py::array_t<float> compute_signed_distance(const GridObject& grid, const py::object& points,
                                           const py::object& nsamples, double max_distance,
                                           const py::object& threads)
{
    PointBatch batch(points);
    const std::uint32_t samples = sample_count(nsamples);
    const float limit = distance_limit(max_distance);
    const int thread_limit = thread_count(threads);
    warn_if_open(grid, "compute_signed_distance");
    return each_point_value(grid, batch, thread_limit,
                            [&](const MeshView& mesh, std::span<const Vec3f> chunk,
                                std::span<float> answers) {
                                signed_distances(grid.grid(), mesh, chunk, answers, samples, limit);
                            });
}

py::array_t<float> compute_occupancy(const GridObject& grid, const py::object& points,
                                     const py::object& nsamples, const py::object& threads)
{
    PointBatch batch(points);
    const std::uint32_t samples = sample_count(nsamples);
    const int thread_limit = thread_count(threads);
    warn_if_open(grid, "compute_occupancy");
    return each_point_value(grid, batch, thread_limit,
                            [&](const MeshView& mesh, std::span<const Vec3f> chunk,
                                std::span<float> answers) {
                                sg::compute_occupancy(grid.grid(), mesh, chunk, answers, samples);
                            });
}

constexpr const char* compute_closest_points_doc =
    R"doc(The closest point on the mesh to each point (Open3D's compute_closest_points).

Exact: the search visits the grid's nodes and cells nearest first and stops only
when the next box is farther than the best triangle, with distances in double
precision (docs/SPLIT_GRID.md, "Closest points"). A point equally close to
several triangles gets the smallest triangle id.

Parameters
----------
points : array_like, float32 or float64, shape (..., 3)
    Query points, any leading shape; float64 is rounded to float32.
max_distance : float, optional
    Triangles farther than this are not reported: such points get
    INVALID_ID and NaN points; far points are then cheap. Default infinity.
threads : int or None, optional
    oneTBB threads to use: None or 0 for all hardware threads.

Returns
-------
dict
    points : float32, shape (..., 3)
        The closest point on the mesh; NaN where there is none.
    primitive_ids : uint32, shape (...)
        Its triangle; INVALID_ID where there is none (a NaN or infinite
        query point, or nothing within max_distance).
    primitive_uvs : float32, shape (..., 2)
        Barycentric u, v of the closest point on its triangle.
    primitive_normals : float32, shape (..., 3)
        Unit geometric normal of that triangle; 0 where there is none.
)doc";

constexpr const char* compute_distance_doc =
    R"doc(The distance from each point to the mesh (Open3D's compute_distance).

Parameters
----------
points : array_like, float32 or float64, shape (..., 3)
    Query points, any leading shape.
max_distance : float, optional
    Beyond it the answer is inf, found cheaply. Default infinity.
threads : int or None, optional
    oneTBB threads to use: None or 0 for all hardware threads.

Returns
-------
numpy.ndarray of float32, shape (...)
    The distance to the closest point (compute_closest_points); NaN for a
    point with a NaN or infinite coordinate.
)doc";

constexpr const char* compute_signed_distance_doc =
    R"doc(The signed distance from each point to the closed mesh, negative inside
(Open3D's compute_signed_distance).

The magnitude is compute_distance's; the sign is compute_occupancy's, which is
exact for points farther from the surface than 2^-17 times the largest
coordinate of the mesh's box, whatever the rays meet on the way (edges,
vertices). Nearer, the sign may be either; the magnitude is then below that
band.

Parameters
----------
points : array_like, float32 or float64, shape (..., 3)
    Query points, any leading shape.
nsamples : int, optional
    Rays voting on the side, odd; 1 (the default) is exact for a closed mesh,
    more help only where the mesh has holes.
max_distance : float, optional
    Beyond it the answer is +inf, without a side. Default infinity.
threads : int or None, optional
    oneTBB threads to use: None or 0 for all hardware threads.

Returns
-------
numpy.ndarray of float32, shape (...)

Warns
-----
OpenMeshWarning
    Once per call when the mesh is not closed.
)doc";

constexpr const char* compute_occupancy_doc =
    R"doc(1.0 for a point inside the closed mesh, 0.0 outside (Open3D's
compute_occupancy).

The parity of the number of triangles a ray from the point crosses, counted as
count_intersections counts them: exact for every point farther from the surface
than 2^-17 times the largest coordinate of the mesh's box (docs/SPLIT_GRID.md,
"Inside or outside"), where other tools vote over jittered rays. Valid for a
mesh whose every edge is shared by an even number of triangles
(SplitGrid.stats()["edges"] tells).

Parameters
----------
points : array_like, float32 or float64, shape (..., 3)
    Query points, any leading shape.
nsamples : int, optional
    Rays voting, odd; 1 (the default) is exact for a closed mesh.
threads : int or None, optional
    oneTBB threads to use: None or 0 for all hardware threads.

Returns
-------
numpy.ndarray of float32, shape (...)
    1.0 inside, 0.0 outside, NaN for a point with a NaN or infinite
    coordinate.

Warns
-----
OpenMeshWarning
    Once per call when the mesh is not closed, counting its open and
    non-manifold edges.
)doc";

}  // namespace

void bind_point_queries(py::class_<GridObject>& grid_class)
{
    const double inf = std::numeric_limits<double>::infinity();
    grid_class
        .def("compute_closest_points", &compute_closest_points, py::arg("points"),
             py::kw_only(), py::arg("max_distance") = inf, py::arg("threads") = py::none(),
             compute_closest_points_doc)
        .def("compute_distance", &compute_distance, py::arg("points"), py::kw_only(),
             py::arg("max_distance") = inf, py::arg("threads") = py::none(),
             compute_distance_doc)
        .def("compute_signed_distance", &compute_signed_distance, py::arg("points"),
             py::kw_only(), py::arg("nsamples") = 1, py::arg("max_distance") = inf,
             py::arg("threads") = py::none(), compute_signed_distance_doc)
        .def("compute_occupancy", &compute_occupancy, py::arg("points"), py::kw_only(),
             py::arg("nsamples") = 1, py::arg("threads") = py::none(), compute_occupancy_doc);
}

}  // namespace sg::python
