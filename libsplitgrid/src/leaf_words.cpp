#include "splitgrid/leaf_words.hpp"

#include "splitgrid/error.hpp"

namespace sg {
namespace {

bool is_narrow(std::span<const std::uint32_t> sorted_ids) noexcept
{
    return sorted_ids.back() - sorted_ids.front() < leaf_code::narrow_span;
}

void push_pair(std::vector<std::uint16_t>& words, std::uint32_t value)
{
    words.push_back(static_cast<std::uint16_t>(value & 0xFFFFu));
    words.push_back(static_cast<std::uint16_t>(value >> 16));
}

}  // namespace

std::size_t leaf_word_count(std::span<const std::uint32_t> sorted_ids) noexcept
{
    return is_narrow(sorted_ids) ? sorted_ids.size() + 1 : 2 * sorted_ids.size();
}

std::uint32_t append_leaf(std::vector<std::uint16_t>& words,
                          std::span<const std::uint32_t> sorted_ids)
{
    if (sorted_ids.empty()) throw ConfigError("leaf: a leaf holds at least one triangle");
    for (std::size_t k = 1; k < sorted_ids.size(); ++k)
        if (sorted_ids[k] <= sorted_ids[k - 1])
            throw ConfigError("leaf: triangle ids must be strictly ascending");
    if (sorted_ids.back() > max_referenced_triangle)
        throw ConfigError("leaf: triangle id must be below 2^30");
    const auto first = static_cast<std::uint32_t>(words.size());
    const std::uint32_t base = sorted_ids.front();
    const bool narrow = is_narrow(sorted_ids);
    const std::size_t n = sorted_ids.size();
    push_pair(words, base | (n == 1 ? leaf_code::last_bit : 0u) |
                         (narrow ? 0u : leaf_code::wide_bit));
    for (std::size_t k = 1; k < n; ++k) {
        const bool last = k + 1 == n;
        if (narrow)
            words.push_back(static_cast<std::uint16_t>((sorted_ids[k] - base) |
                                                       (last ? leaf_code::narrow_last_bit : 0u)));
        else
            push_pair(words, sorted_ids[k] | (last ? leaf_code::last_bit : 0u));
    }
    return first;
}

std::vector<std::uint32_t> leaf_ids(std::span<const std::uint16_t> words, std::size_t first)
{
    std::vector<std::uint32_t> ids;
    if (read_leaf(words, first, [&](std::uint32_t id) { ids.push_back(id); }) == 0) ids.clear();
    return ids;
}

std::size_t count_references(std::span<const std::uint16_t> words)
{
    std::size_t count = 0;
    (void)for_each_leaf(words, [&](std::size_t, std::size_t, std::span<const std::uint32_t> ids) {
        count += ids.size();
    });
    return count;
}

}  // namespace sg
