#include "splitgrid/viz/image_field.hpp"

#include <cmath>
#include <limits>
#include <string>

#include "splitgrid/error.hpp"
#include "splitgrid/formats/output_file.hpp"
#include "vtk_arrays.hpp"
#include "xml_writing.hpp"

#include <vtkDoubleArray.h>
#include <vtkFloatArray.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkTypeInt64Array.h>
#include <vtkXMLImageDataWriter.h>

namespace sg::viz {
namespace {

/// Refuses what would make a wrong or unreadable file, before anything is written.
void check_field(const std::string& target, const ImageField& field)
{
    const ImageGeometry& g = field.geometry;
    for (int a = 0; a < 3; ++a) {
        if (g.dimensions[a] < 1 ||
            g.dimensions[a] > static_cast<std::uint32_t>(std::numeric_limits<int>::max()))
            throw ConfigError(target + ": image dimension " + std::to_string(a) + " is " +
                              std::to_string(g.dimensions[a]) + ", expected 1 to 2^31 - 1");
        if (!std::isfinite(g.origin[a]) || !std::isfinite(g.spacing[a]) || !(g.spacing[a] > 0.0))
            throw ConfigError(target + ": image origin or spacing on axis " + std::to_string(a) +
                              " is not finite, or the spacing is not positive");
    }
    if (field.floats.empty())
        throw ConfigError(target + ": an image field needs at least one float array");
    const std::uint64_t points = g.point_count();
    for (const FloatPointArray& a : field.floats)
        if (a.components < 1 ||
            a.values.size() != points * static_cast<std::uint64_t>(a.components))
            throw ConfigError(target + ": array " + a.name + " holds " +
                              std::to_string(a.values.size()) + " values for " +
                              std::to_string(points) + " points of " +
                              std::to_string(a.components) + " component(s)");
    for (const IdPointArray& a : field.ids)
        if (a.values.size() != points)
            throw ConfigError(target + ": array " + a.name + " holds " +
                              std::to_string(a.values.size()) + " values for " +
                              std::to_string(points) + " points");
}

// VTK's arrays take a non-const pointer: save = 1 tells them not to free it, and the writer
// only reads, so the caller's arrays are written without a copy (a field of 64 million points
// would otherwise hold its answers twice).
vtkSmartPointer<vtkFloatArray> wrap(const FloatPointArray& a)
{
    auto array = vtkSmartPointer<vtkFloatArray>::New();
    array->SetName(a.name.c_str());
    array->SetNumberOfComponents(a.components);
    array->SetArray(const_cast<float*>(a.values.data()),
                    detail::as_id(a.values.size(), a.name.c_str()), 1);
    return array;
}

vtkSmartPointer<vtkTypeInt64Array> convert(const IdPointArray& a)
{
    auto array = detail::named_array<vtkTypeInt64Array>(a.name.c_str(),
                                                        detail::as_id(a.values.size(),
                                                                      a.name.c_str()));
    for (std::size_t i = 0; i < a.values.size(); ++i)
        array->SetValue(static_cast<vtkIdType>(i),
                        a.values[i] == 0xFFFFFFFFu ? -1 : static_cast<vtkTypeInt64>(a.values[i]));
    return array;
}

}  // namespace

void write_image_field(OutputFile& output, const ImageField& field)
{
    const std::string target = output.target().string();
    check_field(target, field);
    const ImageGeometry& g = field.geometry;
    vtkNew<vtkImageData> image;
    image->SetDimensions(static_cast<int>(g.dimensions[0]), static_cast<int>(g.dimensions[1]),
                         static_cast<int>(g.dimensions[2]));
    image->SetOrigin(g.origin.data());
    image->SetSpacing(g.spacing.data());
    vtkPointData& point_data = *image->GetPointData();
    for (const FloatPointArray& a : field.floats) point_data.AddArray(wrap(a));
    for (const IdPointArray& a : field.ids) point_data.AddArray(convert(a));
    point_data.SetActiveScalars(field.floats.front().name.c_str());
    vtkFieldData& facts = *image->GetFieldData();
    for (const auto& [name, text] : field.text_facts)
        detail::add_string_field(facts, name.c_str(), text);
    for (const auto& [name, number] : field.number_facts)
        detail::add_field<vtkDoubleArray>(facts, name.c_str(), number);

    vtkNew<vtkXMLImageDataWriter> writer;
    writer->SetInputData(image);
    writer->SetFileName(output.temporary_path().c_str());
    detail::write_xml(*writer, target + ": writing the VTK image data failed, nothing was "
                                        "written");
    output.commit_written();
}

}  // namespace sg::viz
