// Tests of formats/src/atomic_file.cpp through the public writers: a write either replaces
// the target completely or leaves it (and the folder) as it was.

#include <csignal>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include "file_helpers.hpp"
#include "splitgrid/builder.hpp"
#include "splitgrid/error.hpp"
#include "splitgrid/formats/ray_file.hpp"
#include "splitgrid/formats/sg_file.hpp"
#include "splitgrid/formats/text_file.hpp"
#include "support/random_scene.hpp"

namespace sg {
namespace {

SgContents some_contents(std::size_t triangles)
{
    SgContents c;
    c.mesh = test::random_triangles(3, triangles, Aabb{{0, 0, 0}, {1, 1, 1}}, 0.2f);
    c.grid = build_split_grid(c.mesh.view(), BuildConfig{});
    c.source_name = "atomic.obj";
    return c;
}

template <class F>
std::string io_error_of(F write)
{
    try {
        write();
    } catch (const IoError& e) {
        return e.what();
    } catch (const std::exception& e) {
        ADD_FAILURE() << "wrong exception type: " << e.what();
        return {};
    }
    ADD_FAILURE() << "the write succeeded";
    return {};
}

TEST(AtomicWrite, LeavesOnlyTheTargetBehind)
{
    test::ScratchDir dir;
    write_sg_file(dir / "a.sg", some_contents(50));
    write_ray_file(dir / "r.rays", std::vector<Ray>(3));
    EXPECT_EQ(dir.entries(), (std::vector<std::string>{"a.sg", "r.rays"}));
}

TEST(AtomicWrite, TextFileIsReadBackAsWrittenAndReplacesTheOld)
{
    test::ScratchDir dir;
    const auto path = dir / "results.csv";
    test::write_text(path, std::string(5000, 'x'));
    const std::string text = "scene,structure\ndragon,splitgrid\n";
    write_text_file(path, text);
    EXPECT_EQ(test::read_text(path), text);
    EXPECT_EQ(dir.entries(), (std::vector<std::string>{"results.csv"}));
    EXPECT_NE(io_error_of([&] { write_text_file(dir / "no" / "such.csv", text); }).find("such.csv"),
              std::string::npos);
}

TEST(AtomicWrite, ReplacesAnExistingFileCompletely)
{
    test::ScratchDir dir;
    const auto path = dir / "a.sg";
    test::write_text(path, std::string(100000, 'x'));  // longer than the new contents
    const SgContents c = some_contents(50);
    write_sg_file(path, c);
    EXPECT_EQ(test::read_bytes(path), encode_sg(c));
    EXPECT_EQ(dir.entries(), (std::vector<std::string>{"a.sg"}));
}

TEST(AtomicWrite, NewFilesGetTheUsualPermissions)
{
    // mkstemp would leave 0600; the writer creates with 0666 minus the umask like any tool.
    test::ScratchDir dir;
    const mode_t old_mask = ::umask(022);
    write_sg_file(dir / "a.sg", some_contents(10));
    ::umask(old_mask);
    struct stat info {};
    ASSERT_EQ(::stat((dir / "a.sg").c_str(), &info), 0);
    EXPECT_EQ(info.st_mode & 0777, 0644u);
}

TEST(AtomicWrite, MissingFolderIsAnIoErrorAndCreatesNothing)
{
    test::ScratchDir dir;
    const auto path = dir / "no" / "such" / "folder" / "a.sg";
    const std::string m = io_error_of([&] { write_sg_file(path, some_contents(10)); });
    EXPECT_EQ(m.rfind(path.string() + ": ", 0), 0u) << m;
    EXPECT_NE(m.find("No such file or directory"), std::string::npos) << m;
    EXPECT_TRUE(dir.entries().empty());
    EXPECT_THROW(write_hit_file(dir / "no" / "h.hits", {}), IoError);
    EXPECT_TRUE(dir.entries().empty());
}

TEST(AtomicWrite, TargetThatIsAFolderIsAnIoErrorAndLeavesNoTemporary)
{
    test::ScratchDir dir;
    std::filesystem::create_directory(dir / "taken.sg");
    test::write_text(dir / "taken.sg" / "inside", "keep me");
    const std::string m = io_error_of([&] { write_sg_file(dir / "taken.sg", some_contents(10)); });
    EXPECT_EQ(m.rfind((dir / "taken.sg").string() + ": ", 0), 0u) << m;
    EXPECT_EQ(dir.entries(), (std::vector<std::string>{"taken.sg"}));
    EXPECT_TRUE(std::filesystem::is_directory(dir / "taken.sg"));
}

TEST(AtomicWrite, FailureInTheMiddleOfTheWriteKeepsTheOldFile)
{
    // A file size limit makes write() fail part-way, as a full disk would. The old target
    // must survive unchanged and the temporary file must be gone.
    test::ScratchDir dir;
    const auto path = dir / "a.sg";
    const SgContents small = some_contents(10);
    write_sg_file(path, small);
    const std::vector<std::uint8_t> before = test::read_bytes(path);
    const SgContents big = some_contents(2000);
    ASSERT_GT(encode_sg(big).size(), 65536u);

    rlimit old_limit{};
    ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &old_limit), 0);
    auto* const old_handler = std::signal(SIGXFSZ, SIG_IGN);  // get EFBIG instead of a signal
    rlimit limit = old_limit;
    limit.rlim_cur = 65536;
    ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &limit), 0);
    const std::string m = io_error_of([&] { write_sg_file(path, big); });
    ::setrlimit(RLIMIT_FSIZE, &old_limit);
    std::signal(SIGXFSZ, old_handler);

    EXPECT_NE(m.find("cannot write"), std::string::npos) << m;
    EXPECT_EQ(test::read_bytes(path), before);
    EXPECT_EQ(dir.entries(), (std::vector<std::string>{"a.sg"}));
}

TEST(AtomicWrite, ReadOnlyFolderIsAnIoError)
{
    if (::geteuid() == 0) GTEST_SKIP() << "root ignores folder permissions";
    test::ScratchDir dir;
    std::filesystem::create_directory(dir / "ro");
    std::filesystem::permissions(dir / "ro", std::filesystem::perms::owner_read |
                                                 std::filesystem::perms::owner_exec);
    EXPECT_THROW(write_sg_file(dir / "ro" / "a.sg", some_contents(10)), IoError);
    std::filesystem::permissions(dir / "ro", std::filesystem::perms::owner_all);
    EXPECT_TRUE(std::filesystem::is_empty(dir / "ro"));
}

}  // namespace
}  // namespace sg
