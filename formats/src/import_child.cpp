// Mesh import in a child process (import_child.hpp). Assimp 5.2 calls abort() from internal
// assertions on some malformed files and may loop or exhaust memory on others; only a
// separate process turns those into an error message instead of the end of the tool.
//
// fork() without exec: the child already has Assimp and the import code mapped, needs no
// helper executable to be found at run time, and leaves with _exit() so that none of the
// parent's atexit handlers, buffered streams or sanitizer leak checks run twice.

#include "import_child.hpp"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <new>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include <fcntl.h>
#include <poll.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include "splitgrid/error.hpp"
#include "splitgrid/formats/temporary_paths.hpp"

namespace sg::detail {
namespace {

// ----- The answer the child sends: a status byte, then a message or the mesh and report.

enum class ChildStatus : std::uint8_t {
    ok = 0,
    input_error = 1,
    io_error = 2,
    out_of_memory = 3,
    other_error = 4,
};

/// Bytes of captured stderr kept: enough for the last lines of any report.
constexpr std::size_t stderr_keep_bytes = 16384;
/// Longest quotation of the child's last line in an error message.
constexpr std::size_t quoted_line_max = 200;

class WireWriter {
public:
    void u64(std::uint64_t value) { raw(&value, sizeof value); }
    void text(const std::string& s)
    {
        u64(s.size());
        raw(s.data(), s.size());
    }
    template <class T>
    void array(const std::vector<T>& values)
    {
        u64(values.size());
        raw(values.data(), values.size() * sizeof(T));
    }
    void raw(const void* data, std::size_t bytes)
    {
        const auto* p = static_cast<const std::uint8_t*>(data);
        bytes_.insert(bytes_.end(), p, p + bytes);
    }
    [[nodiscard]] const std::vector<std::uint8_t>& bytes() const noexcept { return bytes_; }

private:
    std::vector<std::uint8_t> bytes_;
};

/// Reads what WireWriter wrote; returns false on a short read rather than throwing, since a
/// short answer only means the child died while writing.
class WireReader {
public:
    explicit WireReader(const std::vector<std::uint8_t>& bytes) : bytes_(bytes) {}
    bool u64(std::uint64_t& value) { return raw(&value, sizeof value); }
    bool text(std::string& s)
    {
        std::uint64_t size = 0;
        if (!u64(size) || size > remaining()) return false;
        s.assign(reinterpret_cast<const char*>(bytes_.data() + at_), size);
        at_ += size;
        return true;
    }
    template <class T>
    bool array(std::vector<T>& values)
    {
        std::uint64_t count = 0;
        if (!u64(count) || count > remaining() / sizeof(T)) return false;
        values.resize(count);
        return raw(values.data(), count * sizeof(T));
    }
    bool raw(void* out, std::size_t bytes)
    {
        if (bytes > remaining()) return false;
        if (bytes != 0) std::memcpy(out, bytes_.data() + at_, bytes);
        at_ += bytes;
        return true;
    }
    [[nodiscard]] bool at_end() const noexcept { return at_ == bytes_.size(); }

private:
    [[nodiscard]] std::size_t remaining() const noexcept { return bytes_.size() - at_; }
    const std::vector<std::uint8_t>& bytes_;
    std::size_t at_ = 0;
};

void encode_mesh(WireWriter& out, const ImportedMesh& imported)
{
    const ImportReport& r = imported.report;
    for (const std::size_t n : {r.meshes, r.faces_read, r.triangles_read, r.points_skipped,
                                r.lines_skipped, r.nonfinite_dropped, r.degenerate_dropped,
                                r.vertices_before_welding, r.vertices})
        out.u64(n);
    out.u64(r.warnings.size());
    for (const std::string& w : r.warnings) out.text(w);
    out.u64(r.opened_files.size());
    for (const std::string& f : r.opened_files) out.text(f);
    out.array(imported.mesh.vertices);
    out.array(imported.mesh.triangles);
}

bool decode_mesh(WireReader& in, ImportedMesh& imported)
{
    ImportReport& r = imported.report;
    for (std::size_t* n : {&r.meshes, &r.faces_read, &r.triangles_read, &r.points_skipped,
                           &r.lines_skipped, &r.nonfinite_dropped, &r.degenerate_dropped,
                           &r.vertices_before_welding, &r.vertices}) {
        std::uint64_t value = 0;
        if (!in.u64(value)) return false;
        *n = static_cast<std::size_t>(value);
    }
    std::uint64_t warnings = 0;
    if (!in.u64(warnings)) return false;
    for (std::uint64_t i = 0; i < warnings; ++i) {
        std::string w;
        if (!in.text(w)) return false;
        r.warnings.push_back(std::move(w));
    }
    std::uint64_t opened_files = 0;
    if (!in.u64(opened_files)) return false;
    for (std::uint64_t i = 0; i < opened_files; ++i) {
        std::string f;
        if (!in.text(f)) return false;
        r.opened_files.push_back(std::move(f));
    }
    return in.array(imported.mesh.vertices) && in.array(imported.mesh.triangles) &&
           in.at_end();
}

// ----- Child side.

void write_all(int fd, const std::vector<std::uint8_t>& bytes)
{
    std::size_t done = 0;
    while (done < bytes.size()) {
        const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return;  // the parent is gone or gave up: nobody to tell
        done += static_cast<std::size_t>(n);
    }
}

/// Address space in use now (VmSize), from /proc/self/statm; 0 if unknown.
std::uint64_t address_space_bytes()
{
    std::ifstream statm("/proc/self/statm");
    std::uint64_t pages = 0;
    statm >> pages;
    return pages * static_cast<std::uint64_t>(::sysconf(_SC_PAGESIZE));
}

void apply_limits(const ImportOptions& options)
{
    // The limits count from what the child inherits: the parent's own heap is not the
    // import's fault.
    if (options.memory_limit_bytes != 0) {
        const rlim_t limit = address_space_bytes() + options.memory_limit_bytes;
        const rlimit as{limit, limit};
        ::setrlimit(RLIMIT_AS, &as);
    }
    // A backstop for a parent that cannot kill (it always does at the wall-clock limit):
    // SIGXCPU one second after the limit, SIGKILL one second later.
    const auto cpu = static_cast<rlim_t>(std::ceil(options.time_limit_seconds)) + 1;
    const rlimit cpu_limit{cpu, cpu + 1};
    ::setrlimit(RLIMIT_CPU, &cpu_limit);
}

[[noreturn]] void run_child(pid_t parent, int answer_fd, int output_fd,
                            const ImportOptions& options,
                            const std::function<ImportedMesh()>& import)
{
    // A parent killed outright (SIGKILL) cannot stop the child: the kernel does, so that no
    // import is left running for nobody. Checked once more in case the parent died before.
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (::getppid() != parent) ::_exit(1);
    // Assimp is silent, but an assertion or a sanitizer report goes to stderr: capture both
    // streams, so nothing lands in the tool's own output (stdout may be JSON).
    ::dup2(output_fd, STDOUT_FILENO);
    ::dup2(output_fd, STDERR_FILENO);
    ::close(output_fd);
    apply_limits(options);

    WireWriter answer;
    try {
        const ImportedMesh imported = import();
        answer.raw("\0", 1);
        encode_mesh(answer, imported);
    } catch (const std::bad_alloc&) {
        answer = WireWriter{};
        const auto status = static_cast<std::uint8_t>(ChildStatus::out_of_memory);
        answer.raw(&status, 1);
    } catch (const std::exception& e) {
        const ChildStatus status = dynamic_cast<const InputError*>(&e) != nullptr
                                       ? ChildStatus::input_error
                                   : dynamic_cast<const IoError*>(&e) != nullptr
                                       ? ChildStatus::io_error
                                       : ChildStatus::other_error;
        answer = WireWriter{};
        const auto byte = static_cast<std::uint8_t>(status);
        answer.raw(&byte, 1);
        answer.text(e.what());
    }
    write_all(answer_fd, answer.bytes());
    ::_exit(0);
}

// ----- Parent side.

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

void open_pipe(Pipe& p, const std::filesystem::path& path)
{
    int fds[2];
    if (::pipe2(fds, O_CLOEXEC) != 0)
        throw IoError(path.string() + ": cannot start the import process: pipe: " +
                      std::error_code(errno, std::generic_category()).message());
    p.read.reset(fds[0]);
    p.write.reset(fds[1]);
}

/// What the parent collected from one child.
struct ChildResult {
    std::vector<std::uint8_t> answer;
    std::string output;  ///< the child's stdout and stderr (the last stderr_keep_bytes)
    int wait_status = 0;
    bool timed_out = false;
};

/// Reads both pipes until the child closes them or the deadline passes, then reaps the
/// child (killing it first on a timeout).
ChildResult collect(pid_t pid, Fd& answer_fd, Fd& output_fd, double time_limit_seconds)
{
    using Clock = std::chrono::steady_clock;
    const auto deadline =
        Clock::now() + std::chrono::duration_cast<Clock::duration>(
                           std::chrono::duration<double>(time_limit_seconds));
    ChildResult result;
    std::vector<std::uint8_t> buffer(65536);
    while (answer_fd.get() >= 0 || output_fd.get() >= 0) {
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
            deadline - Clock::now());
        if (left.count() <= 0) {
            result.timed_out = true;
            break;
        }
        pollfd fds[2] = {{answer_fd.get(), POLLIN, 0}, {output_fd.get(), POLLIN, 0}};
        const int ready = ::poll(fds, 2, static_cast<int>(std::min<std::int64_t>(
                                             left.count(), 1000)));
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
                if (result.output.size() > 2 * stderr_keep_bytes)
                    result.output.erase(0, result.output.size() - stderr_keep_bytes);
            }
        }
    }
    // The pipes close when the child exits, but a child could also close them and go on
    // (sleeping, so RLIMIT_CPU would not end it): the deadline holds for the exit too.
    while (!result.timed_out) {
        const pid_t done = ::waitpid(pid, &result.wait_status, WNOHANG);
        if (done == pid || (done < 0 && errno != EINTR)) return result;
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

/// The last non-empty line the child printed, made printable and short, or "".
std::string last_line(const std::string& output)
{
    std::size_t end = output.size();
    while (end > 0 && (output[end - 1] == '\n' || output[end - 1] == '\r' ||
                       output[end - 1] == ' '))
        --end;
    const std::size_t begin = output.find_last_of("\r\n", end == 0 ? 0 : end - 1);
    std::string line =
        output.substr(begin == std::string::npos ? 0 : begin + 1,
                      end - (begin == std::string::npos ? 0 : begin + 1));
    for (char& c : line)
        if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7F)
            c = '?';
    if (line.size() > quoted_line_max) line = line.substr(0, quoted_line_max) + "...";
    return line;
}

