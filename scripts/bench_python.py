#!/usr/bin/python3
"""Measures the splitgrid Python package's ray queries on the scenes of ../shared/meshes,
beside the same queries in C++ and in the peers a Python user would pick (docs/PYTHON.md,
"Benchmark").

Per scene and thread count (1 and 2 by default), on the same rays:

- Python: SplitGrid.cast_rays and test_occlusions, warm (the median of --repeats calls in one
  process) and cold (the first call of a fresh process, --repeats processes);
- C++, cold: sg-trace's own timing of its trace loop (one fresh process per run), alternated
  with the cold Python runs, so that both see the same machine: their ratio is the binding's
  cost;
- C++, warm, and Embree 3: sg-bench's incoherent workload, which is these random rays
  (sg-rays random --seed S+1 makes the rays sg-bench --seed S traces), median of --repeats
  passes in one process; Embree runs only inside sg-bench;
- Open3D's RaycastingScene (python3-open3d), the same rays.

Every peer's answers are checked first: the package's against a brute-force oracle written here
(double precision, all triangles, a sample of rays) and against sg-trace's hit file (every ray,
bit for bit), Open3D's against the same oracle sample. A peer that answers wrongly is reported
as wrong, with how many rays, and not timed. sg-bench checks its structures itself
(oracle_disagreements in its results.json, reported here).

Writes results.json to --out, and with --docs the table (stdout, Markdown) and the chart
docs/images/python_bench.png. Run with Debian's /usr/bin/python3 (numpy, Open3D, matplotlib),
after scripts/setup.sh: bash scripts/setup.sh && /usr/bin/python3 scripts/bench_python.py --docs
"""

import argparse
import json
import os
import pathlib
import platform
import statistics
import struct
import subprocess
import sys
import tempfile
import time

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests" / "python"))
import oracle  # noqa: E402
DEFAULT_SCENES = [
    "models/teapot.obj", "scanned/bunny_npm.obj", "gltf/smallpine/scene.gltf",
    "gltf/balloon/scene.gltf", "models/tachikoma.obj", "scenes/mountain.obj",
    "scenes/crytek_sponza_columns_shrubbery_part.obj", "scanned/lionstatue.obj",
    "scanned/stanford_bunny.obj", "scanned/nefertiti.obj", "scanned/igea_triangles.ply",
    "scanned/stanford_dragon_vrip_res2.ply", "scenes/bmw_m6.ply",
    "scanned/stanford_dragon_vrip.ply",
]
ORACLE_PAIRS = 2e8  # ray-triangle pairs of the oracle sample per workload
CAMERA = (1024, 768)

COLD_RUN = """
import sys, time, numpy as np, splitgrid
grid = splitgrid.load(sys.argv[1])
rays = np.load(sys.argv[2])
start = time.perf_counter()
grid.{query}(rays, threads=int(sys.argv[3]))
print(time.perf_counter() - start)
"""


def run(*args, **kwargs):
    done = subprocess.run([str(a) for a in args], capture_output=True, text=True, **kwargs)
    if done.returncode != 0:
        sys.exit(f"bench_python.py: {args[0]} failed ({done.returncode}): {done.stderr}")
    return done.stdout


def read_rays(path):
    """(n, 6) float32 rays of a ray file (docs/FORMAT.md): origin, direction; t_min 0 and
    t_max infinity, as sg-rays writes them (checked)."""
    data = pathlib.Path(path).read_bytes()
    assert data[:8] == b"SGRAY001"
    (count,) = struct.unpack("<Q", data[8:16])
    records = np.frombuffer(data[16:], dtype="<f4").reshape(count, 8)
    assert np.all(records[:, 6] == 0) and np.all(np.isinf(records[:, 7]))
    return np.ascontiguousarray(records[:, :6])


def read_hits(path):
    data = pathlib.Path(path).read_bytes()
    return np.frombuffer(data[16:], dtype=np.dtype([("id", "<u4"), ("t", "<f4"),
                                                    ("u", "<f4"), ("v", "<f4")]))


# ----- The oracle of the package's tests (tests/python/oracle.py: brute force in double
# precision over all triangles, with margins so that a float32 answer within rounding of an edge
# is not counted wrong).

def oracle_bounds(vertices, triangles, rays):
    """Per ray: the closest t no right answer is nearer than, and the one every right answer
    is at least as near as; inf for none."""
    bounds = oracle.closest_hits(vertices, triangles, rays)
    return bounds["t_loose"], bounds["t_strict"]


def wrong_closest(t_hit, loose, strict):
    """Rays whose t_hit (inf for a miss) the oracle's bounds rule out."""
    tol = oracle.T_TOLERANCE * np.maximum(1.0, np.abs(np.where(np.isfinite(t_hit), t_hit, 0)))
    missed = np.isinf(t_hit)
    return int(np.sum((missed & np.isfinite(strict))
                      | (~missed & ((t_hit < loose - tol) | (t_hit > strict + tol)))))


