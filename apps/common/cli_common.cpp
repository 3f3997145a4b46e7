#include "cli_common.hpp"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <memory>
#include <system_error>
#include <utility>

#include "splitgrid/error.hpp"
#include "splitgrid/version.hpp"

#include <spdlog/fmt/fmt.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

namespace sg::apps {
namespace {

// Ranges of the BuildConfig fields as build_config.hpp documents them. CLI11 uses them to
// refuse a bad value at parse time with a usage error; sg::validate() stays the authority.
constexpr std::uint32_t max_count_flag = 1u << 20;
constexpr double max_sigma_flag = 1e9;
constexpr double max_min_cell_width_flag = 1e6;
constexpr std::uint32_t max_threads_flag = 1024;

/// Keeps an error report on one line even if a message carries a newline (CLI11 and the OS
/// sometimes do), so that each failure is exactly one line of stderr.
std::string one_line(std::string text)
{
    for (char& c : text)
        if (c == '\n' || c == '\r') c = ' ';
    return text;
}

/// CLI11 2.1 prints each option description on one line however long it is; this formatter
/// word-wraps descriptions so that --help fits in about 100 columns.
class WrappingFormatter : public CLI::Formatter {
public:
    std::string make_option_desc(const CLI::Option* option) const override
    {
        return wrap(CLI::Formatter::make_option_desc(option));
    }

private:
    static constexpr std::size_t description_width = 68;

