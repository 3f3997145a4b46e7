// End-to-end tests of interrupted runs (apps/common/interrupt.hpp): each tool is started, the
// test waits until its temporary file or staging folder exists, then sends the signal. The
// tool must remove what it made, print exactly "error: interrupted", exit with 130 (SIGINT)
// or 143 (SIGTERM) and leave an existing output of the same name untouched.
//
// To interrupt at a known point without timing anything, the input is a named pipe that the
// test never writes: the tool has reserved its output and then blocks opening its input (in
// sg-build and sg-bench inside the import's child process, which must then be gone too).
// Two tests interrupt real work instead: the parallel build of a 360,000-triangle mesh and
// the VTK writers of its export, frozen with SIGSTOP at the moment the test sees the work in
// progress. SIGKILL cannot be caught: the import child dies with the tool (the kernel sees
// to that), and the next run removes what the killed run left behind.

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <ostream>
#include <string>
#include <thread>
#include <vector>

#include "app_test_support.hpp"
#include "splitgrid/mesh.hpp"
#include "support/random_scene.hpp"

#include <gtest/gtest.h>

namespace sg::test {
namespace {

namespace fs = std::filesystem;

/// A named pipe nobody writes to: whoever opens it for reading blocks.
fs::path make_fifo(const fs::path& path)
{
    if (::mkfifo(path.c_str(), 0644) != 0)
        throw std::runtime_error("mkfifo " + path.string() + ": " + std::strerror(errno));
    return path;
}

/// Whether some process still has the pipe open for reading: opening it for writing without
/// blocking succeeds only then (and that reader then reads an empty file).
bool pipe_has_reader(const fs::path& fifo)
{
    const int fd = ::open(fifo.c_str(), O_WRONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) return false;
    ::close(fd);
    return true;
}

/// The child processes of `pid` (of its main thread), from /proc.
std::vector<pid_t> children_of(pid_t pid)
{
    std::ifstream in("/proc/" + std::to_string(pid) + "/task/" + std::to_string(pid) +
                     "/children");
    std::vector<pid_t> children;
    for (pid_t child = 0; in >> child;) children.push_back(child);
    return children;
}

/// Whether `pid` has ended (a zombie) or has SIGKILL pending, from /proc/<pid>/status.
bool is_dead_or_being_killed(pid_t pid)
{
    std::ifstream in("/proc/" + std::to_string(pid) + "/status");
    const std::uint64_t sigkill_bit = std::uint64_t{1} << (SIGKILL - 1);
    for (std::string line; std::getline(in, line);) {
        if (line.rfind("State:", 0) == 0 && (line.find('Z') != std::string::npos ||
                                              line.find('X') != std::string::npos))
            return true;
        if (line.rfind("SigPnd:", 0) == 0 || line.rfind("ShdPnd:", 0) == 0) {
            const std::uint64_t pending = std::stoull(line.substr(7), nullptr, 16);
            if ((pending & sigkill_bit) != 0) return true;
        }
    }
    return false;
}

/// `mesh` as a binary STL file.
void write_binary_stl(const fs::path& path, const Mesh& mesh)
{
    std::ofstream out(path, std::ios::binary);
    const std::string header(80, '\0');
    out.write(header.data(), 80);
    const auto count = static_cast<std::uint32_t>(mesh.triangles.size());
    out.write(reinterpret_cast<const char*>(&count), 4);
    for (const Triangle& t : mesh.triangles) {
        float record[12] = {};
        for (int corner = 0; corner < 3; ++corner)
            for (int axis = 0; axis < 3; ++axis)
                record[3 + 3 * corner + axis] = mesh.vertices[t.v[corner]][axis];
        out.write(reinterpret_cast<const char*>(record), sizeof record);
        const std::uint16_t attributes = 0;
        out.write(reinterpret_cast<const char*>(&attributes), 2);
    }
    if (!out) throw std::runtime_error("cannot write " + path.string());
}

/// The entries of `folder` other than the runs' own stdout and stderr files.
std::vector<std::string> entries_but_runs(const fs::path& folder)
{
    std::vector<std::string> names;
    for (const std::string& name : folder_entries(folder))
        if (name.rfind("run", 0) != 0) names.push_back(name);
    return names;
}

/// Waits until `folder` has an entry starting with `prefix`; fails the test (with what the
/// tool said) if the tool ends first.
void wait_for_entry(const RunningTool& tool, const fs::path& folder, const std::string& prefix)
{
    const bool found =
        wait_until(tool, [&] { return !entries_starting_with(folder, prefix).empty(); });
    ASSERT_TRUE(found) << prefix << "* never appeared in " << folder << ":\n"
                       << describe(finish_tool(tool));
}

/// What every interrupted run ends with.
void expect_interrupted(const ToolRun& run, int signal_number)
{
    EXPECT_EQ(run.exit_code, 128 + signal_number) << describe(run);
    EXPECT_EQ(run.err, "error: interrupted\n") << describe(run);
    EXPECT_EQ(run.out, "");
}

struct SignalCase {
    int signal_number;
    const char* name;
};

void PrintTo(const SignalCase& c, std::ostream* out) { *out << c.name; }

class Interrupt : public ::testing::TestWithParam<SignalCase> {
protected:
    int signal_number() const { return GetParam().signal_number; }

