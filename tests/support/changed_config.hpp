#pragma once

#include "splitgrid/build_config.hpp"

namespace sg::test {

/// A BuildConfig with every field away from its default, for the tests that follow each
/// field on its way (a .sg file's CONF record, the tools' flags). The counts differ from one
/// another and so do the reals, so a field read in the place of another shows. The four
/// switches are all `switches` (false is away from each default).
[[nodiscard]] inline BuildConfig every_field_changed(bool switches)
{
    BuildConfig c;
    c.resolution_min = 3;
    c.resolution_max = 11;
    c.resolution_sigma = 17.5;
    c.leaf_size = 4;
    c.max_depth = 5;
    c.no_progress_fraction = 0.75;
    c.min_cell_width = 0.5;
    c.stop_by_cost = switches;
    c.bounding_planes = switches;
    c.bounding_nodes = switches;
    c.clip_triangles = switches;
    c.threads = 2;
    return c;
}

}  // namespace sg::test
