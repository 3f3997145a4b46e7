// Tests of the import process isolation (formats/src/import_child.cpp): the mesh and report
// that come back from the child must equal an import in the calling process, errors must
// keep their kind and message, and an Assimp abort must become an InputError. The tool-level
// runs over many hostile files are in tests/hostile_mesh/.

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "file_helpers.hpp"
#include "splitgrid/error.hpp"
#include "splitgrid/formats/mesh_import.hpp"

namespace sg {
namespace {

const std::filesystem::path models = SG_ASSIMP_MODELS_DIR;

ImportOptions in_process()
{
    ImportOptions options;
    options.isolation = ImportIsolation::in_process;
    return options;
}

class IsolatedImport : public ::testing::TestWithParam<std::string> {};

TEST_P(IsolatedImport, GivesTheSameMeshAndReportAsAnImportInProcess)
{
    const std::filesystem::path model = models / GetParam();
    ASSERT_TRUE(std::filesystem::exists(model)) << model << ": install assimp-testmodels";
    const ImportedMesh local = import_mesh(model, in_process());
    const ImportedMesh isolated = import_mesh(model);
    EXPECT_GT(isolated.mesh.triangles.size(), 0u);
    EXPECT_EQ(isolated.mesh, local.mesh);
    const ImportReport& a = isolated.report;
    const ImportReport& b = local.report;
    EXPECT_EQ(a.meshes, b.meshes);
    EXPECT_EQ(a.faces_read, b.faces_read);
    EXPECT_EQ(a.triangles_read, b.triangles_read);
    EXPECT_EQ(a.points_skipped, b.points_skipped);
    EXPECT_EQ(a.lines_skipped, b.lines_skipped);
    EXPECT_EQ(a.nonfinite_dropped, b.nonfinite_dropped);
    EXPECT_EQ(a.degenerate_dropped, b.degenerate_dropped);
    EXPECT_EQ(a.vertices, b.vertices);
    EXPECT_EQ(a.warnings, b.warnings);
}

// Several formats and sizes (Wuson.ply: 18k triangles, several pipe buffers).
INSTANTIATE_TEST_SUITE_P(Models, IsolatedImport,
                         ::testing::Values("PLY/Wuson.ply", "OBJ/box.obj",
                                           "glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb",
                                           "STL/Spider_binary.stl"));

template <class E>
std::string message_of(const std::filesystem::path& path, const ImportOptions& options)
{
    try {
        (void)import_mesh(path, options);
    } catch (const E& e) {
        return e.what();
    }
    ADD_FAILURE() << path << ": no error of the expected kind";
    return {};
}

TEST(IsolatedImportErrors, KeepTheirKindAndMessage)
{
    test::ScratchDir scratch;
    const std::filesystem::path missing = scratch / "missing.obj";
    EXPECT_EQ(message_of<IoError>(missing, {}), message_of<IoError>(missing, in_process()));
    const std::filesystem::path empty = models / "invalid" / "empty.obj";
    const std::string message = message_of<InputError>(empty, {});
    EXPECT_EQ(message, message_of<InputError>(empty, in_process()));
    EXPECT_EQ(message.rfind(empty.string() + ": ", 0), 0u) << message;
}

TEST(IsolatedImportErrors, AssimpAbortBecomesInputError)
{
    // Half of an ASCII PLY: the header is whole, the face list short, and Assimp 5.2's
    // triangulation asserts (abort) in the process that runs it.
    test::ScratchDir scratch;
    std::vector<std::uint8_t> bytes = test::read_bytes(models / "PLY" / "Wuson.ply");
    bytes.resize(bytes.size() / 2);
    const std::filesystem::path cut = scratch / "Wuson.ply";
    test::write_bytes(cut, bytes);
    const std::string message = message_of<InputError>(cut, {});
    EXPECT_EQ(message.rfind(cut.string() + ": importer crashed (signal 6, Aborted)", 0), 0u)
        << message;
    // The child's last line is quoted: here Assimp's own assertion message.
    EXPECT_NE(message.find("ai_assert"), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos);
}

TEST(IsolatedImportErrors, LimitsOutOfRangeAreConfigErrors)
{
    ImportOptions options;
    options.time_limit_seconds = 0.0;
    EXPECT_THROW((void)import_mesh(models / "PLY" / "cube.ply", options), ConfigError);
    options.time_limit_seconds = -1.0;
    EXPECT_THROW((void)import_mesh(models / "PLY" / "cube.ply", options), ConfigError);
}

}  // namespace
}  // namespace sg
