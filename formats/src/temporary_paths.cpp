#include "splitgrid/formats/temporary_paths.hpp"

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cstddef>
#include <stdexcept>
#include <system_error>
#include <utility>

namespace sg {
namespace {

namespace fs = std::filesystem;

enum class EntryKind { file, folder, empty_folder, process, stale_temporaries };

struct Entry {
    std::size_t id = 0;
    EntryKind kind = EntryKind::file;
    fs::path path;
    pid_t pid = 0;
    std::string temporary_kind;
};

struct Registry {
    std::mutex mutex;
    std::vector<Entry> entries;
    std::size_t next_id = 1;
};

/// Never destroyed: an interrupt may arrive while the process runs its exit handlers, and
/// the cleanup must still find the registry.
Registry& registry()
{
    static Registry* const instance = new Registry;
    return *instance;
}

/// Adds `entry`; the caller holds the registry's mutex.
std::size_t add_locked(Entry entry)
{
    Registry& r = registry();
    entry.id = r.next_id++;
    r.entries.push_back(std::move(entry));
    return r.entries.back().id;
}

std::size_t add(Entry entry)
{
    const std::lock_guard lock(registry().mutex);
    return add_locked(std::move(entry));
}

void remove_entry(Registry& r, std::size_t id)
{
    for (auto it = r.entries.begin(); it != r.entries.end(); ++it)
        if (it->id == id) {
            r.entries.erase(it);
            return;
        }
}

/// remove_all, repeated while the folder is still there: another thread of the process may
/// be writing into it (an export in progress) and create a file between the scan and the
/// final rmdir. Once the folder itself is gone nothing can be created inside it.
void remove_folder(const fs::path& folder) noexcept
{
    for (int attempt = 0; attempt < 100; ++attempt) {
        std::error_code ec;
        fs::remove_all(folder, ec);
        if (!fs::exists(fs::symlink_status(folder, ec))) return;
    }
}

bool process_exists(pid_t pid) noexcept { return ::kill(pid, 0) == 0 || errno == EPERM; }

fs::path folder_of(const fs::path& target)
{
    return target.has_parent_path() ? target.parent_path() : fs::path(".");
}

}  // namespace

CleanupEntry::~CleanupEntry() { release(); }

CleanupEntry::CleanupEntry(CleanupEntry&& other) noexcept : id_(std::exchange(other.id_, 0)) {}

CleanupEntry& CleanupEntry::operator=(CleanupEntry&& other) noexcept
{
    if (this != &other) {
        release();
        id_ = std::exchange(other.id_, 0);
    }
    return *this;
}

CleanupEntry CleanupEntry::file(const fs::path& path)
{
    return CleanupEntry(add({0, EntryKind::file, path, 0, {}}));
}

CleanupEntry CleanupEntry::folder(const fs::path& path)
{
    return CleanupEntry(add({0, EntryKind::folder, path, 0, {}}));
}

CleanupEntry CleanupEntry::empty_folder(const fs::path& path)
{
    return CleanupEntry(add({0, EntryKind::empty_folder, path, 0, {}}));
}

CleanupEntry CleanupEntry::process(pid_t pid)
{
    return CleanupEntry(add({0, EntryKind::process, {}, pid, {}}));
}

CleanupEntry CleanupEntry::process(pid_t pid, const CleanupHold& hold)
{
    if (hold.mutex() != &registry().mutex || !hold.owns_lock())
        throw std::logic_error("CleanupEntry::process: the cleanup registry is not held");
    return CleanupEntry(add_locked({0, EntryKind::process, {}, pid, {}}));
}

CleanupEntry CleanupEntry::stale_temporaries(const fs::path& target, std::string_view kind)
{
    return CleanupEntry(add({0, EntryKind::stale_temporaries, target, 0, std::string(kind)}));
}

void CleanupEntry::release() noexcept
{
    if (id_ == 0) return;
    Registry& r = registry();
    const std::lock_guard lock(r.mutex);
    release_locked();
}

void CleanupEntry::release_locked() noexcept
{
    if (id_ == 0) return;
    remove_entry(registry(), id_);
    id_ = 0;
}

CleanupHold hold_off_cleanup() { return CleanupHold(registry().mutex); }

void run_interrupt_cleanup() noexcept
{
    Registry& r = registry();
    // Never unlocked: the process ends right after this, and nothing may be renamed into
    // place or registered in the meantime.
    r.mutex.lock();
    for (const Entry& e : r.entries) {
        if (e.kind != EntryKind::process) continue;
        ::kill(e.pid, SIGKILL);
        // The owner may reap it first (then this fails with ECHILD): either way it is gone.
        while (::waitpid(e.pid, nullptr, 0) < 0 && errno == EINTR) {
        }
    }
    for (const Entry& e : r.entries) {
        if (e.kind == EntryKind::file) ::unlink(e.path.c_str());
        if (e.kind == EntryKind::folder) remove_folder(e.path);
    }
    for (const Entry& e : r.entries)
        if (e.kind == EntryKind::stale_temporaries)
            (void)remove_stale_temporaries(e.path, e.temporary_kind);
    for (const Entry& e : r.entries)
        if (e.kind == EntryKind::empty_folder) ::rmdir(e.path.c_str());
}

std::string temporary_prefix(const fs::path& target, std::string_view kind)
{
    // Appended piece by piece: g++ 12 gives a false -Wrestrict warning for "." + string.
    std::string prefix = ".";
    prefix += target.filename().string();
    prefix += '.';
    prefix += kind;
    prefix += '-';
    prefix += std::to_string(::getpid());
    prefix += '-';
    return prefix;
}

std::vector<fs::path> remove_stale_temporaries(const fs::path& target, std::string_view kind)
{
    std::string start = ".";
    start += target.filename().string();
    start += '.';
    start += kind;
    start += '-';
    std::vector<fs::path> removed;
    std::error_code ec;
    std::vector<std::pair<fs::path, pid_t>> candidates;
    for (const fs::directory_entry& entry : fs::directory_iterator(folder_of(target), ec)) {
        const std::string name = entry.path().filename().string();
        if (name.size() <= start.size() || name.compare(0, start.size(), start) != 0) continue;
        // "<pid>-<random>": a temporary of another pattern (another output whose name
        // starts the same) fails here.
        const char* digits = name.data() + start.size();
        const char* end = name.data() + name.size();
        pid_t pid = 0;
        const auto [after, error] = std::from_chars(digits, end, pid);
        if (error != std::errc{} || after == digits || after == end || *after != '-' || pid <= 0)
            continue;
        candidates.emplace_back(entry.path(), pid);
    }
    for (const auto& [path, pid] : candidates) {
        if (pid == ::getpid() || process_exists(pid)) continue;
        if (fs::is_directory(fs::symlink_status(path, ec)))
            remove_folder(path);
        else
            fs::remove(path, ec);
        if (!fs::exists(fs::symlink_status(path, ec))) removed.push_back(path);
    }
    return removed;
}

}  // namespace sg
