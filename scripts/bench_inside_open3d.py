#!/usr/bin/python3
"""Asks Open3D the questions of sg-bench's inside tests: is each point inside or outside?

Usage: bench_inside_open3d.py RESULTS_JSON POINTS_DIR [--build BUILD_DIR]

RESULTS_JSON is an sg-bench results.json with inside tests (docs/BENCH.md, "Inside tests"),
POINTS_DIR the folder its run wrote with --save-points: per set `<set>.points` (the points),
`<set>.expected` (the oracle's answer: 1 inside, 0 outside, NaN undecided) and the set's scene
`<scene>.sg`. For every set this script loads the scene's vertices and triangles with the
splitgrid package (the arrays sg-bench measured), gives them to Open3D's RaycastingScene
(python3-open3d, Debian 12: Open3D 0.16) and counts the points whose answer differs from the
oracle's:

- compute_occupancy: inside when it returns 1;
- compute_signed_distance: inside when the distance is negative;

and, as a check that the files are read as sg-bench wrote them, the splitgrid package's own
compute_occupancy, which must have as many wrong answers as sg-bench's Split Grid. Open3D is
not timed: a method that answers wrongly gets no speed (CONTRIBUTING.md, "Benchmarks").

Writes `inside_open3d.json` beside RESULTS_JSON, draws `inside_tests.png` there again with
Open3D's points (bench_charts.py), and prints the wrong-answer table (method | points | wrong |
speed) in Markdown on stdout. Run with Debian's /usr/bin/python3 (numpy, Open3D, matplotlib).
"""

import argparse
import json
import pathlib
import sys

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "scripts"))
import bench_charts  # noqa: E402
from bench_common import label  # noqa: E402


def read_records(path, magic, dtype, width):
    """The records of a point file (SGPTS001) or an occupancy file (SGOCC001),
    docs/FORMAT.md section 6: 8 magic bytes, a uint64 count, then the records."""
    data = pathlib.Path(path).read_bytes()
    if data[:8] != magic:
        sys.exit(f"bench_inside_open3d.py: {path}: not a {magic.decode()} file")
    count = int(np.frombuffer(data[8:16], dtype="<u8")[0])
    values = np.frombuffer(data[16:], dtype=dtype)
    if len(values) != count * width:
        sys.exit(f"bench_inside_open3d.py: {path}: {len(values)} values for {count} records")
    return values.reshape(count, width) if width > 1 else values


def wrong_answers(inside, expected):
    """Points the oracle decides whose `inside` (bool) differs from it."""
    decided = ~np.isnan(expected)
    return int(np.sum(decided & (inside != (expected == 1.0))))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("results", help="sg-bench's results.json")
    parser.add_argument("points", help="the folder sg-bench --save-points wrote")
    parser.add_argument("--build", default=str(ROOT / "build"), help="the build folder")
    args = parser.parse_args()
    sys.path.insert(0, str(pathlib.Path(args.build) / "python"))
    import splitgrid
    import open3d

    results = json.loads(pathlib.Path(args.results).read_text())
    tests = results.get("inside_tests") or []
    if not tests:
        sys.exit(f"bench_inside_open3d.py: {args.results} has no inside tests")
    folder = pathlib.Path(args.points)
    entries = []
    for test in tests:
        points = read_records(folder / f"{test['set']}.points", b"SGPTS001", "<f4", 3)
        expected = read_records(folder / f"{test['set']}.expected", b"SGOCC001", "<f4", 1)
        if len(points) != test["points"] or len(expected) != len(points):
            sys.exit(f"bench_inside_open3d.py: {test['set']}: {len(points)} points in the "
                     f"files, {test['points']} in {args.results}")
        grid = splitgrid.load(folder / f"{test['scene']}.sg")
        scene = open3d.t.geometry.RaycastingScene()
        scene.add_triangles(open3d.core.Tensor(np.ascontiguousarray(grid.vertices)),
                            open3d.core.Tensor(np.ascontiguousarray(grid.triangles)))
        tensor = open3d.core.Tensor(np.ascontiguousarray(points))
        occupancy = scene.compute_occupancy(tensor).numpy() == 1
        signed = scene.compute_signed_distance(tensor).numpy() < 0
        ours = grid.compute_occupancy(points) == 1
        ours_in_sg_bench = next(m["wrong"] for m in test["methods"] if m["method"] == "splitgrid")
        entry = {"set": test["set"], "scene": test["scene"], "points": len(points),
                 "decided": int(np.sum(~np.isnan(expected))),
                 "inside": int(np.sum(expected == 1.0)),
                 "wrong_occupancy": wrong_answers(occupancy, expected),
                 "wrong_signed_distance": wrong_answers(signed, expected),
                 "splitgrid_python_wrong": wrong_answers(ours, expected)}
        if entry["splitgrid_python_wrong"] != ours_in_sg_bench:
            sys.exit(f"bench_inside_open3d.py: {test['set']}: the splitgrid package has "
                     f"{entry['splitgrid_python_wrong']} wrong answers, sg-bench's Split Grid "
                     f"{ours_in_sg_bench}: the files are not the run's")
        entries.append(entry)
        print(f"{test['set']}: Open3D wrong on {entry['wrong_occupancy']} (occupancy), "
              f"{entry['wrong_signed_distance']} (signed distance) of {entry['decided']}",
              file=sys.stderr)

    document = {"tool": "bench_inside_open3d.py", "open3d_version": open3d.__version__,
                "splitgrid_version": splitgrid.__version__, "sets": entries}
    out = pathlib.Path(args.results).resolve().parent
    (out / "inside_open3d.json").write_text(json.dumps(document, indent=2) + "\n")
    chart = bench_charts.inside_tests(results, str(out), open3d=entries)
    print(f"bench_inside_open3d.py: wrote {out / 'inside_open3d.json'} and {chart}",
          file=sys.stderr)
    print(table(tests, entries, open3d.__version__))


def table(tests, entries, open3d_version):
    """The wrong-answer table: one row per set and method."""
    rows = ["| set | method | points (decided) | wrong | speed (1 thread) |",
            "|---|---|---|---|---|"]
    for test, entry in zip(tests, entries):
        size = f"{entry['points']:,} ({entry['decided']:,})"
        for m in test["methods"]:
            if m["status"] != "ok":
                rows.append(f"| {test['set']} | {label(m['method'])} | {size} | "
                            f"{m['status']} | - |")
                continue
            rows.append(f"| {test['set']} | {label(m['method'])} | {size} | {m['wrong']:,} | "
                        f"{m['points_per_s'] / 1e3:,.0f} k/s |")
        for query, key in (("compute_occupancy", "wrong_occupancy"),
                           ("compute_signed_distance", "wrong_signed_distance")):
            rows.append(f"| {test['set']} | Open3D {open3d_version} {query} | {size} | "
                        f"{entry[key]:,} | not timed |")
    return "\n".join(rows)


if __name__ == "__main__":
    main()
