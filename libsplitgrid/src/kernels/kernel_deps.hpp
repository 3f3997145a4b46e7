#pragma once

// Everything the traversal kernels use from outside, included by each kernels_<isa>.cpp
// before its instruction-set region opens: these headers are then compiled for the baseline
// instruction set only, so no function of theirs can be emitted with AVX instructions and
// picked by the linker for a processor without them.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <span>
#include <type_traits>
#include <vector>

#if defined(__x86_64__)
#include <immintrin.h>
#endif

#include "kernel_table.hpp"
#include "point_search.hpp"
#include "../structure_box.hpp"
#include "splitgrid/aabb.hpp"
#include "splitgrid/baselines/bvh.hpp"
#include "splitgrid/baselines/kd_tree.hpp"
#include "splitgrid/baselines/uniform_grid.hpp"
#include "splitgrid/builder.hpp"
#include "splitgrid/leaf_words.hpp"
#include "splitgrid/cell_math.hpp"
#include "splitgrid/error.hpp"
#include "splitgrid/grid_node.hpp"
#include "splitgrid/mesh.hpp"
#include "splitgrid/query.hpp"
#include "splitgrid/ray.hpp"
#include "splitgrid/ray_triangle.hpp"
#include "splitgrid/split_grid.hpp"
#include "splitgrid/traversal_counters.hpp"
