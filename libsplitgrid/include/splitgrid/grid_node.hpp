#pragma once

#include <cstdint>
#include <type_traits>

#include "splitgrid/error.hpp"

namespace sg {

/// Largest resolution (cells per node) the record can hold: 2^30 - 1.
inline constexpr std::uint32_t max_resolution_bits = 30;
inline constexpr std::uint32_t max_node_resolution = (1u << max_resolution_bits) - 1u;

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
///   offset  8  uint32   first_cell   index of cell 0 in SplitGrid::cells; cells
///                                    first_cell .. first_cell + N - 1 belong to this node
///   offset 12  uint32   axis_res     bits 0-1: axis (0 = x, 1 = y, 2 = z; 3 is invalid)
///                                    bits 2-31: resolution N (1 .. 2^30 - 1)
///
/// Difference from the poster: the node does not store the cell width; it is recomputed
/// from lo, hi and N by cell_math.hpp, the one place both builder and traverser use.
class GridNode {
public:
    float lo = 0.0f;
    float hi = 0.0f;

    /// Builds a node record. Throws ConfigError if axis > 2 or resolution is 0 or too large.
    [[nodiscard]] static GridNode make(int axis, float lo, float hi, std::uint32_t resolution,
                                       std::uint32_t first_cell)
    {
        if (axis < 0 || axis > 2) throw ConfigError("GridNode: axis must be 0, 1 or 2");
        if (resolution == 0 || resolution > max_node_resolution)
            throw ConfigError("GridNode: resolution must be in [1, 2^30 - 1]");
        GridNode n;
        n.lo = lo;
        n.hi = hi;
        n.first_cell_ = first_cell;
        n.axis_res_ = static_cast<std::uint32_t>(axis) | (resolution << 2);
        return n;
    }

    [[nodiscard]] constexpr int axis() const noexcept { return static_cast<int>(axis_res_ & 3u); }
    [[nodiscard]] constexpr std::uint32_t resolution() const noexcept { return axis_res_ >> 2; }
    [[nodiscard]] constexpr std::uint32_t first_cell() const noexcept { return first_cell_; }
    /// Raw packed word, for file I/O and validation only.
    [[nodiscard]] constexpr std::uint32_t axis_res_bits() const noexcept { return axis_res_; }
    /// Rebuilds a record from raw fields without range checks (file reader; check afterwards
    /// with check_invariants).
    [[nodiscard]] static constexpr GridNode from_raw(float lo, float hi, std::uint32_t first_cell,
                                                     std::uint32_t axis_res) noexcept
    {
        GridNode n;
        n.lo = lo;
        n.hi = hi;
        n.first_cell_ = first_cell;
        n.axis_res_ = axis_res;
        return n;
    }

    friend constexpr bool operator==(const GridNode&, const GridNode&) = default;

private:
    std::uint32_t first_cell_ = 0;
    std::uint32_t axis_res_ = 0;
};
static_assert(sizeof(GridNode) == 16 && alignof(GridNode) == 4,
              "GridNode must be 16 bytes (2 floats + 2 uint32) with no padding");
static_assert(std::is_trivially_copyable_v<GridNode>, "GridNode is stored in .sg files as bytes");

/// Kinds of cell. `Empty` cells hold nothing; a `Leaf` lists triangles; an `Inner` cell is
/// refined by a child GridNode.
enum class CellKind : std::uint8_t { Empty, Leaf, Inner };

/// One cell of a node (or the root cell of the whole structure).
///
/// Layout (8 bytes, 4-byte aligned):
///   offset 0  uint32  index   Leaf: index of the first triangle reference in
///                             SplitGrid::triangle_refs; Inner: child node index in
///                             SplitGrid::nodes; Empty: 0
///   offset 4  uint32  count   Leaf: number of triangle references (>= 1);
///                             Inner: 0xFFFFFFFF; Empty: 0
/// So count == 0 is empty, count == 0xFFFFFFFF is inner, anything else a leaf.
/// The poster does not give a cell layout; this one keeps a leaf's references contiguous so
/// that a leaf costs one 8-byte read plus its references.
class CellRef {
public:
    static constexpr std::uint32_t inner_tag = 0xFFFFFFFFu;

    [[nodiscard]] static constexpr CellRef make_empty() noexcept { return {}; }
    /// Throws ConfigError if count is 0 or the inner tag.
    [[nodiscard]] static CellRef make_leaf(std::uint32_t first_ref, std::uint32_t count)
    {
        if (count == 0 || count == inner_tag)
            throw ConfigError("CellRef: leaf triangle count must be in [1, 2^32 - 2]");
        return CellRef(first_ref, count);
    }
    [[nodiscard]] static constexpr CellRef make_inner(std::uint32_t child_node) noexcept
    {
        return CellRef(child_node, inner_tag);
    }
    [[nodiscard]] static constexpr CellRef from_raw(std::uint32_t index,
                                                    std::uint32_t count) noexcept
    {
        return CellRef(index, count);
    }

    [[nodiscard]] constexpr CellKind kind() const noexcept
    {
        return count_ == 0 ? CellKind::Empty
                           : (count_ == inner_tag ? CellKind::Inner : CellKind::Leaf);
    }
    [[nodiscard]] constexpr bool is_empty() const noexcept { return count_ == 0; }
    [[nodiscard]] constexpr bool is_leaf() const noexcept
    {
        return count_ != 0 && count_ != inner_tag;
    }
    [[nodiscard]] constexpr bool is_inner() const noexcept { return count_ == inner_tag; }
    /// Leaf: first triangle reference. Inner: child node. Empty: 0.
    [[nodiscard]] constexpr std::uint32_t index() const noexcept { return index_; }
    [[nodiscard]] constexpr std::uint32_t first_ref() const noexcept { return index_; }
    [[nodiscard]] constexpr std::uint32_t child() const noexcept { return index_; }
    /// Leaf: number of references; 0 for empty and inner cells.
    [[nodiscard]] constexpr std::uint32_t ref_count() const noexcept
    {
        return is_leaf() ? count_ : 0u;
    }
    [[nodiscard]] constexpr std::uint32_t raw_count() const noexcept { return count_; }

    friend constexpr bool operator==(const CellRef&, const CellRef&) = default;

    constexpr CellRef() = default;

private:
    constexpr CellRef(std::uint32_t index, std::uint32_t count) : index_(index), count_(count) {}
    std::uint32_t index_ = 0;
    std::uint32_t count_ = 0;
};
static_assert(sizeof(CellRef) == 8 && alignof(CellRef) == 4,
              "CellRef must be 8 bytes (2 uint32) with no padding");
static_assert(std::is_trivially_copyable_v<CellRef>, "CellRef is stored in .sg files as bytes");

/// A triangle reference is a plain 32-bit triangle id (4 bytes).
using TriangleRef = std::uint32_t;

}  // namespace sg
