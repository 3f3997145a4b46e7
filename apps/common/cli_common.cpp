#include "cli_common.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <system_error>
#include <utility>
#include <variant>

#include "interrupt.hpp"
#include "splitgrid/error.hpp"
#include "splitgrid/query.hpp"
#include "splitgrid/version.hpp"

#include <spdlog/fmt/fmt.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>
#include <spdlog/version.h>
#include <tbb/info.h>
#include <tbb/version.h>

namespace sg::apps {
namespace {

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

/// The tools' one logger: stderr, so stdout carries only results (and --json stays clean).
/// Colours only on a terminal. Messages read "warning: ...", "error: ...".
void create_logger()
{
    auto logger = spdlog::stderr_color_mt("sg");
    logger->set_pattern("%^%l%$: %v");
    logger->set_level(spdlog::level::info);
    spdlog::set_default_logger(std::move(logger));
}

/// CLI11's refusal of a flag given twice ("--leaf-size: At Most 1 required but received 2")
/// said in the tools' words, or nothing if no option was given too often. Looks into the
/// subcommands too (sg-rays' modes have flags of their own).
std::optional<std::string> repeated_flag_message(const CLI::App& app)
{
    for (const CLI::Option* option : app.get_options()) {
        const int most = option->get_items_expected_max();
        if (most < 1 || option->results().size() <= static_cast<std::size_t>(most)) continue;
        return fmt::format("{} is given {} times ({}); give it once", option->get_name(),
                           option->results().size(), fmt::join(option->results(), ", "));
    }
    for (const CLI::App* subcommand : app.get_subcommands({})) {
        if (auto message = repeated_flag_message(*subcommand)) return message;
    }
    return std::nullopt;
}

/// Ends a tool's run: marks the work finished (if an interrupt came first this does not
/// return, see InterruptHandling::finish), then logs `message` as the one error line.
int finish_with(InterruptHandling& interrupts, ExitCode code, const std::string& message)
{
    interrupts.finish();
    if (!message.empty()) spdlog::error("{}", one_line(message));
    return static_cast<int>(code);
}

/// A flag's current value as help and error messages print it.
std::string field_value_text(const BuildConfig& config, const BuildConfigField& field)
{
    if (const auto* count = std::get_if<BuildConfigField::CountMember>(&field.member))
        return std::to_string(config.**count);
    if (const auto* real = std::get_if<BuildConfigField::RealMember>(&field.member))
        return number_text(config.**real);
    return config.*std::get<BuildConfigField::SwitchMember>(field.member) ? "on" : "off";
}

/// Refuses (as a usage error) a BuildConfig field above the field it may not exceed, by
/// flag: "--resolution-min 20 is above --resolution-max 16 (its default)".
void check_field_limits(const CLI::App& app, const BuildConfig& config)
{
    for (const BuildConfigField& field : build_config_fields) {
        if (field.at_most.empty()) continue;
        const BuildConfigField& limit = *find_build_config_field(field.at_most);
        const auto value = config.*std::get<BuildConfigField::CountMember>(field.member);
        const auto limit_value = config.*std::get<BuildConfigField::CountMember>(limit.member);
        if (value <= limit_value) continue;
        const std::string flag = build_config_flag(field);
        const std::string limit_flag = build_config_flag(limit);
        const bool limit_given = app.count(limit_flag) > 0;
        throw CLI::ValidationError(fmt::format("{} {} is above {} {}{}", flag, value, limit_flag,
                                               limit_value, limit_given ? "" : " (its default)"));
    }
}

}  // namespace

CLI::Validator count_in(std::uint64_t lo, std::uint64_t hi)
{
    return CLI::Validator(
        [lo, hi](std::string& text) -> std::string {
            std::uint64_t value = 0;
            const char* end = text.data() + text.size();
            const auto [ptr, ec] = std::from_chars(text.data(), end, value);
            if (ec != std::errc{} || ptr != end || value < lo || value > hi)
                return fmt::format("{} is not an integer in {}", text, count_range(lo, hi));
            return {};
        },
        "", "");
}

CLI::Validator uint_in(std::uint32_t lo, std::uint32_t hi) { return count_in(lo, hi); }

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
                return fmt::format("{} is not a number in {}", text,
                                   real_range(lo, hi, open_below));
            return {};
        },
        "", "");
}

std::string count_range(std::uint64_t lo, std::uint64_t hi)
{
    return fmt::format("[{}, {}]", lo, hi);
}

std::string number_text(double value)
{
    // {:g} writes 1e+09; help texts and messages write 1e9.
    std::string text = fmt::format("{:g}", value);
    const std::size_t e = text.find("e+");
    if (e != std::string::npos) {
        std::size_t digits = e + 2;
        while (digits + 1 < text.size() && text[digits] == '0') ++digits;
        text = text.substr(0, e + 1) + text.substr(digits);
    }
    return text;
}

