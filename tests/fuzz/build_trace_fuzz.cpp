// Fuzz target: bytes -> small mesh, build configuration and rays -> cleaned mesh -> Split Grid
// -> traced rays, with every answer compared with brute force over all triangles.
//
// Any disagreement, any grid that breaks its invariants or misses a triangle in a cell it
// overlaps, any file round trip that changes the grid, and any sanitizer report aborts, and
// libFuzzer keeps the input. tests/fuzz/fuzz_mesh_input.hpp gives the byte layout.

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "fuzz_mesh_input.hpp"
#include "fuzz_support.hpp"
#include "splitgrid/builder.hpp"
#include "splitgrid/error.hpp"
#include "splitgrid/formats/sg_file.hpp"
#include "splitgrid/validate.hpp"

namespace {

constexpr std::size_t probed_triangles = 64;

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    sg::fuzz::MeshCase c = sg::fuzz::decode_mesh_case(std::span(data, size));
    // What sg-build does with an imported mesh: drop what cannot be traced.
    (void)sg::clean_mesh(c.mesh);
    const sg::MeshView mesh = c.mesh.view();

    sg::SplitGrid grid;
    try {
        grid = sg::build_split_grid(mesh, c.config);
        sg::check_invariants(grid);
        sg::check_coverage(grid, mesh);
    } catch (const sg::Error& e) {
        // The mesh is clean and the config valid, so the builder must succeed and its grid
        // must pass both checkers.
        sg::fuzz::fail(std::string("build: ") + e.what());
    }

    // The file round trip must give back the same mesh and grid, checksums and all. Compared
    // as bytes, re-encoded: unused vertices may be NaN (clean_mesh keeps them), and NaN != NaN
    // would make operator== report a difference that is not there.
    const std::vector<std::uint8_t> bytes = sg::encode_sg({c.mesh, grid, "fuzz"});
    try {
        if (sg::encode_sg(sg::read_sg_bytes(bytes, "fuzz.sg")) != bytes)
            sg::fuzz::fail("the grid read back from its .sg bytes differs");
    } catch (const sg::Error& e) {
        sg::fuzz::fail(std::string("round trip: ") + e.what());
    }

    std::vector<sg::Ray> rays = sg::fuzz::probe_rays(mesh, grid.root_box, probed_triangles);
    rays.insert(rays.end(), c.rays.begin(), c.rays.end());
    sg::fuzz::require_brute_force_agreement(grid, mesh, rays);
    return 0;
}
