"""Shows an sg-export in ParaView the way docs/VIZ.md describes it: the Split Grid's cells
down to a depth as wireframe boxes coloured by depth, the mesh as an opaque surface inside.

In the ParaView GUI (the export is named by an environment variable, since --script takes no
arguments):

    SG_EXPORT=out/dragon.vtm paraview --script=scripts/paraview_view_export.py

Headless, saving a screenshot (Debian's ParaView renders through X, hence xvfb-run):

    xvfb-run -a pvbatch scripts/paraview_view_export.py out/dragon.vtm shot.png [MAX_DEPTH]

MAX_DEPTH (default 3, or SG_MAX_DEPTH) keeps the wireframe readable: a threshold on the
`depth` array keeps the cells of nodes at depth 0 to MAX_DEPTH.
"""

import os
import sys

from paraview import simple

try:
    import paraview_style
except ImportError:  # the GUI's --script may not put this folder on the path
    sys.path.insert(0, os.environ.get("SG_SCRIPTS", "scripts"))
    import paraview_style

DEFAULT_MAX_DEPTH = 3


def extract(source, block_name):
    """The block `block_name` ("cells", "planes", "leaves" or "mesh") of the export."""
    block = simple.ExtractBlock(registrationName=block_name, Input=source)
    block.Selectors = ["/Root/" + block_name]
    return block


def show_export(vtm_path, max_depth=DEFAULT_MAX_DEPTH, view=None):
    """Opens `vtm_path`, shows cells of depth 0..max_depth as wireframe coloured by depth
    and the mesh as a light grey surface, and frames the camera. Returns the view and a dict
    of the pipeline objects (reader, cells, threshold, mesh)."""
    if view is None:
        view = simple.GetActiveViewOrCreate("RenderView")
    reader = simple.XMLMultiBlockDataReader(
        registrationName=os.path.basename(vtm_path), FileName=[vtm_path])
    pipeline = {"reader": reader}

    cells = extract(reader, "cells")
    shallow = simple.Threshold(registrationName="cells_to_depth_%d" % max_depth, Input=cells)
    shallow.Scalars = ["CELLS", "depth"]
    shallow.LowerThreshold = 0
    shallow.UpperThreshold = max_depth
    shallow.ThresholdMethod = "Between"
    # The boxes' edges as lines: looks like the Wireframe representation, but Debian's
    # software OpenGL (llvmpipe, as under Xvfb) draws lines much faster than it draws polygons
    # in wireframe mode (docs/VIZ.md, "ParaView on Debian 12").
    edges = simple.ExtractEdges(registrationName="cell_edges", Input=shallow)
    boxes = simple.Show(edges, view)
    simple.ColorBy(boxes, ("CELLS", "depth"))
    depth_lut = simple.GetColorTransferFunction("depth")
    depth_lut.ApplyPreset("Viridis (matplotlib)", True)
    # One flat colour per depth level, centred on the integers.
    depth_lut.Discretize = 1
    depth_lut.NumberOfTableValues = max_depth + 1
    depth_lut.RescaleTransferFunction(-0.5, max_depth + 0.5)
    depth_lut.AutomaticRescaleRangeMode = "Never"
    boxes.Opacity = float(os.environ.get("SG_BOX_OPACITY", 0.35))
    bar = paraview_style.style_scalar_bar(boxes, depth_lut, view, "depth")
    bar.UseCustomLabels = 1
    bar.CustomLabels = list(range(max_depth + 1))
    bar.AddRangeLabels = 0
    bar.LabelFormat = "%.0f"
    pipeline.update(cells=cells, threshold=shallow, edges=edges)

    mesh = extract(reader, "mesh")
    paraview_style.show_plain(mesh, view)
    pipeline["mesh"] = mesh

    paraview_style.frame(view, azimuth=35, elevation=25, dolly=1.25)
    return view, pipeline


def main(argv):
    args = paraview_style.plain_arguments(argv)
    vtm_path = args[0] if args else os.environ.get("SG_EXPORT")
    if not vtm_path:
        raise SystemExit("usage: pvbatch paraview_view_export.py EXPORT.vtm [SHOT.png "
                         "[MAX_DEPTH]] (or SG_EXPORT=EXPORT.vtm paraview --script=...)")
    screenshot = args[1] if len(args) > 1 else None
    max_depth = int(args[2] if len(args) > 2 else
                    os.environ.get("SG_MAX_DEPTH", DEFAULT_MAX_DEPTH))
    view, _ = show_export(vtm_path, max_depth)
    paraview_style.save_or_render(view, screenshot)


# Run unless imported as a module (tests/paraview/check_export.py imports show_export); the
# ParaView GUI runs --script files under a name of its own.
if __name__ != "paraview_view_export":
    main(sys.argv)
