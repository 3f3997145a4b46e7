#pragma once

#include <sstream>

#include "splitgrid/error.hpp"

namespace sg::detail {

/// Throws ConfigError "<config>.<field> = <value> is out of range [low, high]" (an open lower
/// end prints as "(") unless low <= value <= high (low < value when low_open). A NaN value
/// is out of every range.
template <class T, class L, class H>
void check_config_range(const char* config, const char* field, T value, L low, H high,
                        bool low_open = false)
{
    const bool ok = (low_open ? value > static_cast<T>(low) : value >= static_cast<T>(low)) &&
                    value <= static_cast<T>(high);
    if (ok) return;
    std::ostringstream msg;
    msg << config << '.' << field << " = " << value << " is out of range " << (low_open ? '(' : '[')
        << low << ", " << high << "]";
    throw ConfigError(msg.str());
}

}  // namespace sg::detail
