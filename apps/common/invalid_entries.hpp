#pragma once

#include <algorithm>
#include <cstddef>
#include <filesystem>
#include <iterator>
#include <string>
#include <string_view>

#include "splitgrid/error.hpp"

#include <spdlog/fmt/fmt.h>
#include <spdlog/spdlog.h>

/// One policy for well-formed input files whose entries cannot be answered (sg-trace's invalid
/// rays, sg-points' non-finite points): they are the generator's fault, not the file's, so by
/// default they are answered as documented and counted in one warning, so that a broken
/// generator does not pass unnoticed; --strict refuses the file instead (exit code 2).
namespace sg::apps {

/// How the messages name the entries.
struct InvalidEntryWords {
    std::string_view entry;       ///< one entry: "ray", "point"
    std::string_view why;         ///< what makes one invalid: sg::invalid_ray_description
    std::string_view written_as;  ///< what is written for one: "misses", "NaN"
};

/// Counts the entries of `entries` (a range) for which `is_invalid` holds. None: returns 0.
/// Some, with `strict`: throws InputError "<file>: 2 of 3 rays are invalid (<why>; the first
/// is ray 1): refused by --strict". Some, without: logs that line as a warning, followed by
/// ": the file is well formed, the rays are not; they are written as <written_as> (--strict
/// refuses such a file)", and returns the count.
template <class Entries, class IsInvalid>
std::size_t check_invalid_entries(const std::filesystem::path& file, const Entries& entries,
                                  IsInvalid is_invalid, const InvalidEntryWords& words,
                                  bool strict)
{
    const auto invalid = static_cast<std::size_t>(
        std::count_if(std::begin(entries), std::end(entries), is_invalid));
    if (invalid == 0) return 0;
    const auto first =
        std::find_if(std::begin(entries), std::end(entries), is_invalid) - std::begin(entries);
    const std::size_t total = static_cast<std::size_t>(std::size(entries));
    const std::string what =
        fmt::format("{}: {} of {} {}s are invalid ({}; the first is {} {})", file.string(),
                    invalid, total, words.entry, words.why, words.entry, first);
    if (strict) throw InputError(what + ": refused by --strict");
    spdlog::warn("{}: the file is well formed, the {}s are not; they are written as {} (--strict "
                 "refuses such a file)",
                 what, words.entry, words.written_as);
    return invalid;
}

}  // namespace sg::apps
