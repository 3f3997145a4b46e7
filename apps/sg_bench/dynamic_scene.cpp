#include "dynamic_scene.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "splitgrid/error.hpp"

namespace sg::bench {
namespace {

constexpr double two_pi = 2.0 * std::numbers::pi;

// The model's horizontal reach: the largest distance of a vertex from the vertical (y) axis
// through `centre`, and from `centre` itself.
struct Reach {
    float horizontal = 0.0f;
    float radius = 0.0f;
};

Reach reach(const MeshView& model, Vec3f centre)
{
    Reach r;
    for (const Vec3f& v : model.vertices) {
        const Vec3f d = v - centre;
        r.horizontal = std::max(r.horizontal, std::sqrt(d.x * d.x + d.z * d.z));
        r.radius = std::max(r.radius, std::sqrt(dot(d, d)));
    }
    return r;
}

// Rigid motion: each copy turns about its own vertical axis (1.5 to 2.25 turns over the run,
// either way, each copy at its own speed and phase) while its centre circles its arena slot
// once.
constexpr float orbit_share = 0.5f;  // the circle's radius, in model radii

// Deformation: a twist of up to `twist` radians between the model's foot and its top, and a
// swelling of up to `swell` of the distance from the axis, in a wave that runs up the model.
constexpr double twist = 0.6;
constexpr double swell = 0.08;

template <class PerVertex>
void for_each_vertex(std::size_t count, const PerVertex& per_vertex)
{
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 16384),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                          for (std::size_t k = r.begin(); k != r.end(); ++k) per_vertex(k);
                      });
}

// Where the rigid copies go: a square lattice of `side` x `side` slots, `spacing` apart, each
// slot `room` wide on every side of its centre, enough for a copy (every vertex within
// `radius` of the origin of the centred model) turning on a circle of orbit_share * radius.
// The one layout make_dynamic_scene frames and animate moves the copies on.
struct RigidLayout {
    float radius = 0.0f;
    float room = 0.0f;
    float spacing = 0.0f;
    std::uint32_t side = 1;
};

RigidLayout rigid_layout(const MeshView& centred_model, std::uint32_t copies)
{
    RigidLayout l;
    l.radius = reach(centred_model, Vec3f{0.0f, 0.0f, 0.0f}).radius;
    l.room = l.radius * (1.0f + orbit_share) * 1.001f;
    l.spacing = 2.0f * l.room;
    l.side = static_cast<std::uint32_t>(std::ceil(std::sqrt(static_cast<double>(copies))));
    while (l.side * l.side < copies) ++l.side;
    return l;
}

}  // namespace

const char* motion_name(Motion motion) noexcept
{
    return motion == Motion::rigid ? "rigid" : "deform";
}

DynamicScene make_dynamic_scene(const std::string& stem, const std::string& source,
                                const MeshView& model, Motion motion, std::size_t min_triangles)
{
    if (model.triangles.empty()) throw InputError(source + ": no triangles to animate");
    DynamicScene scene;
    scene.name = stem + "_" + motion_name(motion);
    scene.motion = motion;
    const Aabb box = bounds(model);
    const Vec3f centre = (box.lower + box.upper) * 0.5f;
    scene.model.triangles.assign(model.triangles.begin(), model.triangles.end());
    scene.model.vertices.assign(model.vertices.begin(), model.vertices.end());
    if (motion == Motion::deform) {
        scene.triangles = scene.model.triangles;
        const float out = reach(model, centre).horizontal * static_cast<float>(1.0 + swell) * 1.001f;
        scene.arena = Aabb{{centre.x - out, box.lower.y, centre.z - out},
                           {centre.x + out, box.upper.y, centre.z + out}};
        scene.source = source + ", twisted and swelling";
        return scene;
    }
    for (Vec3f& v : scene.model.vertices) v = v - centre;
    const std::size_t n = model.triangles.size();
    scene.copies = static_cast<std::uint32_t>(std::max<std::size_t>(2, (min_triangles + n - 1) / n));
    const std::size_t vertices = model.vertices.size();
    if (vertices * scene.copies >= std::size_t{0xFFFFFFFFu})
        throw InputError(source + ": too many vertices for " + std::to_string(scene.copies) +
                         " copies");
    scene.triangles.reserve(n * scene.copies);
    for (std::uint32_t c = 0; c < scene.copies; ++c)
        for (const Triangle& t : model.triangles) {
            Triangle shifted = t;
            for (auto& index : shifted.v)
                index += static_cast<std::uint32_t>(c * vertices);
            scene.triangles.push_back(shifted);
        }
    const RigidLayout l = rigid_layout(scene.model.view(), scene.copies);
    const float far = static_cast<float>(l.side - 1) * l.spacing + l.room;
    scene.arena = Aabb{{-l.room, -l.radius * 1.001f, -l.room}, {far, l.radius * 1.001f, far}};
    scene.source = source + ", " + std::to_string(scene.copies) +
                   " copies turning and circling on an arena";
    return scene;
}

void animate(const DynamicScene& scene, std::uint32_t frame, std::uint32_t frames,
             std::span<Vec3f> out)
{
    SG_ASSERT(out.size() == scene.vertex_count());
    const double t = frames > 0 ? static_cast<double>(frame) / frames : 0.0;
    const std::vector<Vec3f>& model = scene.model.vertices;
    if (scene.motion == Motion::deform) {
        const Aabb box = bounds(scene.model.view());
        const Vec3f centre = (box.lower + box.upper) * 0.5f;
        const double height = std::max(1e-30, double(box.extent(1)));
        const double amount = std::sin(two_pi * t);
        for_each_vertex(model.size(), [&](std::size_t k) {
            const Vec3f v = model[k];
            const double h = (double(v.y) - box.lower.y) / height;  // 0 at the foot, 1 on top
            const double angle = twist * amount * h;
            const double scale = 1.0 + swell * amount * std::sin(two_pi * (h - t));
            const double x = (double(v.x) - centre.x) * scale, z = (double(v.z) - centre.z) * scale;
            out[k] = Vec3f{static_cast<float>(centre.x + x * std::cos(angle) - z * std::sin(angle)),
                           v.y,
                           static_cast<float>(centre.z + x * std::sin(angle) + z * std::cos(angle))};
        });
        return;
    }
    const RigidLayout l = rigid_layout(scene.model.view(), scene.copies);
    const std::size_t per_copy = model.size();
    for_each_vertex(out.size(), [&](std::size_t k) {
        const std::size_t c = k / per_copy;
        const double phase = 0.618034 * static_cast<double>(c);  // golden-ratio spread
        const double speed = 1.5 * (c % 2 == 0 ? 1.0 : -1.0) * (1.0 + 0.25 * double(c % 3));
        const double angle = two_pi * (phase + speed * t);
        const double around = two_pi * (phase + t);
        const double orbit = orbit_share * l.radius;
        const double cx = double(c % l.side) * l.spacing + orbit * std::cos(around);
        const double cz = double(c / l.side) * l.spacing + orbit * std::sin(around);
        const Vec3f v = model[k % per_copy];
        out[k] = Vec3f{static_cast<float>(cx + v.x * std::cos(angle) - v.z * std::sin(angle)), v.y,
                       static_cast<float>(cz + v.x * std::sin(angle) + v.z * std::cos(angle))};
    });
}

}  // namespace sg::bench
