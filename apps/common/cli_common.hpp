#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "output_paths.hpp"
#include "splitgrid/build_config.hpp"
#include "splitgrid/formats/library_versions.hpp"
#include "splitgrid/formats/stats_json.hpp"
#include "splitgrid/stats.hpp"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

/// Code shared by the command-line tools: exit codes, the one logger, the command-line
/// convention (option help, -o/--output, -v/-q, --version, --threads, the BuildConfig flags),
/// the run wrapper and JSON conversion. Everything a tool's main.cpp needs beyond its own
/// options and its own work.
///
/// The convention: every option's help ends with "Range [lo, hi]." where a number is
/// bounded and "Default <value>." for every option that takes a value and is not required;
/// every output is -o/--output (with --out as an alias); a refusal names the flag
/// ("--resolution-min 9 is above --resolution-max 8").
namespace sg::apps {

/// Process exit codes of every tool. Stable: scripts may rely on them (README, --help).
enum class ExitCode : int {
    ok = 0,         ///< the tool did its work
    usage = 1,      ///< the command line is wrong: unknown flag, missing or out-of-range value
    bad_input = 2,  ///< an input or output file is missing, unreadable or malformed, or the
                    ///< mesh or rays cannot be used (sg::InputError, FormatError, IoError,
                    ///< ConfigError)
    internal = 3,   ///< anything else: a bug or resource exhaustion
    // 130 and 143: interrupted by SIGINT or SIGTERM (interrupt.hpp).
};

// The JSON documents and their helpers live in formats (stats_json.hpp), which the Python
// package shares.
using sg::Json;
using sg::json_schema_version;
using sg::per_triangle;
using sg::to_json;

/// Verbosity chosen on the command line (-v / -q).
struct LogOptions {
    bool verbose = false;  ///< also print debug messages
    /// Hide progress, information and the summary of a tool whose result is a file; warnings,
    /// errors and results on stdout (sg-stats' statistics, --json) still print.
    bool quiet = false;

