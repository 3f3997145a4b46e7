"""The real-client test of sg-points --grid: ParaView opens a signed distance field of a box,
finds it placed where sg-points --json says and every sample equal to the box's exact signed
distance; contours at 0 and at an offset enclose the box and the box grown by that offset;
the view of scripts/paraview_view_sdf.py renders to a non-trivial image.

Run by ctest (label `paraview`) as
    sh with_xvfb.sh pvbatch check_field.py SG_BUILD SG_POINTS SG_EXPORT WORK_DIR VIEW_SCRIPT_DIR
Any failed check raises, and pvbatch then exits with status 1.
"""

import json
import os
import shutil
import sys
import time

from paraview import servermanager, simple

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from check_export import check, image_is_not_trivial, run  # noqa: E402

LOWER = (0.0, 0.0, 0.0)
UPPER = (2.0, 1.0, 1.0)
COUNTS = (21, 13, 11)
OFFSET = 0.2


def box_obj():
    """The box LOWER..UPPER as 12 triangles over 8 shared corners."""
    corners = [(x, y, z) for z in (LOWER[2], UPPER[2]) for y in (LOWER[1], UPPER[1])
               for x in (LOWER[0], UPPER[0])]
    quads = [(1, 3, 4, 2), (5, 6, 8, 7), (1, 2, 6, 5), (3, 7, 8, 4), (1, 5, 7, 3), (2, 4, 8, 6)]
    lines = ["v %g %g %g" % c for c in corners]
    for a, b, c, d in quads:
        lines += ["f %d %d %d" % (a, b, c), "f %d %d %d" % (a, c, d)]
    return "\n".join(lines) + "\n"


def box_signed_distance(p):
    """The exact signed distance to the box, negative inside."""
    q = [abs(p[a] - (LOWER[a] + UPPER[a]) / 2) - (UPPER[a] - LOWER[a]) / 2 for a in range(3)]
    outside = sum(max(v, 0.0) ** 2 for v in q) ** 0.5
    return outside + min(max(q), 0.0)


def contour_bounds(field, value):
    contour = simple.Contour(Input=field, ContourBy=["POINTS", "signed_distance"],
                             Isosurfaces=[value])
    contour.UpdatePipeline()
    check(contour.GetDataInformation().GetNumberOfPoints() > 0, "contour at %g is empty" % value)
    return contour.GetDataInformation().GetBounds()


def main(sg_build, sg_points, sg_export, work_dir, view_script_dir):
    started = time.time()
    shutil.rmtree(work_dir, ignore_errors=True)
    os.makedirs(work_dir)
    obj = os.path.join(work_dir, "box.obj")
    with open(obj, "w") as f:
        f.write(box_obj())
    sg = os.path.join(work_dir, "box.sg")
    vti = os.path.join(work_dir, "box.vti")
    run(sg_build, obj, "-o", sg, "-q")
    summary = json.loads(run(sg_points, sg, "--grid", ",".join(map(str, COUNTS)), "--query",
                             "signed-distance", "-o", vti, "--json"))
    run(sg_export, sg, "-o", os.path.join(work_dir, "mesh"), "--parts", "mesh", "-q")

    field = simple.XMLImageDataReader(FileName=[vti])
    field.UpdatePipeline()
    image = servermanager.Fetch(field)
    check(tuple(image.GetDimensions()) == COUNTS, "dimensions %s" % (image.GetDimensions(),))
    for a in range(3):
        check(abs(image.GetOrigin()[a] - summary["grid"]["origin"][a]) < 1e-12, "origin")
        check(abs(image.GetSpacing()[a] - summary["grid"]["spacing"][a]) < 1e-12, "spacing")
    scalars = image.GetPointData().GetScalars()
    check(scalars is not None and scalars.GetName() == "signed_distance", "active scalars")
    worst, inside = 0.0, 0
    for n in range(image.GetNumberOfPoints()):
        p = image.GetPoint(n)
        expected = box_signed_distance(p)
        got = scalars.GetValue(n)
        worst = max(worst, abs(got - expected))
        check(abs(got - expected) <= 1e-6, "sample %d at %s: %g, the box says %g"
              % (n, p, got, expected))
        inside += got < 0
    check(inside == summary["inside"], "%d samples inside, sg-points says %d"
          % (inside, summary["inside"]))

    # The user's first filters: contours at 0 and at an offset, to within a grid step.
    step = max(summary["grid"]["spacing"])
    for value in (0.0, OFFSET):
        bounds = contour_bounds(field, value)
        for a in range(3):
            check(abs(bounds[2 * a] - (LOWER[a] - value)) <= step and
                  abs(bounds[2 * a + 1] - (UPPER[a] + value)) <= step,
                  "contour at %g spans %s" % (value, bounds))

    sys.path.insert(0, view_script_dir)
    import paraview_style
    import paraview_view_sdf
    view, _ = paraview_view_sdf.show_field(vti, os.path.join(work_dir, "mesh", "box.vtm"))
    png = os.path.join(work_dir, "screenshot.png")
    paraview_style.save_or_render(view, png, size=(800, 600))
    del view
    colours, drawn = image_is_not_trivial(png)
    print("ok: %d samples, worst error %.2g, %d inside; screenshot %s with %d colours, %.0f%% "
          "drawn; %.1f s" % (image.GetNumberOfPoints(), worst, inside, png, colours, 100 * drawn,
                             time.time() - started))


if __name__ == "__main__":
    if len(sys.argv) != 6:
        raise SystemExit(__doc__)
    main(*sys.argv[1:])
