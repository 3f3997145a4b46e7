#pragma once

#include <cstdint>
#include <type_traits>

#include "splitgrid/error.hpp"

namespace sg {

/// Largest resolution (cells per node) the record can hold: 2^30 - 1.
inline constexpr std::uint32_t max_resolution_bits = 30;
inline constexpr std::uint32_t max_node_resolution = (1u << max_resolution_bits) - 1u;

/// Kinds of cell. `Empty` cells hold nothing; a `Leaf` lists triangles; an `Inner` cell is
/// refined by a child GridNode.
enum class CellKind : std::uint8_t { Empty, Leaf, Inner };

/// Largest index a CellRef can hold (first word of a leaf, or child node): 2^30 - 1.
inline constexpr std::uint32_t max_cell_index = (1u << 30) - 1u;

/// One cell of a node (or the root cell of the whole structure).
///
/// Layout (4 bytes, 4-byte aligned), one uint32 word:
///   bits 0-1   kind: 0 = empty, 1 = leaf, 2 = inner with a child of two or more cells,
///              3 = inner with a one-cell child (a bounding node)
///   bits 2-31  index: Leaf: its first word in SplitGrid::leaf_words (leaf_words.hpp);
///              Inner: the child node in SplitGrid::nodes; Empty: 0
/// A leaf's words end at the reference marked last (leaf_words.hpp), so the cell needs no
/// count. The poster does not give a cell layout; this one keeps a leaf's references
/// contiguous, so a leaf costs one 4-byte read plus its references, and makes a node's cells
/// half the size of an (index, count) pair (docs/SPLIT_GRID.md, "Records"; measured in
/// docs/notebook/layout.md, "Cells in one 4-byte word, leaves marked at their end (format
/// version 2)").
/// The two inner kinds tell the walk which way a child node is entered (docs/SPLIT_GRID.md,
/// "Traversal") from the word it already holds, before the child's record arrives from memory
/// (docs/notebook/layout.md, "An inner cell that says how its child is entered (format
/// version 4)").
class CellRef {
public:
    [[nodiscard]] static constexpr CellRef make_empty() noexcept { return {}; }
    /// Throws ConfigError if first_word is above max_cell_index.
    [[nodiscard]] static CellRef make_leaf(std::uint32_t first_word)
    {
        if (first_word > max_cell_index)
            throw ConfigError("CellRef: leaf word index must be below 2^30");
        return CellRef((first_word << 2) | leaf_tag);
    }
    /// An inner cell refined by node `child_node` of `child_resolution` cells. Throws
    /// ConfigError if child_node is above max_cell_index.
    [[nodiscard]] static CellRef make_inner(std::uint32_t child_node,
                                            std::uint32_t child_resolution)
    {
        if (child_node > max_cell_index)
            throw ConfigError("CellRef: child node index must be below 2^30");
        return CellRef((child_node << 2) | (child_resolution == 1 ? inner_one_tag : inner_tag));
    }
    /// Rebuilds a record from its raw word without checks (file reader; check afterwards
    /// with check_invariants).
    [[nodiscard]] static constexpr CellRef from_raw(std::uint32_t bits) noexcept
    {
        return CellRef(bits);
    }

    [[nodiscard]] constexpr CellKind kind() const noexcept
    {
        return is_leaf() ? CellKind::Leaf : (is_inner() ? CellKind::Inner : CellKind::Empty);
    }
    /// True for a valid empty cell (word 0). A word with an empty kind and a non-zero index
    /// is neither empty, leaf nor inner: has_valid_kind() is false.
    [[nodiscard]] constexpr bool is_empty() const noexcept { return bits_ == 0; }
    [[nodiscard]] constexpr bool is_leaf() const noexcept { return (bits_ & 3u) == leaf_tag; }
    /// Either inner kind.
    [[nodiscard]] constexpr bool is_inner() const noexcept { return (bits_ & inner_tag) != 0; }
    /// Inner, and the child is a one-cell node (check_invariants checks that the kind matches
    /// the child's resolution).
    [[nodiscard]] constexpr bool has_one_cell_child() const noexcept
    {
        return (bits_ & 3u) == inner_one_tag;
    }
    [[nodiscard]] constexpr bool has_valid_kind() const noexcept
    {
        return is_empty() || is_leaf() || is_inner();
    }
    /// Leaf: its first word in SplitGrid::leaf_words. Inner: child node. Empty: 0.
    [[nodiscard]] constexpr std::uint32_t index() const noexcept { return bits_ >> 2; }
    [[nodiscard]] constexpr std::uint32_t first_word() const noexcept { return bits_ >> 2; }
    [[nodiscard]] constexpr std::uint32_t child() const noexcept { return bits_ >> 2; }
    /// Raw word, for file I/O and validation only.
    [[nodiscard]] constexpr std::uint32_t raw_bits() const noexcept { return bits_; }

    friend constexpr bool operator==(const CellRef&, const CellRef&) = default;

