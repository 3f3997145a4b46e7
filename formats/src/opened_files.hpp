#pragma once

#include <string>
#include <vector>

namespace Assimp {
class Importer;
}

namespace sg::detail {

/// Gives `importer` a file system that works like Assimp's default one and also records the
/// path of every file it opens: the mesh itself and what the mesh pulls in (a glTF's .bin
/// buffers, an OBJ's .mtl library), as Assimp spelled the paths. The tools compare their
/// outputs with these files (ImportReport::opened_files). The list lives as long as the
/// importer.
[[nodiscard]] const std::vector<std::string>& record_opened_files(Assimp::Importer& importer);

}  // namespace sg::detail
