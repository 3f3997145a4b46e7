#pragma once

// Rays aimed at the places where grid traversal goes wrong first (rows 3 and 10 of
// docs/ROBUSTNESS.md): on and along the planes of the built structure, and along the axes
// exactly through vertices. Header-only (see robustness_support.hpp).

#include <cstdint>
#include <random>
#include <vector>

#include "robustness_support.hpp"
#include "splitgrid/mesh.hpp"
#include "splitgrid/split_grid.hpp"

namespace sg::test {

/// Rays made by rays_on_planes, and what they cover.
struct PlaneRays {
    std::vector<Ray> rays;
    std::size_t planes = 0;
    std::size_t nodes = 0;
    std::uint32_t deepest = 0;
};

/// Rays on the planes of `node_count` nodes drawn at random from every node of the grid: on
/// both bounding planes and up to two cell boundaries of each, six rays per plane starting
/// on it: lying in it (crossing component +0.0, -0.0, or along an axis of the plane), and
/// crossing it.
inline PlaneRays rays_on_planes(const SplitGrid& grid, std::uint32_t seed, std::size_t node_count)
{
    const std::vector<NodeBox> boxes = node_boxes(grid);
    std::mt19937 rng(seed);
    std::uniform_int_distribution<std::size_t> pick(0, boxes.size() - 1);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::uniform_real_distribution<float> dir(-1.0f, 1.0f);
    PlaneRays out;
    for (std::size_t n = 0; n < node_count; ++n) {
        const NodeBox& nb = boxes[pick(rng)];
        const GridNode& node = grid.nodes[nb.node];
        const int axis = node.axis();
        const CellMath cm(node.lo, node.hi, node.resolution());
        ++out.nodes;
        out.deepest = std::max(out.deepest, nb.depth);
        // Both bounding planes and up to two interior boundaries.
        std::vector<float> planes{node.lo, node.hi};
        if (node.resolution() > 1) {
            std::uniform_int_distribution<std::uint32_t> inner(1, node.resolution() - 1);
            planes.push_back(cm.boundary(inner(rng)));
            planes.push_back(cm.boundary(inner(rng)));
        }
        for (const float plane : planes) {
            ++out.planes;
            for (int rep = 0; rep < 6; ++rep) {
                Ray r;
                for (int k = 0; k < 3; ++k)
                    r.origin[k] = nb.box.lower[k] + u(rng) * nb.box.extent(k);
                r.origin[axis] = plane;
                r.direction = {dir(rng), dir(rng), dir(rng)};
                if (rep == 0) r.direction[axis] = 0.0f;   // in the plane
                if (rep == 1) r.direction[axis] = -0.0f;  // in the plane, negative zero
                if (rep == 2) {                            // in the plane, along an axis
                    r.direction = {};
                    const int other = (rng() & 1) != 0 ? 1 : 2;
                    r.direction[(axis + other) % 3] = (rng() & 1) != 0 ? 1.0f : -1.0f;
                }
                // rep 3..5: starting on the plane and crossing it, either way.
                if (r.direction == Vec3f{}) r.direction[(axis + 1) % 3] = 1.0f;
                out.rays.push_back(r);
            }
        }
    }
    return out;
}

/// Axis-aligned rays exactly through random vertices: +-x, +-y, +-z in turn, half of them
/// starting outside the scene box and half on the vertex itself.
inline std::vector<Ray> axis_rays_through_vertices(const Mesh& mesh, const Aabb& box,
                                                   std::uint32_t seed, std::size_t count)
{
    std::mt19937 rng(seed);
    std::uniform_int_distribution<std::size_t> pick(0, mesh.triangles.size() - 1);
    std::vector<Ray> rays;
    for (std::size_t k = 0; k < count; ++k) {
        const Triangle& t = mesh.triangles[pick(rng)];
        const Vec3f v = mesh.vertices[t.v[k % 3]];
        const auto axis = static_cast<int>((k / 2) % 3);
        const bool forward = k % 2 == 0;
        Ray r;
        r.origin = v;
        r.direction = {};
        r.direction[axis] = forward ? 1.0f : -1.0f;
        if ((k / 6) % 2 == 0) {
            const float margin = box.extent(axis) + 1.0f;
            r.origin[axis] = forward ? box.lower[axis] - margin : box.upper[axis] + margin;
        }
        rays.push_back(r);
    }
    return rays;
}

}  // namespace sg::test
