#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

/// Child processes of a tool: started with their output read through pipes, waited for under
/// a time limit, killed (SIGKILL) at the limit, and registered with the interrupt cleanup
/// (temporary_paths.hpp) while they run, so that an interrupted tool leaves none behind. The
/// mesh import runs Assimp in a forked child (run_in_fork); sg-bench runs its chart script
/// (run_program).
namespace sg {

/// How long to wait for a child, and how much of its output to keep.
struct ChildWait {
    /// Seconds from the start of the wait after which the child is killed; infinity waits
    /// for as long as it runs.
    double time_limit_seconds = std::numeric_limits<double>::infinity();
    /// The child's captured output beyond this many bytes is dropped from the front (the last
    /// lines are the ones that explain a failure).
    std::size_t output_keep_bytes = std::numeric_limits<std::size_t>::max();
};

/// What a child left when it ended.
struct ChildResult {
    /// The bytes it wrote to its answer descriptor (run_in_fork only).
    std::vector<std::uint8_t> answer;
    /// What it wrote to its captured streams (see ChildWait::output_keep_bytes).
    std::string output;
    /// Its status as waitpid() reports it (WIFEXITED, WIFSIGNALED, ...).
    int wait_status = 0;
    /// True if the time limit passed and the child was killed.
    bool timed_out = false;
    /// True if it was reaped by someone else: the interrupt cleanup, while the tool ends.
    bool reaped_elsewhere = false;

    /// True for a child that exited with status 0 in time.
    [[nodiscard]] bool exited_cleanly() const noexcept;
};

/// How a child ended, for messages: "exited with status 3", or "crashed (signal 6,
/// Aborted)" for a child a signal ended.
[[nodiscard]] std::string exit_status_text(int wait_status);

/// Runs the program argv[0], found on PATH, with arguments `argv` and the tool's environment;
/// its stdout is read through a pipe (ChildResult::output), its stderr is the tool's. Waits
/// for it as `wait` says. Throws IoError "<what>: pipe: <reason>" or "<what>: posix_spawn:
/// <reason>" when it cannot be started. Precondition: argv is not empty.
[[nodiscard]] ChildResult run_program(const std::vector<std::string>& argv, const ChildWait& wait,
                                      std::string_view what);

/// Runs `body(answer_fd)` in a forked child of this process, which then exits with status 0
/// through _exit(), so that none of the parent's atexit handlers, buffered streams or
/// sanitizer leak checks run twice; a child whose parent dies is killed by the kernel. The
/// child's stdout and stderr are read through one pipe (ChildResult::output), what it writes
/// to `answer_fd` through another (ChildResult::answer). Waits for it as `wait` says. Throws
/// IoError "<what>: pipe: <reason>" or "<what>: fork: <reason>" when it cannot be started.
/// `body` must not throw (catch inside it) and must not touch the interrupt cleanup: the
/// child inherits the registry's lock held.
[[nodiscard]] ChildResult run_in_fork(const std::function<void(int answer_fd)>& body,
                                      const ChildWait& wait, std::string_view what);

}  // namespace sg
