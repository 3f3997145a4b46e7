#include "splitgrid/formats/mesh_import.hpp"

#include "import_child.hpp"
#include "mesh_import_assimp.hpp"

namespace sg {

ImportedMesh import_mesh(const std::filesystem::path& path, const ImportOptions& options)
{
    switch (options.isolation) {
    case ImportIsolation::in_process: return detail::import_mesh_in_process(path);
    case ImportIsolation::child_process:
        return detail::import_in_child(path, options,
                                       [&path] { return detail::import_mesh_in_process(path); });
    }
    return detail::import_mesh_in_process(path);
}

}  // namespace sg
