#pragma once

#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>

#include <vtkFieldData.h>
#include <vtkSmartPointer.h>
#include <vtkStringArray.h>
#include <vtkType.h>

/// Small builders of VTK arrays shared by the writers of viz/ (the export's blocks, the image
/// data of point fields).
namespace sg::viz::detail {

/// A new array named `name` with `tuples` tuples (of the array's component count, 1 unless
/// set before filling).
template <class Array>
vtkSmartPointer<Array> named_array(const char* name, vtkIdType tuples)
{
    auto array = vtkSmartPointer<Array>::New();
    array->SetName(name);
    array->SetNumberOfTuples(tuples);
    return array;
}

/// `count` as VTK's index type; throws std::length_error naming `what` beyond its range.
inline vtkIdType as_id(std::uint64_t count, const char* what)
{
    if (count > static_cast<std::uint64_t>(std::numeric_limits<vtkIdType>::max()))
        throw std::length_error(std::string(what) + ": more elements than VTK can index");
    return static_cast<vtkIdType>(count);
}

/// Adds a one-tuple numeric field-data array.
template <class Array, class Value>
void add_field(vtkFieldData& fields, const char* name, Value value)
{
    auto array = named_array<Array>(name, 1);
    array->SetValue(0, value);
    fields.AddArray(array);
}

/// Adds a one-tuple string field-data array.
inline void add_string_field(vtkFieldData& fields, const char* name, const std::string& value)
{
    auto array = vtkSmartPointer<vtkStringArray>::New();
    array->SetName(name);
    array->InsertNextValue(value);
    fields.AddArray(array);
}

}  // namespace sg::viz::detail
