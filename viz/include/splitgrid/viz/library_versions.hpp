#pragma once

#include <vector>

#include "splitgrid/formats/library_versions.hpp"

namespace sg::viz {

/// The library behind splitgrid_viz: VTK (image writers, the ParaView export), as loaded.
[[nodiscard]] std::vector<LibraryVersion> viz_library_versions();

}  // namespace sg::viz
