#include "splitgrid/build_config.hpp"

#include <cmath>
#include <cstdint>
#include <sstream>
#include <string>
#include <variant>

#include "config_check.hpp"
#include "splitgrid/error.hpp"

namespace sg {
namespace {

/// A count or real field's value as a double (counts are at most 2^32 - 1: exact).
double numeric_value(const BuildConfig& config, const BuildConfigField& field)
{
    return std::visit([&](auto member) { return static_cast<double>(config.*member); },
                      field.member);
}

/// The value as the user wrote it: counts as integers, reals in the shortest form.
std::string value_text(const BuildConfig& config, const BuildConfigField& field)
{
    if (const auto* count = std::get_if<BuildConfigField::CountMember>(&field.member))
        return std::to_string(config.**count);
    std::ostringstream text;
    text << numeric_value(config, field);
    return text.str();
}

std::string field_label(std::string_view name) { return "BuildConfig." + std::string(name); }

void check_field_range(const BuildConfig& config, const BuildConfigField& field)
{
    const std::string name(field.name);
    if (const auto* count = std::get_if<BuildConfigField::CountMember>(&field.member)) {
        // Bounds as integers, so that the message prints 1048576 rather than 1.04858e+06.
        detail::check_config_range("BuildConfig", name.c_str(), config.**count,
                                   static_cast<std::uint32_t>(field.low),
                                   static_cast<std::uint32_t>(field.high), field.low_open);
    } else if (const auto* real = std::get_if<BuildConfigField::RealMember>(&field.member)) {
        if (!std::isfinite(config.**real))
            throw ConfigError(field_label(field.name) + " must be a finite number");
        detail::check_config_range("BuildConfig", name.c_str(), config.**real, field.low,
                                   field.high, field.low_open);
    }
}

/// Whether `value` lies in the field's range, checked in double precision so that values no
/// field type can hold (-1 for a count, 1e300 for a real) are refused like any other.
void check_value_range(const BuildConfigField& field, double value)
{
    if (field.is_count()) {
        // Bounds as integers, so that the message prints 1048576 rather than 1.04858e+06; the
        // value as an integer too when it is one.
        if (value == std::floor(value) && std::abs(value) < 9e15)
            detail::check_config_range("BuildConfig", std::string(field.name).c_str(),
                                       static_cast<std::int64_t>(value),
                                       static_cast<std::int64_t>(field.low),
                                       static_cast<std::int64_t>(field.high), field.low_open);
        else
            detail::check_config_range("BuildConfig", std::string(field.name).c_str(), value,
                                       static_cast<std::uint32_t>(field.low),
                                       static_cast<std::uint32_t>(field.high), field.low_open);
        return;
    }
    if (!std::isfinite(value))
        throw ConfigError(field_label(field.name) + " must be a finite number");
    detail::check_config_range("BuildConfig", std::string(field.name).c_str(), value, field.low,
                               field.high, field.low_open);
}

}  // namespace

void set_build_config_field(BuildConfig& config, const BuildConfigField& field, double value)
{
    if (const auto* switched = std::get_if<BuildConfigField::SwitchMember>(&field.member)) {
        config.**switched = value != 0.0;
        return;
    }
    check_value_range(field, value);
    if (const auto* count = std::get_if<BuildConfigField::CountMember>(&field.member)) {
        if (value != std::floor(value)) {
            std::ostringstream text;
            text << field_label(field.name) << " = " << value << " is not a whole number";
            throw ConfigError(text.str());
        }
        config.**count = static_cast<std::uint32_t>(value);
    } else if (const auto* real = std::get_if<BuildConfigField::RealMember>(&field.member)) {
        config.**real = value;
    }
}

void validate(const BuildConfig& config)
{
    // The structured binding stops compiling when a field is added to BuildConfig: then add it
    // to build_config_fields, which everything else iterates.
    [[maybe_unused]] const auto& [resolution_min, resolution_max, resolution_sigma, leaf_size,
                                  max_depth, no_progress_fraction, min_cell_width, stop_by_cost,
                                  bounding_planes, bounding_nodes, clip_triangles, threads] = config;

    for (const BuildConfigField& field : build_config_fields) check_field_range(config, field);
    for (const BuildConfigField& field : build_config_fields) {
        if (field.at_most.empty()) continue;
        const BuildConfigField& limit = *find_build_config_field(field.at_most);
        const double value = numeric_value(config, field);
        const double limit_value = numeric_value(config, limit);
        if (value <= limit_value) continue;
        throw ConfigError(field_label(field.name) + " = " + value_text(config, field) +
                          " is above " + field_label(limit.name) + " = " +
                          value_text(config, limit));
    }
}

BuildConfig apply_build_preset(BuildConfig config, std::string_view name)
{
    if (name == "poster") {
        config.bounding_nodes = false;
        config.stop_by_cost = false;
    } else if (name != "default") {
        std::string known;
        for (std::string_view preset : build_preset_names)
            known += (known.empty() ? "" : ", ") + std::string(preset);
        throw ConfigError("unknown build preset '" + std::string(name) + "' (the presets are " +
                          known + ")");
    }
    return config;
}

}  // namespace sg
