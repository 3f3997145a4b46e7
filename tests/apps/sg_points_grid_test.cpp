// End-to-end tests of sg-points --grid: the .vti file read back with VTK's own reader, its
// placement against the mesh's box computed here, and every sample of each query held to the
// brute-force oracle in double; slices; the refusals of bad --grid text, zero or too many
// points, a wrong output name, an output over the input and a build without VTK (exit codes,
// one line, nothing written).

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "app_test_support.hpp"
#include "sg_points_support.hpp"
#include "splitgrid/formats/point_file.hpp"
#include "splitgrid/formats/sg_file.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

// The reading back needs VTK, which apps_tests links in builds with VTK.
#ifdef SG_APPS_TESTS_READ_VTK
#include "support/vtk_readback.hpp"

#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkPointData.h>
#include <vtkXMLImageDataReader.h>
#endif

namespace sg::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

#ifdef SG_APPS_TESTS_READ_VTK
/// Whether sg-points (SG_POINTS_EXE) writes grids: a build with VTK.
constexpr bool tool_writes_grids = true;
#else
constexpr bool tool_writes_grids = false;
#endif

class SgPointsGrid : public ::testing::Test {
protected:
    void SetUp() override { build_with_sg_build(sphere_and_cube(), sg_file_, scratch_); }

    ToolRun grid(const std::string& counts, const std::string& query,
                 std::vector<std::string> extra, const std::string& exe = SG_POINTS_EXE)
    {
        std::vector<std::string> args = {sg_file_.string(), "--grid",  counts, "-o",
                                         out_.string(),     "--query", query};
        args.insert(args.end(), extra.begin(), extra.end());
        return run_tool(exe, args, scratch_);
    }

    void expect_refused(const ToolRun& run, int code, const std::string& named)
    {
        expect_refused_leaving_nothing(run, code, named, out_, scratch_.path());
    }

    ScratchDir scratch_;
    fs::path sg_file_ = scratch_ / "shapes.sg";
    fs::path out_ = scratch_ / "field.vti";
};

#ifdef SG_APPS_TESTS_READ_VTK

struct ReadField {
    vtkSmartPointer<vtkImageData> image;
    std::vector<Vec3f> points;  ///< each sample's position, rounded to float as queried
};

ReadField read_field(const fs::path& path)
{
    vtkNew<vtkXMLImageDataReader> reader;
    reader->SetFileName(path.c_str());
    reader->Update();
    ReadField field{reader->GetOutput(), {}};
    for (vtkIdType n = 0; n < field.image->GetNumberOfPoints(); ++n) {
        double p[3];
        field.image->GetPoint(n, p);
        field.points.push_back(
            {static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2])});
    }
    return field;
}

std::vector<double> point_values(vtkImageData* image, const char* name, int component = 0)
{
    vtkDataArray* array = image->GetPointData()->GetArray(name);
    if (array == nullptr) throw std::runtime_error(std::string("no point array ") + name);
    std::vector<double> values;
    for (vtkIdType i = 0; i < array->GetNumberOfTuples(); ++i)
        values.push_back(array->GetComponent(i, component));
    return values;
}

/// The grid the tool should lay: the mesh's box widened by `padding` times its diagonal,
/// computed here in double from the mesh the .sg file holds.
struct ExpectedGrid {
    std::array<double, 3> origin{};
    std::array<double, 3> spacing{};
};

ExpectedGrid expected_grid(const Mesh& mesh, std::array<int, 3> counts, double padding)
{
    std::array<double, 3> lower{1e30, 1e30, 1e30}, upper{-1e30, -1e30, -1e30};
    for (const Triangle& t : mesh.triangles)
        for (const std::uint32_t v : t.v)
            for (int a = 0; a < 3; ++a) {
                lower[a] = std::min<double>(lower[a], mesh.vertices[v][a]);
                upper[a] = std::max<double>(upper[a], mesh.vertices[v][a]);
            }
    double diagonal = 0.0;
    for (int a = 0; a < 3; ++a) diagonal += (upper[a] - lower[a]) * (upper[a] - lower[a]);
    const double pad = padding * std::sqrt(diagonal);
    ExpectedGrid grid;
    for (int a = 0; a < 3; ++a) {
        const double lo = lower[a] - pad, hi = upper[a] + pad;
        grid.origin[a] = counts[a] == 1 ? (lo + hi) / 2 : lo;
        grid.spacing[a] = counts[a] == 1 ? hi - lo : (hi - lo) / (counts[a] - 1);
    }
    return grid;
}

