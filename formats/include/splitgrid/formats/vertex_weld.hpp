#pragma once

#include <cstddef>

#include "splitgrid/mesh.hpp"

namespace sg {

/// What weld_identical_vertices() did.
struct WeldReport {
    std::size_t vertices_before = 0;  ///< vertices referenced by a triangle before welding
    std::size_t vertices_after = 0;   ///< vertices left: one per distinct bit pattern
};

/// Merges the vertices whose positions are bit-identical (the three float32 bit patterns are
/// equal) into one, and removes the vertices no triangle references. Only vertex indices
/// change: triangles keep their order and their corners' exact positions, so a ray hits the
/// welded mesh exactly as it hits the input (same triangle id, t, u and v).
/// Bit-identical, not within a tolerance: -0.0 and +0.0 stay two vertices (merging them would
/// change a corner's bits, and with them possibly the sign of a zero in a hit's t, u or v;
/// keeping both costs a few vertices on the planes x, y or z = 0 at most), and NaN
/// vertices are welded only with the same NaN bit pattern (import_mesh() drops triangles with
/// non-finite corners before it welds, so none are left there). The kept vertices are in the
/// order of their first occurrence in the input vertex array (the lowest index with that
/// position that a triangle references), so a mesh without duplicates keeps its order.
/// Throws InputError for a vertex index past the vertex array (clean_mesh drops such
/// triangles). Cost: one pass over the triangles and vertices with a hash table of
/// 2 to 4 four-byte slots per vertex and a four-byte index per vertex.
WeldReport weld_identical_vertices(Mesh& mesh);

}  // namespace sg
