#pragma once

#include <filesystem>
#include <string_view>

namespace sg {

class OutputFile;

/// Replaces the file at `path` with `text` atomically: a temporary file in the same folder,
/// flushed and renamed over `path`, so a reader sees the old file or the whole new one, never
/// a partial write. For the tools' reports (sg-bench's JSON and CSV). Throws IoError
/// "<path>: <reason>"; the temporary file is removed first.
void write_text_file(const std::filesystem::path& path, std::string_view text);

/// The same into an output reserved earlier (OutputFile), which it commits.
void write_text_file(OutputFile& output, std::string_view text);

}  // namespace sg