def wrong_occluded(occluded, loose, strict):
    return int(np.sum((~occluded & np.isfinite(strict)) | (occluded & np.isinf(loose))))


# ----- Counting: the binding's cost independent of the machine's load (valgrind's cachegrind,
# as ../shared/tools/kernel-cost counts sg-trace): per ray = (run with n rays - run with n / 10
# rays) / (0.9 n), so start-up, loading and checks cancel out.

COUNT_RUN = """
import sys, numpy as np, splitgrid
grid = splitgrid.load(sys.argv[1])
grid.cast_rays(np.load(sys.argv[2]), threads=1)
"""


def cachegrind_totals(command, folder):
    """Instructions, D1 misses and last-level misses of `command` (data reads and writes)."""
    out = folder / "cg.out"
    run("valgrind", "--tool=cachegrind", "--cache-sim=yes", f"--cachegrind-out-file={out}",
        *command)
    for line in out.read_text().splitlines():
        if line.startswith("events:"):
            events = line.split()[1:]
        if line.startswith("summary:"):
            totals = dict(zip(events, map(int, line.split()[1:])))
    return {"instructions": totals["Ir"], "d1_misses": totals["D1mr"] + totals["D1mw"],
            "ll_misses": totals["DLmr"] + totals["DLmw"]}


def counted_cost(tools, sg_file, ray_file, count, folder):
    """Per-ray counts of cast_rays (1 thread) and of sg-trace on `count` rays of `ray_file`,
    evenly strided over it."""
    data = pathlib.Path(ray_file).read_bytes()
    records = np.frombuffer(data[16:], dtype=np.uint8).reshape(-1, 32)
    picked = records[np.linspace(0, len(records) - 1, count).astype(np.int64)]
    result = {}
    for name in ("python", "sg_trace"):
        runs = []
        for subset in (picked[::10], picked):
            (folder / "count.rays").write_bytes(
                data[:8] + struct.pack("<Q", len(subset)) + subset.tobytes())
            np.save(folder / "count.npy", read_rays(folder / "count.rays"))
            if name == "python":
                command = [sys.executable, "-c", COUNT_RUN, sg_file, folder / "count.npy"]
            else:
                command = [tools / "sg-trace", sg_file, "--rays", folder / "count.rays", "-o",
                           folder / "count.hits", "--threads", 1, "-q"]
            runs.append(cachegrind_totals(command, folder))
        extra = len(picked) - len(picked[::10])
        result[name] = {key: (runs[1][key] - runs[0][key]) / extra for key in runs[0]}
    return result


# ----- Timing.

