#pragma once

#include <gtest/gtest.h>

#include <cctype>
#include <filesystem>
#include <string>

namespace sg::test {

/// A parameterised test's name for a mesh path of ../shared/meshes: the file's stem with every
/// character that is not a letter or digit replaced by '_' ("scanned/bunny_npm.obj" gives
/// "bunny_npm").
inline std::string mesh_test_name(const ::testing::TestParamInfo<const char*>& info)
{
    std::string name = std::filesystem::path(info.param).stem().string();
    for (char& c : name)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    return name;
}

}  // namespace sg::test
