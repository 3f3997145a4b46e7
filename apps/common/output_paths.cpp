#include "output_paths.hpp"

#include <algorithm>
#include <system_error>

#include "splitgrid/error.hpp"

#include <spdlog/spdlog.h>

namespace sg::apps {
namespace {

namespace fs = std::filesystem;

bool same_file(const fs::path& a, const fs::path& b)
{
    std::error_code ec;
    return fs::equivalent(a, b, ec) && !ec;
}

/// Whether `inner` lies in `folder` (at any depth), comparing the paths with every symbolic
/// link resolved.
bool is_inside(const fs::path& inner, const fs::path& folder)
{
    std::error_code ec;
    const fs::path f = fs::canonical(folder, ec);
    if (ec) return false;
    const fs::path i = fs::weakly_canonical(inner, ec);
    if (ec) return false;
    const auto [end_of_folder, at] = std::mismatch(f.begin(), f.end(), i.begin(), i.end());
    return end_of_folder == f.end();
}

}  // namespace

void check_output_path(const fs::path& path)
{
    std::error_code ec;
    if (fs::is_directory(path, ec))
        throw IoError(path.string() + ": is a directory, expected a file name");
    const fs::path folder = path.has_parent_path() ? path.parent_path() : fs::path(".");
    if (!fs::is_directory(folder, ec))
        throw IoError(path.string() + ": folder " + folder.string() + " does not exist");
}

void refuse_output_over_input(const fs::path& output, const std::vector<fs::path>& inputs,
                              const fs::path& read_by)
{
    for (const fs::path& input : inputs) {
        if (!same_file(output, input)) continue;
        if (read_by.empty())
            throw IoError(output.string() + ": refusing to write the output over the input " +
                          input.string());
        throw IoError(output.string() + ": refusing to write the output over " +
                      input.string() + ", which the input " + read_by.string() + " reads");
    }
}

void refuse_folder_over_input(const fs::path& folder, const std::vector<fs::path>& inputs)
{
    refuse_output_over_input(folder, inputs);
    for (const fs::path& input : inputs)
        if (is_inside(input, folder))
            throw IoError(folder.string() + ": refusing to replace the folder, it holds the "
                                            "input " +
                          input.string());
}

std::unique_ptr<OutputFile> reserve_output(const fs::path& path)
{
    check_output_path(path);
    auto output = std::make_unique<OutputFile>(path);
    report_stale_removed(output->stale_removed());
    return output;
}

OutputFolder::OutputFolder(fs::path folder) : folder_(std::move(folder))
{
    std::error_code ec;
    if (fs::is_directory(folder_, ec)) return;
    cleanup_ = CleanupEntry::empty_folder(folder_);
    if (!fs::create_directory(folder_, ec) || ec)
        throw IoError(folder_.string() + ": cannot create the folder: " +
                      (ec ? ec.message() : std::string("it exists and is not a folder")));
    created_ = true;
}

OutputFolder::~OutputFolder()
{
    if (!created_) return;
    std::error_code ec;
    fs::remove(folder_, ec);  // only an empty folder: remove() does not recurse
}

void OutputFolder::keep() noexcept
{
    created_ = false;
    cleanup_.release();
}

void report_stale_removed(const std::vector<fs::path>& removed)
{
    for (const fs::path& path : removed)
        spdlog::warn("removed {}, left behind by a run that was killed", path.string());
}

std::vector<fs::path> as_paths(const std::vector<std::string>& files)
{
    return {files.begin(), files.end()};
}

}  // namespace sg::apps
