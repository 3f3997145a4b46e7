#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "splitgrid/baselines/bvh.hpp"
#include "splitgrid/baselines/kd_tree.hpp"
#include "splitgrid/baselines/uniform_grid.hpp"
#include "splitgrid/build_config.hpp"
#include "splitgrid/closest_point.hpp"
#include "splitgrid/mesh.hpp"
#include "splitgrid/query.hpp"
#include "splitgrid/ray.hpp"
#include "splitgrid/traversal_counters.hpp"

/// The one interface sg-bench measures every acceleration structure through: build on a mesh
/// with a thread count, report memory, trace batches of rays. Batches, not single rays, cross
/// the virtual call, so the per-ray loop of each structure is its own inlined code.
namespace sg::bench {

/// Which ray/triangle test and interval padding a query uses (query.hpp). The default is the
/// exact pair; the others feed the speed-against-accuracy chart.
using QueryVariant = QueryOptions;
/// "watertight", "watertight-nopad", "moller-trumbore", "moller-trumbore-nopad".
[[nodiscard]] std::string variant_name(const QueryVariant& variant);
/// The four variants of our own structures, exact first.
[[nodiscard]] std::vector<QueryVariant> all_variants();

/// The queries of the point and multi-hit workloads (point_bench.hpp).
enum class PointQuery { count, occupancy, closest };
/// "count", "occupancy", "closest".
[[nodiscard]] std::string_view point_query_name(PointQuery query) noexcept;

/// What answers the point and multi-hit workloads: our structures, and CGAL (cgal_peer.hpp).
/// Every query runs serially in the calling thread and is const: several threads call at once.
class PointQueries {
public:
    virtual ~PointQueries() = default;
    /// "" if `query` is answered, else why not (the results say "n/a: <why>").
    [[nodiscard]] virtual std::string unavailable(PointQuery query) const = 0;
    /// True for our structures, whose distances come from the computation of
    /// closest_point_brute_force (closest_point.hpp) and so equal it bit for bit; false for a
    /// peer, whose distances agree with it within a tolerance.
    [[nodiscard]] virtual bool exact_distances() const = 0;
    /// The number of triangles each ray hits (count_intersections), into `counts`.
    virtual void count_intersections(std::span<const Ray> rays,
                                     std::span<std::int32_t> counts) const = 0;
    /// Inside (1) or outside (0) of each point: compute_occupancy with the triangle test
    /// `test` (a peer runs its own test, whatever `test` says).
    virtual void occupancy(std::span<const Vec3f> points, std::span<float> inside,
                           TriangleTest test) const = 0;
    /// The closest point of the mesh to each point (closest_points; a peer fills the
    /// distance, the triangle and the point, not the barycentrics).
    virtual void closest_points(std::span<const Vec3f> points,
                                std::span<ClosestPoint> out) const = 0;
};

/// A built structure over one mesh (which the caller keeps alive).
class BenchStructure {
public:
    virtual ~BenchStructure() = default;