void expect_placed(vtkImageData* image, const ExpectedGrid& expected, std::array<int, 3> counts)
{
    int dims[3];
    double origin[3], spacing[3];
    image->GetDimensions(dims);
    image->GetOrigin(origin);
    image->GetSpacing(spacing);
    for (int a = 0; a < 3; ++a) {
        EXPECT_EQ(dims[a], counts[a]) << a;
        EXPECT_NEAR(origin[a], expected.origin[a], 1e-12) << a;
        EXPECT_NEAR(spacing[a], expected.spacing[a], 1e-12) << a;
    }
}

TEST_F(SgPointsGrid, SignedDistanceFieldReadsBackPlacedAndAgreesWithTheOracle)
{
    const std::array<int, 3> counts{17, 9, 8};
    const ToolRun run = grid("17,9,8", "signed-distance", {"--padding", "0.1", "--json"});
    ASSERT_EQ(run.exit_code, 0) << describe(run);
    const SgContents contents = read_sg_file(sg_file_);
    const ReadField field = read_field(out_);
    expect_placed(field.image, expected_grid(contents.mesh, counts, 0.1), counts);
    EXPECT_STREQ(field.image->GetPointData()->GetScalars()->GetName(), "signed_distance");
    EXPECT_EQ(field_string(field.image, "query"), "signed-distance");
    EXPECT_EQ(field_string(field.image, "structure_name"), "shapes.sg");
    EXPECT_EQ(field_number(field.image, "padding"), 0.1);
    EXPECT_EQ(field.image->GetFieldData()->GetAbstractArray("max_distance"), nullptr)
        << "no --max-distance, no field";
    EXPECT_EQ(field_number(field.image, "nsamples"), 1.0);

    const std::vector<double> values = point_values(field.image, "signed_distance");
    ASSERT_EQ(values.size(), std::size_t{17 * 9 * 8});
    std::size_t inside = 0, sides_checked = 0;
    double worst = 0.0;
    for (std::size_t n = 0; n < values.size(); ++n) {
        const Vec3f p = field.points[n];
        const PointOracle o = point_oracle(contents.mesh.view(), p);
        const double error = std::abs(std::abs(values[n]) - o.distance);
        worst = std::max(worst, error);
        EXPECT_LE(error, distance_tolerance(o.distance, p)) << "sample " << n;
        inside += values[n] < 0.0 ? 1 : 0;
        if (o.distance <= side_band) continue;
        ++sides_checked;
        EXPECT_EQ(values[n] < 0.0, o.inside) << "sample " << n;
    }
    EXPECT_GT(inside, 50u) << "premise: samples inside both shapes";
    EXPECT_EQ(sides_checked, values.size());
    const json j = json::parse(run.out);
    EXPECT_EQ(j.at("grid").at("dimensions"), json({17, 9, 8}));
    EXPECT_EQ(j.at("grid").at("padding"), 0.1);
    EXPECT_FALSE(j.contains("points_file"));
    EXPECT_EQ(j.at("point_count"), values.size());
    EXPECT_EQ(j.at("inside"), inside);
    expect_documented_points_json(j);
}

