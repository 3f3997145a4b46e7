#pragma once

#include <cstddef>
#include <memory>
#include <string>

#include "bench_structure.hpp"
#include "splitgrid/mesh.hpp"

/// CGAL 5.5 (Debian's libcgal-dev, header-only, GPL) as the reference of sg-bench's point
/// workloads: the inside test a user would pick (Side_of_triangle_mesh, exact predicates of the
/// Exact_predicates_inexact_constructions_kernel) and its closest points (AABB_tree over the
/// faces of a Surface_mesh, with the distance hint of accelerate_distance_queries). Only
/// sg-bench links CGAL, and only when configured with SG_WITH_CGAL (cgal_peer.cpp); without it
/// (no_cgal.cpp) has_cgal() is false and the results have no CGAL entries.
namespace sg::bench {

/// CGAL's structures over one mesh, built once. Both answer const queries from several threads
/// at once: everything CGAL would build lazily on a first query (the Side_of_triangle_mesh's
/// tree, the AABB tree and its search tree) is built before build_cgal returns.
class CgalPeer : public PointQueries {
public:
    /// Faces Surface_mesh::add_face refused: a face that would make an edge or a vertex
    /// non-manifold, that is wound against a neighbour sharing its edge, or that repeats a
    /// corner. CGAL answers nothing when it refused any (its mesh would not be ours).
    [[nodiscard]] virtual std::size_t refused_faces() const = 0;
    /// CGAL::is_closed of the Surface_mesh: Side_of_triangle_mesh requires a closed mesh.
    [[nodiscard]] virtual bool is_closed() const = 0;
    /// Seconds to make the Surface_mesh from our arrays.
    [[nodiscard]] virtual double mesh_seconds() const = 0;
    /// Seconds to make the Side_of_triangle_mesh and its AABB tree (0 when not closed).
    [[nodiscard]] virtual double side_of_seconds() const = 0;
    /// Seconds to make the AABB tree of the closest point queries and its search tree.
    [[nodiscard]] virtual double tree_seconds() const = 0;
};

/// True if this build of sg-bench includes CGAL (SG_WITH_CGAL).
[[nodiscard]] bool has_cgal();
/// CGAL's version ("5.5.1"), or "" without CGAL.
[[nodiscard]] std::string cgal_version();

/// Builds CGAL's structures over `mesh` (which must outlive them), on the calling thread (CGAL
/// 5.5 builds its AABB trees serially). Throws ConfigError in a build without CGAL.
[[nodiscard]] std::unique_ptr<CgalPeer> build_cgal(const MeshView& mesh);

}  // namespace sg::bench
