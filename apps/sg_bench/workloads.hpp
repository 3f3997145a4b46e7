#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "bench_structure.hpp"
#include "splitgrid/camera.hpp"
#include "splitgrid/mesh.hpp"
#include "splitgrid/ray.hpp"

/// The ray sets sg-bench traces. Every structure traces exactly the same rays: each workload
/// is generated once per scene, from fixed seeds, and kept as an array.
namespace sg::bench {

/// One workload: its rays and whether they are any-hit (shadow) queries.
struct Workload {
    std::string name;
    bool any_hit = false;
    std::vector<Ray> rays;
};

/// Sizes of the workloads; the defaults are the paper's image size (Figure 3: 1024 x 768,
/// path tracing with 3 diffuse bounces).
struct WorkloadSizes {
    int width = 1024;
    int height = 768;
    std::uint32_t bounces = 3;
    std::size_t incoherent_rays = 1'000'000;
};

/// The camera of the primary rays: the whole scene framed (frame_box) for width/height.
[[nodiscard]] Camera workload_camera(const MeshView& mesh, const WorkloadSizes& sizes);

/// Builds the four workloads of a scene, in this order:
///   "primary"    one ray through each pixel centre of the framed camera;
///   "path"       the rays of a diffuse path tracer at one sample per pixel: each primary ray
///                and up to `bounces` cosine-sampled bounce rays spawned from its hits (the
///                offset rule of ray_offset.hpp), as the paper's Figure 3 workload;
///   "incoherent" origins uniform in the scene's box, directions uniform on the sphere;
///   "shadow"     any-hit rays from every primary hit towards a point light above the scene,
///                ending just before the light.
/// Bounces and shadow rays need hits: `reference` (any structure over `mesh`) finds them.
/// Deterministic for a seed, and independent of the thread count.
[[nodiscard]] std::vector<Workload> make_scene_workloads(const MeshView& mesh,
                                                         const BenchStructure& reference,
                                                         const WorkloadSizes& sizes,
                                                         std::uint32_t seed);

/// The rays of a diffuse path tracer at one sample per pixel of `camera` (the "path"
/// workload): each pixel's primary ray and up to `bounces` cosine-sampled bounce rays spawned
/// from its hits, found by `reference`; pixel by pixel, rows in order.
[[nodiscard]] std::vector<Ray> path_rays(const MeshView& mesh, const BenchStructure& reference,
                                         const PrimaryRays& camera, std::uint32_t bounces,
                                         std::uint32_t seed);

/// A closed UV sphere with shared vertices, at least `min_triangles` triangles, for the
/// watertightness workload.
[[nodiscard]] Mesh closed_sphere(Vec3f centre, float radius, std::size_t min_triangles);

/// Rays from random points inside the closed `sphere` (centre, radius as made by
/// closed_sphere): two thirds towards random directions, one sixth aimed exactly at vertices,
/// one sixth at edge midpoints, the hardest places for a test that is not watertight. Every
/// one of them must hit: a miss is a leak. Ray k is of kind interior_ray_kind(k).
/// 0: random direction, 1: aimed at a vertex, 2: aimed at an edge midpoint.
[[nodiscard]] constexpr std::size_t interior_ray_kind(std::size_t k) noexcept
{
    return k % 6 < 4 ? 0 : (k % 6 == 4 ? 1 : 2);
}

[[nodiscard]] std::vector<Ray> interior_rays(const Mesh& sphere, Vec3f centre, float radius,
                                             std::size_t count, std::uint32_t seed);

}  // namespace sg::bench