def median_seconds(work, repeats):
    work()  # warm: pages touched, oneTBB's workers started
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        work()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def measure_scene(args, scene_path, folder, splitgrid, open3d):
    name = scene_path.stem if scene_path.stem != "scene" else scene_path.parent.name
    print(f"{name}: building and making rays", file=sys.stderr)
    tools = pathlib.Path(args.build) / "apps"
    sg_file = folder / f"{name}.sg"
    run(tools / "sg-build", scene_path, "-o", sg_file, "-q")
    workloads = {}
    random_file = folder / f"{name}_random.rays"
    run(tools / "sg-rays", "random", sg_file, "--count", args.rays, "--seed", args.seed + 1,
        "-o", random_file, "-q")
    workloads["random"] = random_file
    camera_file = folder / f"{name}_camera.rays"
    run(tools / "sg-rays", "camera", sg_file, "--width", CAMERA[0], "--height", CAMERA[1],
        "-o", camera_file, "-q")
    workloads["camera"] = camera_file

    grid = splitgrid.load(sg_file)
    vertices, triangles = grid.vertices, grid.triangles.astype(np.int64)
    result = {"scene": name, "source": str(scene_path.relative_to(args.meshes)),
              "triangles": len(triangles), "workloads": []}
    o3d_scene = None
    if open3d is not None:
        o3d_scene = open3d.t.geometry.RaycastingScene()
        o3d_scene.add_triangles(open3d.core.Tensor(np.ascontiguousarray(vertices)),
                                open3d.core.Tensor(grid.triangles.copy()))

    for workload, ray_file in workloads.items():
        rays = read_rays(ray_file)
        np.save(folder / "rays.npy", rays)
        sample_size = int(min(args.oracle_rays, max(20, ORACLE_PAIRS / len(triangles))))
        sample = np.linspace(0, len(rays) - 1, sample_size).astype(np.int64)
        loose, strict = oracle_bounds(vertices, triangles, rays[sample])
        for query, any_hit in (("cast_rays", False), ("test_occlusions", True)):
            print(f"{name}, {workload}, {query}: checking", file=sys.stderr)
            entry = {"workload": workload, "query": query, "rays": len(rays),
                     "oracle_rays": sample_size, "peers": {}}
            answer = getattr(grid, query)(rays)
            if any_hit:
                ours_wrong = wrong_occluded(answer[sample], loose, strict)
                entry["hit_fraction"] = float(answer.mean())
            else:
                ours_wrong = wrong_closest(answer["t_hit"][sample], loose, strict)
                entry["hit_fraction"] = float(np.mean(answer["primitive_ids"] != 0xFFFFFFFF))
            entry["oracle_disagreements"] = ours_wrong
            # sg-trace on the same file and rays: the same answers, every ray, bit for bit.
            hits_file = folder / "hits.bin"
            run(tools / "sg-trace", sg_file, "--rays", ray_file, "-o", hits_file, "-q",
                *(["--any-hit"] if any_hit else []))
            hits = read_hits(hits_file)
            if any_hit:
                same = np.array_equal(answer, hits["id"] != 0xFFFFFFFF)
            else:
                same = (np.array_equal(answer["primitive_ids"], hits["id"]) and np.array_equal(
                    answer["t_hit"], np.where(hits["id"] != 0xFFFFFFFF, hits["t"], np.inf)))
            entry["same_as_sg_trace"] = bool(same)

            if o3d_scene is not None:
                tensor = open3d.core.Tensor(rays)
                theirs = getattr(o3d_scene, query)(tensor)
                if any_hit:
                    theirs = theirs.numpy().astype(bool)
                    wrong = wrong_occluded(theirs[sample], loose, strict)
                    differ = int(np.sum(theirs != answer))
                else:
                    theirs = theirs["t_hit"].numpy()
                    wrong = wrong_closest(theirs[sample], loose, strict)
                    ours_hit = answer["primitive_ids"] != 0xFFFFFFFF
                    differ = int(np.sum(ours_hit != np.isfinite(theirs)))
                peer = {"oracle_disagreements": wrong, "hit_or_miss_differs_from_splitgrid": differ}
                if wrong == 0:
                    peer["mrays_per_s"] = {
                        str(t): len(rays) / 1e6 / median_seconds(
                            lambda: getattr(o3d_scene, query)(tensor, nthreads=t), args.repeats)
                        for t in args.threads}
                entry["peers"]["open3d"] = peer

            if ours_wrong == 0 and same:
                print(f"{name}, {workload}, {query}: timing", file=sys.stderr)
                entry["python_warm"] = {}
                entry["python_cold"] = {}
                entry["sg_trace"] = {}
                for t in args.threads:
                    entry["python_warm"][str(t)] = len(rays) / 1e6 / median_seconds(
                        lambda: getattr(grid, query)(rays, threads=t), args.repeats)
                    cold, trace = [], []
                    for _ in range(args.repeats):  # alternated: C++, Python, C++, Python, ...
                        out = run(tools / "sg-trace", sg_file, "--rays", ray_file, "-o",
                                  hits_file, "--threads", t, "--json",
                                  *(["--any-hit"] if any_hit else []))
                        trace.append(json.loads(out)["seconds"])
                        out = run(sys.executable, "-c", COLD_RUN.format(query=query), sg_file,
                                  folder / "rays.npy", t)
                        cold.append(float(out))
                    entry["sg_trace"][str(t)] = len(rays) / 1e6 / statistics.median(trace)
                    entry["python_cold"][str(t)] = len(rays) / 1e6 / statistics.median(cold)
                    # Each Python run beside the sg-trace run just before it: the two saw the
                    # same load, so the median of these ratios is steadier than a ratio of
                    # medians on a busy machine.
                    entry.setdefault("cold_ratio", {})[str(t)] = statistics.median(
                        c_seconds / p_seconds for c_seconds, p_seconds in zip(trace, cold))
            result["workloads"].append(entry)

    if args.counted:
        print(f"{name}: counting with cachegrind", file=sys.stderr)
        result["counted"] = counted_cost(tools, sg_file, workloads["random"], args.counted,
                                         folder)

    # sg-bench: our structure and Embree on its incoherent workload, these random rays.
    print(f"{name}: sg-bench", file=sys.stderr)
    bench_dir = folder / f"{name}_bench"
    run(tools / "sg-bench", scene_path, "-o", bench_dir, "--structures", "splitgrid,embree",
        "--threads", ",".join(map(str, args.threads)), "--incoherent-rays", args.rays,
        "--seed", args.seed, "--trace-repeats", args.repeats, "--build-repeats", 1,
        "--width", 32, "--height", 24, "--bounces", 0, "--watertight-rays", 0, "--no-sweep",
        "--no-charts", "-q")
    bench = json.loads((bench_dir / "results.json").read_text())
    result["sg_bench"] = {}
    for structure in bench["scenes"][0]["structures"]:
        for w in structure["workloads"]:
            if w["workload"] == "incoherent":
                result["sg_bench"][structure["structure"]] = {
                    "mrays_per_s": w["mrays_per_s"], "hit_fraction": w["hit_fraction"],
                    "oracle_disagreements": w["oracle_disagreements"],
                    "oracle_rays": w["oracle_rays"]}
    result["embree_version"] = bench.get("embree_version", "")
    return result


