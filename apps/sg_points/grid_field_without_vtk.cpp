// sg-points built without VTK (SG_WITH_VTK=OFF): --grid is refused before any work.

#include "grid_field.hpp"
#include "splitgrid/error.hpp"

namespace sg::apps {

std::string why_no_grid_field()
{
    return "--grid writes VTK image data (.vti), and this sg-points was built without VTK "
           "(SG_WITH_VTK=OFF): give --points instead, or use a build with VTK";
}

std::vector<LibraryVersion> grid_field_libraries() { return {}; }

void write_grid_field(OutputFile& output, const SamplingGrid&, PointQuery, const PointAnswers&,
                      const GridFieldFacts&)
{
    throw ConfigError(output.target().string() + ": " + why_no_grid_field());
}

}  // namespace sg::apps
