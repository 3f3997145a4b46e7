#pragma once

// Helpers for the end-to-end tests of the command-line tools: run a tool binary and capture
// its exit code, stdout and stderr; a scratch folder per test; paths of the test models.
// Header-only because tests/CMakeLists.txt compiles only tests/apps/*_test.cpp.

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

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

/// Runs `exe` with `args` (no shell: arguments are passed as they are), stdout and stderr
/// redirected to files in `scratch`, and waits for it.
inline ToolRun run_tool(const std::string& exe, const std::vector<std::string>& args,
                        const ScratchDir& scratch)
{
    static std::atomic<int> run_counter{0};
    const int id = run_counter++;
    const std::filesystem::path out_path = scratch / ("run" + std::to_string(id) + ".stdout");
    const std::filesystem::path err_path = scratch / ("run" + std::to_string(id) + ".stderr");

    std::vector<std::string> storage;
    storage.reserve(args.size() + 1);
    storage.push_back(exe);
    storage.insert(storage.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (std::string& arg : storage) argv.push_back(arg.data());
    argv.push_back(nullptr);

    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, out_path.c_str(),
                                     O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, err_path.c_str(),
                                     O_WRONLY | O_CREAT | O_TRUNC, 0644);
    pid_t pid = 0;
    const int spawn_error = ::posix_spawn(&pid, exe.c_str(), &actions, nullptr, argv.data(),
                                          environ);
    posix_spawn_file_actions_destroy(&actions);
    if (spawn_error != 0)
        throw std::runtime_error("cannot start " + exe + ": " + std::strerror(spawn_error));

    int status = 0;
    while (::waitpid(pid, &status, 0) < 0)
        if (errno != EINTR) throw std::runtime_error("waitpid failed for " + exe);

    ToolRun run;
    run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    run.out = read_text(out_path);
    run.err = read_text(err_path);
    return run;
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