    /// Whether a tool whose result is a file prints its summary (not with -q).
    [[nodiscard]] bool shows_summary() const noexcept { return !quiet; }
};

/// Sets the tool's description, a --version flag, a help formatter that wraps long option
/// descriptions, and a --help footer listing the exit codes, preceded by `extra_footer`
/// (tool-specific notes; may be empty). --version prints the tool's name and version (the
/// splitgrid version) and the libraries it links with their versions: oneTBB, Assimp and
/// zlib (through formats), CLI11, spdlog and nlohmann-json, then `extra_libraries` (VTK for
/// the tools that use viz, Embree for sg-bench).
void describe_tool(CLI::App& app, const std::string& description,
                   const std::string& extra_footer = {},
                   const std::vector<LibraryVersion>& extra_libraries = {});

/// The text --version prints (see describe_tool).
[[nodiscard]] std::string version_text(const std::string& tool,
                                       const std::vector<LibraryVersion>& extra_libraries);

/// CLI11 validator for a whole number in [lo, hi]; its refusal reads
/// "<value> is not an integer in [lo, hi]". The help text is left to the option's description.
[[nodiscard]] CLI::Validator count_in(std::uint64_t lo, std::uint64_t hi);
/// count_in for 32-bit values.
[[nodiscard]] CLI::Validator uint_in(std::uint32_t lo, std::uint32_t hi);

/// CLI11 validator for a number in [lo, hi], or in (lo, hi] when `open_below`; NaN and text
/// that is not a number from end to end are refused with "<value> is not a number in [lo, hi]".
[[nodiscard]] CLI::Validator number_in(double lo, double hi, bool open_below);

/// "[1, 1048576]".
[[nodiscard]] std::string count_range(std::uint64_t lo, std::uint64_t hi);
/// "(0, 1e9]" or "[0, 1e6]": the shortest form of each bound.
[[nodiscard]] std::string real_range(double lo, double hi, bool open_below);
/// A number as help texts print it: 48, 0.9, 1e9.
[[nodiscard]] std::string number_text(double value);

/// An option's help in the tools' one form: `help`, then " Range <range>." unless `range` is
/// empty, then " Default <default_value>.".
[[nodiscard]] std::string help_text(std::string_view help, std::string_view range,
                                    std::string_view default_value);

/// Adds a whole-number option in [lo, hi], refused outside it, whose help ends with its range
/// and its default (the value `value` holds now, unless `default_value` is given).
template <class T>
CLI::Option* add_count_option(CLI::App& app, const std::string& name, T& value,
                              std::uint64_t lo, std::uint64_t hi, std::string_view help,
                              std::string_view default_value = {})
{
    const std::string shown = default_value.empty() ? std::to_string(value)
                                                    : std::string(default_value);
    return app.add_option(name, value, help_text(help, count_range(lo, hi), shown))
        ->check(count_in(lo, hi));
}

/// Adds a real-number option (float or double) in [lo, hi] ((lo, hi] when `open_below`),
/// like add_count_option.
template <class T>
CLI::Option* add_real_option(CLI::App& app, const std::string& name, T& value, double lo,
                             double hi, bool open_below, std::string_view help,
                             std::string_view default_value = {})
{
    const std::string shown = default_value.empty() ? number_text(static_cast<double>(value))
                                                    : std::string(default_value);
    return app.add_option(name, value, help_text(help, real_range(lo, hi, open_below), shown))
        ->check(number_in(lo, hi, open_below));
}

/// Adds the output option "-o,--output" (and "--out", kept for older command lines) writing
/// into `path`, required unless `required` is false. "-" (stdout) and an empty name are
/// refused (exit code 1): the tools write files, atomically, never to stdout. `type_name` is
/// FILE or DIR.
CLI::Option* add_output_option(CLI::App& app, std::filesystem::path& path,
                               const std::string& description, bool required = true,
                               const std::string& type_name = "FILE");

/// Adds -v/--verbose and -q/--quiet (mutually exclusive) writing into `options`.
void add_log_flags(CLI::App& app, LogOptions& options);

/// Adds one flag per entry of build_config_fields (--resolution-min, ..., switches as
/// --stop-by-cost / --no-stop-by-cost), --threads only if `with_threads` (sg-bench has a
/// --threads list of its own), each with the field's help, range and default. Values outside
/// a field's range are refused by CLI11 (exit code 1); after parsing, fields that may not
/// exceed another are checked and refused by flag ("--resolution-min 20 is above
/// --resolution-max 16 (its default)"), then sg::validate() runs as the final authority.
/// `config` must outlive the parse.
void add_build_config_flags(CLI::App& app, BuildConfig& config, bool with_threads = true);

/// The flag of a BuildConfig field: "--leaf-size" for leaf_size.
[[nodiscard]] std::string build_config_flag(const BuildConfigField& field);

/// Runs a tool: takes over SIGINT and SIGTERM (interrupt.hpp), parses the command line, sets
/// up the logger from `log`, calls `work` and returns its exit code. The one place where
/// exceptions become exit codes: CLI11 parse errors give ExitCode::usage (--help and
/// --version give ok; a flag given twice reads "--leaf-size is given 2 times (4, 8); give it
/// once"), sg::InputError, FormatError, IoError, ConfigError and
/// std::filesystem::filesystem_error give bad_input, anything else internal. Each failure is
/// logged as one line "error: <message>" on stderr. `log` must be the LogOptions given to
/// add_log_flags (read after parsing).
[[nodiscard]] int run_tool(CLI::App& app, int argc, const char* const* argv,
                           const LogOptions& log, const std::function<void()>& work);

/// The thread count to hand to oneTBB for a `requested` count from `flag` (0 = all hardware
/// threads, left as 0). A count above the hardware's threads (as oneTBB sees them: the
/// process's CPU affinity) gets one warning, "--threads 16 is more than the 2 hardware
/// threads; using 2", and the hardware's count, so that oneTBB never warns on its own and
/// a summary can report what ran.
[[nodiscard]] unsigned threads_to_use(unsigned requested, std::string_view flag = "--threads");

/// The name of the instruction set the traversal kernels run on ("scalar", "sse2", "avx2" or
/// "avx512": sg::kernel_isa()), for the --json of a tool that traces ("isa"). When the
/// environment's SG_ISA asked for another (a name of no instruction set, or one this processor
/// cannot run), logs the library's one-line reason as a warning first, "SG_ISA=avx2x is not
/// one of scalar, sse2, avx2, avx512; using avx2", so that no run silently measures other
/// kernels than the ones asked for. Every tool that traces calls it before its work.
[[nodiscard]] std::string kernel_isa_in_use();

/// The number of threads a run with `threads` (threads_to_use's result) really uses.
[[nodiscard]] unsigned threads_that_run(unsigned threads);

/// "1.23 MiB" style size, for human-readable summaries.
[[nodiscard]] std::string human_bytes(std::size_t bytes);

/// Progress of a long step, for the library's progress callbacks. Short steps stay silent;
/// once a step has run for more than two seconds it logs "<task>: 42% of <unit> after 3.0 s"
/// at most once a second, so a long step shows it is alive without flooding the terminal.
/// Not synchronised: the callers (builder, renderer) serialise their progress calls.
class ProgressLog {
public:
    ProgressLog(std::string task, std::string unit, std::chrono::steady_clock::time_point start);
    void operator()(double fraction_done);

private:
    static constexpr double quiet_seconds = 2.0;
    static constexpr double report_interval = 1.0;
    std::string task_;
    std::string unit_;
    std::chrono::steady_clock::time_point start_;
    double last_report_ = 0.0;
};

/// Seconds elapsed since `start` on the steady clock.
[[nodiscard]] double seconds_since(std::chrono::steady_clock::time_point start) noexcept;

/// BuildConfig as one line of text, "resolution_min 2, resolution_max 16, ..., stop_by_cost
/// on, ...", one item per entry of build_config_fields.
[[nodiscard]] std::string to_text(const BuildConfig& config);

}  // namespace sg::apps
