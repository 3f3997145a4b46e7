#pragma once

#include <string>

#include "splitgrid/mesh.hpp"
#include "splitgrid/split_grid.hpp"

namespace sg {

/// Checks the structural invariants of a grid, so that traversal of a grid that passes is
/// memory-safe and terminates:
/// - every node index, cell range and leaf lies inside its array;
/// - every node is the child of exactly one cell (no cycles, no sharing), reachable from the
///   root, and at depth <= max_supported_depth;
/// - every cell word has a valid kind, and an inner cell's kind matches its child's
///   resolution (the walk enters the child as the kind says);
/// - axes are 0..2, resolutions >= 1, lo <= hi, planes finite, and [lo, hi] lies inside the
///   node's box on its axis;
/// - every leaf is well formed (leaf_words.hpp: it ends at a reference marked last, and is
///   wide exactly when its ids span 2^15 or more), its triangle ids strictly ascending and
///   < triangle_count; every leaf word belongs to exactly one leaf, so the leaves follow each
///   other through the whole array;
/// - the root box is finite and non-empty unless the root is empty.
/// Throws FormatError with a one-line message naming the first violation. Cost: O(size).
void check_invariants(const SplitGrid& grid);

/// The geometric invariant, against the mesh: every triangle is referenced by every leaf whose
/// box it overlaps, and never overlaps an empty cell or the space cut away by bounding planes.
/// Overlap is decided independently of the builder's clipping, with a separating-axis
/// triangle/box test in double precision. Throws FormatError naming the triangle and cell.
/// Cost: one descent per triangle through the cells its bounding box touches.
/// Precondition: check_invariants(grid) passes and mesh has grid.triangle_count triangles.
void check_coverage(const SplitGrid& grid, const MeshView& mesh);

}  // namespace sg
