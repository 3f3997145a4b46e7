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

class EmbreeStructure final : public BenchStructure {
public:
    EmbreeStructure(const MeshView& mesh, bool robust, unsigned threads)
    {
        const std::string config = "threads=" + std::to_string(threads == 0 ? 0 : threads);
        device_ = rtcNewDevice(config.c_str());
        if (!device_) throw ConfigError("Embree: rtcNewDevice failed");
        rtcSetDeviceMemoryMonitorFunction(device_, monitor, &bytes_);

        const long long before = bytes_.held.load();
        bytes_.peak.store(before);
        const auto start = std::chrono::steady_clock::now();
        scene_ = rtcNewScene(device_);
        rtcSetSceneFlags(scene_, robust ? RTC_SCENE_FLAG_ROBUST : RTC_SCENE_FLAG_NONE);
        rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_MEDIUM);
        RTCGeometry geometry = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
        // Embree reads vertices with 16-byte loads, so its vertex buffer is its own padded
        // copy (counted by the monitor); the index buffer is shared with the mesh.
        auto* vertices = static_cast<float*>(
            rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                    3 * sizeof(float), std::max<std::size_t>(1, mesh.vertices.size())));
        if (!mesh.vertices.empty())
            std::memcpy(vertices, mesh.vertices.data(), mesh.vertices.size() * sizeof(Vec3f));
        vertex_buffer_bytes_ = mesh.vertices.size() * sizeof(Vec3f);
        if (!mesh.triangles.empty())
            rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                       mesh.triangles.data(), 0, sizeof(Triangle),
                                       mesh.triangles.size());
        rtcCommitGeometry(geometry);
        if (!mesh.triangles.empty()) rtcAttachGeometry(scene_, geometry);
        rtcReleaseGeometry(geometry);
        tbb::task_arena arena(threads == 0 ? tbb::task_arena::automatic : static_cast<int>(threads));
        arena.execute([&] { rtcCommitScene(scene_); });
        build_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        const long long peak = bytes_.peak.load() - before - static_cast<long long>(vertex_buffer_bytes_);
        build_peak_bytes_ = static_cast<std::size_t>(std::max(0LL, peak));
        if (rtcGetDeviceError(device_) != RTC_ERROR_NONE)
            throw InputError("Embree: the scene could not be built");
    }
    ~EmbreeStructure() override
    {
        if (scene_) rtcReleaseScene(scene_);
        if (device_) rtcReleaseDevice(device_);
    }
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

private:
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

    RTCDevice device_ = nullptr;
    RTCScene scene_ = nullptr;
    DeviceBytes bytes_;
    std::size_t vertex_buffer_bytes_ = 0;
    std::size_t build_peak_bytes_ = 0;
    double build_seconds_ = 0.0;
};

}  // namespace

bool has_embree() { return true; }
std::string embree_version() { return RTC_VERSION_STRING; }

std::unique_ptr<BenchStructure> build_embree(const MeshView& mesh, bool robust, unsigned threads)
{
    return std::make_unique<EmbreeStructure>(mesh, robust, threads);
}

}  // namespace sg::bench