    /// Seconds the build took, measured by the structure around its own build call (for
    /// Embree: scene creation to commit, without creating the device).
    [[nodiscard]] virtual double build_seconds() const = 0;
    /// Bytes of the acceleration structure alone, without the mesh (for Embree: what its
    /// memory monitor counts, less its own copy of the vertices). Everything needed to trace
    /// is this plus the mesh: 12 bytes per vertex and 12 per triangle for every structure.
    [[nodiscard]] virtual std::size_t structure_bytes() const = 0;
    /// Highest number of bytes its build held at once, where the structure measures it itself
    /// (Embree: the highest sum of its memory monitor over the build, less its copy of the
    /// vertices); empty for ours, whose allocations build_memory.hpp counts.
    [[nodiscard]] virtual std::optional<std::size_t> own_build_peak_bytes() const
    {
        return std::nullopt;
    }
    /// Triangle references held by the structure (for Embree: 0, not exposed).
    [[nodiscard]] virtual std::size_t reference_count() const = 0;
    /// Whether `variant` can be run (Embree runs only its own test: the default variant).
    [[nodiscard]] virtual bool supports(const QueryVariant& variant) const
    {
        return variant == QueryVariant{};
    }
    /// Closest hits of `rays` into `hits` (same size), serially in the calling thread.
    virtual void intersect(std::span<const Ray> rays, std::span<Hit> hits,
                           const QueryVariant& variant) const = 0;
    /// Any-hit answers (1 = occluded) of `rays` into `occluded` (same size).
    virtual void occluded(std::span<const Ray> rays, std::span<std::uint8_t> occluded) const = 0;
    /// Adds the traversal work of each ray's query (closest hit, or any hit) to `sum`; false
    /// if the structure does not count its work (Embree).
    virtual bool count_work(std::span<const Ray> rays, bool any_hit, TraversalCounters& sum) const
    {
        (void)rays;
        (void)any_hit;
        (void)sum;
        return false;
    }
    /// The point and multi-hit queries, or nullptr where the structure has none (Embree:
    /// Debian's is built without the filter functions that counting hits needs).
    [[nodiscard]] virtual const PointQueries* point_queries() const { return nullptr; }
};

/// Parameters of every structure sg-bench can build; each keeps its library defaults
/// unless a flag changes them.
struct StructureConfigs {
    BuildConfig split_grid;
    UniformGridConfig uniform_grid;
    KdTreeConfig kd_tree;
    BvhConfig bvh;
    /// Embree's scene flags: RTC_SCENE_FLAG_ROBUST when true (the "embree-robust" variant).
    bool embree_robust = false;
};

/// Names sg-bench accepts for --structures, in report order: "splitgrid" (the build flags'
/// construction, by default the default preset), "splitgrid_poster" (the same flags with the
/// poster preset applied), "uniform_grid", "kd_tree", "bvh", and "embree" when the build
/// found Embree (SG_WITH_EMBREE).
[[nodiscard]] std::vector<std::string> structure_names();
/// True if this build of sg-bench includes Embree.
[[nodiscard]] bool has_embree();
/// Version string of the Embree library, or "" without Embree.
[[nodiscard]] std::string embree_version();

/// Builds structure `name` (one of structure_names()) over `mesh` with `threads` worker
/// threads. Throws ConfigError for an unknown name or bad config.
[[nodiscard]] std::unique_ptr<BenchStructure> build_structure(const std::string& name,
                                                              const MeshView& mesh,
                                                              const StructureConfigs& configs,
                                                              unsigned threads);

/// Embree (embree_structure.cpp), only in builds with SG_WITH_EMBREE.
[[nodiscard]] std::unique_ptr<BenchStructure> build_embree(const MeshView& mesh, bool robust,
                                                           unsigned threads);

/// A structure kept over the frames of a dynamic scene (dynamic.hpp): made on the first
/// frame's mesh, then brought up to date with every later frame's vertex positions. The
/// mesh's arrays stay where they are (the vertices are overwritten in place), so a structure
/// may keep views of them.
class FrameStructure {
public:
    virtual ~FrameStructure() = default;
    /// Brings the structure up to date with `moved` (the mesh it was made on, vertices
    /// moved); returns the seconds that took. The first call returns the time of the build
    /// the constructor made, on the mesh it was made on.
    virtual double update(const MeshView& moved) = 0;
    /// The structure as it stands, for tracing; valid until the next update() (a rebuild
    /// replaces it).
    [[nodiscard]] virtual const BenchStructure& structure() const = 0;
};

/// The usual shape of a FrameStructure: the constructor builds (that build is frame 0's
/// update); every later frame calls next_frame.
class FrameStructureBase : public FrameStructure {
public:
    double update(const MeshView& moved) final
    {
        if (!first_done_) {
            first_done_ = true;
            return structure().build_seconds();
        }
        return next_frame(moved);
    }

protected:
    /// Brings the structure up to date with `moved`; returns the seconds that took.
    virtual double next_frame(const MeshView& moved) = 0;

private:
    bool first_done_ = false;
};

/// How Embree follows a dynamic scene: rebuilds at MEDIUM quality (its default, as in the
/// static runs); or, with the DYNAMIC scene flag and scene quality LOW (its two-level
/// structure, the only one that heeds a geometry's quality), rebuilds the geometry at LOW
/// quality (its Morton builder) or refits the geometry's first tree (quality REFIT).
enum class EmbreeFrameMode { medium, low, refit };

/// Embree over the frames of a dynamic scene (one device and scene for all frames). Embree
/// reads the mesh's vertex array in place (no copy), so the array must be followed by at
/// least 4 readable bytes. Only in builds with SG_WITH_EMBREE.
[[nodiscard]] std::unique_ptr<FrameStructure> embree_frames(const MeshView& mesh,
                                                            EmbreeFrameMode mode,
                                                            unsigned threads);

/// Names of the ways a structure can follow a dynamic scene, in report order: every
/// structure_names() entry rebuilt on each frame ("embree": its scene committed again at
/// MEDIUM), then "bvh_refit" (our BVH built on the first frame and refitted, Bvh::refit),
/// and with Embree "embree_low" and "embree_refit" (EmbreeFrameMode).
[[nodiscard]] std::vector<std::string> frame_structure_names();

/// Makes `name` (one of frame_structure_names()) over the first frame `mesh` with `threads`
/// worker threads. Throws ConfigError for an unknown name.
[[nodiscard]] std::unique_ptr<FrameStructure> make_frame_structure(const std::string& name,
                                                                   const MeshView& mesh,
                                                                   const StructureConfigs& configs,
                                                                   unsigned threads);

}  // namespace sg::bench
