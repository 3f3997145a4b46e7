#pragma once

#include <filesystem>
#include <functional>

#include "splitgrid/formats/mesh_import.hpp"

namespace sg::detail {

/// Runs `import` in a forked child process under the limits of `options` and returns what it
/// returned, read back through a pipe. The child's exceptions come back as the same kind
/// (InputError, IoError, std::bad_alloc as a memory-limit InputError, anything else as
/// InputError); a child killed by a signal, one that exceeds the time limit and one that
/// exits without a complete answer each become an InputError "<path>: <reason>". Whatever
/// the child writes to stdout or stderr is captured; its last line is quoted in a crash
/// message (for example Assimp's failed assertion). Throws IoError if the pipes or the
/// process cannot be created.
[[nodiscard]] ImportedMesh import_in_child(const std::filesystem::path& path,
                                           const ImportOptions& options,
                                           const std::function<ImportedMesh()>& import);

}  // namespace sg::detail
