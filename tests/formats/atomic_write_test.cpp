// Tests of formats/src/output_file.cpp, directly and through the public writers: a write
// either replaces the target completely or leaves it (and the folder) as it was; the
// temporary file exists from the reservation on, is named after the target and the process,
// and one left by a process that no longer exists is removed by the next reservation. Also
// the interrupt cleanup of formats/src/temporary_paths.cpp, run in a child process.

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "file_helpers.hpp"
#include "splitgrid/builder.hpp"
#include "splitgrid/error.hpp"
#include "splitgrid/formats/output_file.hpp"
#include "splitgrid/formats/ray_file.hpp"
#include "splitgrid/formats/sg_file.hpp"
#include "splitgrid/formats/temporary_paths.hpp"
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

/// The IoError message of a write, or a test failure.
template <class F>
std::string io_error_of(F write)
{
    return test::error_of<IoError>(write);
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

TEST(AtomicWrite, TargetThatIsAPipeIsAnIoErrorAndStaysAPipe)
{
    // As a device such as /dev/null would, a named pipe would be replaced by the rename.
    test::ScratchDir dir;
    ASSERT_EQ(::mkfifo((dir / "pipe.sg").c_str(), 0666), 0);
    const std::string m = io_error_of([&] { write_sg_file(dir / "pipe.sg", some_contents(10)); });
    EXPECT_EQ(m.rfind((dir / "pipe.sg").string() + ": is not a regular file", 0), 0u) << m;
    EXPECT_EQ(dir.entries(), (std::vector<std::string>{"pipe.sg"}));
    EXPECT_TRUE(std::filesystem::is_fifo(dir / "pipe.sg"));
    // A symbolic link to a file is still replaced by the new file (the documented behaviour).
    test::write_text(dir / "real.sg", "old");
    std::filesystem::create_symlink("real.sg", dir / "link.sg");
    EXPECT_NO_THROW(write_sg_file(dir / "link.sg", some_contents(10)));
    EXPECT_TRUE(std::filesystem::is_regular_file(std::filesystem::symlink_status(dir / "link.sg")));
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

/// The pid of a process that has ended and been reaped: no process has it (until the
/// system reuses it, which takes a full turn of the pid space).
pid_t ended_pid()
{
    const pid_t pid = ::fork();
    if (pid == 0) ::_exit(0);
    int status = 0;
    ::waitpid(pid, &status, 0);
    return pid;
}

TEST(OutputFile, TheTemporaryFileExistsFromTheReservationOn)
{
    test::ScratchDir dir;
    {
        const OutputFile output(dir / "a.sg");
        const std::string prefix = ".a.sg.tmp-" + std::to_string(::getpid()) + "-";
        ASSERT_EQ(dir.entries().size(), 1u);
        EXPECT_EQ(dir.entries()[0].rfind(prefix, 0), 0u) << dir.entries()[0];
        EXPECT_EQ(output.temporary_path(), dir / dir.entries()[0]);
        EXPECT_EQ(output.target(), dir / "a.sg");
        EXPECT_TRUE(output.stale_removed().empty());
    }
    EXPECT_TRUE(dir.entries().empty()) << "an output never committed leaves nothing";
}

TEST(OutputFile, CommitWrittenRenamesWhatAWriterWroteByName)
{
    test::ScratchDir dir;
    test::write_text(dir / "image.png", "the old image");
    OutputFile output(dir / "image.png");
    {
        std::ofstream writer(output.temporary_path(), std::ios::binary | std::ios::trunc);
        writer << "the new image";
    }
    EXPECT_EQ(test::read_text(dir / "image.png"), "the old image") << "not before the commit";
    output.commit_written();
    EXPECT_EQ(test::read_text(dir / "image.png"), "the new image");
    EXPECT_EQ(dir.entries(), (std::vector<std::string>{"image.png"}));
}

TEST(OutputFile, AFolderThatCannotBeWrittenIsRefusedAtTheReservation)
{
    // Root may write into read-only folders; the kernel refuses new files in /sys to anyone.
    test::ScratchDir dir;
    std::filesystem::path folder = "/sys";
    if (::geteuid() != 0) {
        folder = dir / "ro";
        std::filesystem::create_directory(folder);
        std::filesystem::permissions(folder, std::filesystem::perms::owner_read |
                                                 std::filesystem::perms::owner_exec);
    }
    const std::string m = io_error_of([&] { const OutputFile output(folder / "a.sg"); });
    EXPECT_EQ(m.rfind((folder / "a.sg").string() + ": cannot create a temporary file", 0), 0u) << m;
    EXPECT_FALSE(std::filesystem::exists(folder / "a.sg"));
}

TEST(OutputFile, TemporariesOfEndedProcessesAreRemovedOthersStay)
{
    test::ScratchDir dir;
    const std::string dead = ".a.sg.tmp-" + std::to_string(ended_pid()) + "-00000000deadbeef";
    const std::string alive = ".a.sg.tmp-" + std::to_string(::getpid()) + "-0000000000a11e0e";
    const std::string other_target = ".b.sg.tmp-" + std::to_string(ended_pid()) + "-1234";
    const std::string not_ours = ".a.sg.tmp-notapid";
    for (const std::string& name : {dead, alive, other_target, not_ours})
        test::write_text(dir / name, "left behind");
    {
        OutputFile output(dir / "a.sg");
        EXPECT_EQ(output.stale_removed(), (std::vector<std::filesystem::path>{dir / dead}));
        output.commit(std::vector<std::uint8_t>{1, 2, 3});
    }
    std::vector<std::string> expected = {alive, other_target, not_ours, "a.sg"};
    std::sort(expected.begin(), expected.end());
    EXPECT_EQ(dir.entries(), expected);
}

TEST(TemporaryPaths, InterruptCleanupKillsProcessesAndRemovesWhatIsRegistered)
{
    // run_interrupt_cleanup() keeps the registry held for good, as the process is about to
    // end: run it in a child process, which registers what a tool would.
    test::ScratchDir dir;
    test::write_text(dir / "kept.txt", "not registered");
    std::filesystem::create_directory(dir / "made");
    int report[2];
    ASSERT_EQ(::pipe(report), 0);
    const pid_t child = ::fork();
    if (child == 0) {
        ::close(report[0]);
        const pid_t sleeper = ::fork();
        if (sleeper == 0) {
            ::pause();
            ::_exit(0);
        }
        std::filesystem::create_directories(dir / "staging" / "deep");
        test::write_text(dir / "staging" / "deep" / "block.vtu", "part of an export");
        test::write_text(dir / "results.json.tmp", "half a file");
        const CleanupEntry folder = CleanupEntry::folder(dir / "staging");
        const CleanupEntry file = CleanupEntry::file(dir / "results.json.tmp");
        const CleanupEntry empty = CleanupEntry::empty_folder(dir / "made");
        const CleanupEntry process = CleanupEntry::process(sleeper);
        CleanupEntry released = CleanupEntry::file(dir / "kept.txt");
        released.release();
        run_interrupt_cleanup();
        // The sleeper was killed and reaped: waiting for it again finds no child.
        const char answer = ::waitpid(sleeper, nullptr, WNOHANG) < 0 && errno == ECHILD ? 'y' : 'n';
        (void)::write(report[1], &answer, 1);
        ::_exit(0);
    }
    ::close(report[1]);
    char answer = 0;
    ASSERT_EQ(::read(report[0], &answer, 1), 1);
    ::close(report[0]);
    int status = 0;
    ::waitpid(child, &status, 0);
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
    EXPECT_EQ(answer, 'y') << "the registered process was not reaped";
    EXPECT_EQ(dir.entries(), (std::vector<std::string>{"kept.txt"}));
}

}  // namespace
}  // namespace sg
