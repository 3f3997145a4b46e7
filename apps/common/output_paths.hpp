#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "splitgrid/formats/output_file.hpp"

/// Checks of a tool's output paths against the file system and against its inputs, made
/// before the long work starts. Each refusal is an sg::IoError (exit code 2) naming the
/// paths.
namespace sg::apps {

/// Refuses an output path whose folder does not exist or that names a folder. Creates
/// nothing. (Whether the folder can be written is found by reserving the output:
/// sg::OutputFile creates its temporary file at once.)
void check_output_path(const std::filesystem::path& path);

/// Refuses `output` when it is the same file as one of `inputs`: the same path or another
/// name of it (a hard or symbolic link), "r.bin: refusing to write the output over the input
/// r.bin". With `read_by` the inputs are files that input pulls in (a glTF's .bin, an OBJ's
/// .mtl): "m.bin: refusing to write the output over m.bin, which the input m.gltf reads".
/// Inputs or an output that do not exist are never the same file.
void refuse_output_over_input(const std::filesystem::path& output,
                              const std::vector<std::filesystem::path>& inputs,
                              const std::filesystem::path& read_by = {});

/// The same for an output folder that replaces everything in it (sg-export --force): also
/// refuses a folder that holds one of `inputs` at any depth, "out: refusing to replace the
/// folder, it holds the input out/a.sg".
void refuse_folder_over_input(const std::filesystem::path& folder,
                              const std::vector<std::filesystem::path>& inputs);

/// check_output_path, then reserves the output (sg::OutputFile creates its temporary file
/// now, so a folder that cannot be written is refused before the work), and reports each
/// temporary of a killed run that it removed as a warning.
[[nodiscard]] std::unique_ptr<OutputFile> reserve_output(const std::filesystem::path& path);

/// An output folder for several files (sg-bench's results): created if missing, and removed
/// again, if this run created it and it is still empty, on destruction before keep() and on
/// an interrupt. Throws IoError naming the folder if it cannot be created.
class OutputFolder {
public:
    explicit OutputFolder(std::filesystem::path folder);
    ~OutputFolder();
    OutputFolder(const OutputFolder&) = delete;
    OutputFolder& operator=(const OutputFolder&) = delete;

    /// The files are written: the folder stays.
    void keep() noexcept;

private:
    std::filesystem::path folder_;
    bool created_ = false;
    CleanupEntry cleanup_;
};

/// Logs one warning per temporary file or staging folder of a killed run that was removed:
/// "removed .a.sg.tmp-1234-..., left behind by a run that was killed".
void report_stale_removed(const std::vector<std::filesystem::path>& removed);

/// The paths in `files` as filesystem paths (ImportReport::opened_files).
[[nodiscard]] std::vector<std::filesystem::path> as_paths(const std::vector<std::string>& files);

}  // namespace sg::apps
