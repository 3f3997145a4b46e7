#include "numpy_arguments.hpp"

namespace sg::python {

py::array as_array(const py::handle& object)
{
    py::array array = py::array::ensure(object);
    if (!array) throw py::error_already_set();
    return array;
}

std::string shape_text(std::span<const py::ssize_t> shape)
{
    std::string text = "(";
    for (std::size_t d = 0; d < shape.size(); ++d)
        text += (d == 0 ? "" : ", ") + std::to_string(shape[d]);
    return text + (shape.size() == 1 ? ",)" : ")");
}

std::string shape_text(const py::array& array)
{
    return shape_text({array.shape(), static_cast<std::size_t>(array.ndim())});
}

std::string type_name(const py::handle& value)
{
    return py::str(py::type::of(value).attr("__name__")).cast<std::string>();
}

std::string dtype_text(const py::array& array)
{
    return py::str(array.dtype()).cast<std::string>();
}

}  // namespace sg::python
