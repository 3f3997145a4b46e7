#include "splitgrid/build_config.hpp"

#include <cmath>

#include "config_check.hpp"
#include "splitgrid/error.hpp"

namespace sg {
namespace {

template <class T, class L, class H>
void check_range(const char* field, T value, L low, H high, bool low_open = false)
{
    detail::check_config_range("BuildConfig", field, value, low, high, low_open);
}

}  // namespace

void validate(const BuildConfig& config)
{
    check_range("resolution_max", config.resolution_max, 2, 1u << 20);
    check_range("resolution_min", config.resolution_min, 1, config.resolution_max);
    if (!std::isfinite(config.resolution_sigma))
        throw ConfigError("BuildConfig.resolution_sigma must be a finite number");
    check_range("resolution_sigma", config.resolution_sigma, 0.0, 1e9, true);
    check_range("leaf_size", config.leaf_size, 1, 1u << 20);
    check_range("max_depth", config.max_depth, 0, max_supported_depth);
    if (!std::isfinite(config.no_progress_fraction))
        throw ConfigError("BuildConfig.no_progress_fraction must be a finite number");
    check_range("no_progress_fraction", config.no_progress_fraction, 0.0, 1.0, true);
    if (!std::isfinite(config.min_cell_width))
        throw ConfigError("BuildConfig.min_cell_width must be a finite number");
    check_range("min_cell_width", config.min_cell_width, 0.0, 1e6);
    check_range("threads", config.threads, 0, 1024);
}

}  // namespace sg
