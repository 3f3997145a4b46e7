#pragma once

namespace sg {

/// Version of the splitgrid library (semantic versioning).
inline constexpr int version_major = 0;
inline constexpr int version_minor = 1;
inline constexpr int version_patch = 0;
inline constexpr const char* version_string = "0.1.0";

}  // namespace sg
