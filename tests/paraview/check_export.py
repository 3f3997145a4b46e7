"""The real-client test of sg-export: ParaView opens an export of a real model, and the blocks,
arrays and ranges it sees agree with what sg-stats says about the same .sg file; a threshold on
`depth` keeps the right cells; the view of scripts/paraview_view_export.py, with the leaves
coloured by triangle_count, renders to a non-trivial image.

Run by ctest (label `paraview`) as
    sh with_xvfb.sh pvbatch check_export.py SG_BUILD SG_STATS SG_EXPORT MODEL WORK_DIR VIEW_SCRIPT_DIR
Any failed check raises, and pvbatch then exits with status 1.
"""

import json
import os
import shutil
import subprocess
import sys
import time

from paraview import servermanager, simple
from vtkmodules.vtkIOImage import vtkPNGReader

MAX_DEPTH = 4  # exported depth levels: enough to reach leaves, small enough to stay fast
THRESHOLD = (1, 2)  # depth range kept by the Threshold check


def run(*command):
    result = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if result.returncode != 0:
        raise AssertionError("%s failed (%d): %s" % (command[0], result.returncode, result.stderr))
    return result.stdout


def check(condition, message):
    if not condition:
        raise AssertionError(message)


def check_range(source, name, low, high):
    """The cell array `name` of `source` as ParaView reports it lies within [low, high]."""
    array = source.CellData[name]
    check(array is not None, "%s: no cell array %s" % (source, name))
    lo, hi = array.GetRange()
    check(low <= lo and hi <= high, "%s range (%g, %g) outside [%g, %g]" % (name, lo, hi, low, high))
    return lo, hi


def block(reader, name):
    extracted = simple.ExtractBlock(registrationName="check_" + name, Input=reader)
    extracted.Selectors = ["/Root/" + name]
    extracted.UpdatePipeline()
    return extracted


def cells_at_depths(grid, first, last):
    """Cells (empty ones included) of the nodes at depths first..last, from sg-stats."""
    total = 0.0
    for d in range(first, min(last, len(grid["nodes_per_depth"]) - 1) + 1):
        total += grid["nodes_per_depth"][d] * grid["mean_resolution_per_depth"][d]
    return int(round(total))


def nodes_at_depths(grid, first, last):
    return sum(grid["nodes_per_depth"][first:last + 1])


def image_is_not_trivial(png):
    """Reads the screenshot back and requires many colours and a good share of pixels that
    are not the white background."""
    reader = vtkPNGReader()
    reader.SetFileName(png)
    reader.Update()
    image = reader.GetOutput()
    width, height, _ = image.GetDimensions()
    check(width >= 400 and height >= 300, "screenshot is only %dx%d" % (width, height))
    scalars = image.GetPointData().GetScalars()
    colours, drawn, sampled = set(), 0, 0
    for i in range(0, width * height, 7):
        rgb = tuple(int(scalars.GetComponent(i, c)) for c in range(3))
        colours.add(rgb)
        drawn += rgb != (255, 255, 255)
        sampled += 1
    check(len(colours) > 100, "screenshot has only %d colours" % len(colours))
    check(drawn > 0.15 * sampled, "screenshot is mostly empty (%d of %d pixels drawn)" % (drawn, sampled))
    return len(colours), drawn / sampled


