/// sg-points: point queries against the mesh of a .sg file, through its Split Grid: for each
/// point of a point file (or a text file of points), or of a grid of points around the mesh,
/// inside or outside, the distance, the signed distance or the closest point, written to a
/// point result file (docs/FORMAT.md, section 6) or, for a grid, as VTK image data for
/// ParaView (docs/VIZ.md).

#include "cli_common.hpp"
#include "grid_field.hpp"
#include "points_options.hpp"
#include "points_run.hpp"

int main(int argc, char** argv)
{
    sg::apps::PointsOptions options;
    CLI::App app{"", "sg-points"};
    sg::apps::describe_tool(
        app,
        "Answers a query for every point of a point file, or of a grid of points around the\n"
        "mesh, against the mesh of a .sg file, through its Split Grid, and writes one answer\n"
        "per point, in point order (the files: docs/FORMAT.md), or for --grid a VTK image\n"
        "data file for ParaView (docs/VIZ.md).",
        "Points (--points): a point file (SGPTS001: 8 magic bytes, a uint64 count, float32\n"
        "x, y, z per point) or a text or CSV file, one point 'x y z' per line, separated by\n"
        "commas and/or blanks; inf and nan are allowed, blank lines and lines starting with #\n"
        "are skipped, and a first line that does not start with a number is a header. So a\n"
        "text file is all it takes: no converter is needed. An error names the line:\n"
        "'error: pts.csv:3: field 2 'x' is not a number'. The two are told apart by the\n"
        "content (a point file starts with SGPTS).\n"
        "Grid (--grid NX,NY,NZ): NX x NY x NZ points spread evenly over the mesh's bounding\n"
        "box widened by --padding times its diagonal on every side (an axis of 1 point: a\n"
        "slice through the box's centre); the output is VTK image data (.vti, x fastest)\n"
        "placed on the mesh, whose point-data array is named after the query: occupancy,\n"
        "distance, signed_distance; closest: distance, closest_point and triangle_id (-1 for\n"
        "none). Needs a build with VTK.\n"
        "Queries (--query), each file 8 magic bytes, a uint64 count, then one record per point:\n"
        "  occupancy: SGOCC001, a float32: 1 inside, 0 outside, by the parity of the\n"
        "    triangles a ray from the point crosses, counted exactly (edges and vertices\n"
        "    decided as for a slightly moved ray), so every point not within rounding of the\n"
        "    surface is answered right on a closed mesh; --nsamples rays per point take a\n"
        "    majority vote, which helps only where the mesh is not closed. A mesh with edges\n"
        "    shared by an odd number of triangles (open edges) gets one warning naming how\n"
        "    many open and non-manifold edges it has. Points outside the mesh's box are\n"
        "    outside.\n"
        "  distance: SGDST001, a float32: the distance to the nearest point of the mesh,\n"
        "    exact to within rounding (docs/SPLIT_GRID.md, 'Closest points').\n"
        "  signed-distance: SGSDF001, a float32: the distance, negative inside (the side as\n"
        "    for occupancy, with its warning for a mesh that is not closed).\n"
        "  closest: SGCLP001, 28 bytes: uint32 triangle id, float32 distance, u, v\n"
        "    (barycentrics), x, y, z of the closest point; a point without an answer has id\n"
        "    0xFFFFFFFF and x, y, z NaN.\n"
        "  With --max-distance D the distance queries answer a point farther than D from the\n"
        "  mesh +inf (closest: no triangle) without searching beyond D.\n"
        "Points with a NaN or infinite coordinate are answered NaN with a warning that counts\n"
        "them; --strict refuses such a file instead (exit code 2). The output does not\n"
        "depend on --threads.",
        sg::apps::grid_field_libraries());
    sg::apps::add_points_options(app, options);
    return sg::apps::run_tool(app, argc, argv, options.log, [&] { sg::apps::run_points(options); });
}
