// Child processes (child_process.hpp): one way to start a child under the interrupt cleanup,
// read its pipes, bound its run and reap it, for the forked import and the spawned chart
// script alike.

#include "splitgrid/formats/child_process.hpp"

#include <fcntl.h>
#include <poll.h>
#include <spawn.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <system_error>

#include "splitgrid/error.hpp"
#include "splitgrid/formats/temporary_paths.hpp"

extern char** environ;

namespace sg {
namespace {

/// Closes a descriptor once.
class Fd {
public:
    Fd() = default;
    Fd(const Fd&) = delete;
    Fd& operator=(const Fd&) = delete;
    ~Fd() { reset(); }
    void reset(int fd = -1)
    {
        if (fd_ >= 0) ::close(fd_);
        fd_ = fd;
    }
    [[nodiscard]] int get() const noexcept { return fd_; }

private:
    int fd_ = -1;
};

struct Pipe {
    Fd read;
    Fd write;
};

std::string errno_text(int error)
{
    return std::error_code(error, std::generic_category()).message();
}

void open_pipe(Pipe& p, std::string_view what)
{
    int fds[2];
    if (::pipe2(fds, O_CLOEXEC) != 0)
        throw IoError(std::string(what) + ": pipe: " + errno_text(errno));
    p.read.reset(fds[0]);
    p.write.reset(fds[1]);
}

/// Reads both pipes (`answer_fd` may be empty) until the child closes them or the time
/// limit passes, then reaps the child, killing it first at the limit.
ChildResult collect(pid_t pid, Fd& answer_fd, Fd& output_fd, const ChildWait& wait)
{
    using Clock = std::chrono::steady_clock;
    const bool bounded = std::isfinite(wait.time_limit_seconds);
    const auto deadline =
        bounded ? Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                     std::chrono::duration<double>(wait.time_limit_seconds))
                : Clock::time_point::max();
    const std::size_t keep = wait.output_keep_bytes;
    ChildResult result;
    std::vector<std::uint8_t> buffer(65536);
    while (answer_fd.get() >= 0 || output_fd.get() >= 0) {
        std::int64_t poll_ms = 1000;
        if (bounded) {
            const auto left =
                std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
            if (left.count() <= 0) {
                result.timed_out = true;
                break;
            }
            poll_ms = std::min<std::int64_t>(left.count(), poll_ms);
        }
        pollfd fds[2] = {{answer_fd.get(), POLLIN, 0}, {output_fd.get(), POLLIN, 0}};
        const int ready = ::poll(fds, 2, static_cast<int>(poll_ms));
        if (ready < 0 && errno != EINTR) break;
        for (int i = 0; i < 2; ++i) {
            if (fds[i].fd < 0 || fds[i].revents == 0) continue;
            const ssize_t n = ::read(fds[i].fd, buffer.data(), buffer.size());
            if (n < 0 && errno == EINTR) continue;
            Fd& fd = i == 0 ? answer_fd : output_fd;
            if (n <= 0) {
                fd.reset();
                continue;
            }
            if (i == 0) {
                result.answer.insert(result.answer.end(), buffer.begin(), buffer.begin() + n);
            } else {
                result.output.append(reinterpret_cast<const char*>(buffer.data()),
                                     static_cast<std::size_t>(n));
                // Trimmed once it holds twice what is kept, so that the cost stays linear.
                if (result.output.size() > keep && result.output.size() - keep > keep)
                    result.output.erase(0, result.output.size() - keep);
            }
        }
    }
    // The pipes close when the child exits, but a child could also close them and go on
    // (sleeping, so a CPU-time limit would not end it): the deadline holds for the exit too.
    while (!result.timed_out) {
        const pid_t done = ::waitpid(pid, &result.wait_status, WNOHANG);
        if (done == pid) return result;
        if (done < 0 && errno != EINTR) {
            result.reaped_elsewhere = true;
            return result;
        }
        if (Clock::now() >= deadline) {
            result.timed_out = true;
            break;
        }
        ::usleep(1000);
    }
    ::kill(pid, SIGKILL);
    while (::waitpid(pid, &result.wait_status, 0) < 0 && errno == EINTR) {
    }
    return result;
}

}  // namespace

