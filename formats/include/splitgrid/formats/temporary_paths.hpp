#pragma once

#include <sys/types.h>

#include <filesystem>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

/// Temporary files, staging folders and helper processes of a tool: how they are named, how
/// the ones a killed run left behind are found, and what is removed when a run is
/// interrupted.
///
/// Every temporary made for an output is named after the output and the process that made
/// it: ".<output name>.<kind>-<pid>-<random>" beside the output (kind "tmp" for files,
/// "sg-export" for staging folders). A run that is killed outright (SIGKILL) cannot clean up;
/// the next run for the same output removes the temporaries whose process no longer exists
/// (remove_stale_temporaries), and never those of a process still running.
///
/// While a temporary exists its owner keeps a CleanupEntry for it. On SIGINT or SIGTERM the
/// tools' interrupt handler (apps/common/interrupt.hpp) calls run_interrupt_cleanup(), which
/// kills the registered processes and removes the registered paths before the process ends.
/// This lives in formats, the lowest part that writes files: viz (image files, staging
/// folders) and the tools register with it, and the core library, which writes nothing,
/// stays free of it.
namespace sg {

/// The registry held by hold_off_cleanup(): while it is held the interrupt cleanup cannot run.
using CleanupHold = std::unique_lock<std::mutex>;

/// One registered cleanup; deregisters on destruction. Move-only. An empty entry does
/// nothing.
class CleanupEntry {
public:
    CleanupEntry() = default;
    ~CleanupEntry();
    CleanupEntry(CleanupEntry&& other) noexcept;
    CleanupEntry& operator=(CleanupEntry&& other) noexcept;
    CleanupEntry(const CleanupEntry&) = delete;
    CleanupEntry& operator=(const CleanupEntry&) = delete;

    /// A file to unlink.
    [[nodiscard]] static CleanupEntry file(const std::filesystem::path& path);
    /// A folder to remove with everything in it.
    [[nodiscard]] static CleanupEntry folder(const std::filesystem::path& path);
    /// A folder to remove only if it is empty once the files and folders above are gone (an
    /// output folder the tool created for files it had not written yet).
    [[nodiscard]] static CleanupEntry empty_folder(const std::filesystem::path& path);
    /// A child process to kill (SIGKILL) and reap, before any path is removed, so that it
    /// cannot write into a folder being removed. A child that writes temporaries of its own
    /// beside an output (sg-bench's chart script) also gets a stale_temporaries entry.
    [[nodiscard]] static CleanupEntry process(pid_t pid);
    /// The same, registered by a caller that holds hold_off_cleanup(): fork or spawn the
    /// child and register it under one hold, so that an interrupt either comes before the
    /// child exists (and the hold waits forever: no child is made) or finds it registered.
    [[nodiscard]] static CleanupEntry process(pid_t pid, const CleanupHold& hold);
    /// The temporaries of `kind` beside `target` whose process no longer exists, swept after
    /// the processes are killed.
    [[nodiscard]] static CleanupEntry stale_temporaries(const std::filesystem::path& target,
                                                        std::string_view kind);

    /// Forgets the entry now (the path was renamed into place, the process was reaped).
    /// Call it while holding hold_off_cleanup() when the step before it must not be undone.
    void release() noexcept;
    /// Like release(), for a caller that already holds hold_off_cleanup().
    void release_locked() noexcept;

private:
    explicit CleanupEntry(std::size_t id) : id_(id) {}
    std::size_t id_ = 0;  ///< 0: empty
};

/// Keeps the interrupt cleanup from running while held, so that a step and the release of
/// its entry (renaming a temporary over the output, then forgetting the temporary) happen
/// either both before the cleanup or not at all. If the cleanup is running, it waits, and
/// the process ends without returning.
[[nodiscard]] CleanupHold hold_off_cleanup();

/// Kills and reaps the registered processes, then removes the registered files and folders
/// and sweeps the registered stale temporaries. Called once, by the interrupt handler, on
/// its own thread; it returns holding the registry, so nothing can be renamed into place
/// afterwards, and the caller ends the process.
void run_interrupt_cleanup() noexcept;

/// The name prefix of every temporary of `kind` this process makes for `target`:
/// ".<target's file name>.<kind>-<pid>-". `target` must have a file name.
[[nodiscard]] std::string temporary_prefix(const std::filesystem::path& target,
                                           std::string_view kind);

/// Removes the temporaries of `kind` beside `target` that a process which no longer exists
/// left behind (see the namespace comment), and returns their paths. Errors are ignored:
/// a temporary that cannot be removed stays, as it would without this sweep.
std::vector<std::filesystem::path> remove_stale_temporaries(const std::filesystem::path& target,
                                                             std::string_view kind);

}  // namespace sg
