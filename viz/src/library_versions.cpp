#include "splitgrid/viz/library_versions.hpp"

#include <vtkVersion.h>

namespace sg::viz {

std::vector<LibraryVersion> viz_library_versions()
{
    return {{"VTK", vtkVersion::GetVTKVersion()}};
}

}  // namespace sg::viz
