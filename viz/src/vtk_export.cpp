#include "splitgrid/viz/vtk_export.hpp"

#include <algorithm>
#include <cstddef>
#include <string>
#include <vector>

#include "hierarchy.hpp"
#include "selection.hpp"
#include "staged_folder.hpp"
#include "vtk_blocks.hpp"
#include "xml_writing.hpp"

#include <vtkCompositeDataSet.h>
#include <vtkDataSet.h>
#include <vtkInformation.h>
#include <vtkMultiBlockDataSet.h>
#include <vtkNew.h>
#include <vtkXMLMultiBlockDataWriter.h>

namespace sg::viz {
namespace {

namespace fs = std::filesystem;
using detail::Hierarchy;
using detail::Selection;

constexpr std::size_t max_name_length = 100;

bool is_name_char(char c) noexcept
{
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
           c == '_' || c == '-' || c == '.';
}

void check_name(const std::string& name)
{
    if (name.empty() || name.size() > max_name_length || name.front() == '.' ||
        !std::all_of(name.begin(), name.end(), is_name_char))
        throw ConfigError("export name \"" + name +
                          "\" must be 1 to 100 letters, digits, '_', '-' or '.', not starting "
                          "with '.'");
}

/// Everything the counting pass finds, kept for the writing pass.
struct Plan {
    Hierarchy hierarchy;
    Selection selection;
    std::vector<std::uint32_t> nodes;
    ExportCounts counts;
};

Plan make_plan(const SplitGrid& grid, const MeshView& mesh, const ExportOptions& options)
{
    check_name(options.name);
    if (options.min_depth > options.max_depth)
        throw ConfigError("minimum depth " + std::to_string(options.min_depth) +
                          " is above the maximum depth " + std::to_string(options.max_depth));
    Plan plan;
    plan.hierarchy = detail::analyse_hierarchy(grid);
    plan.selection = {options.min_depth, options.max_depth, options.subtree, options.empty_cells};
    plan.nodes = detail::selected_nodes(grid, plan.hierarchy, plan.selection);

    const ExportParts& parts = options.parts;
    ExportCounts& counts = plan.counts;
    std::vector<std::uint64_t> per_depth;
    const auto add = [&](std::uint32_t depth, std::uint64_t primitives) {
        if (per_depth.size() <= depth) per_depth.resize(depth + 1, 0);
        per_depth[depth] += primitives;
    };
    detail::for_each_cell(grid, plan.hierarchy, plan.nodes, plan.selection,
                          [&](const detail::CellRecord& r) {
                              const bool leaf = r.kind == CellKind::Leaf;
                              counts.cells += parts.cells ? 1 : 0;
                              counts.leaves += parts.leaves && leaf ? 1 : 0;
                              add(r.depth, (parts.cells ? 1 : 0) + (parts.leaves && leaf ? 1 : 0));
                          });
    for (const std::uint32_t id : plan.nodes)
        if (parts.planes) {
            counts.planes += 2;
            add(plan.hierarchy.nodes[id].depth, 2);
        }
    counts.selected_nodes = plan.nodes.size();
    counts.mesh_triangles = parts.mesh ? mesh.triangles.size() : 0;
    // Cumulative: primitives_by_max_depth[d] counts everything selected down to depth d.
    std::uint64_t running = 0;
    for (const std::uint64_t primitives : per_depth) {
        running += primitives;
        counts.primitives_by_max_depth.push_back(running);
    }
    return plan;
}

/// Every file under `folder`, the .vtm files first, with their sizes.
std::vector<ExportedFile> list_files(const fs::path& folder)
{
    std::vector<ExportedFile> files;
    for (const fs::directory_entry& entry : fs::recursive_directory_iterator(folder))
        if (entry.is_regular_file()) files.push_back({entry.path(), entry.file_size()});
    std::sort(files.begin(), files.end(), [](const ExportedFile& a, const ExportedFile& b) {
        const bool a_vtm = a.path.extension() == ".vtm";
        const bool b_vtm = b.path.extension() == ".vtm";
        return a_vtm != b_vtm ? a_vtm : a.path < b.path;
    });
    return files;
}

/// Writes `blocks` to `vtm_path`; a failure is reported as an IoError about `out_dir` (the
/// folder the user named, not the staging folder).
void write_multiblock(vtkMultiBlockDataSet& blocks, const fs::path& vtm_path,
                      const fs::path& out_dir)
{
    vtkNew<vtkXMLMultiBlockDataWriter> writer;
    writer->SetInputData(&blocks);
    writer->SetFileName(vtm_path.c_str());
    detail::write_xml(*writer, out_dir.string() + ": writing the export failed, nothing was "
                                                  "written");
}

}  // namespace

std::string export_name_for(const fs::path& file)
{
    std::string name = file.stem().string();
    std::replace_if(name.begin(), name.end(), [](char c) { return !is_name_char(c); }, '_');
    name.erase(0, name.find_first_not_of('.'));
    if (name.size() > max_name_length) name.resize(max_name_length);
    return name.empty() ? "splitgrid" : name;
}

ExportCounts count_export(const SplitGrid& grid, const MeshView& mesh,
                          const ExportOptions& options)
{
    return make_plan(grid, mesh, options).counts;
}

ExportSummary export_vtk(const SplitGrid& grid, const MeshView& mesh,
                         const ExportOptions& options, const ExportMetadata& metadata,
                         const fs::path& out_dir)
{
    ExportFolder folder(out_dir, options.replace_existing);
    return export_vtk(grid, mesh, options, metadata, folder);
}

ExportFolder::ExportFolder(const fs::path& out_dir, bool replace_existing)
    : out_dir_(out_dir), replace_existing_(replace_existing),
      staged_(std::make_unique<detail::StagedFolder>(out_dir, replace_existing))
{
}

ExportFolder::~ExportFolder() = default;

const std::vector<fs::path>& ExportFolder::stale_removed() const noexcept
{
    return staged_->stale_removed();
}

ExportSummary export_vtk(const SplitGrid& grid, const MeshView& mesh,
                         const ExportOptions& options, const ExportMetadata& metadata,
                         ExportFolder& folder)
{
    if (options.replace_existing != folder.replace_existing())
        throw ConfigError(folder.path().string() + ": the export folder was reserved with a "
                                                   "different replace_existing");
    Plan plan = make_plan(grid, mesh, options);
    const ExportCounts& counts = plan.counts;
    if (options.primitive_limit != 0 && counts.primitives() > options.primitive_limit)
        throw ExportLimitError("the selection holds " + std::to_string(counts.primitives()) +
                                   " cells and planes, more than the limit of " +
                                   std::to_string(options.primitive_limit),
                               counts, options.primitive_limit);
    const fs::path& out_dir = folder.path();
    detail::StagedFolder& staged = folder.staged();

    const detail::FieldFacts facts{&grid, &metadata, &options, plan.hierarchy.total_cost};
    vtkNew<vtkMultiBlockDataSet> blocks;
    unsigned int index = 0;
    const auto add_block = [&](vtkDataSet* block, const char* name) {
        // VTK's composite writer drops an empty data set and leaves an unnamed hole in the
        // block list; leaving the block out keeps the names and indices of the others plain.
        if (block->GetNumberOfCells() == 0) return;
        detail::add_field_data(*block, facts);
        blocks->SetBlock(index, block);
        blocks->GetMetaData(index)->Set(vtkCompositeDataSet::NAME(), name);
        ++index;
    };
    const ExportParts& parts = options.parts;
    if (parts.cells)
        add_block(detail::make_cell_block(grid, plan.hierarchy, plan.nodes, plan.selection,
                                          detail::CellBlockKind::all_exported, counts.cells),
                  "cells");
    if (parts.planes)
        add_block(detail::make_plane_block(grid, plan.hierarchy, plan.nodes), "planes");
    if (parts.leaves)
        add_block(detail::make_cell_block(grid, plan.hierarchy, plan.nodes, plan.selection,
                                          detail::CellBlockKind::leaves_only, counts.leaves),
                  "leaves");
    if (parts.mesh) add_block(detail::make_mesh_block(grid, mesh), "mesh");

    write_multiblock(*blocks, staged.path() / (options.name + ".vtm"), out_dir);
    staged.commit();

    ExportSummary summary;
    summary.counts = counts;
    summary.vtm_path = out_dir / (options.name + ".vtm");
    summary.files = list_files(out_dir);
    for (const ExportedFile& file : summary.files) summary.total_bytes += file.bytes;
    return summary;
}

}  // namespace sg::viz
