// Intel Embree 3 as the outside reference of sg-bench: the same mesh and the same rays through
// rtcIntersect1 / rtcOccluded1, memory (held, and the peak of a build) counted by Embree's own
// memory monitor.

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstring>
#include <limits>
#include <string>

#include <embree3/rtcore.h>
#include <sys/types.h>
#include <tbb/task_arena.h>

#include "bench_structure.hpp"
#include "build_memory.hpp"
#include "splitgrid/error.hpp"

namespace sg::bench {
namespace {

// The bytes an Embree device holds: the running sum of what its memory monitor reports, and
// the highest value the sum has reached.
struct DeviceBytes {
    std::atomic<long long> held{0};
    std::atomic<long long> peak{0};
};

// Embree reports each allocation and release (negative bytes) here.
bool monitor(void* user, ssize_t bytes, bool /*post*/)
{
    auto& d = *static_cast<DeviceBytes*>(user);
    raise_peak(d.peak, d.held.fetch_add(static_cast<long long>(bytes)) + bytes);
    return true;
}

// How a scene is built: the static runs' default (MEDIUM, the mesh's vertices copied), or one
// of the dynamic workload's frame modes (the application's vertex array shared, rebuilt or
// refitted on every commit).
struct EmbreeSetup {
    bool robust = false;
    RTCBuildQuality quality = RTC_BUILD_QUALITY_MEDIUM;
    bool refit = false;           // with quality LOW: geometry build quality REFIT
    bool dynamic = false;         // scene flag DYNAMIC
    bool share_vertices = false;  // the mesh's vertex array is Embree's vertex buffer
};

class EmbreeStructure final : public BenchStructure {
public:
    EmbreeStructure(const MeshView& mesh, const EmbreeSetup& setup, unsigned threads)
        : threads_(threads)
    {
        const std::string config = "threads=" + std::to_string(threads == 0 ? 0 : threads);
        device_ = rtcNewDevice(config.c_str());
        if (!device_) throw ConfigError("Embree: rtcNewDevice failed");
        rtcSetDeviceMemoryMonitorFunction(device_, monitor, &bytes_);
        try {
            build(mesh, setup);
        } catch (...) {
            release();  // the destructor does not run for a constructor that throws
            throw;
        }
    }
    ~EmbreeStructure() override { release(); }
    EmbreeStructure(const EmbreeStructure&) = delete;
    EmbreeStructure& operator=(const EmbreeStructure&) = delete;

    double build_seconds() const override { return build_seconds_; }
    std::optional<std::size_t> own_build_peak_bytes() const override { return build_peak_bytes_; }
    // The BVH and Embree's other bookkeeping, without its copy of the vertices (which
    // trace_mesh_bytes counts in its place of the mesh's own vertex array).
    std::size_t structure_bytes() const override
    {
        const long long total = bytes_.held.load();
        const auto held = static_cast<std::size_t>(std::max(0LL, total));
        return held > vertex_buffer_bytes_ ? held - vertex_buffer_bytes_ : 0;
    }
    std::size_t reference_count() const override { return 0; }

    void intersect(std::span<const Ray> rays, std::span<Hit> hits,
                   const QueryVariant& /*variant*/) const override
    {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        for (std::size_t k = 0; k < rays.size(); ++k) {
            RTCRayHit rh = to_embree(rays[k]);
            rtcIntersect1(scene_, &context, &rh);
            Hit h;
            h.t = rays[k].t_max;
            if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) {
                h.t = rh.ray.tfar;
                h.triangle = rh.hit.primID;
                h.u = rh.hit.u;
                h.v = rh.hit.v;
            }
            hits[k] = h;
        }
    }
    void occluded(std::span<const Ray> rays, std::span<std::uint8_t> out) const override
    {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        for (std::size_t k = 0; k < rays.size(); ++k) {
            RTCRay ray = to_embree(rays[k]).ray;
            rtcOccluded1(scene_, &context, &ray);
            out[k] = ray.tfar == -std::numeric_limits<float>::infinity() ? 1 : 0;
        }
    }