    /// Starts `exe`, waits for `prefix`* in the scratch folder, interrupts it and returns the
    /// run.
    ToolRun interrupt_when(const std::string& exe, const std::vector<std::string>& args,
                           const std::string& prefix)
    {
        const RunningTool tool = start_tool(exe, args, scratch_);
        wait_for_entry(tool, scratch_.path(), prefix);
        ::kill(tool.pid, signal_number());
        return finish_tool(tool);
    }

    ScratchDir scratch_;
};

TEST_P(Interrupt, SgBuildRemovesItsTemporaryFileAndStopsTheImport)
{
    const fs::path mesh = make_fifo(scratch_ / "mesh.stl");
    const fs::path out = scratch_ / "out.sg";
    write_text(out, "an earlier file of the same name");
    const ToolRun run =
        interrupt_when(SG_BUILD_EXE, {mesh.string(), "-o", out.string()}, ".out.sg.tmp-");
    expect_interrupted(run, signal_number());
    EXPECT_EQ(read_text(out), "an earlier file of the same name");
    EXPECT_EQ(entries_but_runs(scratch_.path()), (std::vector<std::string>{"mesh.stl", "out.sg"}));
    EXPECT_FALSE(pipe_has_reader(mesh)) << "the import's child process is still running";
}

TEST_P(Interrupt, SgTraceRemovesItsTemporaryFileWhileReadingTheSgFile)
{
    const fs::path sg = make_fifo(scratch_ / "scene.sg");
    const fs::path rays = scratch_ / "rays.bin";
    write_text(rays, "not read");
    const fs::path out = scratch_ / "hits.bin";
    write_text(out, "earlier hits");
    const ToolRun run = interrupt_when(
        SG_TRACE_EXE, {sg.string(), "--rays", rays.string(), "-o", out.string()}, ".hits.bin.tmp-");
    expect_interrupted(run, signal_number());
    EXPECT_EQ(read_text(out), "earlier hits");
    EXPECT_EQ(entries_but_runs(scratch_.path()),
              (std::vector<std::string>{"hits.bin", "rays.bin", "scene.sg"}));
}

TEST_P(Interrupt, SgPointsRemovesItsTemporaryFileWhileReadingTheSgFile)
{
    const fs::path sg = make_fifo(scratch_ / "scene.sg");
    const fs::path points = scratch_ / "points.csv";
    write_text(points, "not read");
    const fs::path out = scratch_ / "inside.bin";
    write_text(out, "earlier answers");
    const ToolRun run = interrupt_when(SG_POINTS_EXE,
                                       {sg.string(), "--points", points.string(), "-o",
                                        out.string(), "--query", "occupancy"},
                                       ".inside.bin.tmp-");
    expect_interrupted(run, signal_number());
    EXPECT_EQ(read_text(out), "earlier answers");
    EXPECT_EQ(entries_but_runs(scratch_.path()),
              (std::vector<std::string>{"inside.bin", "points.csv", "scene.sg"}));
}

TEST_P(Interrupt, SgRaysRemovesItsTemporaryFileWhileReadingItsInput)
{
    const fs::path text = make_fifo(scratch_ / "rays.csv");
    const fs::path out = scratch_ / "rays.bin";
    write_text(out, "earlier rays");
    const ToolRun run =
        interrupt_when(SG_RAYS_EXE, {"text", text.string(), "-o", out.string()}, ".rays.bin.tmp-");
    expect_interrupted(run, signal_number());
    EXPECT_EQ(read_text(out), "earlier rays");
    EXPECT_EQ(entries_but_runs(scratch_.path()),
              (std::vector<std::string>{"rays.bin", "rays.csv"}));
}

#ifdef SG_RENDER_EXE
TEST_P(Interrupt, SgRenderRemovesItsTemporaryFile)
{
    const fs::path sg = make_fifo(scratch_ / "scene.sg");
    const fs::path out = scratch_ / "image.png";
    write_text(out, "an earlier image");
    const ToolRun run =
        interrupt_when(SG_RENDER_EXE, {sg.string(), "-o", out.string()}, ".image.png.tmp-");
    expect_interrupted(run, signal_number());
    EXPECT_EQ(read_text(out), "an earlier image");
    EXPECT_EQ(entries_but_runs(scratch_.path()),
              (std::vector<std::string>{"image.png", "scene.sg"}));
}

TEST_P(Interrupt, SgExportRemovesItsStagingFolderAndKeepsTheEarlierExport)
{
    const fs::path sg = make_fifo(scratch_ / "scene.sg");
    const fs::path out = scratch_ / "out";
    fs::create_directory(out);
    write_text(out / "scene.vtm", "an earlier export");
    const ToolRun run = interrupt_when(
        SG_EXPORT_EXE, {sg.string(), "-o", out.string(), "--force"}, ".out.sg-export-");
    expect_interrupted(run, signal_number());
    EXPECT_EQ(folder_entries(out), (std::vector<std::string>{"scene.vtm"}));
    EXPECT_EQ(read_text(out / "scene.vtm"), "an earlier export");
    EXPECT_EQ(entries_but_runs(scratch_.path()), (std::vector<std::string>{"out", "scene.sg"}));
}
#endif

TEST_P(Interrupt, SgBenchRemovesItsTemporariesAndTheFolderItMade)
{
    const fs::path mesh = make_fifo(scratch_ / "mesh.stl");
    const fs::path out = scratch_ / "bench";
    const RunningTool tool =
        start_tool(SG_BENCH_EXE, {"--quick", mesh.string(), "-o", out.string()}, scratch_);
    wait_for_entry(tool, out, ".results.csv.tmp-");
    ::kill(tool.pid, signal_number());
    expect_interrupted(finish_tool(tool), signal_number());
    EXPECT_EQ(entries_but_runs(scratch_.path()), (std::vector<std::string>{"mesh.stl"}));
    EXPECT_FALSE(pipe_has_reader(mesh)) << "the import's child process is still running";
}

INSTANTIATE_TEST_SUITE_P(Signals, Interrupt,
                         ::testing::Values(SignalCase{SIGINT, "SIGINT"},
                                           SignalCase{SIGTERM, "SIGTERM"}),
                         [](const auto& test_info) { return std::string(test_info.param.name); });

/// A 360,000-triangle sphere as a binary STL: large enough that its build and the VTK
/// export of its grid take a good part of a second, so the test sees them in progress.
fs::path write_large_mesh(const ScratchDir& scratch)
{
    const fs::path stl = scratch / "sphere.stl";
    write_binary_stl(stl, uv_sphere({0.0f, 0.0f, 0.0f}, 1.0f, 300, 600));
    return stl;
}

TEST(InterruptWork, SgBuildInterruptedDuringTheParallelBuild)
{
    ScratchDir scratch;
    const fs::path stl = write_large_mesh(scratch);
    const fs::path out = scratch / "sphere.sg";
    const RunningTool tool = start_tool(SG_BUILD_EXE, {stl.string(), "-o", out.string(), "-v"},
                                        scratch);
    // The debug line of the import report comes after the import and right before the build.
    const bool building = wait_until(tool, [&] {
        return read_text(tool.err_path).find("triangles read") != std::string::npos;
    });
    ::kill(tool.pid, SIGSTOP);
    ASSERT_TRUE(building) << describe(finish_tool(tool));
    ASSERT_EQ(read_text(tool.err_path).find("debug: wrote"), std::string::npos)
        << "test premise: the build had not finished when the tool was stopped";
    ASSERT_EQ(entries_starting_with(scratch.path(), ".sphere.sg.tmp-").size(), 1u);
    ::kill(tool.pid, SIGINT);
    ::kill(tool.pid, SIGCONT);
    const ToolRun run = finish_tool(tool);
    EXPECT_EQ(run.exit_code, 130) << describe(run);
    const std::string last_line = "\nerror: interrupted\n";
    EXPECT_EQ(run.err.rfind(last_line), run.err.size() - last_line.size()) << run.err;
    EXPECT_EQ(run.out, "");
    EXPECT_EQ(entries_but_runs(scratch.path()), (std::vector<std::string>{"sphere.stl"}));
}

#ifdef SG_EXPORT_EXE
/// Whether any file lies somewhere below a staging folder of `out` in `parent`.
bool staging_holds_a_file(const fs::path& parent, const std::string& prefix)
{
    for (const std::string& name : entries_starting_with(parent, prefix)) {
        std::error_code ec;
        for (const auto& e : fs::recursive_directory_iterator(parent / name, ec))
            if (e.is_regular_file(ec)) return true;
    }
    return false;
}

TEST(InterruptWork, SgExportInterruptedWhileVtkWritesTheFiles)
{
    ScratchDir scratch;
    const fs::path stl = write_large_mesh(scratch);
    const fs::path sg = scratch / "sphere.sg";
    ASSERT_EQ(run_tool(SG_BUILD_EXE, {stl.string(), "-o", sg.string(), "-q"}, scratch).exit_code,
              0);
    const fs::path out = scratch / "out";
    const RunningTool tool =
        start_tool(SG_EXPORT_EXE, {sg.string(), "-o", out.string(), "--limit", "0"}, scratch);
    const bool writing =
        wait_until(tool, [&] { return staging_holds_a_file(scratch.path(), ".out.sg-export-"); });
    ::kill(tool.pid, SIGSTOP);
    ASSERT_TRUE(writing) << describe(finish_tool(tool));
    ASSERT_FALSE(fs::exists(out)) << "test premise: the export had not finished when stopped";
    ::kill(tool.pid, SIGTERM);
    ::kill(tool.pid, SIGCONT);
    const ToolRun run = finish_tool(tool);
    expect_interrupted(run, SIGTERM);
    EXPECT_EQ(entries_but_runs(scratch.path()),
              (std::vector<std::string>{"sphere.sg", "sphere.stl"}));
}
#endif

TEST(InterruptKill, TheNextRunRemovesTheTemporaryFileOfAKilledRun)
{
    ScratchDir scratch;
    const fs::path mesh = make_fifo(scratch / "mesh.stl");
    const fs::path out = scratch / "out.sg";
    // This test process adopts the processes its tools leave behind, so that it can see the
    // import child of the killed tool.
    ASSERT_EQ(::prctl(PR_SET_CHILD_SUBREAPER, 1), 0);
    const RunningTool killed = start_tool(SG_BUILD_EXE, {mesh.string(), "-o", out.string()},
                                          scratch);
    wait_for_entry(killed, scratch.path(), ".out.sg.tmp-");
    ASSERT_TRUE(wait_until(killed, [&] { return !children_of(killed.pid).empty(); }))
        << "the import child never started";
    const pid_t import_child = children_of(killed.pid).front();
    ::kill(killed.pid, SIGKILL);
    EXPECT_EQ(finish_tool(killed).exit_code, 128 + SIGKILL);
    // The kernel sends the child SIGKILL as its parent dies; a child killed before it could
    // ask for that (between fork and prctl) finds its parent gone and exits on its own. Either
    // way it is dead, or has the signal pending, within moments.
    bool child_ended = false;
    for (int k = 0; k < 500 && !child_ended; ++k) {
        child_ended = is_dead_or_being_killed(import_child);
        if (!child_ended) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    EXPECT_TRUE(child_ended) << "the import child outlives the killed tool by 5 s";
    ::kill(import_child, SIGKILL);
    ::waitpid(import_child, nullptr, 0);
    ::prctl(PR_SET_CHILD_SUBREAPER, 0);
    const std::vector<std::string> left = entries_starting_with(scratch.path(), ".out.sg.tmp-");
    ASSERT_EQ(left.size(), 1u) << "SIGKILL cannot be caught: the temporary file stays";
    // A temporary of a process that is still running (this test's) is never touched.
    const std::string live = ".out.sg.tmp-" + std::to_string(::getpid()) + "-0123456789abcdef";
    write_text(scratch / live, "still being written");

    const ToolRun next = run_tool(
        SG_BUILD_EXE, {assimp_model("OFF/Cube.off").string(), "-o", out.string()}, scratch);
    EXPECT_EQ(next.exit_code, 0) << describe(next);
    EXPECT_NE(next.err.find("warning: removed " + (scratch / left[0]).string() +
                            ", left behind by a run that was killed\n"),
              std::string::npos)
        << next.err;
    EXPECT_EQ(entries_but_runs(scratch.path()),
              (std::vector<std::string>{live, "mesh.stl", "out.sg"}));
}

#ifdef SG_EXPORT_EXE
TEST(InterruptKill, TheNextRunRemovesTheStagingFolderOfAKilledExport)
{
    ScratchDir scratch;
    const fs::path sg = make_fifo(scratch / "scene.sg");
    const fs::path out = scratch / "out";
    const RunningTool killed = start_tool(SG_EXPORT_EXE, {sg.string(), "-o", out.string()}, scratch);
    wait_for_entry(killed, scratch.path(), ".out.sg-export-");
    ::kill(killed.pid, SIGKILL);
    EXPECT_EQ(finish_tool(killed).exit_code, 128 + SIGKILL);
    const std::vector<std::string> left = entries_starting_with(scratch.path(), ".out.sg-export-");
    ASSERT_EQ(left.size(), 1u) << "SIGKILL cannot be caught: the staging folder stays";

    fs::remove(sg);
    const ToolRun built = run_tool(
        SG_BUILD_EXE, {assimp_model("OFF/Cube.off").string(), "-o", sg.string()}, scratch);
    ASSERT_EQ(built.exit_code, 0) << describe(built);
    const ToolRun next = run_tool(SG_EXPORT_EXE, {sg.string(), "-o", out.string()}, scratch);
    EXPECT_EQ(next.exit_code, 0) << describe(next);
    EXPECT_NE(next.err.find("warning: removed " + (scratch / left[0]).string() +
                            ", left behind by a run that was killed\n"),
              std::string::npos)
        << next.err;
    EXPECT_EQ(entries_but_runs(scratch.path()), (std::vector<std::string>{"out", "scene.sg"}));
}
#endif

}  // namespace
}  // namespace sg::test
