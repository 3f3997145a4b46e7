#pragma once

#include <filesystem>

namespace sg::detail {

/// Refuses, before Assimp sees them, inputs on which Assimp 5.2 is known to loop forever
/// rather than fail. Throws InputError "<path>: <reason>" for such a file, IoError
/// "<path>: cannot open: <reason>" if the file cannot be read; returns otherwise.
///
/// Known case: a PLY file (".ply" extension, or content starting with "ply", which Assimp
/// detects whatever the extension) whose header has no "end_header" line, as in a file cut
/// off inside its header. Assimp's PLY header parser then never reaches end of input.
/// Reads at most the first MiB of the file.
void refuse_known_assimp_hangs(const std::filesystem::path& path);

}  // namespace sg::detail
