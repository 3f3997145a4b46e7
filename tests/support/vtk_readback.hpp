#pragma once

// Reads an sg-export back with VTK's own XML readers, for the suites that check the files
// (viz, and apps when built with VTK). Header-only: only suites that link VTK include it.

#include <array>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "splitgrid/aabb.hpp"

#include <vtkAbstractArray.h>
#include <vtkCellData.h>
#include <vtkCompositeDataSet.h>
#include <vtkDataArray.h>
#include <vtkDataSet.h>
#include <vtkFieldData.h>
#include <vtkIdList.h>
#include <vtkInformation.h>
#include <vtkMultiBlockDataSet.h>
#include <vtkNew.h>
#include <vtkSmartPointer.h>
#include <vtkStringArray.h>
#include <vtkXMLMultiBlockDataReader.h>

namespace sg::test {

/// One block of an export as read back.
struct ReadBlock {
    std::string name;
    vtkSmartPointer<vtkDataSet> data;
};

/// The blocks of a .vtm file in file order. Throws if the file does not read.
inline std::vector<ReadBlock> read_export(const std::filesystem::path& vtm)
{
    if (!std::filesystem::exists(vtm)) throw std::runtime_error(vtm.string() + ": missing");
    vtkNew<vtkXMLMultiBlockDataReader> reader;
    reader->SetFileName(vtm.c_str());
    reader->Update();
    auto* root = vtkMultiBlockDataSet::SafeDownCast(reader->GetOutputDataObject(0));
    if (root == nullptr) throw std::runtime_error(vtm.string() + ": VTK read nothing");
    std::vector<ReadBlock> blocks;
    for (unsigned int i = 0; i < root->GetNumberOfBlocks(); ++i) {
        ReadBlock block;
        if (root->HasMetaData(i) && root->GetMetaData(i)->Has(vtkCompositeDataSet::NAME()))
            block.name = root->GetMetaData(i)->Get(vtkCompositeDataSet::NAME());
        block.data = vtkDataSet::SafeDownCast(root->GetBlock(i));
        blocks.push_back(block);
    }
    return blocks;
}

/// The block named `name`, or null.
inline vtkDataSet* find_block(const std::vector<ReadBlock>& blocks, const std::string& name)
{
    for (const ReadBlock& b : blocks)
        if (b.name == name) return b.data;
    return nullptr;
}

/// Names of the blocks, in order.
inline std::vector<std::string> block_names(const std::vector<ReadBlock>& blocks)
{
    std::vector<std::string> names;
    for (const ReadBlock& b : blocks) names.push_back(b.name);
    return names;
}

/// The cell-data array `name` of `data` as doubles (exact for integers below 2^53). Throws if
/// it is missing.
inline std::vector<double> cell_values(vtkDataSet* data, const char* name)
{
    vtkDataArray* array = data->GetCellData()->GetArray(name);
    if (array == nullptr) throw std::runtime_error(std::string("no cell array ") + name);
    std::vector<double> values(static_cast<std::size_t>(array->GetNumberOfTuples()));
    for (vtkIdType i = 0; i < array->GetNumberOfTuples(); ++i)
        values[static_cast<std::size_t>(i)] = array->GetComponent(i, 0);
    return values;
}

/// A one-tuple numeric field-data value.
inline double field_number(vtkDataSet* data, const char* name)
{
    vtkDataArray* array = vtkDataArray::SafeDownCast(data->GetFieldData()->GetAbstractArray(name));
    if (array == nullptr) throw std::runtime_error(std::string("no numeric field ") + name);
    return array->GetComponent(0, 0);
}

/// A one-tuple string field-data value.
inline std::string field_string(vtkDataSet* data, const char* name)
{
    auto* array = vtkStringArray::SafeDownCast(data->GetFieldData()->GetAbstractArray(name));
    if (array == nullptr) throw std::runtime_error(std::string("no string field ") + name);
    return array->GetValue(0);
}

/// The points of cell `cell`, in the cell's own order.
inline std::vector<std::array<double, 3>> cell_points(vtkDataSet* data, vtkIdType cell)
{
    vtkNew<vtkIdList> ids;
    data->GetCellPoints(cell, ids);
    std::vector<std::array<double, 3>> points(static_cast<std::size_t>(ids->GetNumberOfIds()));
    for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k)
        data->GetPoint(ids->GetId(k), points[static_cast<std::size_t>(k)].data());
    return points;
}

/// The bounding box of cell `cell`'s points, as an Aabb (points are floats in the files).
inline Aabb cell_bounds(vtkDataSet* data, vtkIdType cell)
{
    Aabb box;
    for (const auto& p : cell_points(data, cell))
        box.extend(Vec3f{static_cast<float>(p[0]), static_cast<float>(p[1]),
                         static_cast<float>(p[2])});
    return box;
}

/// The first `bytes` bytes of a file (the XML header of a VTK file is text).
inline std::string file_head(const std::filesystem::path& path, std::size_t bytes = 4096)
{
    std::ifstream in(path, std::ios::binary);
    std::string head(bytes, '\0');
    in.read(head.data(), static_cast<std::streamsize>(bytes));
    head.resize(static_cast<std::size_t>(in.gcount()));
    return head;
}

}  // namespace sg::test
