// CGAL 5.5 as the reference of sg-bench's point workloads (cgal_peer.hpp). The only file of the
// project that includes CGAL (GPL): compiled into sg-bench only when SG_WITH_CGAL is on.

#include "cgal_peer.hpp"

#include <chrono>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/helpers.h>
#include <CGAL/version.h>

#include "cli_common.hpp"

// Without thread support CGAL builds its lazy trees without a lock and may keep state in
// statics; the point workloads query from several threads.
#ifndef CGAL_HAS_THREADS
#error \
    "CGAL is configured without thread support (CGAL_HAS_THREADS); sg-bench queries it from several threads"
#endif

namespace sg::bench {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point>;
using SideOf = CGAL::Side_of_triangle_mesh<SurfaceMesh, Kernel>;
using Primitive = CGAL::AABB_face_graph_triangle_primitive<SurfaceMesh>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

Point to_cgal(Vec3f p) { return {p.x, p.y, p.z}; }

class Cgal final : public CgalPeer {
public:
    explicit Cgal(const MeshView& mesh)
    {
        auto start = std::chrono::steady_clock::now();
        std::vector<SurfaceMesh::Vertex_index> vertices;
        vertices.reserve(mesh.vertices.size());
        for (const Vec3f v : mesh.vertices) vertices.push_back(mesh_.add_vertex(to_cgal(v)));
        face_triangle_.reserve(mesh.triangles.size());
        for (std::uint32_t t = 0; t < mesh.triangle_count(); ++t) {
            const Triangle& tri = mesh.triangles[t];
            const SurfaceMesh::Face_index f =
                mesh_.add_face(vertices[tri.v[0]], vertices[tri.v[1]], vertices[tri.v[2]]);
            if (f == SurfaceMesh::null_face()) {
                ++refused_;
                continue;
            }
            face_triangle_.push_back(t);
        }
        closed_ = CGAL::is_closed(mesh_);
        mesh_seconds_ = apps::seconds_since(start);
        if (refused_ > 0) return;

        if (closed_) {
            start = std::chrono::steady_clock::now();
            side_of_.emplace(mesh_);
            // The tree is built on the first query inside the mesh's box: here, not in a
            // timed pass (and not by two threads racing for its lock).
            const Aabb box = bounds(mesh);
            (void)(*side_of_)(to_cgal((box.lower + box.upper) * 0.5f));
            side_of_seconds_ = apps::seconds_since(start);
        }
        start = std::chrono::steady_clock::now();
        tree_.emplace(faces(mesh_).first, faces(mesh_).second, mesh_);
        tree_->build();
        tree_->accelerate_distance_queries();
        tree_seconds_ = apps::seconds_since(start);
    }

    std::size_t refused_faces() const override { return refused_; }
    bool is_closed() const override { return closed_; }
    double mesh_seconds() const override { return mesh_seconds_; }
    double side_of_seconds() const override { return side_of_seconds_; }
    double tree_seconds() const override { return tree_seconds_; }

    std::string unavailable(PointQuery query) const override
    {
        if (query == PointQuery::count) return "CGAL is not measured on hit counts";
        if (refused_ > 0)
            return std::to_string(refused_) +
                   " faces refused by Surface_mesh (non-manifold or inconsistently oriented)";
        if (query == PointQuery::occupancy && !closed_)
            return "mesh not closed (Side_of_triangle_mesh needs a closed mesh)";
        return "";
    }
    bool exact_distances() const override { return false; }

    void count_intersections(std::span<const Ray>, std::span<std::int32_t>) const override {}

    void occupancy(std::span<const Vec3f> points, std::span<float> inside,
                   TriangleTest) const override
    {
        // On the surface (CGAL::ON_BOUNDARY) counts as outside; compute_occupancy may answer
        // either there.
        for (std::size_t k = 0; k < points.size(); ++k)
            inside[k] = (*side_of_)(to_cgal(points[k])) == CGAL::ON_BOUNDED_SIDE ? 1.0f : 0.0f;
    }

    void closest_points(std::span<const Vec3f> points, std::span<ClosestPoint> out) const override
    {
        for (std::size_t k = 0; k < points.size(); ++k) {
            const Point p = to_cgal(points[k]);
            const auto [q, face] = tree_->closest_point_and_primitive(p);
            ClosestPoint& c = out[k];
            c.distance = static_cast<float>(std::sqrt(CGAL::squared_distance(p, q)));
            c.triangle = face_triangle_[static_cast<std::size_t>(face)];
            c.point = Vec3f{static_cast<float>(q.x()), static_cast<float>(q.y()),
                            static_cast<float>(q.z())};
        }
    }

private:
    SurfaceMesh mesh_;
    std::vector<std::uint32_t> face_triangle_;  // our triangle id of each CGAL face
    std::size_t refused_ = 0;
    bool closed_ = false;
    std::optional<SideOf> side_of_;
    std::optional<Tree> tree_;
    double mesh_seconds_ = 0.0;
    double side_of_seconds_ = 0.0;
    double tree_seconds_ = 0.0;
};

}  // namespace

bool has_cgal() { return true; }

std::string cgal_version() { return CGAL_VERSION_STR; }

std::unique_ptr<CgalPeer> build_cgal(const MeshView& mesh) { return std::make_unique<Cgal>(mesh); }

}  // namespace sg::bench
