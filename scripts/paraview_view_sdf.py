"""Shows a signed distance field from `sg-points --grid ... --query signed-distance` beside its
mesh in ParaView, the way docs/VIZ.md describes it: a slice through the field coloured by
signed_distance (blue inside, red outside) with its iso-lines (contours of the field at
steps of the distance, the surface's among them), and the half of the mesh in front of the
slice as a translucent grey surface.

In the ParaView GUI (the files are named by environment variables, since --script takes no
arguments):

    SG_FIELD=sdf.vti SG_MESH=mesh_export/bunny.vtm paraview --script=scripts/paraview_view_sdf.py

Headless, saving a screenshot (Debian's ParaView renders through X, hence xvfb-run):

    xvfb-run -a pvbatch scripts/paraview_view_sdf.py sdf.vti mesh_export/bunny.vtm shot.png

The mesh is an `sg-export FILE.sg -o DIR --parts mesh` export (optional: without it the zero
contour of the field stands in for the surface).
"""

import os
import sys

from paraview import simple

try:
    import paraview_style
except ImportError:  # the GUI's --script may not put this folder on the path
    sys.path.insert(0, os.environ.get("SG_SCRIPTS", "scripts"))
    import paraview_style

# Steps between the iso-lines on the slice, as a share of the field's diagonal.
ISO_LINE_STEP = 0.02
# The front half of the mesh, seen through to the slice.
MESH_OPACITY = 0.3


def diagonal(source):
    bounds = source.GetDataInformation().GetBounds()
    return sum((bounds[2 * a + 1] - bounds[2 * a]) ** 2 for a in range(3)) ** 0.5


def show_field(vti_path, mesh_vtm=None, view=None):
    """Opens `vti_path` (and the mesh export `mesh_vtm`), sets up the view and frames the
    camera. Returns the view and a dict of the pipeline objects."""
    if view is None:
        view = simple.GetActiveViewOrCreate("RenderView")
    field = simple.XMLImageDataReader(registrationName=os.path.basename(vti_path),
                                      FileName=[vti_path])
    field.PointArrayStatus = ["signed_distance"]
    field.UpdatePipeline()
    size = diagonal(field)
    low, high = field.PointData["signed_distance"].GetRange()
    pipeline = {"field": field}

    # A slice through the middle, normal to z, coloured by the signed distance on a
    # diverging map centred on 0 (the surface): blue inside, red outside.
    centre = field.GetDataInformation().GetBounds()
    centre = [(centre[2 * a] + centre[2 * a + 1]) / 2 for a in range(3)]
    cut = simple.Slice(registrationName="slice", Input=field)
    cut.SliceType = "Plane"
    cut.SliceType.Origin = centre
    cut.SliceType.Normal = [0.0, 0.0, 1.0]
    shown = simple.Show(cut, view)
    simple.ColorBy(shown, ("POINTS", "signed_distance"))
    # Blue to white from the deepest point to the surface, white to red from the surface to
    # the farthest point: 0 is white whatever the range (ParaView's "Cool to Warm" colours).
    lut = simple.GetColorTransferFunction("signed_distance")
    lut.AutomaticRescaleRangeMode = "Never"
    lut.ColorSpace = "Diverging"
    lut.RGBPoints = [min(low, -1e-9 * size), 0.23, 0.299, 0.754,
                     0.0, 0.865, 0.865, 0.865,
                     max(high, 1e-9 * size), 0.706, 0.016, 0.150]
    # Unlit, so the colours read as the map gives them whatever the angle of view.
    shown.Ambient = 1.0
    shown.Diffuse = 0.0
    paraview_style.style_scalar_bar(shown, lut, view, "signed distance")
    pipeline["slice"] = cut

    # Iso-lines on the slice every ISO_LINE_STEP of the diagonal, and the surface's (0)
    # drawn thicker.
    step = ISO_LINE_STEP * size
    levels = [k * step for k in range(int(low / step), int(high / step) + 1) if k != 0]
    for name, values, width, colour in (("iso_lines", levels, 1.2, [0.25, 0.25, 0.25]),
                                        ("zero_line", [0.0], 3.5, [0.05, 0.05, 0.05])):
        lines = simple.Contour(registrationName=name, Input=cut)
        lines.ContourBy = ["POINTS", "signed_distance"]
        lines.Isosurfaces = values
        paraview_style.show_plain(lines, view, colour).LineWidth = width
        pipeline[name] = lines

    # The surface: the mesh itself where an export is given, else the field's zero contour;
    # its half in front of the slice, translucent, so the slice shows through it where it
    # cuts the inside.
    if mesh_vtm:
        mesh = simple.XMLMultiBlockDataReader(registrationName=os.path.basename(mesh_vtm),
                                              FileName=[mesh_vtm])
    else:
        mesh = simple.Contour(registrationName="surface", Input=field)
        mesh.ContourBy = ["POINTS", "signed_distance"]
        mesh.Isosurfaces = [0.0]
    front = simple.Clip(registrationName="front_half", Input=mesh)
    front.ClipType = "Plane"
    front.ClipType.Origin = centre
    front.ClipType.Normal = [0.0, 0.0, 1.0]
    front.Invert = 0
    paraview_style.show_plain(front, view).Opacity = MESH_OPACITY
    pipeline["mesh"] = mesh
    pipeline["front_half"] = front

    paraview_style.frame(view, azimuth=25, elevation=15, dolly=1.3)
    return view, pipeline


def main(argv):
    args = paraview_style.plain_arguments(argv)
    vti_path = args[0] if args else os.environ.get("SG_FIELD")
    if not vti_path:
        raise SystemExit("usage: pvbatch paraview_view_sdf.py FIELD.vti [MESH.vtm [SHOT.png]] "
                         "(or SG_FIELD=FIELD.vti SG_MESH=MESH.vtm paraview --script=...)")
    mesh_vtm = args[1] if len(args) > 1 else os.environ.get("SG_MESH")
    screenshot = args[2] if len(args) > 2 else None
    view, _ = show_field(vti_path, mesh_vtm)
    paraview_style.save_or_render(view, screenshot)


if __name__ != "paraview_view_sdf":
    main(sys.argv)