# ----- Point queries (--points): compute_distance and compute_occupancy against Open3D and,
# through sg-bench on the very same points, the C++ Split Grid and CGAL.

# The closed scans of ../shared/meshes (every edge in an even number of triangles).
POINT_SCENES = ["scanned/bunny_npm.obj", "scanned/nefertiti.obj",
                "scanned/stanford_dragon_vrip_res2.ply", "scanned/igea_triangles.ply",
                "scanned/stanford_dragon_vrip.ply"]
POINT_ORACLE_PAIRS = 5e7  # point-triangle pairs of the oracle sample per point set


def read_point_file(path):
    """(n, 3) float32 points of a point file (docs/FORMAT.md 6.1)."""
    data = pathlib.Path(path).read_bytes()
    assert data[:8] == b"SGPTS001"
    (count,) = struct.unpack("<Q", data[8:16])
    return np.frombuffer(data[16:], dtype="<f4").reshape(count, 3)


def wrong_distances(distances, expected, magnitude):
    """Distances that differ from the oracle's (float64) by more than 1e-5 relative plus 4
    float ulps of the scene's largest coordinate `magnitude`: what a computation in float
    (Open3D's, through Embree's point query) can reach near the surface, where the distance
    is small against the coordinates (Open3D's errors there stay below one such ulp)."""
    tolerance = 1e-5 * expected + 4 * 2.0 ** -23 * magnitude
    return int(np.sum(~(np.abs(distances - expected) <= tolerance)))


