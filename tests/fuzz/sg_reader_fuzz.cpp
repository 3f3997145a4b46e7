// Fuzz target: the .sg reader (formats/src/sg_file_read.cpp) on arbitrary bytes.
//
// The section checksums are not verified (SgReadOptions::verify_checksums = false): a fuzzer
// cannot forge CRC-32s, and with them on it would never get past the gate to the structure
// checks behind it, which are what protect traversal from a forged file. A file that is
// accepted is then used: its rays are traced, so an accepted structure that is unsafe to
// trace shows up as a sanitizer report or a failed check.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "fuzz_support.hpp"
#include "splitgrid/error.hpp"
#include "splitgrid/formats/sg_file.hpp"
#include "splitgrid/validate.hpp"

namespace {

/// Triangles aimed at by the probe rays; enough to reach every cell of the small files a
/// fuzzer makes, few enough to keep an execution well under a millisecond.
constexpr std::size_t probed_triangles = 32;

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    const std::vector<std::uint8_t> bytes(data, data + size);
    sg::SgReadOptions options;
    options.verify_checksums = false;
    sg::SgContents contents;
    try {
        contents = sg::read_sg_bytes(bytes, "fuzz.sg", options);
    } catch (const sg::FormatError&) {
        return 0;  // refused with a message: the expected outcome for almost every input
    }

    const sg::MeshView mesh = contents.mesh.view();
    const std::vector<sg::Ray> rays =
        sg::fuzz::probe_rays(mesh, contents.grid.root_box, probed_triangles);
    // Any grid the reader accepts must be safe to trace, covering its mesh or not.
    sg::fuzz::require_sound_hits(contents.grid, mesh, rays);
    // A grid that also covers its mesh must answer exactly like brute force.
    bool covers = true;
    try {
        sg::check_coverage(contents.grid, mesh);
    } catch (const sg::FormatError&) {
        covers = false;
    }
    if (covers) sg::fuzz::require_brute_force_agreement(contents.grid, mesh, rays);
    return 0;
}
