#include "splitgrid/formats/mesh_import.hpp"

#include <string>
#include <vector>

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

std::vector<std::string> import_warnings(const std::filesystem::path& path,
                                         const ImportReport& report)
{
    const std::string name = path.string();
    std::vector<std::string> warnings = report.warnings;
    if (report.points_skipped != 0 || report.lines_skipped != 0)
        warnings.push_back(name + ": skipped " + std::to_string(report.points_skipped) +
                           " point and " + std::to_string(report.lines_skipped) +
                           " line primitives (not triangles)");
    if (report.nonfinite_dropped != 0)
        warnings.push_back(name + ": dropped " + std::to_string(report.nonfinite_dropped) +
                           " triangles with NaN or infinite corners");
    if (report.degenerate_dropped != 0)
        warnings.push_back(name + ": dropped " + std::to_string(report.degenerate_dropped) +
                           " zero-area triangles");
    return warnings;
}

}  // namespace sg
