#include "vtk_blocks.hpp"

#include <array>
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <string>
#include <variant>

#include "splitgrid/build_config.hpp"
#include "splitgrid/version.hpp"
#include "vtk_arrays.hpp"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkFloatArray.h>
#include <vtkIdTypeArray.h>
#include <vtkPoints.h>
#include <vtkStringArray.h>
#include <vtkTypeInt32Array.h>
#include <vtkTypeInt64Array.h>

namespace sg::viz::detail {
namespace {

/// Points of `count` cells of `corners` corners each, filled by the caller, and the cells
/// that use them: cell c is points corners*c .. corners*c + corners - 1, so no two cells
/// share a point (ParaView would otherwise hide the faces between neighbouring cells).
struct OwnPointCells {
    vtkSmartPointer<vtkFloatArray> coordinates;
    vtkSmartPointer<vtkCellArray> cells;

    OwnPointCells(vtkIdType count, vtkIdType corners)
    {
        coordinates = vtkSmartPointer<vtkFloatArray>::New();
        coordinates->SetNumberOfComponents(3);
        coordinates->SetNumberOfTuples(count * corners);
        auto connectivity = vtkSmartPointer<vtkIdTypeArray>::New();
        connectivity->SetNumberOfTuples(count * corners);
        for (vtkIdType i = 0; i < count * corners; ++i) connectivity->SetValue(i, i);
        cells = vtkSmartPointer<vtkCellArray>::New();
        cells->SetData(corners, connectivity);
    }
    void set_point(vtkIdType index, float x, float y, float z)
    {
        const std::array<float, 3> p{x, y, z};
        coordinates->SetTypedTuple(index, p.data());
    }
    [[nodiscard]] vtkSmartPointer<vtkPoints> points() const
    {
        auto points = vtkSmartPointer<vtkPoints>::New();
        points->SetData(coordinates);
        return points;
    }
};

/// The 8 corners of `box` in VTK_HEXAHEDRON order: the bottom face (lower z) counter-
/// clockwise seen from above, starting at the lower x, y corner, then the top face likewise.
void set_hexahedron(OwnPointCells& out, vtkIdType cell, const Aabb& box)
{
    const Vec3f& l = box.lower;
    const Vec3f& u = box.upper;
    const vtkIdType p = cell * 8;
    out.set_point(p + 0, l.x, l.y, l.z);
    out.set_point(p + 1, u.x, l.y, l.z);
    out.set_point(p + 2, u.x, u.y, l.z);
    out.set_point(p + 3, l.x, u.y, l.z);
    out.set_point(p + 4, l.x, l.y, u.z);
    out.set_point(p + 5, u.x, l.y, u.z);
    out.set_point(p + 6, u.x, u.y, u.z);
    out.set_point(p + 7, l.x, u.y, u.z);
}

/// The 4 corners of a flat box (zero extent on `axis`) around its rectangle.
void set_quad(OwnPointCells& out, vtkIdType cell, const Aabb& quad, int axis)
{
    const int a1 = (axis + 1) % 3;
    const int a2 = (axis + 2) % 3;
    const std::array<std::array<bool, 2>, 4> corners{{{false, false},
                                                      {true, false},
                                                      {true, true},
                                                      {false, true}}};
    for (std::size_t k = 0; k < corners.size(); ++k) {
        Vec3f p = quad.lower;
        p[a1] = corners[k][0] ? quad.upper[a1] : quad.lower[a1];
        p[a2] = corners[k][1] ? quad.upper[a2] : quad.lower[a2];
        out.set_point(cell * 4 + static_cast<vtkIdType>(k), p.x, p.y, p.z);
    }
}

}  // namespace

vtkSmartPointer<vtkUnstructuredGrid> make_cell_block(const SplitGrid& grid,
                                                     const Hierarchy& hierarchy,
                                                     const std::vector<std::uint32_t>& nodes,
                                                     const Selection& selection,
                                                     CellBlockKind kind, std::uint64_t count)
{
    const vtkIdType n = as_id(count, "export");
    OwnPointCells geometry(n, 8);
    auto depth = named_array<vtkTypeInt32Array>("depth", n);
    auto node_id = named_array<vtkTypeInt64Array>("node_id", n);
    auto cell_index = named_array<vtkTypeInt32Array>("cell_index", n);
    auto axis = named_array<vtkTypeInt32Array>("axis", n);
    auto kind_array = named_array<vtkTypeInt32Array>("kind", n);
    auto triangle_count = named_array<vtkTypeInt64Array>("triangle_count", n);
    auto cost_share = named_array<vtkDoubleArray>("cost_share", n);

    vtkIdType c = 0;
    for_each_cell(grid, hierarchy, nodes, selection, [&](const CellRecord& r) {
        if (kind == CellBlockKind::leaves_only && r.kind != CellKind::Leaf) return;
        if (c >= n) throw std::logic_error("export: more cells than counted");
        set_hexahedron(geometry, c, r.box);
        depth->SetValue(c, static_cast<vtkTypeInt32>(r.depth));
        node_id->SetValue(c, r.node_id);
        cell_index->SetValue(c, static_cast<vtkTypeInt32>(r.cell_index));
        axis->SetValue(c, r.axis);
        kind_array->SetValue(c, static_cast<vtkTypeInt32>(r.kind));
        triangle_count->SetValue(c, static_cast<vtkTypeInt64>(r.triangle_count));
        cost_share->SetValue(c, r.cost_share);
        ++c;
    });
    if (c != n) throw std::logic_error("export: fewer cells than counted");

    auto block = vtkSmartPointer<vtkUnstructuredGrid>::New();
    block->SetPoints(geometry.points());
    block->SetCells(VTK_HEXAHEDRON, geometry.cells);
    vtkCellData* data = block->GetCellData();
    data->AddArray(node_id);
    data->AddArray(cell_index);
    data->AddArray(axis);
    data->AddArray(kind_array);
    data->AddArray(triangle_count);
    data->AddArray(cost_share);
    data->SetScalars(depth);
    return block;
}

vtkSmartPointer<vtkPolyData> make_plane_block(const SplitGrid& grid, const Hierarchy& hierarchy,
                                              const std::vector<std::uint32_t>& nodes)
{
    const vtkIdType n = as_id(2 * static_cast<std::uint64_t>(nodes.size()), "export");
    OwnPointCells geometry(n, 4);
    auto depth = named_array<vtkTypeInt32Array>("depth", n);
    auto node_id = named_array<vtkTypeInt64Array>("node_id", n);
    auto side = named_array<vtkTypeInt32Array>("side", n);
    auto axis = named_array<vtkTypeInt32Array>("axis", n);
    auto cut_fraction = named_array<vtkDoubleArray>("cut_fraction", n);

    vtkIdType c = 0;
    for (const std::uint32_t id : nodes)
        for (int s = 0; s < 2; ++s, ++c) {
            const PlaneRecord r = plane_record(grid, hierarchy, id, s);
            set_quad(geometry, c, r.quad, r.axis);
            depth->SetValue(c, static_cast<vtkTypeInt32>(r.depth));
            node_id->SetValue(c, r.node_id);
            side->SetValue(c, r.side);
            axis->SetValue(c, r.axis);
            cut_fraction->SetValue(c, r.cut_fraction);
        }

    auto block = vtkSmartPointer<vtkPolyData>::New();
    block->SetPoints(geometry.points());
    block->SetPolys(geometry.cells);
    vtkCellData* data = block->GetCellData();
    data->AddArray(node_id);
    data->AddArray(side);
    data->AddArray(axis);
    data->AddArray(cut_fraction);
    data->SetScalars(depth);
    return block;
}

vtkSmartPointer<vtkPolyData> make_mesh_block(const SplitGrid& grid, const MeshView& mesh)
{
    const vtkIdType vertices = as_id(mesh.vertices.size(), "export");
    const vtkIdType triangles = as_id(mesh.triangles.size(), "export");

    auto coordinates = vtkSmartPointer<vtkFloatArray>::New();
    coordinates->SetNumberOfComponents(3);
    coordinates->SetNumberOfTuples(vertices);
    for (vtkIdType v = 0; v < vertices; ++v) {
        const Vec3f& p = mesh.vertices[static_cast<std::size_t>(v)];
        const std::array<float, 3> xyz{p.x, p.y, p.z};
        coordinates->SetTypedTuple(v, xyz.data());
    }
    auto points = vtkSmartPointer<vtkPoints>::New();
    points->SetData(coordinates);

    auto connectivity = vtkSmartPointer<vtkIdTypeArray>::New();
    connectivity->SetNumberOfTuples(triangles * 3);
    for (vtkIdType t = 0; t < triangles; ++t)
        for (int k = 0; k < 3; ++k)
            connectivity->SetValue(3 * t + k,
                                   mesh.triangles[static_cast<std::size_t>(t)].v[static_cast<std::size_t>(k)]);
    auto polys = vtkSmartPointer<vtkCellArray>::New();
    polys->SetData(3, connectivity);

    auto reference_count = named_array<vtkTypeInt64Array>("reference_count", triangles);
    reference_count->FillValue(0);
    (void)for_each_leaf(grid.leaf_words,
                        [&](std::size_t, std::size_t, std::span<const std::uint32_t> ids) {
                            for (const std::uint32_t id : ids) {
                                const auto t = static_cast<vtkIdType>(id);
                                if (t < triangles)
                                    reference_count->SetValue(t, reference_count->GetValue(t) + 1);
                            }
                        });

    auto block = vtkSmartPointer<vtkPolyData>::New();
    block->SetPoints(points);
    block->SetPolys(polys);
    block->GetCellData()->SetScalars(reference_count);
    return block;
}

void add_field_data(vtkDataObject& block, const FieldFacts& facts)
{
    const SplitGrid& grid = *facts.grid;
    const BuildConfig& c = grid.config;
    const ExportOptions& o = *facts.options;
    vtkFieldData& f = *block.GetFieldData();
    add_string_field(f, "source_name", facts.metadata->source_name);
    add_string_field(f, "structure_name", facts.metadata->structure_name);
    add_string_field(f, "splitgrid_version", version_string);

    // One build_<field> per BuildConfig field (build_config_fields): counts and switches
    // (0 or 1) as integers, reals as doubles. The thread count is left out: it does not
    // change the grid and is not kept in it.
    for (const BuildConfigField& field : build_config_fields) {
        if (field.name == "threads") continue;
        const std::string name = "build_" + std::string(field.name);
        if (const auto* real = std::get_if<BuildConfigField::RealMember>(&field.member))
            add_field<vtkDoubleArray>(f, name.c_str(), c.**real);
        else if (const auto* count = std::get_if<BuildConfigField::CountMember>(&field.member))
            add_field<vtkTypeInt64Array>(f, name.c_str(), c.**count);
        else
            add_field<vtkTypeInt64Array>(
                f, name.c_str(), c.*std::get<BuildConfigField::SwitchMember>(field.member) ? 1 : 0);
    }

    add_field<vtkTypeInt64Array>(f, "grid_triangle_count", grid.triangle_count);
    add_field<vtkTypeInt64Array>(f, "grid_node_count", static_cast<vtkTypeInt64>(grid.nodes.size()));
    add_field<vtkTypeInt64Array>(f, "grid_cell_count",
                                 static_cast<vtkTypeInt64>(grid.cell_count()));
    add_field<vtkTypeInt64Array>(f, "grid_reference_count",
                                 static_cast<vtkTypeInt64>(reference_count(grid)));
    add_field<vtkDoubleArray>(f, "grid_expected_cost", facts.expected_cost);

    // -1 stands for "no limit" / "whole structure".
    const bool depth_limited = o.max_depth != std::numeric_limits<std::uint32_t>::max();
    add_field<vtkTypeInt64Array>(f, "export_min_depth", o.min_depth);
    add_field<vtkTypeInt64Array>(f, "export_max_depth",
                                 depth_limited ? static_cast<vtkTypeInt64>(o.max_depth) : -1);
    add_field<vtkTypeInt64Array>(f, "export_subtree",
                                 o.subtree ? static_cast<vtkTypeInt64>(*o.subtree) : -1);
    add_field<vtkTypeInt64Array>(f, "export_empty_cells", o.empty_cells ? 1 : 0);
}

}  // namespace sg::viz::detail