def main(sg_build, sg_stats, sg_export, model, work_dir, view_script_dir):
    started = time.time()
    shutil.rmtree(work_dir, ignore_errors=True)
    os.makedirs(work_dir)
    sg = os.path.join(work_dir, "model.sg")
    out = os.path.join(work_dir, "export")
    run(sg_build, model, "-o", sg, "-q")
    stats = json.loads(run(sg_stats, sg, "--json"))
    grid = stats["grid"]
    summary = json.loads(run(sg_export, sg, "-o", out, "--max-depth", str(MAX_DEPTH),
                             "--empty-cells", "--json"))
    deepest = min(MAX_DEPTH, grid["max_depth"])

    reader = simple.XMLMultiBlockDataReader(FileName=[summary["vtm"]])
    reader.UpdatePipeline()
    data = servermanager.Fetch(reader)
    names = [data.GetMetaData(i).Get(data.NAME()) for i in range(data.GetNumberOfBlocks())]
    check(names == ["cells", "planes", "leaves", "mesh"], "blocks are %s" % names)
    for i, name in enumerate(names):
        scalars = data.GetBlock(i).GetCellData().GetScalars()
        expected = "reference_count" if name == "mesh" else "depth"
        check(scalars is not None and scalars.GetName() == expected,
              "%s: active scalars are not %s" % (name, expected))

    cells = block(reader, "cells")
    check(cells.GetDataInformation().GetNumberOfCells() == cells_at_depths(grid, 0, deepest),
          "cells: %d, sg-stats says %d" % (cells.GetDataInformation().GetNumberOfCells(),
                                           cells_at_depths(grid, 0, deepest)))
    check(check_range(cells, "depth", 0, deepest) == (0, deepest), "cells: depth range")
    check(check_range(cells, "kind", 0, 2) == (0, 2), "cells: every kind is there")
    check_range(cells, "axis", 0, 2)
    check_range(cells, "cost_share", 0.0, 1.0)
    check_range(cells, "triangle_count", 0, grid["reference_count"])
    check_range(cells, "cell_index", 0, stats["build_config"]["resolution_max"] - 1)
    check_range(cells, "node_id", 0, grid["node_count"] - 1)

    planes = block(reader, "planes")
    check(planes.GetDataInformation().GetNumberOfCells() == 2 * nodes_at_depths(grid, 0, deepest),
          "planes: two per node")
    check(check_range(planes, "side", 0, 1) == (0, 1), "planes: both sides")
    check_range(planes, "cut_fraction", 0.0, 1.0)
    check_range(planes, "depth", 0, deepest)

    leaves = block(reader, "leaves")
    check(check_range(leaves, "kind", 1, 1) == (1, 1), "leaves: only leaves")
    leaf_sizes = check_range(leaves, "triangle_count", grid["leaf_size_min"], grid["leaf_size_max"])

    mesh = block(reader, "mesh")
    check(mesh.GetDataInformation().GetNumberOfCells() == grid["triangle_count"], "mesh: triangles")
    check_range(mesh, "reference_count", 0, grid["reference_count"])
    mesh_data = servermanager.Fetch(mesh).GetBlock(0)
    refs = mesh_data.GetCellData().GetArray("reference_count")
    total = sum(refs.GetValue(i) for i in range(refs.GetNumberOfTuples()))
    check(total == grid["reference_count"], "mesh: %d references, sg-stats says %d"
          % (total, grid["reference_count"]))
    field = mesh_data.GetFieldData().GetAbstractArray("source_name").GetValue(0)
    check(field == stats["source_name"], "source_name field is %r" % field)

    # A user's first filter: Threshold on depth keeps exactly the cells of those levels.
    kept = simple.Threshold(Input=cells)
    kept.Scalars = ["CELLS", "depth"]
    kept.LowerThreshold, kept.UpperThreshold = THRESHOLD
    kept.ThresholdMethod = "Between"
    kept.UpdatePipeline()
    check(kept.GetDataInformation().GetNumberOfCells() == cells_at_depths(grid, *THRESHOLD),
          "threshold on depth kept %d cells, sg-stats says %d"
          % (kept.GetDataInformation().GetNumberOfCells(), cells_at_depths(grid, *THRESHOLD)))

    # The documented view, plus the leaves coloured by triangle_count.
    sys.path.insert(0, view_script_dir)
    import paraview_view_export
    view, _ = paraview_view_export.show_export(summary["vtm"], max_depth=2)
    shown = simple.Show(leaves, view)
    simple.ColorBy(shown, ("CELLS", "triangle_count"))
    shown.RescaleTransferFunctionToDataRange(True, False)
    lut_range = simple.GetColorTransferFunction("triangle_count").RGBPoints
    check((lut_range[0], lut_range[-4]) == leaf_sizes,
          "triangle_count colours span %s, leaves span %s" % ((lut_range[0], lut_range[-4]), leaf_sizes))
    png = os.path.join(work_dir, "screenshot.png")
    view.ViewSize = [800, 600]
    simple.SaveScreenshot(png, view, ImageResolution=[800, 600])
    colours, drawn = image_is_not_trivial(png)
    # pvbatch exits with status 1 (a GLX error) if a render view is still open at exit.
    simple.Delete(view)
    del view
    print("ok: %d cells, %d planes, %d leaves, %d triangles; screenshot %s with %d colours, "
          "%.0f%% drawn; %.1f s" % (summary["counts"]["cells"], summary["counts"]["planes"],
                                    summary["counts"]["leaves"], grid["triangle_count"], png,
                                    colours, 100 * drawn, time.time() - started))


if __name__ == "__main__":
    if len(sys.argv) != 7:
        raise SystemExit(__doc__)
    main(*sys.argv[1:])
