#pragma once

#include <filesystem>

#include "splitgrid/formats/mesh_import.hpp"

namespace sg::detail {

/// The import itself, in the calling process: everything import_mesh() documents except the
/// process isolation. Throws std::bad_alloc when Assimp runs out of memory.
[[nodiscard]] ImportedMesh import_mesh_in_process(const std::filesystem::path& path);

}  // namespace sg::detail