def oracle_sides(vertices, triangles, points, band):
    """1 inside, 0 outside by the winding number (tests/python/oracle.py), NaN for a point the
    winding number does not decide or that lies within compute_occupancy's band of the
    surface (2^-17 of the box's largest coordinate: either answer is right there)."""
    sides = []
    step = max(1, int(4e6 // len(triangles)))  # the winding number holds points x triangles
    for start in range(0, len(points), step):
        chunk = points[start:start + step]
        w = np.abs(oracle.winding_numbers(vertices, triangles, chunk))
        d, _ = oracle.point_distances(vertices, triangles, chunk)
        side = np.where(np.abs(w - 1) < 1e-3, 1.0, np.where(w < 1e-3, 0.0, np.nan))
        sides.append(np.where(d > band, side, np.nan))
    return np.concatenate(sides)


def machine(splitgrid):
    """Where the run ran, for the results' "machine"."""
    return {"cpu": platform.processor() or platform.machine(),
            "hardware_threads": os.cpu_count(), "kernel_isa": splitgrid.kernel_isa(),
            "python": platform.python_version(), "numpy": np.__version__}


def rate(work, count, repeats):
    return count / median_seconds(work, repeats)


def measure_points_scene(args, scene_path, folder, splitgrid, open3d):
    """compute_distance and compute_occupancy of the splitgrid package and Open3D on the points
    sg-bench measured its Split Grid and CGAL on (sg-bench --save-points), every answer checked
    against the oracle before it is timed."""
    name = scene_path.stem
    tools = pathlib.Path(args.build) / "apps"
    points_dir = folder / f"{name}_points"
    bench_dir = folder / f"{name}_bench"
    points_dir.mkdir(exist_ok=True)
    print(f"{name}: sg-bench (Split Grid and CGAL)", file=sys.stderr)
    run(tools / "sg-bench", scene_path, "-o", bench_dir, "--structures", "splitgrid",
        "--threads", ",".join(map(str, args.threads)), "--count-rays", 0,
        "--occupancy-points", args.occupancy_points, "--closest-points", args.distance_points,
        "--inside-vertices", 0, "--save-points", points_dir, "--seed", args.seed,
        "--trace-repeats", args.repeats, "--build-repeats", 1, "--incoherent-rays", 1000,
        "--width", 32, "--height", 24, "--bounces", 0, "--watertight-rays", 0, "--no-sweep",
        "--no-charts", "-q")
    bench = json.loads((bench_dir / "results.json").read_text())
    scene = bench["scenes"][0]
    grid = splitgrid.load(points_dir / f"{name}.sg")
    vertices, triangles = grid.vertices, grid.triangles.astype(np.int64)
    magnitude = float(np.abs(vertices).max())
    band = 2.0 ** -17 * magnitude
    result = {"scene": name, "source": str(scene_path.relative_to(args.meshes)),
              "triangles": len(triangles), "closed": scene["edges"]["closed"],
              "cgal_version": bench["cgal_version"], "sets": []}
    o3d_scene = open3d.t.geometry.RaycastingScene()
    o3d_scene.add_triangles(open3d.core.Tensor(np.ascontiguousarray(vertices)),
                            open3d.core.Tensor(np.ascontiguousarray(grid.triangles)))
    sample_size = int(min(args.oracle_rays, max(20, POINT_ORACLE_PAIRS / len(triangles))))
    for point_set in ("random", "near"):
        points = read_point_file(points_dir / f"{name}.{point_set}.points")
        entry = {"points": point_set, "distance_points": args.distance_points,
                 "occupancy_points": args.occupancy_points, "oracle_points": sample_size}
        for query in ("closest", "occupancy"):
            w = next(w for w in scene["point_workloads"]
                     if w["query"] == query and w["points"] == point_set)
            for m in w["methods"]:
                entry[f"sg_bench_{m['method']}_{query}"] = {
                    "status": m["status"], "points_per_s": m["queries_per_s"]}
        print(f"{name}, {point_set}: checking", file=sys.stderr)
        near = np.ascontiguousarray(points[:args.distance_points])
        sample = np.linspace(0, len(near) - 1, sample_size).astype(np.int64)
        expected, _ = oracle.point_distances(vertices, triangles, near[sample])
        tensor = open3d.core.Tensor(near)
        entry["python_distance_wrong"] = wrong_distances(grid.compute_distance(near)[sample],
                                                         expected, magnitude)
        entry["open3d_distance_wrong"] = wrong_distances(
            o3d_scene.compute_distance(tensor).numpy()[sample], expected, magnitude)
        inside = np.ascontiguousarray(points[:args.occupancy_points])
        occupancy_sample = np.linspace(0, len(inside) - 1, sample_size).astype(np.int64)
        sides = oracle_sides(vertices, triangles, inside[occupancy_sample], band)
        decided = ~np.isnan(sides)
        entry["occupancy_oracle_decided"] = int(decided.sum())
        entry["python_occupancy_wrong"] = int(np.sum(
            grid.compute_occupancy(inside)[occupancy_sample][decided] != sides[decided]))
        entry["open3d_occupancy_wrong"] = int(np.sum(
            o3d_scene.compute_occupancy(open3d.core.Tensor(inside)).numpy()[occupancy_sample]
            [decided] != sides[decided]))
        print(f"{name}, {point_set}: timing", file=sys.stderr)
        for t in args.threads:
            key = str(t)
            if entry["python_distance_wrong"] == 0:
                entry.setdefault("python_distance", {})[key] = rate(
                    lambda: grid.compute_distance(near, threads=t), len(near), args.repeats)
            if entry["open3d_distance_wrong"] == 0:
                entry.setdefault("open3d_distance", {})[key] = rate(
                    lambda: o3d_scene.compute_distance(tensor, nthreads=t), len(near),
                    args.repeats)
            if entry["python_occupancy_wrong"] == 0:
                entry.setdefault("python_occupancy", {})[key] = rate(
                    lambda: grid.compute_occupancy(inside, threads=t), len(inside), args.repeats)
        result["sets"].append(entry)
    return result


def measure_scenes(args, scenes, measure):
    """`measure(path, work_folder)` of every scene file of `scenes` (relative to --meshes) that
    is there, with a temporary folder under --out; returns --out, the results and the
    seconds it took."""
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    results = []
    start = time.time()
    with tempfile.TemporaryDirectory(dir=out) as work:
        for scene in scenes:
            path = args.meshes / scene
            if not path.is_file():
                print(f"bench_python.py: {path} is absent, skipped", file=sys.stderr)
                continue
            results.append(measure(path, pathlib.Path(work)))
    return out, results, time.time() - start


def points_main(args, splitgrid, open3d):
    out, results, seconds = measure_scenes(
        args, args.scenes or POINT_SCENES,
        lambda path, work: measure_points_scene(args, path, work, splitgrid, open3d))
    document = {
        "tool": "bench_python.py --points", "splitgrid_version": splitgrid.__version__,
        "open3d_version": open3d.__version__,
        "machine": machine(splitgrid),
        "plan": {"distance_points": args.distance_points,
                 "occupancy_points": args.occupancy_points, "repeats": args.repeats,
                 "threads": args.threads, "seed": args.seed, "oracle_points": args.oracle_rays},
        "run_seconds": seconds, "scenes": results}
    (out / "points.json").write_text(json.dumps(document, indent=2) + "\n")
    print(f"bench_python.py: wrote {out / 'points.json'}", file=sys.stderr)
    if args.docs:
        print(points_report(results, args.threads))


def ratio_text(a, b):
    return f"{a / b:.2f}x" if a and b and a == a and b == b else "-"


def points_report(results, threads):
    """The tables of docs/notebook/points.md: thousands of points per second, and the targets'
    ratios at the median over the scenes."""
    def k(value):
        return f"{value / 1e3:,.1f}" if value == value else "-"

    def bench(entry, method, query, t):
        return entry.get(f"sg_bench_{method}_{query}", {}).get("points_per_s", {}).get(t, NAN)

    distance_rows, occupancy_rows = [], []
    ratios = {}
    for r in results:
        for e in r["sets"]:
            for t in map(str, threads):
                py = e.get("python_distance", {}).get(t, NAN)
                o3d = e.get("open3d_distance", {}).get(t, NAN)
                cgal = bench(e, "cgal", "closest", t)
                cpp = bench(e, "splitgrid", "closest", t)
                distance_rows.append([r["scene"], e["points"], t, k(py), k(o3d),
                                      ratio_text(py, o3d), k(cpp), k(cgal),
                                      ratio_text(py, cgal), ratio_text(cpp, cgal)])
                pyo = e.get("python_occupancy", {}).get(t, NAN)
                cppo = bench(e, "splitgrid", "occupancy", t)
                cgalo = bench(e, "cgal", "occupancy", t)
                occupancy_rows.append([r["scene"], e["points"], t, k(pyo), k(cppo), k(cgalo),
                                       ratio_text(pyo, cgalo), ratio_text(cppo, cgalo),
                                       f"wrong on {e['open3d_occupancy_wrong']} of "
                                       f"{e['occupancy_oracle_decided']}"])
                for key, a, b in (("distance: Python / Open3D", py, o3d),
                                  ("distance: Python / CGAL", py, cgal),
                                  ("distance: C++ / CGAL", cpp, cgal),
                                  ("occupancy: Python / CGAL", pyo, cgalo),
                                  ("occupancy: C++ / CGAL", cppo, cgalo)):
                    if a == a and b == b and a and b:
                        ratios.setdefault((key, e["points"], t), {})[r["scene"]] = a / b
    checks = [[r["scene"], e["points"],
               f"{e['python_distance_wrong']} / {e['open3d_distance_wrong']} of "
               f"{e['oracle_points']}",
               f"{e['python_occupancy_wrong']} / {e['open3d_occupancy_wrong']} of "
               f"{e['occupancy_oracle_decided']}"]
              for r in results for e in r["sets"]]
    summary = [[key, points, t, f"{statistics.median(v.values()):.2f}x",
                f"{min(v.values()):.2f}-{max(v.values()):.2f}", str(len(v))]
               for (key, points, t), v in sorted(ratios.items())]
    return "\n\n".join([
        markdown(["scene", "points", "threads", "Python compute_distance",
                  "Open3D compute_distance", "Python / Open3D", "C++ closest_points",
                  "CGAL AABB tree", "Python / CGAL", "C++ / CGAL"], distance_rows),
        markdown(["scene", "points", "threads", "Python compute_occupancy",
                  "C++ compute_occupancy", "CGAL Side_of_triangle_mesh", "Python / CGAL",
                  "C++ / CGAL", "Open3D compute_occupancy"], occupancy_rows),
        markdown(["scene", "points", "wrong distances: Python / Open3D (oracle sample)",
                  "wrong sides: Python / Open3D (decided sample)"], checks),
        markdown(["ratio", "points", "threads", "median over scenes", "range", "scenes"],
                 summary)])


# ----- Report.

NAN = float("nan")


def entry_of(scene, workload="random", query="cast_rays"):
    return next(e for e in scene["workloads"] if e["workload"] == workload
                and e["query"] == query)


def markdown(columns, rows):
    lines = ["| " + " | ".join(columns) + " |", "|---" * len(columns) + "|"]
    return "\n".join(lines + ["| " + " | ".join(row) + " |" for row in rows])


def speed_table(results, threads):
    """Mrays/s of cast_rays on the random rays, per scene and thread count; the cold ratio
    (Python's speed over sg-trace's, both the first query of a fresh process, the median of
    the alternated pairs) is the binding's cost."""
    columns = ["scene", "triangles", "threads", "Python warm", "sg-bench (C++) warm",
               "Python cold", "sg-trace (C++) cold", "cold ratio", "Embree 3", "Open3D 0.16"]
    rows = []
    for r in results:
        entry = entry_of(r)
        o3d = entry["peers"].get("open3d")
        for t in map(str, threads):
            bench = {name: r["sg_bench"].get(name, {}).get("mrays_per_s", {}).get(t, NAN)
                     for name in ("splitgrid", "embree")}
            if o3d is None:
                o3d_text = "not installed"
            elif "mrays_per_s" in o3d:
                o3d_text = f"{o3d['mrays_per_s'][t]:.2f}"
            else:
                o3d_text = f"wrong on {o3d['oracle_disagreements']} of {entry['oracle_rays']}"
            rows.append([r["scene"], f"{r['triangles']:,}", t,
                         f"{entry.get('python_warm', {}).get(t, NAN):.2f}",
                         f"{bench['splitgrid']:.2f}",
                         f"{entry.get('python_cold', {}).get(t, NAN):.2f}",
                         f"{entry.get('sg_trace', {}).get(t, NAN):.2f}",
                         f"{entry.get('cold_ratio', {}).get(t, NAN):.3f}",
                         f"{bench['embree']:.2f}", o3d_text])
    return markdown(columns, rows)


def ratio_table(results, threads):
    """The cold ratio of every query and workload: median over the scenes, with its range."""
    rows = []
    for workload in ("random", "camera"):
        for query in ("cast_rays", "test_occlusions"):
            row = [workload, query]
            for t in map(str, threads):
                ratios = [entry_of(r, workload, query)["cold_ratio"][t]
                          for r in results if "cold_ratio" in entry_of(r, workload, query)]
                row.append(f"{statistics.median(ratios):.3f} ({min(ratios):.2f}-"
                           f"{max(ratios):.2f})" if ratios else "-")
            rows.append(row)
    return markdown(["rays", "query"] + [f"{t} thread{'s' if t > 1 else ''}" for t in threads],
                    rows)


def counted_table(results):
    """Counted per ray with cachegrind: cast_rays (1 thread) beside sg-trace."""
    rows = []
    for r in results:
        if "counted" not in r:
            continue
        p, c = r["counted"]["python"], r["counted"]["sg_trace"]
        rows.append([r["scene"], f"{p['instructions']:,.0f} / {c['instructions']:,.0f}",
                     f"{p['d1_misses']:.1f} / {c['d1_misses']:.1f}",
                     f"{p['ll_misses']:.2f} / {c['ll_misses']:.2f}"])
    return markdown(["scene", "instructions", "L1 data misses", "last-level misses"], rows)


def open3d_table(results):
    """Open3D's answers against the oracle and against splitgrid's."""
    rows = []
    for r in results:
        for workload in ("random", "camera"):
            row = [r["scene"], workload]
            for query in ("cast_rays", "test_occlusions"):
                entry = entry_of(r, workload, query)
                peer = entry["peers"].get("open3d")
                if peer is None:
                    row += ["-", "-"]
                    continue
                row += [f"{peer['oracle_disagreements']} of {entry['oracle_rays']}",
                        f"{peer['hit_or_miss_differs_from_splitgrid']:,} of "
                        f"{entry['rays']:,}"]
            rows.append(row)
    return markdown(["scene", "rays", "cast_rays: wrong (oracle sample)",
                     "cast_rays: hit/miss unlike splitgrid", "test_occlusions: wrong (oracle "
                     "sample)", "test_occlusions: unlike splitgrid"], rows)


def chart(results, threads, path):
    """Mrays/s of cast_rays on the random rays: Python and sg-trace as the first query of a
    fresh process (the binding's cost), sg-bench's warm C++ figure and Embree's."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    series = [("Python cast_rays (cold)", "#d62728", lambda r, t: entry_of(r)["python_cold"][t]),
              ("C++ sg-trace (cold)", "#ff9896", lambda r, t: entry_of(r)["sg_trace"][t]),
              ("C++ sg-bench (warm)", "#7f7f7f",
               lambda r, t: r["sg_bench"]["splitgrid"]["mrays_per_s"][t]),
              ("Embree 3 (sg-bench)", "#9467bd",
               lambda r, t: r["sg_bench"]["embree"]["mrays_per_s"][t])]
    wrong = [r["scene"] for r in results
             if "mrays_per_s" not in entry_of(r)["peers"].get("open3d", {"mrays_per_s": 0})]
    fig, axes = plt.subplots(len(threads), 1, figsize=(11, 3.6 * len(threads)), squeeze=False)
    x = np.arange(len(results))
    width = 0.8 / len(series)
    for row, t in enumerate(map(str, threads)):
        ax = axes[row][0]
        for k, (label, colour, value) in enumerate(series):
            ax.bar(x + (k - (len(series) - 1) / 2) * width,
                   [value(r, t) for r in results], width, label=label, color=colour)
        ax.set_xticks(x)
        ax.set_xticklabels([r["scene"] for r in results], rotation=30, ha="right", fontsize=8)
        ax.set_ylabel("Mrays/s")
        title = f"cast_rays, 10^6 random rays, {t} thread{'s' if t != '1' else ''}"
        if wrong:
            title += f"; Open3D 0.16 answered wrongly on {len(wrong)} of {len(results)} " \
                     "scenes (not timed)"
        ax.set_title(title, fontsize=10)
        ax.legend(fontsize=8, ncol=2)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--meshes", default=str(ROOT.parent / "shared" / "meshes"),
                        help="folder of the shared scenes (default ../shared/meshes)")
    parser.add_argument("--scenes", nargs="*",
                        help="scene files relative to --meshes (default: every scene; with "
                             "--points the closed scans)")
    parser.add_argument("--build", default=str(ROOT / "build"), help="the build folder")
    parser.add_argument("--out", default=str(ROOT / "build" / "bench-python"),
                        help="folder for results.json and the intermediate files")
    parser.add_argument("--rays", type=int, default=1_000_000, help="random rays per scene")
    parser.add_argument("--repeats", type=int, default=5, help="timed runs (median)")
    parser.add_argument("--threads", default="1,2", help="thread counts, comma-separated")
    parser.add_argument("--oracle-rays", type=int, default=1000,
                        help="oracle sample per workload (fewer on big scenes)")
    parser.add_argument("--seed", type=int, default=1, help="sg-bench's --seed")
    parser.add_argument("--counted", type=int, default=0,
                        help="also count instructions and cache misses per ray of cast_rays and "
                             "sg-trace on this many random rays with valgrind (0: not)")
    parser.add_argument("--docs", action="store_true",
                        help="print the Markdown tables and write docs/images/python_bench.png")
    parser.add_argument("--report", metavar="RESULTS_JSON",
                        help="measure nothing: the tables and chart of an earlier results.json "
                             "(or, with --points, the tables of an earlier points.json)")
    parser.add_argument("--points", action="store_true",
                        help="measure the point queries instead: compute_distance and "
                             "compute_occupancy against Open3D and (through sg-bench, built with "
                             "SG_WITH_CGAL, on the same points) CGAL, on the closed scenes; "
                             "writes points.json to --out")
    parser.add_argument("--distance-points", type=int, default=20_000,
                        help="with --points: points per set for compute_distance")
    parser.add_argument("--occupancy-points", type=int, default=200_000,
                        help="with --points: points per set for compute_occupancy")
    args = parser.parse_args()
    if args.report:
        document = json.loads(pathlib.Path(args.report).read_text())
        if args.points:
            print(points_report(document["scenes"], document["plan"]["threads"]))
        else:
            report(document["scenes"], document["plan"]["threads"])
        return
    args.threads = [int(t) for t in args.threads.split(",")]
    args.meshes = pathlib.Path(args.meshes)
    sys.path.insert(0, str(pathlib.Path(args.build) / "python"))
    os.environ["PYTHONPATH"] = os.pathsep.join(
        [str(pathlib.Path(args.build) / "python"), os.environ.get("PYTHONPATH", "")])
    import splitgrid
    try:
        import open3d
    except ImportError:
        open3d = None
        print("bench_python.py: open3d not installed (python3-open3d): not measured",
              file=sys.stderr)

    if args.points:
        if open3d is None:
            sys.exit("bench_python.py: --points needs open3d (python3-open3d)")
        points_main(args, splitgrid, open3d)
        return
    out, results, seconds = measure_scenes(
        args, args.scenes or DEFAULT_SCENES,
        lambda path, work: measure_scene(args, path, work, splitgrid, open3d))
    document = {
        "tool": "bench_python.py", "splitgrid_version": splitgrid.__version__,
        "open3d_version": open3d.__version__ if open3d else "",
        "machine": machine(splitgrid),
        "plan": {"rays": args.rays, "repeats": args.repeats, "threads": args.threads,
                 "seed": args.seed, "camera": list(CAMERA), "oracle_rays": args.oracle_rays,
                 "counted_rays": args.counted},
        "run_seconds": seconds, "scenes": results}
    (out / "results.json").write_text(json.dumps(document, indent=2) + "\n")
    print(f"bench_python.py: wrote {out / 'results.json'}", file=sys.stderr)
    if args.docs:
        report(results, args.threads)


def report(results, threads):
    """The tables (stdout) and the chart of docs/PYTHON.md."""
    chart(results, threads, ROOT / "docs" / "images" / "python_bench.png")
    print(speed_table(results, threads), ratio_table(results, threads), counted_table(results),
          open3d_table(results), sep="\n\n")


if __name__ == "__main__":
    main()
