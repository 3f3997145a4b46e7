// Tests of formats/src/mesh_import_assimp.cpp on Debian's Assimp test models
// (assimp-testmodels), a self-made OBJ in tests/data and generated bad files. Expected counts
// and bounds come from the model files themselves (vertex lists in the text formats) or from
// tools independent of our code, as noted at each test.

#include "splitgrid/formats/mesh_import.hpp"

#include <cmath>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "file_helpers.hpp"
#include "splitgrid/error.hpp"

#if defined(__SANITIZE_ADDRESS__)
// Assimp 5.2.5's PLY reader leaks the index arrays of a `tristrips` element (3.2 MB for
// igea_tristrips.ply; reproduced with a bare Importer::ReadFile and no post-processing), so
// LeakSanitizer ignores leaks allocated inside libassimp. LSan calls this hook at start-up.
extern "C" const char* __lsan_default_suppressions() { return "leak:libassimp.so\n"; }
#endif

namespace sg {
namespace {

const std::filesystem::path models = SG_ASSIMP_MODELS_DIR;
const std::filesystem::path data = SG_TEST_DATA_DIR;
const std::filesystem::path shared_meshes = SG_SHARED_MESHES_DIR;

/// Skips the test when Debian's assimp-testmodels package is not installed.
#define SG_REQUIRE_MODEL(path)                                                            \
    do {                                                                                  \
        if (!std::filesystem::exists(path)) GTEST_SKIP() << (path) << " is not installed"; \
    } while (false)

void expect_bounds(const Mesh& mesh, Vec3f lower, Vec3f upper, float tolerance = 1e-6f)
{
    const Aabb box = bounds(mesh.view());
    for (int a = 0; a < 3; ++a) {
        EXPECT_NEAR(box.lower[a], lower[a], tolerance) << "axis " << a;
        EXPECT_NEAR(box.upper[a], upper[a], tolerance) << "axis " << a;
    }
}

/// Checks the report is consistent with the mesh and that nothing was dropped.
void expect_clean(const ImportedMesh& m, std::size_t triangles)
{
    EXPECT_EQ(m.mesh.triangles.size(), triangles);
    EXPECT_EQ(m.report.triangles_read, triangles);
    EXPECT_EQ(m.report.nonfinite_dropped, 0u);
    EXPECT_EQ(m.report.degenerate_dropped, 0u);
    EXPECT_EQ(m.report.points_skipped, 0u);
    EXPECT_EQ(m.report.lines_skipped, 0u);
    EXPECT_EQ(m.report.vertices, m.mesh.vertices.size());
    EXPECT_TRUE(m.report.warnings.empty());
    check_mesh(m.mesh.view());
}

template <class E>
std::string error_of(const std::filesystem::path& path)
{
    try {
        (void)import_mesh(path);
    } catch (const E& e) {
        return e.what();
    } catch (const std::exception& e) {
        ADD_FAILURE() << "wrong exception type: " << e.what();
        return {};
    }
    ADD_FAILURE() << path << " was accepted";
    return {};
}

TEST(MeshImport, ObjBox)
{
    // OBJ/box.obj lists 8 vertices at +-0.5 and 6 quads: 12 triangles over 8 shared vertices.
    const auto path = models / "OBJ/box.obj";
    SG_REQUIRE_MODEL(path);
    const ImportedMesh m = import_mesh(path);
    expect_clean(m, 12);
    EXPECT_EQ(m.report.faces_read, 12u);
    EXPECT_EQ(m.mesh.vertices.size(), 8u);
    expect_bounds(m.mesh, {-0.5f, -0.5f, -0.5f}, {0.5f, 0.5f, 0.5f});
}

TEST(MeshImport, PlyCubeAsciiAndBinaryAgree)
{
    // PLY/cube.ply: the unit cube [0, 1]^3 (8 vertices, 6 quads in the ASCII header's
    // element list); cube_binary.ply is the same cube in binary PLY.
    for (const char* name : {"PLY/cube.ply", "PLY/cube_binary.ply"}) {
        SCOPED_TRACE(name);
        const auto path = models / name;
        SG_REQUIRE_MODEL(path);
        const ImportedMesh m = import_mesh(path);
        expect_clean(m, 12);
        expect_bounds(m.mesh, {0, 0, 0}, {1, 1, 1});
    }
}

TEST(MeshImport, StlSingleTriangleAndSpiderInBothEncodings)
{
    // STL/triangle.stl holds one facet with corners (1,1,0), (-1,1,0), (0,-1,0): bounds
    // [-1, 1] x [-1, 1] x {0}.
    const auto triangle = models / "STL/triangle.stl";
    SG_REQUIRE_MODEL(triangle);
    const ImportedMesh t = import_mesh(triangle);
    expect_clean(t, 1);
    expect_bounds(t.mesh, {-1, -1, 0}, {1, 1, 0});

    // The same spider as ASCII and as binary STL must give the same triangles and bounds
    // (binary STL stores float32, ASCII the same values printed).
    const auto ascii = models / "STL/Spider_ascii.stl";
    const auto binary = models / "STL/Spider_binary.stl";
    SG_REQUIRE_MODEL(ascii);
    SG_REQUIRE_MODEL(binary);
    const ImportedMesh a = import_mesh(ascii);
    const ImportedMesh b = import_mesh(binary);
    EXPECT_GT(a.mesh.triangles.size(), 1000u);
    EXPECT_EQ(a.report.triangles_read, b.report.triangles_read);
    EXPECT_EQ(a.mesh.triangles.size(), b.mesh.triangles.size());
    const Aabb ba = bounds(a.mesh.view());
    const Aabb bb = bounds(b.mesh.view());
    for (int axis = 0; axis < 3; ++axis) {
        EXPECT_NEAR(ba.lower[axis], bb.lower[axis], 1e-4f);
        EXPECT_NEAR(ba.upper[axis], bb.upper[axis], 1e-4f);
    }
    // STL repeats each corner per facet; joining identical vertices must share them.
    EXPECT_LT(a.mesh.vertices.size(), 3 * a.mesh.triangles.size());
}

TEST(MeshImport, OffColladaAnd3dsCubes)
{
    // Each of these files describes a cube: 6 quads or 12 triangles.
    for (const char* name : {"OFF/Cube.off", "Collada/cube_triangulate.dae", "3DS/RotatingCube.3DS"}) {
        SCOPED_TRACE(name);
        const auto path = models / name;
        SG_REQUIRE_MODEL(path);
        const ImportedMesh m = import_mesh(path);
        expect_clean(m, 12);
    }
    const auto off = models / "OFF/Cube.off";
    SG_REQUIRE_MODEL(off);
    expect_bounds(import_mesh(off).mesh, {-0.5f, -0.5f, -0.5f}, {0.5f, 0.5f, 0.5f});
}

TEST(MeshImport, GltfNodeTransformsAreApplied)
{
    // 2CylinderEngine.glb: 29 meshes (34 primitives) placed by 67 mesh nodes in a hierarchy
    // of matrices, so several meshes are instanced more than once. The expected numbers were computed
    // independently of Assimp by a Python script that parses the GLB's JSON and binary chunk,
    // multiplies the node matrices down the hierarchy and transforms every POSITION, and
    // agree with `assimp export 2CylinderEngine.glb out.obj -ptv`:
    //   121496 triangles (mode 4, all instances), 11160 of them degenerate, bounds
    //   (-371.6923, -180.9716, -140.0000) - (371.6922, 92.0416, 128.0000).
    // Without the transforms the primitives span (-330.4, -199.2, -230.0) - (211.2, 469.7, 147.7)
    // (the union of the accessors' min and max), so these bounds prove the transforms and the
    // instancing were applied.
    const auto path = models / "glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb";
    SG_REQUIRE_MODEL(path);
    const ImportedMesh m = import_mesh(path);
    EXPECT_EQ(m.report.triangles_read, 121496u);
    EXPECT_EQ(m.mesh.triangles.size() + m.report.degenerate_dropped + m.report.nonfinite_dropped,
              121496u);
    EXPECT_EQ(m.report.nonfinite_dropped, 0u);
    // The same script counts the zero-area triangles in the file: 11154 repeat a vertex index,
    // 6 have two corners at the same position, none is otherwise collinear.
    EXPECT_EQ(m.report.degenerate_dropped, 11160u);
    EXPECT_EQ(m.mesh.triangles.size(), 121496u - 11160u);
    expect_bounds(m.mesh, {-371.6923f, -180.9716f, -140.0f}, {371.6922f, 92.0416f, 128.0f}, 2e-3f);
    check_mesh(m.mesh.view());
}

TEST(MeshImport, PointsAndLinesAreCountedAndSkipped)
{
    // OBJ/testmixed.obj: 6 quads (12 triangles), 6 "l" polylines of 4 vertices (3 segments
    // each: 18 lines) and 6 "p" statements of 4 points (24 points).
    const auto path = models / "OBJ/testmixed.obj";
    SG_REQUIRE_MODEL(path);
    const ImportedMesh m = import_mesh(path);
    EXPECT_EQ(m.mesh.triangles.size(), 12u);
    EXPECT_EQ(m.report.triangles_read, 12u);
    EXPECT_EQ(m.report.lines_skipped, 18u);
    EXPECT_EQ(m.report.points_skipped, 24u);
    EXPECT_EQ(m.report.faces_read, 12u + 18u + 24u);
    expect_bounds(m.mesh, {-0.5f, -0.5f, -0.5f}, {0.5f, 0.5f, 0.5f});
}

TEST(MeshImport, OnlyPointsOrOnlyLinesIsAnInputErrorWithCounts)
{
    const auto points = models / "OBJ/testpoints.obj";  // 6 "p" statements of 4 points
    const auto lines = models / "OBJ/testline.obj";     // 6 "l" polylines of 4 vertices
    SG_REQUIRE_MODEL(points);
    SG_REQUIRE_MODEL(lines);
    EXPECT_EQ(error_of<InputError>(points),
              points.string() + ": no triangles (24 points, 0 lines skipped, 0 degenerate dropped)");
    EXPECT_EQ(error_of<InputError>(lines),
              lines.string() + ": no triangles (0 points, 18 lines skipped, 0 degenerate dropped)");
}

TEST(MeshImport, NanInfiniteAndDegenerateTrianglesAreDroppedAndCounted)
{
    // The expected numbers are worked out in the comment at the top of the file.
    const auto path = data / "nan_and_degenerate.obj";
    const ImportedMesh m = import_mesh(path);
    EXPECT_EQ(m.report.faces_read, 8u);
    EXPECT_EQ(m.report.triangles_read, 6u);
    EXPECT_EQ(m.report.nonfinite_dropped, 2u);
    EXPECT_EQ(m.report.degenerate_dropped, 1u);
    EXPECT_EQ(m.report.lines_skipped, 1u);
    EXPECT_EQ(m.report.points_skipped, 1u);
    EXPECT_EQ(m.mesh.triangles.size(), 3u);
    EXPECT_EQ(m.report.vertices, 5u);
    EXPECT_EQ(m.mesh.vertices.size(), 5u);
    expect_bounds(m.mesh, {0, 0, 0}, {1, 1, 1});
    check_mesh(m.mesh.view());
    for (const Vec3f& v : m.mesh.vertices) EXPECT_TRUE(is_finite(v));
}

TEST(MeshImport, WarningsNameTheFileAndEveryCountThatIsNotZero)
{
    // The counts of the comment at the top of nan_and_degenerate.obj.
    const auto path = data / "nan_and_degenerate.obj";
    const ImportedMesh m = import_mesh(path);
    const std::string name = path.string();
    EXPECT_EQ(import_warnings(path, m.report),
              (std::vector<std::string>{
                  name + ": skipped 1 point and 1 line primitives (not triangles)",
                  name + ": dropped 2 triangles with NaN or infinite corners",
                  name + ": dropped 1 zero-area triangles"}));
    ImportReport clean;
    clean.warnings = {"the report's own"};
    EXPECT_EQ(import_warnings(path, clean), clean.warnings);
}

TEST(MeshImport, MissingFileOrFolderIsAnIoError)
{
    test::ScratchDir dir;
    const auto missing = dir / "missing.obj";
    EXPECT_EQ(error_of<IoError>(missing), missing.string() + ": cannot open: No such file or directory");
    const std::string folder = error_of<IoError>(dir.path());
    EXPECT_EQ(folder.rfind(dir.path().string() + ": cannot open: ", 0), 0u) << folder;
}

TEST(MeshImport, GarbageEmptyAndTextFilesAreInputErrorsNamingTheFile)
{
    test::ScratchDir dir;
    std::mt19937 random(1234);
    std::vector<std::uint8_t> noise(4096);
    for (auto& b : noise) b = static_cast<std::uint8_t>(random());
    test::write_bytes(dir / "noise.obj", noise);
    test::write_bytes(dir / "noise.ply", noise);
    test::write_bytes(dir / "noise.glb", noise);
    test::write_bytes(dir / "noise.unknownext", noise);
    test::write_text(dir / "empty.obj", "");
    test::write_text(dir / "empty.stl", "");
    test::write_text(dir / "notes.obj",
                     "Meeting notes\nThe split grid is a nesting of 1D grids.\nBring coffee.\n");
    for (const char* name : {"noise.obj", "noise.ply", "noise.glb", "noise.unknownext", "empty.obj",
                             "empty.stl", "notes.obj"}) {
        SCOPED_TRACE(name);
        const std::string m = error_of<InputError>(dir / name);
        EXPECT_EQ(m.rfind((dir / name).string() + ": ", 0), 0u) << m;
        EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    }
}

TEST(MeshImport, PlyHeadersThatWouldHangAssimpAreRefused)
{
    // Assimp 5.2's PLY reader loops forever on a header without an "end_header" line (found
    // by this suite: a PLY cut off inside its header). The guard must refuse these first.
    test::ScratchDir dir;
    const std::string head = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n";
    test::write_text(dir / "cut.ply", head);
    test::write_text(dir / "cut_binary.ply",
                     "ply\nformat binary_little_endian 1.0\nelement vertex 3\n");
    test::write_text(dir / "misspelt.ply", head + "end_headerX\n1\n2\n3\n");
    test::write_text(dir / "magic_only.ply", "plyx\nformat ascii 1.0\n");
    test::write_text(dir / "ply_content.dat", head);  // Assimp detects PLY by content
    for (const char* name :
         {"cut.ply", "cut_binary.ply", "misspelt.ply", "magic_only.ply", "ply_content.dat"}) {
        SCOPED_TRACE(name);
        EXPECT_EQ(error_of<InputError>(dir / name),
                  (dir / name).string() +
                      ": PLY header without an end_header line (within the first 1048576 bytes): "
                      "the file is cut off or not a PLY file");
    }
}

TEST(MeshImport, SmallPlyWithCrLfLineEnds)
{
    // The guard must accept "end_header" followed by CR LF, and at the very end of a file.
    test::ScratchDir dir;
    test::write_text(dir / "crlf.ply",
                     "ply\r\nformat ascii 1.0\r\nelement vertex 3\r\nproperty float x\r\n"
                     "property float y\r\nproperty float z\r\nelement face 1\r\n"
                     "property list uchar int vertex_indices\r\nend_header\r\n"
                     "0 0 0\r\n2 0 0\r\n0 3 0\r\n3 0 1 2\r\n");
    const ImportedMesh m = import_mesh(dir / "crlf.ply");
    expect_clean(m, 1);
    expect_bounds(m.mesh, {0, 0, 0}, {2, 3, 0});
}

TEST(MeshImport, AssimpWritesNothingToStdoutOrStderr)
{
    const auto path = models / "OBJ/box.obj";
    SG_REQUIRE_MODEL(path);
    test::ScratchDir dir;
    test::write_text(dir / "notes.obj", "not a mesh\n");
    ::testing::internal::CaptureStdout();
    ::testing::internal::CaptureStderr();
    (void)import_mesh(path);
    EXPECT_THROW((void)import_mesh(dir / "notes.obj"), InputError);
    const std::string out = ::testing::internal::GetCapturedStdout();
    const std::string err = ::testing::internal::GetCapturedStderr();
    EXPECT_EQ(out, "");
    EXPECT_EQ(err, "");
}

TEST(MeshImport, PlyTristripsGiveAWarning)
{
    // The shared scenes README: igea_tristrips.ply stores 134345 vertices and its faces as
    // one `tristrips` element, which Assimp 5.2 reads as a single triangle.
    const auto path = shared_meshes / "tricky/igea_tristrips.ply";
    if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " is absent";
    const ImportedMesh m = import_mesh(path);
    ASSERT_EQ(m.report.warnings.size(), 1u);
    EXPECT_EQ(m.report.warnings[0],
              "only " + std::to_string(m.mesh.triangles.size()) +
                  " triangles for 134345 vertices: the file may use an element Assimp does not "
                  "read (for example PLY tristrips)");
    EXPECT_LE(m.mesh.triangles.size(), 1u);
}

TEST(MeshImport, NoWarningForARealScan)
{
    const auto path = shared_meshes / "scanned/stanford_dragon_vrip_res4.ply";
    if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " is absent";
    // The shared scenes README: 11,102 triangles.
    const ImportedMesh m = import_mesh(path);
    EXPECT_TRUE(m.report.warnings.empty());
    EXPECT_EQ(m.report.triangles_read, 11102u);
}

}  // namespace
}  // namespace sg
