// sg-bench without CGAL (SG_WITH_CGAL off, the default): the point workloads measure our
// structures only.

#include "cgal_peer.hpp"
#include "splitgrid/error.hpp"

namespace sg::bench {

bool has_cgal() { return false; }
std::string cgal_version() { return ""; }

std::unique_ptr<CgalPeer> build_cgal(const MeshView&)
{
    throw ConfigError("this sg-bench was built without CGAL (SG_WITH_CGAL)");
}

}  // namespace sg::bench
