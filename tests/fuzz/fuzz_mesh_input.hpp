#pragma once

// The byte layout the build-and-trace fuzz target reads: a build configuration, a small
// indexed mesh and rays, in that order. Decoding never fails: every byte string is some
// case (missing bytes read as zero), so the fuzzer wastes no input. The encoder writes the
// seed corpus in the same layout; keeping both here keeps them in step.
//
//   8 bytes      BuildConfig: resolution_min, resolution_max, resolution_sigma, leaf_size,
//                max_depth, no_progress_fraction, min_cell_width, stop_by_cost (see decode)
//   1 byte       vertex count V (0..255), then V * 3 coordinates
//   1 byte       triangle count T (0..255), then T * 3 index bytes (an index >= V is out of
//                range on purpose: such triangles must be dropped)
//   rest         rays: 1 flag byte (bit 0: a t_min follows, bit 1: a t_max follows), origin
//                and direction (6 coordinates), then the t values
//
// A coordinate is one byte c: c < 0xF8 gives (c - 124) / 4, a small set of values that
// coincide with each other and with cell boundaries; c >= 0xF8 is followed by 4 bytes read
// as a raw float (any bit pattern: NaN, infinities, denormals, huge values).

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "splitgrid/build_config.hpp"
#include "splitgrid/mesh.hpp"
#include "splitgrid/ray.hpp"

namespace sg::fuzz {

struct MeshCase {
    BuildConfig config;
    Mesh mesh;
    std::vector<Ray> rays;
};

/// Reads a case from any bytes (see the layout above). BuildConfig::threads is 1: the result
/// is the same for every thread count, and one thread keeps executions short and reproducible.
[[nodiscard]] MeshCase decode_mesh_case(std::span<const std::uint8_t> bytes);

/// Writes a case in the layout above; coordinates that are one of the small values use one
/// byte, others are written raw. The config bytes are given as they are stored.
/// Precondition: at most 255 vertices and 255 triangles.
[[nodiscard]] std::vector<std::uint8_t> encode_mesh_case(const std::uint8_t (&config)[8],
                                                         const Mesh& mesh,
                                                         const std::vector<Ray>& rays);

}  // namespace sg::fuzz