std::string seconds_text(double seconds)
{
    char text[32];
    std::snprintf(text, sizeof text, "%g", seconds);
    return text;
}

[[noreturn]] void throw_child_failure(const std::filesystem::path& path,
                                      const ImportOptions& options, const ChildResult& child)
{
    const std::string name = path.string();
    const bool cpu_limit = WIFSIGNALED(child.wait_status) &&
                           (WTERMSIG(child.wait_status) == SIGXCPU);
    if (child.timed_out || cpu_limit)
        throw InputError(name + ": import exceeded the time limit of " +
                         seconds_text(options.time_limit_seconds) + " s");
    const std::string said = last_line(child.output);
    if (WIFSIGNALED(child.wait_status)) {
        const int sig = WTERMSIG(child.wait_status);
        throw InputError(name + ": importer crashed (signal " + std::to_string(sig) + ", " +
                         ::strsignal(sig) + ")" + (said.empty() ? "" : ": " + said));
    }
    throw InputError(name + ": importer exited with status " +
                     std::to_string(WEXITSTATUS(child.wait_status)) + " without an answer" +
                     (said.empty() ? "" : ": " + said));
}

void check_limits(const std::filesystem::path& path, const ImportOptions& options)
{
    if (!(options.time_limit_seconds > 0.0 && options.time_limit_seconds <= 1e6))
        throw ConfigError(path.string() + ": ImportOptions.time_limit_seconds = " +
                          seconds_text(options.time_limit_seconds) +
                          " is out of range (0, 1e6]");
}

}  // namespace

