#pragma once

#include "splitgrid/baselines/bvh.hpp"
#include "splitgrid/baselines/kd_tree.hpp"
#include "splitgrid/baselines/uniform_grid.hpp"
#include "splitgrid/split_grid.hpp"
#include "support/oracle.hpp"

namespace sg::test {

/// The Split Grid (checked with both checkers) and the three comparison structures, each with
/// its default configuration, built on one mesh, which must outlive them.
struct AllStructures {
    explicit AllStructures(const Mesh& m)
        : mesh(m), grid(build_checked(m)), bvh(Bvh::build(m.view())), kd(KdTree::build(m.view())),
          uniform(UniformGrid::build(m.view()))
    {
    }
    const Mesh& mesh;
    SplitGrid grid;
    Bvh bvh;
    KdTree kd;
    UniformGrid uniform;
};

}  // namespace sg::test
