#include "splitgrid/ray_generation.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "splitgrid/sampling.hpp"

namespace sg {

std::vector<Ray> pixel_centre_rays(const PrimaryRays& camera)
{
    const auto width = static_cast<std::size_t>(camera.width());
    const auto height = static_cast<std::size_t>(camera.height());
    std::vector<Ray> rays(width * height);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, height),
                      [&](const tbb::blocked_range<std::size_t>& rows) {
                          for (std::size_t y = rows.begin(); y < rows.end(); ++y)
                              for (std::size_t x = 0; x < width; ++x)
                                  rays[y * width + x] =
                                      camera.ray(static_cast<float>(x) + 0.5f,
                                                 static_cast<float>(y) + 0.5f);
                      });
    return rays;
}

std::vector<Ray> random_rays_in_box(const Aabb& box, std::size_t count, std::uint64_t seed)
{
    std::vector<Ray> rays(count);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 4096),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                          for (std::size_t k = r.begin(); k < r.end(); ++k) {
                              Rng rng(seed, k);
                              Vec3f origin;
                              for (int a = 0; a < 3; ++a)
                                  origin[a] = box.lower[a] + rng.next_float() * box.extent(a);
                              const float u1 = rng.next_float();
                              const float u2 = rng.next_float();
                              rays[k] = Ray{origin, uniform_sphere(u1, u2)};
                          }
                      });
    return rays;
}

}  // namespace sg