std::string real_range(double lo, double hi, bool open_below)
{
    return fmt::format("{}{}, {}]", open_below ? '(' : '[', number_text(lo), number_text(hi));
}

std::string help_text(std::string_view help, std::string_view range,
                      std::string_view default_value)
{
    std::string text(help);
    if (!range.empty()) text += fmt::format(" Range {}.", range);
    text += fmt::format(" Default {}.", default_value);
    return text;
}

CLI::Option* add_output_option(CLI::App& app, std::filesystem::path& path,
                               const std::string& description, bool required,
                               const std::string& type_name)
{
    CLI::Option* option =
        app.add_option("-o,--output,--out", path, description)
            ->type_name(type_name)
            ->check(CLI::Validator(
                [](std::string& text) -> std::string {
                    if (text.empty()) return "the output name is empty";
                    if (text == "-")
                        return "- (standard output) is not supported: the output is written "
                               "to a file, atomically; give a file name";
                    return {};
                },
                "", ""));
    if (required) option->required();
    return option;
}

std::string version_text(const std::string& tool,
                         const std::vector<LibraryVersion>& extra_libraries)
{
    std::vector<LibraryVersion> libraries{{"oneTBB", TBB_runtime_version()}};
    for (LibraryVersion& library : formats_library_versions())
        libraries.push_back(std::move(library));
    libraries.push_back({"CLI11", CLI11_VERSION});
    libraries.push_back(
        {"spdlog", fmt::format("{}.{}.{}", SPDLOG_VER_MAJOR, SPDLOG_VER_MINOR, SPDLOG_VER_PATCH)});
    libraries.push_back({"nlohmann-json", fmt::format("{}.{}.{}", NLOHMANN_JSON_VERSION_MAJOR,
                                                      NLOHMANN_JSON_VERSION_MINOR,
                                                      NLOHMANN_JSON_VERSION_PATCH)});
    libraries.insert(libraries.end(), extra_libraries.begin(), extra_libraries.end());
    std::string text = fmt::format("{} {} (splitgrid {})\nlinked with:", tool, version_string,
                                   version_string);
    for (const LibraryVersion& library : libraries)
        text += fmt::format("\n  {} {}", library.name, library.version);
    return text;
}

void describe_tool(CLI::App& app, const std::string& description, const std::string& extra_footer,
                   const std::vector<LibraryVersion>& extra_libraries)
{
    app.description(description);
    const std::string tool = app.get_name();
    app.set_version_flag(
        "--version", [tool, extra_libraries] { return version_text(tool, extra_libraries); },
        "Print the tool's version and the versions of the libraries it links, and exit");
    app.formatter(std::make_shared<WrappingFormatter>());
    std::string footer = extra_footer.empty() ? std::string{} : extra_footer + "\n\n";
    footer +=
        "Exit codes:\n"
        "  0  ok\n"
        "  1  usage error: unknown flag, missing or out-of-range value\n"
        "  2  bad input or file: missing, unreadable or malformed file, unusable mesh or rays,\n"
        "     an output that is one of the inputs or that cannot be written\n"
        "  3  internal error\n"
        "  130, 143  interrupted by SIGINT (Ctrl-C) or SIGTERM: temporary files removed";
    app.footer(footer);
}

void add_log_flags(CLI::App& app, LogOptions& options)
{
    auto* verbose = app.add_flag("-v,--verbose", options.verbose, "Also print debug messages");
    auto* quiet = app.add_flag("-q,--quiet", options.quiet,
                               "Hide progress, information and the summary of a tool that "
                               "writes a file; warnings, errors and results on stdout "
                               "(statistics, --json) still print");
    verbose->excludes(quiet);
}

std::string build_config_flag(const BuildConfigField& field)
{
    std::string flag = "--" + std::string(field.name);
    std::replace(flag.begin(), flag.end(), '_', '-');
    return flag;
}

