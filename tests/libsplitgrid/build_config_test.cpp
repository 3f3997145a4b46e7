// Tests of libsplitgrid/src/build_config.cpp and the field table of build_config.hpp: every
// table entry reaches the member it names, the ranges are the ones the header documents, and
// validate() refuses exactly the values outside them, naming the field.

#include <cmath>
#include <limits>
#include <set>
#include <string>
#include <string_view>
#include <type_traits>
#include <variant>

#include "splitgrid/build_config.hpp"
#include "splitgrid/error.hpp"

#include <gtest/gtest.h>

namespace sg {
namespace {

/// The message of validate()'s refusal of `config`, or "" if it is accepted.
std::string refusal(const BuildConfig& config)
{
    try {
        validate(config);
    } catch (const ConfigError& e) {
        return e.what();
    }
    return {};
}

TEST(BuildConfigFields, EveryEntryReachesTheMemberOfItsName)
{
    // The members by name, written out here independently of the table.
    BuildConfig c;
    const auto address_of = [&](const std::string& name) -> const void* {
        if (name == "resolution_min") return &c.resolution_min;
        if (name == "resolution_max") return &c.resolution_max;
        if (name == "resolution_sigma") return &c.resolution_sigma;
        if (name == "leaf_size") return &c.leaf_size;
        if (name == "max_depth") return &c.max_depth;
        if (name == "no_progress_fraction") return &c.no_progress_fraction;
        if (name == "min_cell_width") return &c.min_cell_width;
        if (name == "stop_by_cost") return &c.stop_by_cost;
        if (name == "bounding_planes") return &c.bounding_planes;
        if (name == "bounding_nodes") return &c.bounding_nodes;
        if (name == "clip_triangles") return &c.clip_triangles;
        if (name == "threads") return &c.threads;
        return nullptr;
    };
    std::set<std::string> names;
    for (const BuildConfigField& field : build_config_fields) {
        SCOPED_TRACE(std::string(field.name));
        names.insert(std::string(field.name));
        const void* through_table =
            std::visit([&](auto member) -> const void* { return &(c.*member); }, field.member);
        EXPECT_EQ(through_table, address_of(std::string(field.name)));
        EXPECT_EQ(find_build_config_field(field.name), &field);
        EXPECT_FALSE(field.help.empty());
    }
    EXPECT_EQ(names.size(), 12u) << "one entry per member, none twice";
    EXPECT_EQ(find_build_config_field("no_such_field"), nullptr);
}

/// A documented range (build_config.hpp's comments), written out here.
struct DocumentedRange {
    const char* field;
    double low;
    double high;
    bool low_open;
};

TEST(BuildConfigFields, RangesAreTheDocumentedOnesAndValidateHoldsToThem)
{
    const DocumentedRange ranges[] = {
        {"resolution_min", 1, 1048576, false},     {"resolution_max", 2, 1048576, false},
        {"resolution_sigma", 0, 1e9, true},        {"leaf_size", 1, 1048576, false},
        {"max_depth", 0, 64, false},               {"no_progress_fraction", 0, 1, true},
        {"min_cell_width", 0, 1e6, false},         {"threads", 0, 1024, false},
    };
    for (const DocumentedRange& r : ranges) {
        SCOPED_TRACE(r.field);
        const BuildConfigField* field = find_build_config_field(r.field);
        ASSERT_NE(field, nullptr);
        EXPECT_EQ(field->low, r.low);
        EXPECT_EQ(field->high, r.high);
        EXPECT_EQ(field->low_open, r.low_open);

        const auto with = [&](double value) {
            BuildConfig c;
            c.resolution_max = 1048576;  // so that resolution_min's own range is what counts
            std::visit(
                [&](auto member) {
                    c.*member = static_cast<std::remove_reference_t<decltype(c.*member)>>(value);
                },
                field->member);
            return c;
        };
        EXPECT_EQ(refusal(with(r.high)), "");
        EXPECT_NE(refusal(with(r.high + 1)).find(std::string("BuildConfig.") + r.field), std::string::npos);
        if (r.low_open) {
            EXPECT_NE(refusal(with(r.low)), "");
            EXPECT_EQ(refusal(with(r.low + (r.high - r.low) * 1e-6)), "");
        } else {
            EXPECT_EQ(refusal(with(r.low)), "");
            if (r.low > 0) {
                EXPECT_NE(refusal(with(r.low - 1)), "");
            }
        }
        if (!field->is_count()) {
            EXPECT_NE(refusal(with(std::numeric_limits<double>::quiet_NaN())).find("finite"),
                      std::string::npos);
            EXPECT_NE(refusal(with(std::numeric_limits<double>::infinity())), "");
        }
    }
}

TEST(BuildConfigFields, AFieldAboveItsLimitNamesBoth)
{
    BuildConfig c;
    c.resolution_min = 9;
    c.resolution_max = 8;
    EXPECT_EQ(refusal(c), "BuildConfig.resolution_min = 9 is above BuildConfig.resolution_max = 8");
    c.resolution_min = 8;
    EXPECT_EQ(refusal(c), "");
    EXPECT_EQ(refusal(BuildConfig{}), "") << "the defaults are valid";
}

TEST(BuildConfigFields, SwitchesAreTheFourBooleans)
{
    std::set<std::string> switches;
    for (const BuildConfigField& field : build_config_fields)
        if (field.is_switch()) switches.insert(std::string(field.name));
    EXPECT_EQ(switches, (std::set<std::string>{"stop_by_cost", "bounding_planes", "bounding_nodes",
                                               "clip_triangles"}));
}

/// The message of set_build_config_field's refusal, or "" if it sets the field.
std::string set_refusal(BuildConfig& config, std::string_view name, double value)
{
    try {
        set_build_config_field(config, *find_build_config_field(name), value);
    } catch (const ConfigError& e) {
        return e.what();
    }
    return {};
}

TEST(SetBuildConfigField, SetsInRangeValuesAndRefusesOthersWithValidatesMessage)
{
    BuildConfig c;
    EXPECT_EQ(set_refusal(c, "leaf_size", 5), "");
    EXPECT_EQ(c.leaf_size, 5u);
    EXPECT_EQ(set_refusal(c, "resolution_sigma", 12.5), "");
    EXPECT_EQ(c.resolution_sigma, 12.5);
    EXPECT_EQ(set_refusal(c, "clip_triangles", 0), "");
    EXPECT_FALSE(c.clip_triangles);
    EXPECT_EQ(set_refusal(c, "clip_triangles", 1), "");
    EXPECT_TRUE(c.clip_triangles);

    // The same words as validate(), also for values a uint32 field could not hold.
    BuildConfig in_field;
    in_field.leaf_size = 0;
    EXPECT_EQ(set_refusal(c, "leaf_size", 0), refusal(in_field));
    EXPECT_EQ(set_refusal(c, "leaf_size", -1),
              "BuildConfig.leaf_size = -1 is out of range [1, 1048576]");
    EXPECT_EQ(set_refusal(c, "max_depth", 4294967296.0),
              "BuildConfig.max_depth = 4294967296 is out of range [0, 64]");
    EXPECT_EQ(set_refusal(c, "leaf_size", 2.5),
              "BuildConfig.leaf_size = 2.5 is not a whole number");
    EXPECT_EQ(set_refusal(c, "resolution_sigma", 0),
              "BuildConfig.resolution_sigma = 0 is out of range (0, 1e+09]");
    EXPECT_EQ(set_refusal(c, "min_cell_width", std::numeric_limits<double>::quiet_NaN()),
              "BuildConfig.min_cell_width must be a finite number");
    EXPECT_NE(set_refusal(c, "threads", std::numeric_limits<double>::quiet_NaN()), "");
    EXPECT_EQ(c.leaf_size, 5u) << "a refused value leaves the field as it was";
    // Relations between fields are validate()'s: each field alone is in range.
    EXPECT_EQ(set_refusal(c, "resolution_min", 20), "");
    EXPECT_EQ(refusal(c),
              "BuildConfig.resolution_min = 20 is above BuildConfig.resolution_max = 16");
}

TEST(BuildPresets, PosterTurnsOffWhatThePosterDoesNotHaveAndKeepsTheRest)
{
    BuildConfig mine;
    mine.leaf_size = 3;
    mine.resolution_max = 40;
    mine.clip_triangles = false;
    const BuildConfig poster = apply_build_preset(mine, "poster");
    BuildConfig expected = mine;
    expected.bounding_nodes = false;
    expected.stop_by_cost = false;
    EXPECT_EQ(poster, expected);
    EXPECT_EQ(refusal(poster), "");
    EXPECT_EQ(apply_build_preset(mine, "default"), mine);
    EXPECT_THROW((void)apply_build_preset(mine, "Poster"), ConfigError);
    EXPECT_THROW((void)apply_build_preset(mine, ""), ConfigError);
}

}  // namespace
}  // namespace sg
