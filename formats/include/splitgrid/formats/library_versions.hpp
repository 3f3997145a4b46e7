#pragma once

#include <string>
#include <vector>

namespace sg {

/// A library a tool links, and its version (as the library reports it at run time where it
/// can, so that --version names what is really loaded).
struct LibraryVersion {
    std::string name;
    std::string version;
};

/// The libraries behind splitgrid_formats: Assimp (mesh import) and zlib (CRC-32).
[[nodiscard]] std::vector<LibraryVersion> formats_library_versions();

}  // namespace sg