void add_build_config_flags(CLI::App& app, BuildConfig& config, bool with_threads)
{
    const BuildConfig defaults{};
    const std::string group = "Build parameters (BuildConfig)";
    // Added before the fields: CLI11 runs the callbacks in the order the options were added,
    // so a field's own flag overrides the preset whatever the order on the command line.
    app.add_option_function<std::string>(
           "--preset",
           [&config](const std::string& name) { config = apply_build_preset(config, name); },
           "A named construction. default: the fastest Split Grid this toolkit makes. poster: "
           "the construction of the Eurographics 2014 poster, no bounding nodes and no cost "
           "test (the same as --no-bounding-nodes --no-stop-by-cost; docs/SPLIT_GRID.md lists "
           "every departure from the poster). Flags given with it override it. Default: "
           "default.")
        ->check(CLI::IsMember(std::vector<std::string>(build_preset_names.begin(),
                                                        build_preset_names.end())))
        ->type_name("NAME")
        ->group(group);
    for (const BuildConfigField& field : build_config_fields) {
        if (field.name == "threads" && !with_threads) continue;
        const std::string flag = build_config_flag(field);
        if (const auto* switched = std::get_if<BuildConfigField::SwitchMember>(&field.member)) {
            const std::string off = "--no-" + flag.substr(2);
            app.add_flag(flag + ",!" + off, config.**switched,
                         help_text(field.help, {}, defaults.**switched ? flag : off))
                ->group(group);
            continue;
        }
        std::string range;
        CLI::Validator check;
        if (field.is_count()) {
            range = count_range(static_cast<std::uint64_t>(field.low),
                                static_cast<std::uint64_t>(field.high));
            check = count_in(static_cast<std::uint64_t>(field.low),
                             static_cast<std::uint64_t>(field.high));
        } else {
            range = real_range(field.low, field.high, field.low_open);
            check = number_in(field.low, field.high, field.low_open);
        }
        if (!field.at_most.empty())
            range += ", at most " + build_config_flag(*find_build_config_field(field.at_most));
        const std::string help = help_text(field.help, range, field_value_text(defaults, field));
        std::visit([&](auto member) { app.add_option(flag, config.*member, help); },
                   field.member);
        app.get_option(flag)->check(check)->group(group);
    }

    // Fields that are fine alone can still be wrong together (resolution_min above
    // resolution_max): refused by flag, as a usage error like any other bad flag value. The
    // library's own check stays the final authority.
    app.parse_complete_callback([&app, &config] {
        check_field_limits(app, config);
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
    // First, before any thread exists: every later thread and child inherits the blocked
    // signals (interrupt.hpp).
    InterruptHandling interrupts;
    create_logger();
    try {
        app.parse(argc, argv);
        if (log.quiet)
            spdlog::set_level(spdlog::level::warn);
        else if (log.verbose)
            spdlog::set_level(spdlog::level::debug);
        work();
        return finish_with(interrupts, ExitCode::ok, {});
    } catch (const CLI::ParseError& e) {
        // --help and --version arrive as "errors" with CLI11's success code.
        if (e.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) {
            interrupts.finish();
            app.exit(e);
            return static_cast<int>(ExitCode::ok);
        }
        const std::string message = repeated_flag_message(app).value_or(e.what());
        return finish_with(interrupts, ExitCode::usage, message + " (run with --help for usage)");
    } catch (const InputError& e) {
        return finish_with(interrupts, ExitCode::bad_input, e.what());
    } catch (const FormatError& e) {
        return finish_with(interrupts, ExitCode::bad_input, e.what());
    } catch (const IoError& e) {
        return finish_with(interrupts, ExitCode::bad_input, e.what());
    } catch (const ConfigError& e) {
        return finish_with(interrupts, ExitCode::bad_input, e.what());
    } catch (const std::filesystem::filesystem_error& e) {
        // Raised by the tools' own file queries (file sizes); its message names the path.
        return finish_with(interrupts, ExitCode::bad_input, e.what());
    } catch (const std::exception& e) {
        return finish_with(interrupts, ExitCode::internal, e.what());
    } catch (...) {
        return finish_with(interrupts, ExitCode::internal, "unknown exception");
    }
}

unsigned threads_to_use(unsigned requested, std::string_view flag)
{
    const auto hardware = static_cast<unsigned>(std::max(1, tbb::info::default_concurrency()));
    if (requested <= hardware) return requested;
    spdlog::warn("{} {} is more than the {} hardware thread{}; using {}", flag, requested,
                 hardware, hardware == 1 ? "" : "s", hardware);
    return hardware;
}

std::string kernel_isa_in_use()
{
    const std::string_view note = kernel_isa_note();
    if (!note.empty()) spdlog::warn("{}", note);
    return std::string(isa_name(kernel_isa()));
}

unsigned threads_that_run(unsigned threads)
{
    return threads != 0 ? threads
                        : static_cast<unsigned>(std::max(1, tbb::info::default_concurrency()));
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

std::string to_text(const BuildConfig& config)
{
    std::string text;
    for (const BuildConfigField& field : build_config_fields) {
        if (!text.empty()) text += ", ";
        text += fmt::format("{} {}", field.name, field_value_text(config, field));
    }
    return text;
}

}  // namespace sg::apps
