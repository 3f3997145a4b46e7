// Writes the seed corpora of the fuzz targets into a folder:
//   <out>/sg_reader/*.sg     small valid .sg files (empty, one triangle, a cube, a box of
//                            random triangles, copies of one triangle)
//   <out>/build_trace/*.bin  the same meshes in the build-and-trace layout with a few rays
// Generated rather than committed, so they always follow the current .sg format.

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "fuzz_mesh_input.hpp"
#include "splitgrid/builder.hpp"
#include "splitgrid/formats/sg_file.hpp"
#include "support/random_scene.hpp"

namespace {

namespace fs = std::filesystem;

void write_file(const fs::path& path, const std::vector<std::uint8_t>& bytes)
{
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()),
              static_cast<std::streamsize>(bytes.size()));
    if (!out) throw std::runtime_error("cannot write " + path.string());
}

sg::Mesh one_triangle()
{
    return {{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {sg::Triangle{{0, 1, 2}}}};
}

/// The unit cube's 12 triangles, faces on the planes 0 and 1 (which cells share).
sg::Mesh cube()
{
    sg::Mesh m;
    for (int i = 0; i < 8; ++i)
        m.vertices.push_back({float(i & 1), float((i >> 1) & 1), float((i >> 2) & 1)});
    const std::uint32_t quads[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1},
                                       {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}};
    for (const auto& q : quads) {
        m.triangles.push_back({{q[0], q[1], q[2]}});
        m.triangles.push_back({{q[0], q[2], q[3]}});
    }
    return m;
}

/// Ten copies of one triangle: the builder must stop splitting them.
sg::Mesh copies()
{
    sg::Mesh m = one_triangle();
    for (int i = 1; i < 10; ++i) m.triangles.push_back(m.triangles.front());
    return m;
}

std::vector<std::pair<std::string, sg::Mesh>> seed_meshes()
{
    return {{"empty", sg::Mesh{}},
            {"one_triangle", one_triangle()},
            {"cube", cube()},
            {"copies", copies()},
            {"random40", sg::test::random_triangles(7, 40, {{-4, -4, -4}, {4, 4, 4}}, 2.0f)},
            {"plane", sg::test::axis_plane(2, 0.5f, 4)}};
}

}  // namespace

int main(int argc, char** argv)
{
    if (argc != 2) {
        std::fprintf(stderr, "usage: %s OUT_DIR\n", argv[0]);
        return 1;
    }
    const fs::path out = argv[1];
    fs::create_directories(out / "sg_reader");
    fs::create_directories(out / "build_trace");
    // Config bytes (fuzz_mesh_input.hpp): defaults-like, and a finer one with small leaves and
    // the cost rule off (its width byte 0 decodes to min_cell_width 1/32: the decoder keeps
    // the cap on when the cost rule is off).
    const std::uint8_t default_like[8] = {1, 62, 191, 7, 32, 229, 32, 1};
    const std::uint8_t fine[8] = {3, 30, 3, 1, 12, 240, 0, 0};
    for (const auto& [name, mesh] : seed_meshes()) {
        const sg::SplitGrid grid = sg::build_split_grid(mesh.view(), sg::BuildConfig{});
        write_file(out / "sg_reader" / (name + ".sg"), sg::encode_sg({mesh, grid, name}));
        const std::vector<sg::Ray> rays =
            sg::test::random_rays(11, 4, {{-2, -2, -2}, {2, 2, 2}});
        write_file(out / "build_trace" / (name + ".bin"),
                   sg::fuzz::encode_mesh_case(default_like, mesh, rays));
        write_file(out / "build_trace" / (name + "_fine.bin"),
                   sg::fuzz::encode_mesh_case(fine, mesh, rays));
    }
    return 0;
}
