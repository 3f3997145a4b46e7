#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>

#include "splitgrid/build_config.hpp"
#include "splitgrid/stats.hpp"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

/// Code shared by the command-line tools (sg-build, sg-stats, sg-trace): exit codes, the one
/// logger, CLI11 flags for BuildConfig, the run wrapper and JSON conversion. Everything a
/// tool's main.cpp needs beyond its own options and its own work.
namespace sg::apps {

/// Process exit codes of every tool. Stable: scripts may rely on them (README, --help).
enum class ExitCode : int {
    ok = 0,         ///< the tool did its work
    usage = 1,      ///< the command line is wrong: unknown flag, missing or out-of-range value
    bad_input = 2,  ///< an input or output file is missing, unreadable or malformed, or the
                    ///< mesh or rays cannot be used (sg::InputError, FormatError, IoError,
                    ///< ConfigError)
    internal = 3,   ///< anything else: a bug or resource exhaustion
};

/// JSON type of all tool output: keys stay in insertion order, so the output reads in the
/// order docs/STATS_JSON.md lists it.
using Json = nlohmann::ordered_json;

/// The `schema_version` every JSON document printed by a tool carries (docs/STATS_JSON.md).
/// Bumped only when a key is removed or changes meaning; adding keys keeps the version.
inline constexpr int json_schema_version = 1;

/// Verbosity chosen on the command line (-v / -q).
struct LogOptions {
    bool verbose = false;  ///< also print debug messages
    bool quiet = false;    ///< print errors only
};

/// Sets the tool's description, a --version flag, a help formatter that wraps long option
/// descriptions, and a --help footer listing the exit codes, preceded by `extra_footer`
/// (tool-specific notes; may be empty).
void describe_tool(CLI::App& app, const std::string& description,
                   const std::string& extra_footer = {});

/// CLI11 validator for an unsigned integer in [lo, hi]; its refusal reads
/// "<value> is not an integer in [lo, hi]". The help text is left to the option's description.
[[nodiscard]] CLI::Validator uint_in(std::uint32_t lo, std::uint32_t hi);

/// CLI11 validator for a number in [lo, hi], or in (lo, hi] when `open_below`; NaN and text
/// that is not a number from end to end are refused with "<value> is not a number in [lo, hi]".
[[nodiscard]] CLI::Validator number_in(double lo, double hi, bool open_below);

/// Adds -v/--verbose and -q/--quiet (mutually exclusive) writing into `options`.
void add_log_flags(CLI::App& app, LogOptions& options);

/// Adds one flag per BuildConfig field (--resolution-min, --resolution-max,
/// --resolution-sigma, --leaf-size, --max-depth, --no-progress-fraction, --min-cell-width,
/// --stop-by-cost / --no-stop-by-cost, --bounding-planes / --no-bounding-planes,
/// --clip-triangles / --no-clip-triangles, and --threads unless `with_threads` is false, for
/// a tool with a --threads of its own), each with
/// the field's documentation, valid range and default in --help. Values outside a field's
/// range are refused by CLI11 (exit code 1); after parsing, sg::validate() checks the fields
/// together (e.g. resolution_min <= resolution_max) and a failure is also a usage error.
/// `config` must outlive the parse.
void add_build_config_flags(CLI::App& app, BuildConfig& config, bool with_threads = true);

/// Runs a tool: parses the command line, sets up the logger from `log`, calls `work` and
/// returns its exit code. The one place where exceptions become exit codes: CLI11 parse
/// errors give ExitCode::usage (--help gives ok), sg::InputError, FormatError, IoError,
/// ConfigError and std::filesystem::filesystem_error give bad_input, anything else internal.
/// Each failure is logged as one line "error: <message>" on stderr.
/// `log` must be the LogOptions given to add_log_flags (read after parsing).
[[nodiscard]] int run_tool(CLI::App& app, int argc, const char* const* argv,
                           const LogOptions& log, const std::function<void()>& work);

/// Refuses (IoError) an output path whose folder does not exist or that names a folder,
/// before any long work starts. Creates nothing.
void check_output_path(const std::filesystem::path& path);

/// `bytes` divided by `triangles`, or 0 when there are no triangles.
[[nodiscard]] double per_triangle(std::size_t bytes, std::size_t triangles) noexcept;

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

/// BuildConfig as a JSON object, one key per field with the field's name.
[[nodiscard]] Json to_json(const BuildConfig& config);

/// GridStats as a JSON object, one key per field with the field's name (histograms as
/// arrays, cost_model as an object). docs/STATS_JSON.md documents every key.
[[nodiscard]] Json to_json(const GridStats& stats);

}  // namespace sg::apps
