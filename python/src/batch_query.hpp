#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <initializer_list>
#include <span>
#include <string>
#include <vector>

#include "splitgrid/ray.hpp"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

/// The machinery every batch query of the package shares, so that a query over rays or points
/// is its kernel call and its outputs: checking and reading the input arrays in place, the
/// per-record arguments (tnear, tfar), allocating the outputs numpy returns, and running the
/// records in chunks on oneTBB threads with the GIL released and Ctrl-C honoured.
namespace sg::python {

namespace py = pybind11;

/// Records a chunk function is handed at most at once: its stack buffers in the kernels'
/// layouts (sg::Ray, sg::Hit) hold this many, so no query makes a second full-size copy. Few
/// enough that what the query read for a chunk's hits (the hit triangles' corners, for the
/// normals) is still in the L1 cache when the chunk's results are written.
inline constexpr std::size_t chunk_records = 16;

/// The `threads` argument of every query and build: None or 0 for all hardware threads (as
/// Open3D's nthreads=0), else a count in [1, 1024]. Returns 0 for "all". Throws TypeError or
/// ValueError naming `argument`.
[[nodiscard]] int thread_count(const py::object& threads, const char* argument = "threads");

/// The records of a batch query: an array of shape (..., width), float32 or float64 (rays:
/// width 6, origin and direction; points: width 3). A C-contiguous array of native byte order is
/// read in place, float64 converted chunk by chunk; anything else (a list, a strided view, the
/// other byte order) is made into one contiguous array of its own precision first. Any leading
/// shape, including none: (6,) is one ray, and its outputs have shape ().
class RecordArray {
public:
    /// Throws TypeError for a dtype other than float32 and float64, ValueError for a shape
    /// whose last dimension is not `width`; both messages name `argument`.
    RecordArray(const py::handle& object, const char* argument, py::ssize_t width);

    [[nodiscard]] std::size_t size() const noexcept { return size_; }
    [[nodiscard]] const char* argument() const noexcept { return argument_; }
    [[nodiscard]] const std::vector<py::ssize_t>& leading_shape() const noexcept
    {
        return leading_shape_;
    }

    /// Record `i`'s `width` values as floats (float64 rounded to nearest).
    void read(std::size_t i, float* out) const noexcept
    {
        const std::size_t first = i * static_cast<std::size_t>(width_);
        if (doubles_ != nullptr) {
            for (py::ssize_t k = 0; k < width_; ++k)
                out[k] = static_cast<float>(doubles_[first + static_cast<std::size_t>(k)]);
        } else {
            for (py::ssize_t k = 0; k < width_; ++k)
                out[k] = floats_[first + static_cast<std::size_t>(k)];
        }
    }

    /// Record `i`'s position in the leading shape, "(3, 7)" (or "3" for one leading axis).
    [[nodiscard]] std::string index_text(std::size_t i) const;

    /// A new C-contiguous output array of the leading shape followed by `trailing`.
    template <class T>
    [[nodiscard]] py::array_t<T> new_output(std::initializer_list<py::ssize_t> trailing = {}) const
    {
        std::vector<py::ssize_t> shape = leading_shape_;
        shape.insert(shape.end(), trailing.begin(), trailing.end());
        return py::array_t<T>(shape);
    }

private:
    py::array array_;
    const char* argument_;
    py::ssize_t width_;
    const float* floats_ = nullptr;
    const double* doubles_ = nullptr;
    std::size_t size_ = 0;
    std::vector<py::ssize_t> leading_shape_;
};

/// A real argument given per record: one number for every record (tnear=0.0), or an array of
/// the records' leading shape (integer or float; read in place when float32 or float64 and
/// C-contiguous). Throws TypeError or ValueError naming `argument`.
class PerRecordReal {
public:
    PerRecordReal(const py::handle& object, const char* argument, const RecordArray& records);

    [[nodiscard]] float operator[](std::size_t i) const noexcept
    {
        if (floats_ != nullptr) return floats_[i];
        if (doubles_ != nullptr) return static_cast<float>(doubles_[i]);
        return value_;
    }

private:
    py::array array_;
    float value_ = 0.0f;
    const float* floats_ = nullptr;
    const double* doubles_ = nullptr;
};

/// The rays of a ray query with their tnear and tfar: `rays` (..., 6), `tnear`, `tfar`
/// (numbers or arrays of the rays' leading shape). Counts the invalid rays (sg::is_valid), which
/// every query answers as misses, for one warning after the query.
class RayBatch {
public:
    RayBatch(const py::handle& rays, const py::handle& tnear, const py::handle& tfar);

    [[nodiscard]] const RecordArray& rays() const noexcept { return rays_; }
    [[nodiscard]] std::size_t size() const noexcept { return rays_.size(); }

    /// Rays [begin, end) in the kernels' layout into `out` (end - begin <= chunk_records).
    /// Thread-safe: chunks run at once on several threads.
    void fill(std::size_t begin, std::size_t end, Ray* out) const noexcept;

    /// After a chunk's query: counts the invalid rays among `rays` (rays begin, begin + 1, ...
    /// as fill() made them) for which `missed(k)` holds. An invalid ray is always a miss, so
    /// only the misses are looked at. Thread-safe.
    template <class Missed>
    void count_invalid(std::size_t begin, std::span<const Ray> rays, Missed missed) const noexcept
    {
        std::size_t invalid = 0;
        std::size_t first = SIZE_MAX;
        for (std::size_t k = 0; k < rays.size(); ++k) {
            if (!missed(k) || is_valid(rays[k])) continue;
            first = std::min(first, begin + k);
            ++invalid;
        }
        if (invalid != 0) add_invalid(invalid, first);
    }

    /// After the query, with the GIL: one splitgrid.InvalidRayWarning counting the invalid
    /// rays and naming the first, if there were any.
    void warn_about_invalid_rays() const;

private:
    void add_invalid(std::size_t count, std::size_t first) const noexcept;

    RecordArray rays_;
    PerRecordReal tnear_;
    PerRecordReal tfar_;
    mutable std::atomic<std::size_t> invalid_count_{0};
    mutable std::atomic<std::size_t> first_invalid_{SIZE_MAX};
};

/// Runs `chunk(begin, end)` over the records [0, count), each call at most chunk_records
/// records, on `threads` oneTBB threads (thread_count's value, 0 = all) of an arena of its own,
/// with the GIL released. The records go in rounds of about a twentieth of a second; between
/// rounds the GIL is taken back and pending signals run their Python handlers, so Ctrl-C
/// raises KeyboardInterrupt (py::error_already_set) within a round. Needs the GIL; `chunk`
/// must not touch Python objects.
void run_batch(std::size_t count, int threads,
               const std::function<void(std::size_t begin, std::size_t end)>& chunk);

}  // namespace sg::python
