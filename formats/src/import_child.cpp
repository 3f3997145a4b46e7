// Mesh import in a child process (import_child.hpp). Assimp 5.2 calls abort() from internal
// assertions on some malformed files and may loop or exhaust memory on others; only a
// separate process turns those into an error message instead of the end of the tool.
//
// fork() without exec (run_in_fork, child_process.hpp): the child already has Assimp and the
// import code mapped, and needs no helper executable to be found at run time. This file holds
// what is the import's own: the child's limits, and the answer it sends back.

#include "import_child.hpp"

#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <new>
#include <string>
#include <vector>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include "splitgrid/error.hpp"
#include "splitgrid/formats/child_process.hpp"

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

/// Bytes of the child's captured output kept: enough for the last lines of any report.
constexpr std::size_t output_keep_bytes = 16384;
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

void run_child(int answer_fd, const ImportOptions& options,
               const std::function<ImportedMesh()>& import)
{
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
}

// ----- Parent side.

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
    throw InputError(name + ": importer " + exit_status_text(child.wait_status) +
                     (WIFSIGNALED(child.wait_status) ? "" : " without an answer") +
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
    ChildWait wait;
    wait.time_limit_seconds = options.time_limit_seconds;
    wait.output_keep_bytes = output_keep_bytes;
    const ChildResult child =
        run_in_fork([&](int answer_fd) { run_child(answer_fd, options, import); }, wait,
                    path.string() + ": cannot start the import process");
    if (!child.exited_cleanly() || child.answer.empty()) throw_child_failure(path, options, child);

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
