#pragma once

// Helpers for the end-to-end tests of the command-line tools: run a tool binary and capture
// its exit code, stdout and stderr (or start it and wait for something it does, to send it a
// signal); a scratch folder per test; paths of the test models.
// Header-only because tests/CMakeLists.txt compiles only tests/apps/*_test.cpp.

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "splitgrid/mesh.hpp"
#include "support/scratch_dir.hpp"

#include <gtest/gtest.h>

extern char** environ;

namespace sg::test {

/// What a finished tool run produced.
struct ToolRun {
    int exit_code = -1;  ///< the process's exit status; 128 + signal if it was killed
    std::string out;     ///< everything written to stdout
    std::string err;     ///< everything written to stderr
};

/// A tool started by start_tool() and not yet waited for.
struct RunningTool {
    pid_t pid = -1;
    std::filesystem::path out_path;  ///< where its stdout goes
    std::filesystem::path err_path;  ///< where its stderr goes
    std::string exe;
};

/// Starts `exe` with `args` (no shell: arguments are passed as they are), stdout and stderr
/// redirected to files in `scratch`, in the folder `cwd` (the test's own if empty), with the
/// test's environment plus the "NAME=value" entries of `extra_env` (which win over it).
inline RunningTool start_tool(const std::string& exe, const std::vector<std::string>& args,
                              const ScratchDir& scratch, const std::filesystem::path& cwd = {},
                              const std::vector<std::string>& extra_env = {})
{
    static std::atomic<int> run_counter{0};
    const int id = run_counter++;
    RunningTool tool;
    tool.exe = exe;
    tool.out_path = scratch / ("run" + std::to_string(id) + ".stdout");
    tool.err_path = scratch / ("run" + std::to_string(id) + ".stderr");

    std::vector<std::string> storage;
    storage.reserve(args.size() + 1);
    storage.push_back(exe);
    storage.insert(storage.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (std::string& arg : storage) argv.push_back(arg.data());
    argv.push_back(nullptr);

    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, tool.out_path.c_str(),
                                     O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, tool.err_path.c_str(),
                                     O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (!cwd.empty()) posix_spawn_file_actions_addchdir_np(&actions, cwd.c_str());
    std::vector<std::string> env_storage(extra_env);
    std::vector<char*> env;
    for (std::string& entry : env_storage) env.push_back(entry.data());
    for (char** entry = environ; *entry != nullptr; ++entry) {
        const std::string_view name(*entry, std::strcspn(*entry, "="));
        const bool replaced = std::any_of(extra_env.begin(), extra_env.end(), [&](const auto& e) {
            return e.size() > name.size() && e.compare(0, name.size(), name) == 0 &&
                   e[name.size()] == '=';
        });
        if (!replaced) env.push_back(*entry);
    }
    env.push_back(nullptr);
    const int spawn_error = ::posix_spawn(&tool.pid, exe.c_str(), &actions, nullptr, argv.data(),
                                          env.data());
    posix_spawn_file_actions_destroy(&actions);
    if (spawn_error != 0)
        throw std::runtime_error("cannot start " + exe + ": " + std::strerror(spawn_error));
    return tool;
}

/// Waits for a started tool and collects what it wrote.
inline ToolRun finish_tool(const RunningTool& tool)
{
    int status = 0;
    while (::waitpid(tool.pid, &status, 0) < 0)
        if (errno != EINTR) throw std::runtime_error("waitpid failed for " + tool.exe);
    ToolRun run;
    run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    run.out = read_text(tool.out_path);
    run.err = read_text(tool.err_path);
    return run;
}

/// Runs `exe` with `args` like start_tool() and waits for it.
inline ToolRun run_tool(const std::string& exe, const std::vector<std::string>& args,
                        const ScratchDir& scratch, const std::filesystem::path& cwd = {},
                        const std::vector<std::string>& extra_env = {})
{
    return finish_tool(start_tool(exe, args, scratch, cwd, extra_env));
}

/// Whether the started tool has ended (it stays a zombie for finish_tool to collect).
inline bool has_ended(const RunningTool& tool)
{
    siginfo_t info{};
    return ::waitid(P_PID, static_cast<id_t>(tool.pid), &info, WEXITED | WNOHANG | WNOWAIT) == 0 &&
           info.si_pid == tool.pid;
}

/// Polls `condition` every millisecond until it holds (true) or the tool has ended without
/// it holding (false). There is no time limit: the condition is one the tool reaches
/// (a temporary file that it creates) or the tool ends.
template <class Condition>
bool wait_until(const RunningTool& tool, Condition condition)
{
    for (;;) {
        if (condition()) return true;
        if (has_ended(tool)) return condition();
        ::usleep(1000);
    }
}

/// Names of the entries of `folder` that start with `prefix`.
inline std::vector<std::string> entries_starting_with(const std::filesystem::path& folder,
                                                      const std::string& prefix)
{
    std::vector<std::string> found;
    std::error_code ec;
    for (const auto& e : std::filesystem::directory_iterator(folder, ec)) {
        const std::string name = e.path().filename().string();
        if (name.rfind(prefix, 0) == 0) found.push_back(name);
    }
    return found;
}

/// A folder in which no file can be created: a read-only folder in `scratch`, or, for root
/// (who may write anywhere the permissions forbid), /sys, where the kernel refuses new
/// files even to root.
inline std::filesystem::path unwritable_folder(const ScratchDir& scratch)
{
    if (::geteuid() == 0) return "/sys";
    const std::filesystem::path folder = scratch / "read_only";
    std::filesystem::create_directory(folder);
    std::filesystem::permissions(folder, std::filesystem::perms::owner_read |
                                             std::filesystem::perms::owner_exec);
    return folder;
}

/// For assertion messages: the command's output streams.
inline std::string describe(const ToolRun& run)
{
    std::ostringstream s;
    s << "exit code " << run.exit_code << "\n--- stdout ---\n"
      << run.out << "--- stderr ---\n"
      << run.err;
    return s.str();
}

/// Expects a tool's documented refusal: exit code `code`, one line "error: ..." on stderr
/// naming `named`, nothing on stdout, no file `output` and no temporary file (".NAME.tmp-...")
/// left in `folder`.
inline void expect_refused_leaving_nothing(const ToolRun& run, int code, const std::string& named,
                                           const std::filesystem::path& output,
                                           const std::filesystem::path& folder)
{
    EXPECT_EQ(run.exit_code, code) << describe(run);
    EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
    EXPECT_EQ(run.err.rfind("error: ", 0), 0u) << run.err;
    EXPECT_NE(run.err.find(named), std::string::npos) << "must name " << named << ":\n" << run.err;
    EXPECT_EQ(run.out, "");
    EXPECT_FALSE(std::filesystem::exists(output)) << output;
    for (const auto& entry : std::filesystem::directory_iterator(folder))
        EXPECT_EQ(entry.path().filename().string().find(".tmp-"), std::string::npos)
            << "temporary file left behind: " << entry.path();
}

/// `mesh` as the text of an OBJ file (9 significant digits: every float exactly), for tests
/// that give sg-build a mesh made in the test.
inline std::string obj_of(const Mesh& mesh)
{
    std::ostringstream out;
    out.precision(9);
    for (const Vec3f& v : mesh.vertices) out << "v " << v.x << ' ' << v.y << ' ' << v.z << '\n';
    for (const Triangle& t : mesh.triangles)
        out << "f " << t.v[0] + 1 << ' ' << t.v[1] + 1 << ' ' << t.v[2] + 1 << '\n';
    return out.str();
}

/// Path of a model in Debian's assimp-testmodels (a dependency installed by
/// scripts/setup.sh, so a missing model is a failure, not a skip).
inline std::filesystem::path assimp_model(const std::string& relative)
{
    return std::filesystem::path(SG_ASSIMP_MODELS_DIR) / relative;
}

/// Path of a scene in ../shared/meshes, which only development machines and CI have.
inline std::filesystem::path shared_mesh(const std::string& relative)
{
    return std::filesystem::path(SG_SHARED_MESHES_DIR) / relative;
}

}  // namespace sg::test

/// Skips the current test when the shared scene `path` is absent (users' machines).
#define SG_SKIP_WITHOUT_SHARED_MESH(path)                                                    \
    do {                                                                                     \
        if (!std::filesystem::exists(path))                                                  \
            GTEST_SKIP() << (path).string() << " is absent: ../shared/meshes exists only on " \
                                               "development machines and in CI";             \
    } while (false)