    static std::string wrap(const std::string& text)
    {
        std::string wrapped;
        std::size_t line_length = 0;
        std::size_t start = 0;
        while (start < text.size()) {
            std::size_t end = text.find_first_of(" \n", start);
            if (end == std::string::npos) end = text.size();
            const std::size_t word_length = end - start;
            if (line_length != 0 && line_length + 1 + word_length > description_width) {
                wrapped += '\n';
                line_length = 0;
            } else if (line_length != 0) {
                wrapped += ' ';
                ++line_length;
            }
            wrapped.append(text, start, word_length);
            line_length += word_length;
            if (end < text.size() && text[end] == '\n') {
                wrapped += '\n';
                line_length = 0;
            }
            start = end + 1;
        }
        return wrapped;
    }
};

/// Logs `e` as "error: <message>" and returns `code` as an int.
int fail(ExitCode code, const std::exception& e)
{
    spdlog::error("{}", one_line(e.what()));
    return static_cast<int>(code);
}

/// The tools' one logger: stderr, so stdout carries only results (and --json stays clean).
/// Colours only on a terminal. Messages read "warning: ...", "error: ...".
void create_logger()
{
    auto logger = spdlog::stderr_color_mt("sg");
    logger->set_pattern("%^%l%$: %v");
    logger->set_level(spdlog::level::info);
    spdlog::set_default_logger(std::move(logger));
}

}  // namespace

CLI::Validator uint_in(std::uint32_t lo, std::uint32_t hi)
{
    return CLI::Validator(
        [lo, hi](std::string& text) -> std::string {
            std::uint32_t value = 0;
            const char* end = text.data() + text.size();
            const auto [ptr, ec] = std::from_chars(text.data(), end, value);
            if (ec != std::errc{} || ptr != end || value < lo || value > hi)
                return fmt::format("{} is not an integer in [{}, {}]", text, lo, hi);
            return {};
        },
        "", "");
}

CLI::Validator number_in(double lo, double hi, bool open_below)
{
    return CLI::Validator(
        [lo, hi, open_below](std::string& text) -> std::string {
            double value = 0.0;
            const char* end = text.data() + text.size();
            const auto [ptr, ec] = std::from_chars(text.data(), end, value);
            // Written so that NaN fails: every comparison with NaN is false.
            const bool above_lo = open_below ? value > lo : value >= lo;
            if (ec != std::errc{} || ptr != end || !(above_lo && value <= hi))
                return fmt::format("{} is not a number in {}{}, {}]", text, open_below ? '(' : '[',
                                   lo, hi);
            return {};
        },
        "", "");
}

void describe_tool(CLI::App& app, const std::string& description, const std::string& extra_footer)
{
    app.description(description);
    app.set_version_flag("--version", std::string(version_string));
    app.formatter(std::make_shared<WrappingFormatter>());
    std::string footer = extra_footer.empty() ? std::string{} : extra_footer + "\n\n";
    footer +=
        "Exit codes:\n"
        "  0  ok\n"
        "  1  usage error: unknown flag, missing or out-of-range value\n"
        "  2  bad input or file: missing, unreadable or malformed file, unusable mesh or rays\n"
        "  3  internal error";
    app.footer(footer);
}

void add_log_flags(CLI::App& app, LogOptions& options)
{
    auto* verbose = app.add_flag("-v,--verbose", options.verbose, "Also print debug messages");
    auto* quiet = app.add_flag("-q,--quiet", options.quiet, "Print errors only");
    verbose->excludes(quiet);
}

void add_build_config_flags(CLI::App& app, BuildConfig& config, bool with_threads)
{
    const BuildConfig defaults{};
    const std::string group = "Build parameters (BuildConfig)";
    app.add_option("--resolution-min", config.resolution_min,
                   fmt::format("Fewest cells of an inner node, used by small nodes near the "
                               "leaves (2 makes them binary splits). Range [1, {}], at most "
                               "--resolution-max. Default {}.",
                               max_count_flag, defaults.resolution_min))
        ->check(uint_in(1, max_count_flag))
        ->group(group);
    app.add_option("--resolution-max", config.resolution_max,
                   fmt::format("Most cells of an inner node, reached by nodes with several "
                               "sigma triangles (near the root). Range [2, {}], at least "
                               "--resolution-min. Default {}.",
                               max_count_flag, defaults.resolution_max))
        ->check(uint_in(2, max_count_flag))
        ->group(group);
    app.add_option("--resolution-sigma", config.resolution_sigma,
                   fmt::format("Width of the Gaussian resolution function, in triangles: a "
                               "node with sigma triangles gets 39% of the way from min to max "
                               "cells, 2 sigma 86%, 3 sigma 99%. Range (0, {:g}]. Default {:g}.",
                               max_sigma_flag, defaults.resolution_sigma))
        ->check(number_in(0.0, max_sigma_flag, true))
        ->group(group);
    app.add_option("--leaf-size", config.leaf_size,
                   fmt::format("A cell with at most this many triangles becomes a leaf. "
                               "Range [1, {}]. Default {}.",
                               max_count_flag, defaults.leaf_size))
        ->check(uint_in(1, max_count_flag))
        ->group(group);
    app.add_option("--max-depth", config.max_depth,
                   fmt::format("Deepest inner node (the root is depth 0); cells of a node at "
                               "this depth become leaves. Range [0, {}]. Default {}.",
                               max_supported_depth, defaults.max_depth))
        ->check(uint_in(0, max_supported_depth))
        ->group(group);
    app.add_option("--no-progress-fraction", config.no_progress_fraction,
                   fmt::format("A split makes no progress when two or more cells, or every "
                               "non-empty cell, would receive more than this fraction of the "
                               "node's triangles; it is retried on the other axes before the "
                               "node becomes a leaf. Range (0, 1]. Default {:g}.",
                               defaults.no_progress_fraction))
        ->check(number_in(0.0, 1.0, true))
        ->group(group);
    app.add_option("--min-cell-width", config.min_cell_width,
                   fmt::format("Cells are never narrower than this many times the mean extent "
                               "of the node's triangles along the split axis (slicing finer "
                               "than the triangles only copies references); 0 disables the "
                               "cap. Range [0, {:g}]. Default {:g}.",
                               max_min_cell_width_flag, defaults.min_cell_width))
        ->check(number_in(0.0, max_min_cell_width_flag, false))
        ->group(group);
    app.add_flag("--stop-by-cost,!--no-stop-by-cost", config.stop_by_cost,
                 fmt::format("Keep a split only if it lowers the expected traversal cost of "
                             "the surface-area model (sg-stats), with its cells taken as "
                             "leaves; a split that fails is retried on the other axes. "
                             "Default {}.",
                             defaults.stop_by_cost ? "--stop-by-cost" : "--no-stop-by-cost"))
        ->group(group);
    app.add_flag("--bounding-planes,!--no-bounding-planes", config.bounding_planes,
                 fmt::format("Cut each node's slab down to the tight extent of its triangles "
                             "along the split axis (the Split Grid's bounding planes); "
                             "--no-bounding-planes uses the node box's faces, a plain nested "
                             "grid. Default {}.",
                             defaults.bounding_planes ? "--bounding-planes"
                                                      : "--no-bounding-planes"))
        ->group(group);
    app.add_flag("--clip-triangles,!--no-clip-triangles", config.clip_triangles,
                 fmt::format("Reference a triangle only in the cells the triangle itself "
                             "touches (exact clipping); --no-clip-triangles uses its bounding "
                             "box instead, which builds faster and makes more references. "
                             "Default {}.",
                             defaults.clip_triangles ? "--clip-triangles"
                                                     : "--no-clip-triangles"))
        ->group(group);
    if (with_threads)
        app.add_option("--threads", config.threads,
                       fmt::format("Worker threads for the build, 0 = all hardware threads; the "
                                   "output is bit-identical for every value. Range [0, {}]. "
                                   "Default {}.",
                                   max_threads_flag, defaults.threads))
            ->check(uint_in(0, max_threads_flag))
            ->group(group);

    // Fields that are fine alone can still be wrong together (resolution_min above
    // resolution_max): the library's own check decides, and since the user typed the values,
    // its refusal is reported as a usage error like any other bad flag value.
    app.parse_complete_callback([&config] {
        try {
            validate(config);
        } catch (const ConfigError& e) {
            throw CLI::ValidationError(e.what());
        }
    });
}

int run_tool(CLI::App& app, int argc, const char* const* argv, const LogOptions& log,
             const std::function<void()>& work)
{
    create_logger();
    try {
        app.parse(argc, argv);
        if (log.quiet)
            spdlog::set_level(spdlog::level::err);
        else if (log.verbose)
            spdlog::set_level(spdlog::level::debug);
        work();
        return static_cast<int>(ExitCode::ok);
    } catch (const CLI::ParseError& e) {
        // --help and --version arrive as "errors" with CLI11's success code.
        if (e.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) {
            app.exit(e);
            return static_cast<int>(ExitCode::ok);
        }
        spdlog::error("{} (run with --help for usage)", one_line(e.what()));
        return static_cast<int>(ExitCode::usage);
    } catch (const InputError& e) {
        return fail(ExitCode::bad_input, e);
    } catch (const FormatError& e) {
        return fail(ExitCode::bad_input, e);
    } catch (const IoError& e) {
        return fail(ExitCode::bad_input, e);
    } catch (const ConfigError& e) {
        return fail(ExitCode::bad_input, e);
    } catch (const std::filesystem::filesystem_error& e) {
        // Raised by the tools' own file queries (file sizes); its message names the path.
        return fail(ExitCode::bad_input, e);
    } catch (const std::exception& e) {
        return fail(ExitCode::internal, e);
    } catch (...) {
        spdlog::error("unknown exception");
        return static_cast<int>(ExitCode::internal);
    }
}

void check_output_path(const std::filesystem::path& path)
{
    namespace fs = std::filesystem;
    std::error_code ec;
    if (fs::is_directory(path, ec))
        throw IoError(path.string() + ": is a directory, expected a file name");
    const fs::path folder = path.has_parent_path() ? path.parent_path() : fs::path(".");
    if (!fs::is_directory(folder, ec))
        throw IoError(path.string() + ": folder " + folder.string() + " does not exist");
}

double per_triangle(std::size_t bytes, std::size_t triangles) noexcept
{
    return triangles == 0 ? 0.0 : static_cast<double>(bytes) / static_cast<double>(triangles);
}

std::string human_bytes(std::size_t bytes)
{
    constexpr const char* units[] = {"B", "KiB", "MiB", "GiB", "TiB"};
    double value = static_cast<double>(bytes);
    std::size_t unit = 0;
    while (value >= 1024.0 && unit + 1 < std::size(units)) {
        value /= 1024.0;
        ++unit;
    }
    return unit == 0 ? fmt::format("{} B", bytes) : fmt::format("{:.2f} {}", value, units[unit]);
}

ProgressLog::ProgressLog(std::string task, std::string unit,
                         std::chrono::steady_clock::time_point start)
    : task_(std::move(task)), unit_(std::move(unit)), start_(start)
{
}

void ProgressLog::operator()(double fraction_done)
{
    const double elapsed = seconds_since(start_);
    if (elapsed < quiet_seconds || elapsed < last_report_ + report_interval) return;
    last_report_ = elapsed;
    spdlog::info("{}: {:.0f}% of {} after {:.1f} s", task_, 100.0 * fraction_done, unit_, elapsed);
}

double seconds_since(std::chrono::steady_clock::time_point start) noexcept
{
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

Json to_json(const BuildConfig& config)
{
    // The structured binding stops compiling when a field is added to BuildConfig: then add it
    // here, in add_build_config_flags() and in docs/STATS_JSON.md.
    const auto& [resolution_min, resolution_max, resolution_sigma, leaf_size, max_depth,
                 no_progress_fraction, min_cell_width, stop_by_cost, bounding_planes,
                 clip_triangles, threads] = config;
    Json j;
    j["resolution_min"] = resolution_min;
    j["resolution_max"] = resolution_max;
    j["resolution_sigma"] = resolution_sigma;
    j["leaf_size"] = leaf_size;
    j["max_depth"] = max_depth;
    j["no_progress_fraction"] = no_progress_fraction;
    j["min_cell_width"] = min_cell_width;
    j["stop_by_cost"] = stop_by_cost;
    j["bounding_planes"] = bounding_planes;
    j["clip_triangles"] = clip_triangles;
    j["threads"] = threads;
    return j;
}

Json to_json(const GridStats& stats)
{
    Json j;
    j["triangle_count"] = stats.triangle_count;
    j["node_count"] = stats.node_count;
    j["cell_count"] = stats.cell_count;
    j["empty_cells"] = stats.empty_cells;
    j["leaf_cells"] = stats.leaf_cells;
    j["inner_cells"] = stats.inner_cells;
    j["reference_count"] = stats.reference_count;
    j["referenced_triangles"] = stats.referenced_triangles;
    j["max_depth"] = stats.max_depth;
    j["mean_leaf_depth"] = stats.mean_leaf_depth;
    j["nodes_per_depth"] = stats.nodes_per_depth;
    j["mean_resolution_per_depth"] = stats.mean_resolution_per_depth;
    j["resolution_histogram"] = stats.resolution_histogram;
    j["leaf_size_min"] = stats.leaf_size_min;
    j["leaf_size_max"] = stats.leaf_size_max;
    j["leaf_size_mean"] = stats.leaf_size_mean;
    j["leaf_size_histogram"] = stats.leaf_size_histogram;
    j["empty_cell_fraction"] = stats.empty_cell_fraction;
    j["duplication_factor"] = stats.duplication_factor;
    j["node_bytes"] = stats.node_bytes;
    j["cell_bytes"] = stats.cell_bytes;
    j["reference_bytes"] = stats.reference_bytes;
    j["structure_bytes"] = stats.structure_bytes;
    j["structure_bytes_per_triangle"] = stats.structure_bytes_per_triangle;
    j["sah_cost"] = stats.sah_cost;
    j["cost_model"] = {{"node_cost", stats.cost_model.node_cost},
                       {"cell_cost", stats.cost_model.cell_cost},
                       {"triangle_cost", stats.cost_model.triangle_cost}};
    return j;
}

}  // namespace sg::apps