    /// The shared vertex array changed: commit it and the scene again (a rebuild at the
    /// setup's quality, or a refit). Returns the seconds it took.
    double commit_moved_vertices()
    {
        const auto start = std::chrono::steady_clock::now();
        rtcUpdateGeometryBuffer(geometry_, RTC_BUFFER_TYPE_VERTEX, 0);
        rtcCommitGeometry(geometry_);
        commit_scene();
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }

private:
    // Creates the scene and its one triangle geometry and builds it, timed from scene
    // creation to the end of the commit.
    void build(const MeshView& mesh, const EmbreeSetup& setup)
    {
        const long long before = bytes_.held.load();
        bytes_.peak.store(before);
        const auto start = std::chrono::steady_clock::now();
        scene_ = rtcNewScene(device_);
        int flags = setup.robust ? RTC_SCENE_FLAG_ROBUST : RTC_SCENE_FLAG_NONE;
        if (setup.dynamic) flags |= RTC_SCENE_FLAG_DYNAMIC;
        rtcSetSceneFlags(scene_, static_cast<RTCSceneFlags>(flags));
        rtcSetSceneBuildQuality(scene_, setup.quality);
        geometry_ = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
        // Embree heeds a geometry's build quality only under a scene of quality LOW (its
        // two-level structure), so LOW and REFIT set both.
        if (setup.quality == RTC_BUILD_QUALITY_LOW)
            rtcSetGeometryBuildQuality(geometry_, setup.refit ? RTC_BUILD_QUALITY_REFIT
                                                              : RTC_BUILD_QUALITY_LOW);
        if (setup.share_vertices && !mesh.vertices.empty()) {
            // The caller keeps 4 readable bytes after the last vertex (Embree's 16-byte loads).
            rtcSetSharedGeometryBuffer(geometry_, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                       mesh.vertices.data(), 0, sizeof(Vec3f),
                                       mesh.vertices.size());
        } else {
            // Embree reads vertices with 16-byte loads, so its vertex buffer is its own padded
            // copy (counted by the monitor); the index buffer is shared with the mesh.
            auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
                geometry_, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                std::max<std::size_t>(1, mesh.vertices.size())));
            if (!mesh.vertices.empty())
                std::memcpy(vertices, mesh.vertices.data(), mesh.vertices.size() * sizeof(Vec3f));
            vertex_buffer_bytes_ = mesh.vertices.size() * sizeof(Vec3f);
        }
        if (!mesh.triangles.empty())
            rtcSetSharedGeometryBuffer(geometry_, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                       mesh.triangles.data(), 0, sizeof(Triangle),
                                       mesh.triangles.size());
        rtcCommitGeometry(geometry_);
        if (!mesh.triangles.empty()) rtcAttachGeometry(scene_, geometry_);
        commit_scene();
        build_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        const long long peak = bytes_.peak.load() - before - static_cast<long long>(vertex_buffer_bytes_);
        build_peak_bytes_ = static_cast<std::size_t>(std::max(0LL, peak));
    }

    void release() noexcept
    {
        if (geometry_) rtcReleaseGeometry(geometry_);
        if (scene_) rtcReleaseScene(scene_);
        if (device_) rtcReleaseDevice(device_);
        geometry_ = nullptr;
        scene_ = nullptr;
        device_ = nullptr;
    }

    void commit_scene()
    {
        tbb::task_arena arena(threads_ == 0 ? tbb::task_arena::automatic : static_cast<int>(threads_));
        arena.execute([&] { rtcCommitScene(scene_); });
        if (rtcGetDeviceError(device_) != RTC_ERROR_NONE)
            throw InputError("Embree: the scene could not be built");
    }

    static RTCRayHit to_embree(const Ray& r) noexcept
    {
        RTCRayHit rh;
        rh.ray.org_x = r.origin.x;
        rh.ray.org_y = r.origin.y;
        rh.ray.org_z = r.origin.z;
        rh.ray.tnear = r.t_min;
        rh.ray.dir_x = r.direction.x;
        rh.ray.dir_y = r.direction.y;
        rh.ray.dir_z = r.direction.z;
        rh.ray.time = 0.0f;
        rh.ray.tfar = r.t_max;
        rh.ray.mask = 0xFFFFFFFFu;
        rh.ray.id = 0;
        rh.ray.flags = 0;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        return rh;
    }

    unsigned threads_ = 0;
    RTCDevice device_ = nullptr;
    RTCScene scene_ = nullptr;
    RTCGeometry geometry_ = nullptr;
    DeviceBytes bytes_;
    std::size_t vertex_buffer_bytes_ = 0;
    std::size_t build_peak_bytes_ = 0;
    double build_seconds_ = 0.0;
};

// Embree over the frames of a dynamic scene: one device and scene for all of them.
class EmbreeFrames final : public FrameStructureBase {
public:
    EmbreeFrames(const MeshView& mesh, const EmbreeSetup& setup, unsigned threads)
        : embree_(mesh, setup, threads)
    {
    }
    const BenchStructure& structure() const override { return embree_; }

protected:
    double next_frame(const MeshView& /*moved*/) override
    {
        return embree_.commit_moved_vertices();
    }

private:
    EmbreeStructure embree_;
};

}  // namespace

bool has_embree() { return true; }
std::string embree_version() { return RTC_VERSION_STRING; }

std::unique_ptr<BenchStructure> build_embree(const MeshView& mesh, bool robust, unsigned threads)
{
    EmbreeSetup setup;
    setup.robust = robust;
    return std::make_unique<EmbreeStructure>(mesh, setup, threads);
}

std::unique_ptr<FrameStructure> embree_frames(const MeshView& mesh, EmbreeFrameMode mode,
                                              unsigned threads)
{
    EmbreeSetup setup;
    setup.share_vertices = true;
    if (mode == EmbreeFrameMode::low) {
        setup.quality = RTC_BUILD_QUALITY_LOW;
        setup.dynamic = true;
    } else if (mode == EmbreeFrameMode::refit) {
        setup.quality = RTC_BUILD_QUALITY_LOW;
        setup.refit = true;
        setup.dynamic = true;
    }
    return std::make_unique<EmbreeFrames>(mesh, setup, threads);
}

}  // namespace sg::bench
