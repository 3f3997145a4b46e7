// Tests of the text and CSV ray reader (formats/src/ray_text.cpp) on text written here: the
// numbers of each line, and the line and field named in each refusal.

#include "splitgrid/formats/ray_text.hpp"

#include <cmath>
#include <limits>
#include <string>

#include <gtest/gtest.h>

#include "splitgrid/error.hpp"

namespace sg {
namespace {

std::string refusal_of(const std::string& text)
{
    try {
        (void)parse_ray_text(text, "r.txt");
    } catch (const FormatError& e) {
        return e.what();
    }
    ADD_FAILURE() << "accepted: " << text;
    return {};
}

TEST(RayText, ReadsSixOrEightNumbersPerLine)
{
    const auto rays = parse_ray_text("1,2,3,4,5,6\n-1e2 +2.5\t3 0 -0 1 0.5 inf\r\n", "r.txt");
    ASSERT_EQ(rays.size(), 2u);
    EXPECT_EQ(rays[0].origin, (Vec3f{1, 2, 3}));
    EXPECT_EQ(rays[0].direction, (Vec3f{4, 5, 6}));
    EXPECT_EQ(rays[0].t_min, 0.0f);
    EXPECT_EQ(rays[0].t_max, std::numeric_limits<float>::infinity());
    EXPECT_EQ(rays[1].origin, (Vec3f{-100.0f, 2.5f, 3}));
    EXPECT_TRUE(std::signbit(rays[1].direction.y)) << "-0 is kept";
    EXPECT_EQ(rays[1].t_min, 0.5f);
    EXPECT_EQ(rays[1].t_max, std::numeric_limits<float>::infinity());
}

TEST(RayText, SkipsCommentsBlankLinesAndOneHeader)
{
    const auto rays = parse_ray_text("  # comment\n\nox,oy,oz,dx,dy,dz\n0,0,0,1,0,0\n", "r.txt");
    EXPECT_EQ(rays.size(), 1u);
    // Only the first line that is not blank or a comment may be a header.
    EXPECT_EQ(refusal_of("0,0,0,1,0,0\nox,oy,oz,dx,dy,dz\n"),
              "r.txt:2: field 1 'ox' is not a number");
}

TEST(RayText, RefusalsNameLineAndField)
{
    EXPECT_EQ(refusal_of(",0,0,1,0,0\n"), "r.txt:1: field 1 is empty");
    EXPECT_EQ(refusal_of("0,0,0,1,0,0,\n"), "r.txt:1: field 7 is empty");
    EXPECT_EQ(refusal_of("0,0,0,1,0,0,0,1,2\n"),
              "r.txt:1: 9 fields, expected 6 (origin x y z, direction x y z) or 8 (and t_min "
              "t_max)");
    EXPECT_EQ(refusal_of("\n\n0 0 0 1 0 0 x y\n"), "r.txt:3: field 7 'x' is not a number");
    EXPECT_EQ(refusal_of("0 0 0 1 0 --1\n"), "r.txt:1: field 6 '--1' is not a number");
    EXPECT_EQ(refusal_of(""), "r.txt: no rays (every line is blank, a comment or a header)");
}

}  // namespace
}  // namespace sg