    constexpr CellRef() = default;

private:
    static constexpr std::uint32_t leaf_tag = 1u;
    static constexpr std::uint32_t inner_tag = 2u;
    static constexpr std::uint32_t inner_one_tag = 3u;
    explicit constexpr CellRef(std::uint32_t bits) : bits_(bits) {}
    std::uint32_t bits_ = 0;
};
static_assert(sizeof(CellRef) == 4 && alignof(CellRef) == 4,
              "CellRef must be one uint32 word with no padding");
static_assert(std::is_trivially_copyable_v<CellRef>, "CellRef is stored in .sg files as bytes");

/// An inner node of the Split Grid: a 1D grid along one axis.
///
/// Bauszat, Kastner, Eisemann, Magnor, "The Split Grid", Eurographics 2014 poster: a node
/// holds a split axis, two bounding planes lo <= hi on that axis (the tight extent of its
/// triangles inside its box) and a resolution N; the slab [lo, hi] is cut into N cells of
/// equal width. The node's box is implicit: the root box, narrowed on each ancestor's axis to
/// the ancestor's cell. Nothing of the box is stored.
///
/// Layout (16 bytes, 4-byte aligned; all indices 32-bit):
///   offset  0  float    lo           lower bounding plane on `axis`
///   offset  4  float    hi           upper bounding plane on `axis`
///   offset  8  uint32   cells        N >= 2: first_cell, the index of cell 0 in
///                                    SplitGrid::cells; cells first_cell .. first_cell + N - 1
///                                    belong to this node
///                                    N == 1: only_cell, the node's one cell itself (a CellRef
///                                    word); it has none in SplitGrid::cells
///   offset 12  uint32   axis_res     bits 0-1: axis (0 = x, 1 = y, 2 = z; 3 is invalid)
///                                    bits 2-31: resolution N (1 .. 2^30 - 1)
///
/// Differences from the poster: the node does not store the cell width; it is recomputed
/// from lo, hi and N by cell_math.hpp, the one place both builder and traverser use. A
/// one-cell node (a bounding node, docs/SPLIT_GRID.md; most of the nodes of a default build)
/// keeps its cell in the record, so the walk reads it with the planes instead of from a second
/// array, and the cell costs no 4 bytes of its own (docs/notebook/layout.md, "Lever 5, first
/// part: a one-cell node's cell in its record (format version 3)").
class GridNode {
public:
    float lo = 0.0f;
    float hi = 0.0f;

    /// Builds the record of a node of resolution >= 2 whose cells start at `first_cell`.
    /// Throws ConfigError if axis > 2 or resolution is below 2 or too large.
    [[nodiscard]] static GridNode make(int axis, float lo, float hi, std::uint32_t resolution,
                                       std::uint32_t first_cell)
    {
        if (resolution == 1)
            throw ConfigError("GridNode: a one-cell node holds its cell (make_one_cell)");
        return make_checked(axis, lo, hi, resolution, first_cell);
    }
    /// Builds the record of a one-cell node holding `cell`. Throws ConfigError if axis > 2.
    [[nodiscard]] static GridNode make_one_cell(int axis, float lo, float hi, CellRef cell)
    {
        return make_checked(axis, lo, hi, 1, cell.raw_bits());
    }

    [[nodiscard]] constexpr int axis() const noexcept { return static_cast<int>(axis_res_ & 3u); }
    [[nodiscard]] constexpr std::uint32_t resolution() const noexcept { return axis_res_ >> 2; }
    /// Index of cell 0 in SplitGrid::cells. Precondition: resolution() >= 2.
    [[nodiscard]] constexpr std::uint32_t first_cell() const noexcept { return cells_; }
    /// The cell of a one-cell node. Precondition: resolution() == 1.
    [[nodiscard]] constexpr CellRef only_cell() const noexcept { return CellRef::from_raw(cells_); }
    /// Sets the cell of a one-cell node (the builder stores a child after its parent).
    /// Precondition: resolution() == 1.
    constexpr void set_only_cell(CellRef cell) noexcept { cells_ = cell.raw_bits(); }
    /// Raw words, for file I/O and validation only.
    [[nodiscard]] constexpr std::uint32_t cells_bits() const noexcept { return cells_; }
    [[nodiscard]] constexpr std::uint32_t axis_res_bits() const noexcept { return axis_res_; }
    /// Rebuilds a record from raw fields without range checks (file reader; check afterwards
    /// with check_invariants).
    [[nodiscard]] static constexpr GridNode from_raw(float lo, float hi, std::uint32_t cells,
                                                     std::uint32_t axis_res) noexcept
    {
        GridNode n;
        n.lo = lo;
        n.hi = hi;
        n.cells_ = cells;
        n.axis_res_ = axis_res;
        return n;
    }

    friend constexpr bool operator==(const GridNode&, const GridNode&) = default;

private:
    [[nodiscard]] static GridNode make_checked(int axis, float lo, float hi,
                                               std::uint32_t resolution, std::uint32_t cells)
    {
        if (axis < 0 || axis > 2) throw ConfigError("GridNode: axis must be 0, 1 or 2");
        if (resolution == 0 || resolution > max_node_resolution)
            throw ConfigError("GridNode: resolution must be in [1, 2^30 - 1]");
        return from_raw(lo, hi, cells, static_cast<std::uint32_t>(axis) | (resolution << 2));
    }

    std::uint32_t cells_ = 0;
    std::uint32_t axis_res_ = 0;
};
static_assert(sizeof(GridNode) == 16 && alignof(GridNode) == 4,
              "GridNode must be 16 bytes (2 floats + 2 uint32) with no padding");
static_assert(std::is_trivially_copyable_v<GridNode>, "GridNode is stored in .sg files as bytes");

}  // namespace sg