ImportedMesh import_in_child(const std::filesystem::path& path, const ImportOptions& options,
                             const std::function<ImportedMesh()>& import)
{
    check_limits(path, options);
    Pipe answer;
    Pipe output;
    open_pipe(answer, path);
    open_pipe(output, path);
    // Anything buffered now would be written twice, once by each process.
    std::fflush(nullptr);
    // An interrupted tool kills the child rather than leave it importing (the child keeps the
    // parent's signal mask, so in a tool SIGINT and SIGTERM do not reach it directly). The
    // fork and the registration happen under one hold of the cleanup registry; the child
    // never touches the registry, so its copy of the held lock does not matter.
    CleanupEntry kill_on_interrupt;
    pid_t pid = 0;
    {
        const CleanupHold hold = hold_off_cleanup();
        const pid_t parent = ::getpid();
        pid = ::fork();
        if (pid == 0) {
            answer.read.reset();
            output.read.reset();
            run_child(parent, answer.write.get(), output.write.get(), options, import);
        }
        if (pid > 0) kill_on_interrupt = CleanupEntry::process(pid, hold);
    }
    if (pid < 0)
        throw IoError(path.string() + ": cannot start the import process: fork: " +
                      std::error_code(errno, std::generic_category()).message());
    answer.write.reset();
    output.write.reset();
    const ChildResult child = collect(pid, answer.read, output.read, options.time_limit_seconds);

    const bool exited_cleanly = WIFEXITED(child.wait_status) &&
                                WEXITSTATUS(child.wait_status) == 0 && !child.timed_out;
    if (!exited_cleanly || child.answer.empty()) throw_child_failure(path, options, child);

    WireReader in(child.answer);
    std::uint8_t status_byte = 0;
    in.raw(&status_byte, 1);
    const std::string name = path.string();
    switch (static_cast<ChildStatus>(status_byte)) {
    case ChildStatus::ok: {
        ImportedMesh imported;
        if (!decode_mesh(in, imported))
            throw InputError(name + ": the import process sent an incomplete mesh");
        return imported;
    }
    case ChildStatus::out_of_memory:
        throw InputError(name + ": import exceeded the memory limit of " +
                         std::to_string(options.memory_limit_bytes >> 20) + " MiB");
    case ChildStatus::input_error:
    case ChildStatus::io_error:
    case ChildStatus::other_error: {
        std::string message;
        if (!in.text(message)) message = name + ": the import process failed without a message";
        if (static_cast<ChildStatus>(status_byte) == ChildStatus::io_error)
            throw IoError(message);
        if (static_cast<ChildStatus>(status_byte) == ChildStatus::input_error)
            throw InputError(message);
        throw InputError(name + ": import failed: " + message);
    }
    }
    throw InputError(name + ": the import process sent an unknown answer");
}

}  // namespace sg::detail