bool ChildResult::exited_cleanly() const noexcept
{
    return !timed_out && WIFEXITED(wait_status) && WEXITSTATUS(wait_status) == 0;
}

std::string exit_status_text(int wait_status)
{
    if (WIFSIGNALED(wait_status)) {
        const int sig = WTERMSIG(wait_status);
        return "crashed (signal " + std::to_string(sig) + ", " + ::strsignal(sig) + ")";
    }
    return "exited with status " + std::to_string(WEXITSTATUS(wait_status));
}

ChildResult run_program(const std::vector<std::string>& argv, const ChildWait& wait,
                        std::string_view what)
{
    std::vector<std::string> args = argv;
    std::vector<char*> arg_pointers;
    for (std::string& a : args) arg_pointers.push_back(a.data());
    arg_pointers.push_back(nullptr);
    Pipe output;
    open_pipe(output, what);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, output.write.get(), STDOUT_FILENO);
    // An interrupt kills the child (which, like every child of a tool, does not see SIGINT
    // and SIGTERM itself: it inherits their block). Spawned and registered under one hold of
    // the cleanup registry, so that an interrupt either comes first or finds it registered.
    CleanupEntry kill_on_interrupt;
    pid_t pid = 0;
    int error = 0;
    {
        const CleanupHold hold = hold_off_cleanup();
        error = ::posix_spawnp(&pid, args.front().c_str(), &actions, nullptr,
                               arg_pointers.data(), environ);
        if (error == 0) kill_on_interrupt = CleanupEntry::process(pid, hold);
    }
    posix_spawn_file_actions_destroy(&actions);
    output.write.reset();
    if (error != 0) throw IoError(std::string(what) + ": posix_spawn: " + errno_text(error));
    Fd no_answer;
    return collect(pid, no_answer, output.read, wait);
}

ChildResult run_in_fork(const std::function<void(int answer_fd)>& body, const ChildWait& wait,
                        std::string_view what)
{
    Pipe answer;
    Pipe output;
    open_pipe(answer, what);
    open_pipe(output, what);
    // Anything buffered now would be written twice, once by each process.
    std::fflush(nullptr);
    // An interrupted tool kills the child (the child keeps the parent's signal mask, so in a
    // tool SIGINT and SIGTERM do not reach it directly). The fork and the registration happen
    // under one hold of the cleanup registry; the child never touches the registry, so its
    // copy of the held lock does not matter.
    CleanupEntry kill_on_interrupt;
    pid_t pid = 0;
    {
        const CleanupHold hold = hold_off_cleanup();
        const pid_t parent = ::getpid();
        pid = ::fork();
        if (pid == 0) {
            // A parent killed outright (SIGKILL) cannot stop the child: the kernel does, so
            // that no child is left running for nobody. Checked once more in case the parent
            // died before.
            ::prctl(PR_SET_PDEATHSIG, SIGKILL);
            if (::getppid() != parent) ::_exit(1);
            answer.read.reset();
            output.read.reset();
            // Both streams go to the pipe, so that nothing lands in the tool's own output
            // (stdout may be JSON).
            ::dup2(output.write.get(), STDOUT_FILENO);
            ::dup2(output.write.get(), STDERR_FILENO);
            output.write.reset();
            try {
                body(answer.write.get());
            } catch (...) {
                ::_exit(1);
            }
            ::_exit(0);
        }
        if (pid > 0) kill_on_interrupt = CleanupEntry::process(pid, hold);
    }
    if (pid < 0) throw IoError(std::string(what) + ": fork: " + errno_text(errno));
    answer.write.reset();
    output.write.reset();
    return collect(pid, answer.read, output.read, wait);
}

}  // namespace sg