TEST_F(SgPointsGrid, EveryQueryWritesItsArraysOnTheGrid)
{
    const SgContents contents = read_sg_file(sg_file_);
    const MeshView mesh = contents.mesh.view();

    // Occupancy on a slice through the box's centre (one point along z).
    ASSERT_EQ(grid("23,11,1", "occupancy", {}).exit_code, 0);
    ReadField field = read_field(out_);
    expect_placed(field.image, expected_grid(contents.mesh, {23, 11, 1}, 0.05), {23, 11, 1});
    std::vector<double> values = point_values(field.image, "occupancy");
    ASSERT_EQ(values.size(), std::size_t{23 * 11});
    for (std::size_t n = 0; n < values.size(); ++n) {
        const PointOracle o = point_oracle(mesh, field.points[n]);
        if (o.distance > side_band) {
            EXPECT_EQ(values[n], o.inside ? 1.0 : 0.0) << n;
        }
    }

    // Distance, with a limit.
    ASSERT_EQ(grid("9,7,5", "distance", {"--max-distance", "0.5"}).exit_code, 0);
    field = read_field(out_);
    values = point_values(field.image, "distance");
    std::size_t beyond = 0;
    for (std::size_t n = 0; n < values.size(); ++n) {
        const PointOracle o = point_oracle(mesh, field.points[n]);
        if (o.distance > 0.5 * (1 + 1e-6)) {
            EXPECT_EQ(values[n], std::numeric_limits<double>::infinity()) << n;
            ++beyond;
        } else if (o.distance < 0.5 * (1 - 1e-6)) {
            EXPECT_LE(std::abs(values[n] - o.distance),
                      distance_tolerance(o.distance, field.points[n]))
                << n;
        }
    }
    EXPECT_GT(beyond, 10u);
    EXPECT_EQ(field_number(field.image, "max_distance"), 0.5);

    // Closest: distance, the triangle (-1 beyond the limit) and the point.
    ASSERT_EQ(grid("9,7,5", "closest", {"--max-distance", "0.5"}).exit_code, 0);
    field = read_field(out_);
    EXPECT_STREQ(field.image->GetPointData()->GetScalars()->GetName(), "distance");
    values = point_values(field.image, "distance");
    const std::vector<double> ids = point_values(field.image, "triangle_id");
    ASSERT_EQ(field.image->GetPointData()->GetArray("closest_point")->GetNumberOfComponents(), 3);
    std::array<std::vector<double>, 3> closest;
    for (int a = 0; a < 3; ++a) closest[a] = point_values(field.image, "closest_point", a);
    std::size_t none = 0;
    for (std::size_t n = 0; n < values.size(); ++n) {
        const Vec3f p = field.points[n];
        const PointOracle o = point_oracle(mesh, p);
        if (ids[n] == -1.0) {
            ++none;
            EXPECT_GT(o.distance, 0.5 * (1 - 1e-6)) << n;
            EXPECT_TRUE(std::isnan(closest[0][n])) << n;
            continue;
        }
        const auto t = static_cast<std::uint32_t>(ids[n]);
        EXPECT_TRUE(std::binary_search(o.nearest.begin(), o.nearest.end(), t)) << n;
        EXPECT_LE(std::abs(values[n] - o.distance), distance_tolerance(o.distance, p)) << n;
        const auto corner = [&](int k) {
            const Vec3f v = mesh.vertex(t, k);
            return std::array<double, 3>{v.x, v.y, v.z};
        };
        const std::array<double, 3> expected =
            closest_point_on_triangle({p.x, p.y, p.z}, corner(0), corner(1), corner(2));
        for (int a = 0; a < 3; ++a)
            EXPECT_NEAR(closest[a][n], expected[static_cast<std::size_t>(a)], 1e-6) << n;
    }
    EXPECT_EQ(none, beyond) << "the same grid and limit as the distance field";
}

#endif  // SG_APPS_TESTS_READ_VTK

