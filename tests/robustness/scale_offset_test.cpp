// Row 2 of docs/ROBUSTNESS.md: the leak rate of row 1 for every combination of a translation
// 10^0 ... 10^7 and a scale 10^-6 ... 10^6, printed as a table (copied into the document).
// Wherever the triangles still span at least 2^10 ulps of their own coordinates there must be
// no leak, and the grid must agree with brute force on a sample of the rays; elsewhere the
// rate is only reported (there rounding moves the vertices themselves, so the closed mesh may
// stop being closed around the ray origins: nothing is asserted but "no crash").

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "leak_probe.hpp"
#include "robustness_support.hpp"

namespace sg::test {
namespace {

constexpr double resolved_span_ulps = 1024.0;  // 2^10

struct Cell {
    LeakCount leaks;
    double span_ulps = 0.0;
    std::size_t sampled = 0;
    std::size_t disagreements = 0;
    std::string first_disagreement;
    std::size_t nodes = 0;
};

std::string rate_text(const Cell& c)
{
    char text[32];
    if (c.leaks.leaks() == 0)
        std::snprintf(text, sizeof text, "0");
    else if (c.leaks.leaks() == c.leaks.rays)
        std::snprintf(text, sizeof text, "all");
    else
        std::snprintf(text, sizeof text, "%.1e", c.leaks.rate());
    std::string s = text;
    if (c.span_ulps < resolved_span_ulps) s += "*";
    return s;
}

// The rest of a Markdown table's header: one column per translation.
void print_columns(const std::vector<int>& translations)
{
    for (int t : translations) std::printf(" 1e%d |", t);
    std::printf("\n|---|");
    for (std::size_t k = 0; k < translations.size(); ++k) std::printf("---:|");
    std::printf("\n");
}

TEST(ScaleOffset, LeakRateTableIsZeroWhereTrianglesSpanEnoughUlps)
{
    const std::vector<int> translations{0, 1, 2, 3, 4, 5, 6, 7};  // 10^k
    const std::vector<int> scales{-6, -4, -3, -2, -1, 0, 1, 2, 3, 4, 6};
    // CI: a 2,208-triangle sphere and 1,000 rays per entry; full: 3,968 triangles and 30,000
    // rays. (Where rounding makes the grid a single leaf, every ray tests every triangle.)
    const bool full = full_size();
    const std::uint32_t rings = full ? 32 : 24, segments = full ? 64 : 48;
    const std::size_t random = pick_size(600, 20000), aimed = pick_size(200, 5000);
    const std::size_t sample = pick_size(50, 500);

    std::vector<std::vector<Cell>> table(scales.size(), std::vector<Cell>(translations.size()));
    std::size_t resolved = 0;
    for (std::size_t si = 0; si < scales.size(); ++si) {
        for (std::size_t ti = 0; ti < translations.size(); ++ti) {
            const double t = std::pow(10.0, translations[ti]);
            const auto radius = static_cast<float>(std::pow(10.0, scales[si]));
            const Vec3f center{static_cast<float>(t), static_cast<float>(-0.5 * t),
                               static_cast<float>(0.75 * t)};
            const LeakScene scene(center, radius, rings, segments);
            Cell& cell = table[si][ti];
            cell.span_ulps = smallest_span_in_ulps(scene.mesh.view());
            cell.nodes = scene.grid.nodes.size();
            const auto seed = static_cast<std::uint32_t>(100 * si + ti);
            const std::vector<Ray> rays = scene.random_rays(seed, random);
            cell.leaks += scene.count_leaks(rays);
            cell.leaks += scene.count_leaks(scene.rays_at_vertices(seed + 1, aimed));
            cell.leaks += scene.count_leaks(scene.rays_at_edge_midpoints(seed + 2, aimed));
            const std::vector<Ray> some(rays.begin(),
                                        rays.begin() + static_cast<std::ptrdiff_t>(sample));
            const OracleReport r = parallel_compare(scene.grid, scene.mesh.view(), some);
            cell.sampled = r.rays;
            cell.disagreements = r.closest_disagreements + r.any_hit_disagreements;
            cell.first_disagreement = r.first_failure;
            if (cell.span_ulps < resolved_span_ulps) continue;
            ++resolved;
            SCOPED_TRACE("translation 1e" + std::to_string(translations[ti]) + ", scale 1e" +
                         std::to_string(scales[si]));
            EXPECT_EQ(cell.leaks.leaks(), 0u) << cell.leaks.first_leak;
            EXPECT_GT(cell.leaks.rays, random) << "too few aimed rays could be made";
            EXPECT_EQ(cell.disagreements, 0u) << cell.first_disagreement;
        }
    }
    // The assertion must cover a good part of the table, or it proves little.
    EXPECT_GE(resolved, scales.size() * translations.size() / 3);

    std::printf("\nLeak rate (rays from inside that miss), sphere of %zu triangles, %zu rays per "
                "entry; * = triangles span fewer than 2^10 ulps\n\n| scale \\ translation |",
                std::size_t{2} * segments * (rings - 1), random + 2 * aimed);
    print_columns(translations);
    for (std::size_t si = 0; si < scales.size(); ++si) {
        std::printf("| 1e%d |", scales[si]);
        for (const Cell& c : table[si]) std::printf(" %s |", rate_text(c).c_str());
        std::printf("\n");
    }
    std::printf("\nSmallest triangle span in ulps / grid nodes / disagreements with brute force "
                "on %zu rays per entry\n\n| scale \\ translation |", sample);
    print_columns(translations);
    for (std::size_t si = 0; si < scales.size(); ++si) {
        std::printf("| 1e%d |", scales[si]);
        for (const Cell& c : table[si])
            std::printf(" %.3g / %zu / %zu |", c.span_ulps, c.nodes, c.disagreements);
        std::printf("\n");
    }
}

}  // namespace
}  // namespace sg::test
