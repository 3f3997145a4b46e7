#include "dynamic.hpp"

#include <algorithm>
#include <cmath>
#include <memory>

#include "splitgrid/camera.hpp"
#include "splitgrid/error.hpp"
#include "workloads.hpp"

namespace sg::bench {
namespace {

bool is_embree(const std::string& name) { return name.rfind("embree", 0) == 0; }

}  // namespace

double steady_median(const std::vector<std::uint32_t>& frames, const std::vector<double>& values)
{
    std::vector<double> later;
    for (std::size_t k = 0; k < frames.size() && k < values.size(); ++k)
        if (frames[k] > 0) later.push_back(values[k]);
    if (later.empty()) return values.empty() ? 0.0 : values.front();
    return median(later);
}

DynamicResult run_dynamic(const DynamicScene& scene, const DynamicPlan& plan, const BenchLog& log)
{
    if (plan.structures.empty()) throw ConfigError("no structures for the dynamic workload");
    if (plan.frames == 0) throw ConfigError("the dynamic workload needs at least one frame");
    DynamicResult result;
    result.scene = scene.name;
    result.source = scene.source;
    result.motion = motion_name(scene.motion);
    result.triangles = scene.triangles.size();
    result.frames = plan.frames;
    result.threads = plan.threads;
    result.ray_budgets = plan.ray_budgets;

    // Two spare vertices after the last: Embree reads the array in place with 16-byte loads.
    const std::size_t vertex_count = scene.vertex_count();
    std::vector<Vec3f> positions(vertex_count + 2, Vec3f{0.0f, 0.0f, 0.0f});
    const std::span<Vec3f> moving(positions.data(), vertex_count);
    const MeshView mesh{std::span<const Vec3f>(positions.data(), vertex_count), scene.triangles};
    animate(scene, 0, plan.frames, moving);

    // The rays and the answers every structure is checked against come from our BVH, built
    // on frame 0 and refitted on every frame (exact: tests/libsplitgrid/bvh_test.cpp). It is
    // none of the measured structures, so none of them traces rays it has just traced to
    // make them; each measured structure traces right after its own update.
    const std::unique_ptr<FrameStructure> reference =
        make_frame_structure("bvh_refit", mesh, plan.configs, plan.threads);

    const std::size_t count = plan.structures.size();
    std::vector<std::unique_ptr<FrameStructure>> structures;
    for (const std::string& name : plan.structures) {
        log(scene.name + ": building " + name);
        structures.push_back(make_frame_structure(name, mesh, plan.configs, plan.threads));
        DynamicStructureResult r;
        r.structure = name;
        r.trace_seconds.resize(plan.ray_budgets.size());
        result.structures.push_back(std::move(r));
    }

    // One camera for every frame, framing the box the scene never leaves. Each budget gets
    // an image whose path rays just exceed it (rays per pixel measured on a small image of
    // the first frame), and traces the first `budget` of them.
    const Camera camera = frame_box(scene.arena, 4.0f / 3.0f);
    const double per_pixel = [&] {
        const PrimaryRays probe(camera, 64, 48);
        const auto rays = path_rays(mesh, reference->structure(), probe, plan.bounces, plan.seed);
        return std::max(1.0, static_cast<double>(rays.size()) / (64.0 * 48.0));
    }();
    std::vector<PrimaryRays> images;
    for (const std::size_t budget : plan.ray_budgets) {
        const double pixels = std::ceil(1.2 * static_cast<double>(budget) / per_pixel);
        const int width = std::max(1, static_cast<int>(std::lround(std::sqrt(pixels * 4.0 / 3.0))));
        const int height = std::max(1, static_cast<int>(std::ceil(pixels / width)));
        images.emplace_back(camera, width, height);
        result.images.emplace_back(width, height);
    }
    result.rays_per_frame.assign(plan.ray_budgets.size(), 0.0);

    std::vector<std::uint32_t> stride(count, 1);
    std::vector<std::vector<Ray>> rays(plan.ray_budgets.size());
    std::vector<std::vector<Hit>> expected(plan.ray_budgets.size());
    std::vector<Hit> hits;
    for (std::uint32_t frame = 0; frame < plan.frames; ++frame) {
        if (frame > 0) animate(scene, frame, plan.frames, moving);
        (void)reference->update(mesh);
        for (std::size_t b = 0; b < plan.ray_budgets.size(); ++b) {
            rays[b] = path_rays(mesh, reference->structure(), images[b], plan.bounces,
                                plan.seed + frame);
            if (rays[b].size() > plan.ray_budgets[b]) rays[b].resize(plan.ray_budgets[b]);
            result.rays_per_frame[b] += static_cast<double>(rays[b].size()) / plan.frames;
            (void)trace_closest(reference->structure(), rays[b], plan.threads, expected[b]);
        }
        for (std::size_t k = 0; k < count; ++k) {
            if (frame > 1 && frame % stride[k] != 0) continue;
            DynamicStructureResult& r = result.structures[k];
            r.frames.push_back(frame);
            r.update_seconds.push_back(structures[k]->update(mesh));
            if (frame == 1 && k > 0 && plan.slow_factor > 0.0 &&
                r.update_seconds.back() >
                    plan.slow_factor * result.structures[0].update_seconds.back())
                stride[k] = 10;
            // structure() after the update: a rebuild replaces the object.
            const BenchStructure& updated = structures[k]->structure();
            const bool exact = !is_embree(r.structure);
            for (std::size_t b = 0; b < plan.ray_budgets.size(); ++b) {
                r.trace_seconds[b].push_back(trace_closest(updated, rays[b], plan.threads, hits));
                for (std::size_t i = 0; i < rays[b].size(); ++i)
                    r.disagreements += same_hit(expected[b][i], hits[i], exact) ? 0 : 1;
            }
        }
        if (frame == 0 || (frame + 1) % 10 == 0 || frame + 1 == plan.frames)
            log(scene.name + ": frame " + std::to_string(frame + 1) + " of " +
                std::to_string(plan.frames));
    }
    return result;
}

}  // namespace sg::bench
