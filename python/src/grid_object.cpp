#include "grid_object.hpp"

#include <chrono>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>

#include "batch_query.hpp"
#include "errors.hpp"
#include "numpy_arguments.hpp"
#include "splitgrid/builder.hpp"
#include "splitgrid/error.hpp"
#include "splitgrid/stats.hpp"
#include "splitgrid/validate.hpp"

namespace sg::python {
namespace {

/// How often a build looks for Ctrl-C, at most: each look takes the GIL.
constexpr std::chrono::milliseconds signal_check_interval{100};

/// Thrown out of the builder's progress callback to stop a build that Ctrl-C interrupted.
struct BuildInterrupted {};

std::string names_of_build_parameters()
{
    std::string names;
    for (const BuildConfigField& field : build_config_fields)
        if (field.name != "threads") names += (names.empty() ? "" : ", ") + std::string(field.name);
    return names;
}

/// A keyword argument's value as set_build_config_field takes it, after its type is checked.
double parameter_value(const BuildConfigField& field, const py::handle& value)
{
    const std::string name(field.name);
    const bool is_bool = py::isinstance<py::bool_>(value) ||
                         py::isinstance(value, py::module_::import("numpy").attr("bool_"));
    if (field.is_switch()) {
        if (!is_bool)
            throw py::type_error(name + " must be True or False, not " + type_name(value));
        return value.cast<bool>() ? 1.0 : 0.0;
    }
    const bool is_integer = PyIndex_Check(value.ptr()) != 0;
    const bool is_real = is_integer || PyFloat_Check(value.ptr()) != 0 ||
                         py::isinstance(value, py::module_::import("numpy").attr("floating"));
    if (is_bool || (field.is_count() ? !is_integer : !is_real))
        throw py::type_error(name + " must be " +
                             (field.is_count() ? "a whole number" : "a real number") + ", not " +
                             type_name(value));
    // Integers beyond 2^53 round to the nearest double, which is still out of every range.
    return py::float_(py::reinterpret_borrow<py::object>(value)).cast<double>();
}

}  // namespace

BuildConfig build_config_from(const std::string& preset, const py::object& threads,
                              const py::kwargs& params)
{
    BuildConfig config = apply_build_preset(BuildConfig{}, preset);
    for (const auto& [key, value] : params) {
        const std::string name = py::str(key).cast<std::string>();
        const BuildConfigField* field = find_build_config_field(name);
        if (field == nullptr || field->name == "threads")
            throw py::type_error("build() got an unexpected keyword argument '" + name +
                                 "'; the build parameters are " + names_of_build_parameters());
        set_build_config_field(config, *field, parameter_value(*field, value));
    }
    config.threads = static_cast<std::uint32_t>(thread_count(threads));
    validate(config);
    return config;
}

std::unique_ptr<GridObject> build_grid(Mesh mesh, const BuildConfig& config,
                                       std::string source_name)
{
    using Clock = std::chrono::steady_clock;
    auto object = std::make_unique<GridObject>();
    object->contents.mesh = std::move(mesh);
    object->contents.source_name = std::move(source_name);

    // Python runs signal handlers only in the main thread, and only with the GIL: the calling
    // thread looks from inside the builder's progress reports, which every build thread makes.
    const std::thread::id caller = std::this_thread::get_id();
    auto last_check = Clock::now();
    std::optional<py::error_already_set> interrupt;
    const BuildProgress look_for_signals = [&](double) {
        if (std::this_thread::get_id() != caller ||
            Clock::now() - last_check < signal_check_interval)
            return;
        last_check = Clock::now();
        const py::gil_scoped_acquire gil;
        if (PyErr_CheckSignals() == 0) return;
        interrupt.emplace();
        throw BuildInterrupted{};
    };
    try {
        const py::gil_scoped_release release;
        object->contents.grid = build_split_grid(object->mesh(), config, look_for_signals);
        try {
            check_invariants(object->contents.grid);
        } catch (const FormatError& e) {
            // A bug in the builder, not a bad input.
            throw std::logic_error(std::string("built grid fails its invariants: ") + e.what());
        }
    } catch (const BuildInterrupted&) {
        throw *interrupt;
    }
    return object;
}

std::unique_ptr<GridObject> load_grid(const std::filesystem::path& path)
{
    auto object = std::make_unique<GridObject>();
    const py::gil_scoped_release release;
    object->contents = read_sg_file(path);
    object->file = SgFileFacts{path.string(), read_sg_info(path)};
    return object;
}

void warn_if_open(const GridObject& grid, const char* query)
{
    const EdgeReport* edges = nullptr;
    {
        const py::gil_scoped_release release;
        edges = &grid.edges();
    }
    if (edges->is_closed()) return;
    warn_open_mesh(std::string(query) + ": the mesh is not closed: " +
                   std::to_string(edges->open_edges) +
                   " open edges (shared by an odd number of triangles) and " +
                   std::to_string(edges->nonmanifold_edges) + " non-manifold edges of " +
                   std::to_string(edges->edges) +
                   "; inside and outside may be wrong near the openings (nsamples above 1 takes "
                   "the majority of more rays)");
}

py::dict grid_stats(const GridObject& grid)
{
    Json document;
    {
        const py::gil_scoped_release release;
        const GridStats stats = compute_stats(grid.grid());
        document = sg_stats_json(grid.contents, stats, grid.edges(),
                                 grid.file ? &*grid.file : nullptr, false);
    }
    return py::dict(to_python(document));
}

py::object to_python(const Json& json)
{
    return py::module_::import("json").attr("loads")(json.dump());
}

}  // namespace sg::python
