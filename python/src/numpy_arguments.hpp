#pragma once

#include <span>
#include <string>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

/// Reading Python arguments, shared by every function that takes arrays: conversion of
/// array-likes, and shapes, dtypes and types as error messages print them.
namespace sg::python {

namespace py = pybind11;

/// `object` as a numpy array: itself if it is one, else what numpy.asarray makes of it (a list,
/// a scalar, an object array for anything else).
[[nodiscard]] py::array as_array(const py::handle& object);

/// `array` as an array of T with the layout `flags` asks for (py::array::c_style, or 0 for any
/// strides) in native byte order: itself when it already is one, else one converted copy.
template <class T, int Flags = 0>
[[nodiscard]] py::array converted(const py::array& array)
{
    auto result = py::array_t<T, Flags | py::array::forcecast>::ensure(array);
    if (!result) throw py::error_already_set();
    return result;
}

/// A shape as numpy prints it: "(4, 5)", "(9,)", "()".
[[nodiscard]] std::string shape_text(std::span<const py::ssize_t> shape);
[[nodiscard]] std::string shape_text(const py::array& array);

/// The name of `value`'s Python type: "float", "str", "NoneType".
[[nodiscard]] std::string type_name(const py::handle& value);

/// A dtype as numpy prints it: "int64", "<U4", ">f4".
[[nodiscard]] std::string dtype_text(const py::array& array);

}  // namespace sg::python
