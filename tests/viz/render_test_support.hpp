#pragma once

// Helpers for the viz suite: small scenes with their grids, and images read back from files
// with VTK's own readers (independent of the writers the library uses).
// Header-only because tests/CMakeLists.txt compiles only tests/viz/*_test.cpp.

#include <cmath>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "splitgrid/camera.hpp"
#include "splitgrid/mesh.hpp"
#include "splitgrid/split_grid.hpp"
#include "splitgrid/viz/image.hpp"
#include "support/oracle.hpp"
#include "support/random_scene.hpp"

#include <vtkImageData.h>
#include <vtkImageReader2.h>
#include <vtkNew.h>
#include <vtkPNGReader.h>
#include <vtkSmartPointer.h>

namespace sg::test {

/// A mesh and its checked grid.
struct Scene {
    Mesh mesh;
    SplitGrid grid;
};

/// A sphere resting above a floor of unit quads, with random triangles around it: curved and
/// flat surfaces, silhouettes, open sky and background in one small scene.
inline Scene sphere_floor_scene()
{
    Scene scene;
    scene.mesh = axis_plane(1, 0.0f, 8);
    append(scene.mesh, uv_sphere({4.0f, 1.5f, 4.0f}, 1.5f, 16, 32));
    append(scene.mesh,
           random_triangles(7, 300, Aabb{{0.5f, 0.2f, 0.5f}, {7.5f, 4.0f, 7.5f}}, 0.6f));
    BuildConfig config;
    config.leaf_size = 2;
    scene.grid = build_checked(scene.mesh, config);
    return scene;
}

/// Reads an image file with `reader` into an RgbImage (rows from the top). Throws if the
/// file has not three 8-bit channels.
inline RgbImage read_with(vtkImageReader2* reader, const std::filesystem::path& path)
{
    if (!reader->CanReadFile(path.c_str()))
        throw std::runtime_error(path.string() + ": the VTK reader does not accept it");
    reader->SetFileName(path.c_str());
    reader->Update();
    vtkImageData* data = reader->GetOutput();
    int dims[3];
    data->GetDimensions(dims);
    if (data->GetNumberOfScalarComponents() != 3 || data->GetScalarType() != VTK_UNSIGNED_CHAR)
        throw std::runtime_error(path.string() + ": expected 8-bit RGB");
    RgbImage image(dims[0], dims[1]);
    const auto* pixels = static_cast<const unsigned char*>(data->GetScalarPointer());
    const auto row_bytes = static_cast<std::size_t>(dims[0]) * 3u;
    // VTK's row 0 is the bottom of the picture.
    for (int y = 0; y < dims[1]; ++y)
        std::memcpy(image.rgb.data() + static_cast<std::size_t>(y) * row_bytes,
                    pixels + static_cast<std::size_t>(dims[1] - 1 - y) * row_bytes, row_bytes);
    return image;
}

inline RgbImage read_png(const std::filesystem::path& path)
{
    vtkNew<vtkPNGReader> reader;
    return read_with(reader, path);
}

/// Relative luminance (Rec. 709) of an sRGB colour, in [0, 1].
inline double luminance(Rgb8 c)
{
    const auto linear = [](std::uint8_t v) {
        const double s = v / 255.0;
        return s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4);
    };
    return 0.2126 * linear(c.r) + 0.7152 * linear(c.g) + 0.0722 * linear(c.b);
}

}  // namespace sg::test