TEST_F(SgPointsGrid, BadGridsAreRefusedNamingTheArgument)
{
    expect_refused(grid("96,96", "signed-distance", {}), 1, "--grid: '96,96' is not NX,NY,NZ");
    expect_refused(grid("8,8,8,8", "signed-distance", {}), 1, "is not NX,NY,NZ");
    expect_refused(grid("8,0,8", "distance", {}), 1, "the y count '0' is not a whole number");
    expect_refused(grid("8,x,8", "distance", {}), 1, "the y count 'x'");
    expect_refused(grid("-8,8,8", "distance", {}), 1, "the x count '-8'");
    expect_refused(grid("1000,1000,1000", "distance", {}), 1,
                   "'1000,1000,1000' is 1000000000 points, more than the limit of 67108864");
    expect_refused(grid("8,8,8", "distance", {"--padding", "-0.1"}), 1, "--padding");
    expect_refused(grid("8,8,8", "distance", {"--padding", "11"}), 1, "--padding");

    const fs::path points = scratch_ / "points.bin";
    write_point_file(points, std::vector<Vec3f>{{0, 0, 0}});
    expect_refused(grid("8,8,8", "distance", {"--points", points.string()}), 1,
                   "--points and --grid are both given");

    // An existing output is left as it was by every refusal.
    write_text(out_, "an earlier field");
    EXPECT_EQ(grid("0,1,1", "distance", {}).exit_code, 1);
    EXPECT_EQ(read_text(out_), "an earlier field");

    // Refusals made after the check that VTK is there.
    if (!tool_writes_grids) return;
    // The output must be a .vti file, so that ParaView opens it.
    const fs::path bin = scratch_ / "field.bin";
    const ToolRun wrong_name =
        run_tool(SG_POINTS_EXE,
                 {sg_file_.string(), "--grid", "8,8,8", "-o", bin.string(), "--query", "distance"},
                 scratch_);
    expect_refused_leaving_nothing(wrong_name, 1, "name the output FILE.vti", bin, scratch_.path());

    // An output over the input (a .sg file named .vti) is refused and the input kept.
    const fs::path odd_name = scratch_ / "shapes_sg.vti";
    fs::copy_file(sg_file_, odd_name);
    const std::string bytes = read_text(odd_name);
    const ToolRun over = run_tool(SG_POINTS_EXE,
                                  {odd_name.string(), "--grid", "8,8,8", "-o", odd_name.string(),
                                   "--query", "distance"},
                                  scratch_);
    EXPECT_EQ(over.exit_code, 2) << describe(over);
    EXPECT_EQ(over.err, "error: " + odd_name.string() +
                            ": refusing to write the output over the input " + odd_name.string() +
                            "\n");
    EXPECT_EQ(read_text(odd_name), bytes);

    // A flat mesh without padding has no extent to spread points over along its normal.
    Mesh flat;
    flat.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    flat.triangles = {Triangle{{0, 1, 2}}};
    const fs::path flat_sg = scratch_ / "flat.sg";
    build_with_sg_build(flat, flat_sg, scratch_);
    const ToolRun coincide = run_tool(SG_POINTS_EXE,
                                      {flat_sg.string(), "--grid", "4,4,4", "--padding", "0", "-o",
                                       out_.string(), "--query", "distance"},
                                      scratch_);
    EXPECT_EQ(coincide.exit_code, 2) << describe(coincide);
    EXPECT_EQ(coincide.err,
              "error: --grid: the mesh is flat along z and --padding is 0, so its "
              "4 points would coincide; give --padding above 0 or 1 point along "
              "z\n");
    EXPECT_EQ(read_text(out_), "an earlier field");
    const ToolRun slice = run_tool(SG_POINTS_EXE,
                                   {flat_sg.string(), "--grid", "4,4,1", "--padding", "0", "-o",
                                    out_.string(), "--query", "distance", "-q"},
                                   scratch_);
    EXPECT_EQ(slice.exit_code, 0) << describe(slice);
}

/// sg-points as a build without VTK makes it: the test build has a copy of the tool built so
/// (apps/CMakeLists.txt) where the tool itself has VTK.
#ifdef SG_POINTS_WITHOUT_VTK_EXE
constexpr const char* points_without_vtk = SG_POINTS_WITHOUT_VTK_EXE;
#else
constexpr const char* points_without_vtk = SG_POINTS_EXE;
#endif

TEST_F(SgPointsGrid, WithoutVtkTheGridIsRefusedAndPointsAreAnswered)
{
    const ToolRun run = grid("8,8,8", "signed-distance", {}, points_without_vtk);
    expect_refused(run, 1,
                   "--grid writes VTK image data (.vti), and this sg-points was built "
                   "without VTK (SG_WITH_VTK=OFF)");

    const SgContents contents = read_sg_file(sg_file_);
    const std::vector<Vec3f> points{{0, 0, 0}, {3, 0, 0}, {1.5f, 0.25f, -0.5f}};
    const fs::path points_file = scratch_ / "points.bin";
    write_point_file(points_file, points);
    const fs::path out = scratch_ / "sdf.bin";
    const ToolRun answered = run_tool(points_without_vtk,
                                      {sg_file_.string(), "--points", points_file.string(), "-o",
                                       out.string(), "--query", "signed-distance"},
                                      scratch_);
    ASSERT_EQ(answered.exit_code, 0) << describe(answered);
    const std::vector<float> got = read_signed_distance_file(out);
    ASSERT_EQ(got.size(), points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
        const PointOracle o = point_oracle(contents.mesh.view(), points[i]);
        EXPECT_LE(std::abs(std::abs(got[i]) - o.distance),
                  distance_tolerance(o.distance, points[i]));
        EXPECT_EQ(got[i] < 0.0f, o.inside) << i;
    }
}

}  // namespace
}  // namespace sg::test
