#include "splitgrid/formats/library_versions.hpp"

#include <assimp/version.h>
#include <zlib.h>

namespace sg {

std::vector<LibraryVersion> formats_library_versions()
{
    const std::string assimp = std::to_string(aiGetVersionMajor()) + "." +
                               std::to_string(aiGetVersionMinor()) + "." +
                               std::to_string(aiGetVersionPatch());
    return {{"Assimp", assimp}, {"zlib", zlibVersion()}};
}

}  // namespace sg
