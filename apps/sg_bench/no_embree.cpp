// sg-bench without Embree (SG_WITH_EMBREE off or Embree 3 not found): the structure list
// simply lacks "embree".

#include "bench_structure.hpp"
#include "splitgrid/error.hpp"

namespace sg::bench {

bool has_embree() { return false; }
std::string embree_version() { return ""; }

std::unique_ptr<BenchStructure> build_embree(const MeshView&, bool, unsigned)
{
    throw ConfigError("this sg-bench was built without Embree (SG_WITH_EMBREE)");
}

std::unique_ptr<FrameStructure> embree_frames(const MeshView&, EmbreeFrameMode, unsigned)
{
    throw ConfigError("this sg-bench was built without Embree (SG_WITH_EMBREE)");
}

}  // namespace sg::bench
