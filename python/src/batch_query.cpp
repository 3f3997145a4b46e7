#include "batch_query.hpp"

#include <algorithm>
#include <chrono>
#include <cstdint>

#include "errors.hpp"
#include "numpy_arguments.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

namespace sg::python {
namespace {

/// Longest round of run_batch between two looks at the signals, and its bounds in records: a
/// round is sized from the last one's speed, grows at most twofold, so a slower stretch of
/// rays cannot make one round last long.
constexpr double round_seconds = 0.05;
constexpr std::size_t first_round_records = 4096;
constexpr std::size_t max_round_records = std::size_t{1} << 20;

}  // namespace

int thread_count(const py::object& threads, const char* argument)
{
    if (threads.is_none()) return 0;
    if (py::isinstance<py::bool_>(threads) || PyIndex_Check(threads.ptr()) == 0)
        throw py::type_error(std::string(argument) + " must be None or a whole number, not " +
                             type_name(threads));
    const auto index = py::reinterpret_steal<py::object>(PyNumber_Index(threads.ptr()));
    if (!index) throw py::error_already_set();
    int overflow = 0;
    const long long value = PyLong_AsLongLongAndOverflow(index.ptr(), &overflow);
    if (overflow != 0 || value < 0 || value > 1024)
        throw py::value_error(std::string(argument) + " = " + py::str(index).cast<std::string>() +
                              " is out of range: None or 0 for all hardware threads, or 1 to "
                              "1024");
    return static_cast<int>(value);
}

RecordArray::RecordArray(const py::handle& object, const char* argument, py::ssize_t width)
    : argument_(argument), width_(width)
{
    py::array array = as_array(object);
    const char kind = array.dtype().kind();
    const py::ssize_t item = array.itemsize();
    if (kind != 'f' || (item != 4 && item != 8))
        throw py::type_error(std::string(argument) + ": dtype " + dtype_text(array) +
                             " is not supported; give float32 or float64");
    if (array.ndim() < 1 || array.shape(array.ndim() - 1) != width)
        throw py::value_error(std::string(argument) + ": expected an array of shape (..., " +
                              std::to_string(width) + "), got shape " + shape_text(array));
    if (item == 4) {
        array_ = converted<float, py::array::c_style>(array);
        floats_ = static_cast<const float*>(array_.data());
    } else {
        array_ = converted<double, py::array::c_style>(array);
        doubles_ = static_cast<const double*>(array_.data());
    }
    leading_shape_.assign(array_.shape(), array_.shape() + array_.ndim() - 1);
    size_ = static_cast<std::size_t>(array_.size() / width);
}

std::string RecordArray::index_text(std::size_t i) const
{
    if (leading_shape_.size() == 1) return std::to_string(i);
    std::vector<std::size_t> index(leading_shape_.size());
    for (std::size_t d = leading_shape_.size(); d-- > 0;) {
        const auto extent = static_cast<std::size_t>(leading_shape_[d]);
        index[d] = i % extent;
        i /= extent;
    }
    std::string text = "(";
    for (std::size_t d = 0; d < index.size(); ++d)
        text += (d == 0 ? "" : ", ") + std::to_string(index[d]);
    return text + ")";
}

PerRecordReal::PerRecordReal(const py::handle& object, const char* argument,
                             const RecordArray& records)
{
    py::array array = as_array(object);
    const char kind = array.dtype().kind();
    if (kind != 'f' && kind != 'i' && kind != 'u')
        throw py::type_error(std::string(argument) + ": dtype " + dtype_text(array) +
                             " is not supported; give a number or an array of numbers");
    if (array.ndim() == 0) {
        value_ = static_cast<float>(array.attr("item")().cast<double>());
        return;
    }
    const std::vector<py::ssize_t>& shape = records.leading_shape();
    const bool same_shape = static_cast<std::size_t>(array.ndim()) == shape.size() &&
                            std::equal(shape.begin(), shape.end(), array.shape());
    if (!same_shape)
        throw py::value_error(std::string(argument) + ": expected a number or an array of " +
                              records.argument() + "' leading shape " + shape_text(shape) +
                              ", got shape " + shape_text(array));
    if (kind == 'f' && array.itemsize() == 4) {
        array_ = converted<float, py::array::c_style>(array);
        floats_ = static_cast<const float*>(array_.data());
    } else {
        array_ = converted<double, py::array::c_style>(array);
        doubles_ = static_cast<const double*>(array_.data());
    }
}

RayBatch::RayBatch(const py::handle& rays, const py::handle& tnear, const py::handle& tfar)
    : rays_(rays, "rays", 6), tnear_(tnear, "tnear", rays_), tfar_(tfar, "tfar", rays_)
{
}

void RayBatch::fill(std::size_t begin, std::size_t end, Ray* out) const noexcept
{
    for (std::size_t i = begin; i < end; ++i) {
        float v[6];
        rays_.read(i, v);
        Ray& ray = out[i - begin];
        ray.origin = {v[0], v[1], v[2]};
        ray.direction = {v[3], v[4], v[5]};
        ray.t_min = tnear_[i];
        ray.t_max = tfar_[i];
    }
}

void RayBatch::add_invalid(std::size_t count, std::size_t first) const noexcept
{
    invalid_count_.fetch_add(count, std::memory_order_relaxed);
    std::size_t seen = first_invalid_.load(std::memory_order_relaxed);
    while (first < seen &&
           !first_invalid_.compare_exchange_weak(seen, first, std::memory_order_relaxed)) {
    }
}

void RayBatch::warn_about_invalid_rays() const
{
    const std::size_t invalid = invalid_count_.load();
    if (invalid == 0) return;
    warn_invalid_rays(
        "rays: " + std::to_string(invalid) + " of " + std::to_string(size()) +
        " rays are invalid (" + invalid_ray_description +
        "; t_min is tnear and t_max tfar; the first is ray " +
        rays_.index_text(first_invalid_.load()) + "): they are answered as misses");
}

void run_batch(std::size_t count, int threads,
               const std::function<void(std::size_t begin, std::size_t end)>& chunk)
{
    using Clock = std::chrono::steady_clock;
    tbb::task_arena arena(threads == 0 ? tbb::task_arena::automatic : threads);
    const auto body = [&chunk](const tbb::blocked_range<std::size_t>& range) {
        for (std::size_t begin = range.begin(); begin < range.end(); begin += chunk_records)
            chunk(begin, std::min(range.end(), begin + chunk_records));
    };
    std::size_t round = first_round_records;
    for (std::size_t done = 0; done < count;) {
        const std::size_t end = std::min(count, done + round);
        double seconds = 0.0;
        {
            const py::gil_scoped_release release;
            const auto start = Clock::now();
            arena.execute([&] {
                tbb::parallel_for(tbb::blocked_range<std::size_t>(done, end, chunk_records),
                                  body);
            });
            seconds = std::chrono::duration<double>(Clock::now() - start).count();
        }
        if (PyErr_CheckSignals() != 0) throw py::error_already_set();
        const double wanted = seconds > 0.0
                                  ? static_cast<double>(end - done) * round_seconds / seconds
                                  : static_cast<double>(2 * round);
        round = std::clamp(static_cast<std::size_t>(wanted), chunk_records,
                           std::min(2 * round, max_round_records));
        done = end;
    }
}

}  // namespace sg::python
