#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace sg {

/// Largest triangle id a leaf can reference: 2^30 - 1 (the head word's two upper bits are flags).
inline constexpr std::uint32_t max_referenced_triangle = (1u << 30) - 1u;

/// How a leaf's triangle references are stored in SplitGrid::leaf_words (format version 5): in
/// 16-bit words, ids ascending, each leaf contiguous, the leaf's cell pointing at its first word.
///
///   head       two words, the low half first, read as one uint32:
///                bits 0-29  the leaf's first (smallest) triangle id
///                bit  30    wide: the other references are two words each, as below
///                bit  31    last: the leaf holds this one reference only
///   narrow     (bit 30 clear) each further reference is one word:
///                bits 0-14  its id minus the head's id (so below 2^15)
///                bit  15    set on the leaf's last reference
///   wide       (bit 30 set) each further reference is two words, the low half first:
///                bits 0-29  its id
///                bit  30    clear
///                bit  31    set on the leaf's last reference
///
/// A leaf is narrow exactly when its ids span less than 2^15, so the encoding of a list of ids
/// is unique (files are byte-identical for any thread count). A wide head never has the last bit:
/// a one-reference leaf is narrow. Most of the builder's leaves are narrow, so the words about
/// halve what the references cost (docs/notebook/layout.md, "A leaf's references in 16-bit
/// words (format version 5, kept)"). The walk reads a narrow leaf's head pair, then the head's
/// upper word and the next seven words with one 16-byte load.
namespace leaf_code {
inline constexpr std::uint32_t id_mask = max_referenced_triangle;
inline constexpr std::uint32_t wide_bit = 1u << 30;
inline constexpr std::uint32_t last_bit = 1u << 31;
inline constexpr std::uint32_t narrow_last_bit = 1u << 15;
inline constexpr std::uint32_t narrow_offset_mask = narrow_last_bit - 1u;
/// A narrow leaf's ids lie in [head, head + narrow_span).
inline constexpr std::uint32_t narrow_span = 1u << 15;
}  // namespace leaf_code

/// The two words at `words` as one uint32, the first word the low half.
[[nodiscard]] inline std::uint32_t leaf_pair(const std::uint16_t* words) noexcept
{
    return std::uint32_t{words[0]} | (std::uint32_t{words[1]} << 16);
}

/// Words a leaf of these ids takes (`sorted_ids` ascending, not empty).
[[nodiscard]] std::size_t leaf_word_count(std::span<const std::uint32_t> sorted_ids) noexcept;

/// Appends the leaf of `sorted_ids` (strictly ascending, not empty, each at most
/// max_referenced_triangle) to `words` and returns the index of its first word. Throws
/// ConfigError if the ids are empty, unsorted or too large.
std::uint32_t append_leaf(std::vector<std::uint16_t>& words,
                          std::span<const std::uint32_t> sorted_ids);

/// Reads the leaf whose head is at `first`, calling `visit(id)` for each of its triangle ids in
/// order. Returns the index one past its last word, or 0 if the leaf is not well formed: it
/// runs past the end of `words`, or a wide head has the last bit or a wide reference bit 30.
/// (Ids are not checked against a mesh or for their order: check_invariants does that.)
template <class Visit>
[[nodiscard]] std::size_t read_leaf(std::span<const std::uint16_t> words, std::size_t first,
                                    Visit&& visit)
{
    if (first >= words.size() || words.size() - first < 2) return 0;
    const std::uint32_t head = leaf_pair(words.data() + first);
    const std::uint32_t base = head & leaf_code::id_mask;
    visit(base);
    std::size_t w = first + 2;
    if ((head & leaf_code::last_bit) != 0) return (head & leaf_code::wide_bit) != 0 ? 0 : w;
    if ((head & leaf_code::wide_bit) == 0) {
        for (; w < words.size(); ++w) {
            visit(base + (words[w] & leaf_code::narrow_offset_mask));
            if ((words[w] & leaf_code::narrow_last_bit) != 0) return w + 1;
        }
        return 0;
    }
    for (; words.size() - w >= 2; w += 2) {
        const std::uint32_t ref = leaf_pair(words.data() + w);
        if ((ref & leaf_code::wide_bit) != 0) return 0;
        visit(ref & leaf_code::id_mask);
        if ((ref & leaf_code::last_bit) != 0) return w + 2;
    }
    return 0;
}

/// Reads the leaves that follow each other from word 0, calling `visit_leaf(first, end, ids)`
/// for each (its first word, the word after it, its triangle ids), up to the end of `words` or
/// the first leaf that is not well formed. Returns the index where it stopped: words.size()
/// when every word belongs to a well-formed leaf.
template <class VisitLeaf>
std::size_t for_each_leaf(std::span<const std::uint16_t> words, VisitLeaf&& visit_leaf)
{
    std::vector<std::uint32_t> ids;
    std::size_t w = 0;
    while (w < words.size()) {
        ids.clear();
        const std::size_t end = read_leaf(words, w, [&](std::uint32_t id) { ids.push_back(id); });
        if (end == 0) break;
        visit_leaf(w, end, std::span<const std::uint32_t>(ids));
        w = end;
    }
    return w;
}

/// The triangle ids of the leaf at `first`, in order; empty if it is not well formed.
[[nodiscard]] std::vector<std::uint32_t> leaf_ids(std::span<const std::uint16_t> words,
                                                  std::size_t first);

/// Number of references in `words` read as leaves one after another from word 0, up to the
/// end or the first leaf that is not well formed.
[[nodiscard]] std::size_t count_references(std::span<const std::uint16_t> words);

}  // namespace sg
