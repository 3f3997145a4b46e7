#!/usr/bin/python3
"""Charts of an sg-bench run (results.json, schema in docs/BENCH.md).

Usage: bench_charts.py RESULTS_JSON OUT_DIR

Writes into OUT_DIR, each PNG replaced atomically (written beside it, then renamed), and
prints one line "wrote PATH" on stdout per chart (sg-bench reads these lines; everything
else, warnings and errors, goes to stderr):
  figure3.png             the poster's Figure 3 for every scene: traversal time of the path
                          workload, build time and memory per structure
  speed_vs_accuracy.png   Mrays/s against leaks per million on rays from inside a closed
                          sphere, per structure, triangle test and padding
  sweep_build_vs_trace.png  the Split Grid parameter sweep: build time against trace speed,
                          marker area proportional to bytes per triangle
  memory_scaling.png      bytes, references and peak build memory per triangle against
                          scene size
  dynamic.png             the dynamic workload: time per frame (update + trace) against rays
                          per frame, per scene and structure
  point_workloads.png     the point and multi-hit workloads: queries per second of every
                          method (our structures, CGAL) per scene, one panel per workload
  inside_tests.png        the inside tests: points per second on one thread against wrong
                          answers, per method and point set (with Open3D's wrong answers when
                          scripts/bench_inside_open3d.py has added them)
Charts whose data the run did not measure (no sweep, no scale series) are skipped.
"""

import json
import os
import secrets
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from bench_common import colour, crossing, frame_line, human, label  # noqa: E402


def save(fig, path):
    """Writes the figure beside `path` first, so a reader never sees half a PNG. The
    temporary file is named as the tools name theirs (".<name>.tmp-<pid>-<random>"), so that
    sg-bench removes it if this script is killed part-way."""
    tmp = os.path.join(os.path.dirname(path), ".%s.tmp-%d-%s" % (
        os.path.basename(path), os.getpid(), secrets.token_hex(8)))
    try:
        fig.savefig(tmp, dpi=110, bbox_inches="tight", format="png")
        os.replace(tmp, path)
    finally:
        plt.close(fig)
        if os.path.exists(tmp):
            os.remove(tmp)


def workload(structure, name):
    for w in structure["workloads"]:
        if w["workload"] == name:
            return w
    return None


def figure3(results, out_dir):
    scenes = results["scenes"]
    if not scenes:
        return None
    threads = str(results["plan"]["thread_counts"][0])
    structures = [s["structure"] for s in scenes[0]["structures"]]
    fig, axes = plt.subplots(3, 1, figsize=(max(7, 1.2 * len(scenes) + 3), 10), sharex=True)
    width = 0.8 / max(1, len(structures))
    panels = [
        ("traversal: path workload (s, %s thread%s)" % (threads, "" if threads == "1" else "s"),
         lambda s: workload(s, "path")["rays"] / (1e6 * workload(s, "path")["mrays_per_s"][threads])
         if workload(s, "path") and workload(s, "path")["mrays_per_s"][threads] > 0 else 0.0),
        ("build (s, %s thread%s)" % (threads, "" if threads == "1" else "s"),
         lambda s: s["build_seconds"][threads]),
        ("memory: structure + mesh (bytes/triangle)", lambda s: s["total_bytes_per_triangle"]),
    ]
    for ax, (title, value) in zip(axes, panels):
        for k, name in enumerate(structures):
            xs, ys = [], []
            for i, scene in enumerate(scenes):
                for s in scene["structures"]:
                    if s["structure"] == name:
                        xs.append(i + (k - (len(structures) - 1) / 2) * width)
                        ys.append(value(s))
            ax.bar(xs, ys, width=width, color=colour(name), label=label(name))
        ax.set_title(title, fontsize=10)
        ax.set_yscale("log")
        ax.grid(axis="y", alpha=0.3)
    axes[-1].set_xticks(range(len(scenes)))
    axes[-1].set_xticklabels(["%s\n%s tris" % (s["scene"], human(s["triangles"])) for s in scenes],
                             rotation=45, ha="right", fontsize=8)
    axes[0].legend(ncol=min(len(structures), 3), fontsize=8, loc="upper left")
    fig.suptitle("Figure 3 of the Split Grid poster, measured here (log scales)")
    path = os.path.join(out_dir, "figure3.png")
    save(fig, path)
    return path


def speed_vs_accuracy(results, out_dir):
    points = results["accuracy"]
    if not points:
        return None
    positions = sorted({p["position"] for p in points}, key=lambda p: p != "origin")
    fig, axes = plt.subplots(1, len(positions), figsize=(6 * len(positions), 5), sharey=True)
    if len(positions) == 1:
        axes = [axes]
    markers = {"watertight": "o", "watertight-nopad": "s", "moller-trumbore": "^",
               "moller-trumbore-nopad": "v", "default": "D", "robust": "P"}
    for ax, position in zip(axes, positions):
        for p in points:
            if p["position"] != position:
                continue
            ax.scatter(p["mrays_per_s"], max(p["misses_per_million"], 0.1), s=60,
                       color=colour(p["structure"]), marker=markers.get(p["variant"], "x"),
                       label="%s, %s" % (label(p["structure"]), p["variant"]))
        ax.set_yscale("log")
        ax.set_xlabel("Mrays/s (1 thread)")
        ax.set_title("sphere at %s" % ("the origin" if position == "origin" else
                                       "(148376, 1234, -223423)"), fontsize=10)
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("leaks per million rays from inside (0 drawn at 0.1)")
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="center left", bbox_to_anchor=(1.0, 0.5), fontsize=8)
    fig.suptitle("Speed against accuracy: %d rays per position" % points[0]["rays"])
    path = os.path.join(out_dir, "speed_vs_accuracy.png")
    save(fig, path)
    return path


def sweep(results, out_dir):
    points = results["sweep"]["points"]
    if not points:
        return None
    fig, ax = plt.subplots(figsize=(8, 6))
    parameters = sorted({p["parameter"] for p in points})
    cmap = plt.get_cmap("tab10")
    for i, parameter in enumerate(parameters):
        sel = [p for p in points if p["parameter"] == parameter]
        ax.scatter([p["build_seconds"] for p in sel], [p["mrays_per_s"] for p in sel],
                   s=[4 * p["total_bytes_per_triangle"] for p in sel], alpha=0.6,
                   color="black" if parameter == "default" else cmap(i % 10), label=parameter)
        for p in sel:
            ax.annotate(p["value"] or "default", (p["build_seconds"], p["mrays_per_s"]),
                        fontsize=7, xytext=(4, 2), textcoords="offset points")
    ax.set_xlabel("build time (s, %d threads)" % results["sweep"]["threads"])
    ax.set_ylabel("path workload (Mrays/s, %d threads)" % results["sweep"]["threads"])
    ax.set_title("Split Grid parameter sweep on %s (marker area ~ bytes/triangle)"
                 % results["sweep"]["scene"], fontsize=10)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="best")
    path = os.path.join(out_dir, "sweep_build_vs_trace.png")
    save(fig, path)
    return path


def memory_scaling(results, out_dir):
    points = results["scale"]["points"]
    if not points:
        return None
    peaks = all("peak_build_bytes_per_triangle" in p for p in points)
    fig, axes = plt.subplots(1, 3 if peaks else 2, figsize=(18 if peaks else 12, 5))
    ax1, ax2 = axes[0], axes[1]
    for name in dict.fromkeys(p["structure"] for p in points):
        sel = sorted((p for p in points if p["structure"] == name), key=lambda p: p["triangles"])
        xs = [p["triangles"] for p in sel]
        ax1.plot(xs, [p["total_bytes_per_triangle"] for p in sel], "o-", color=colour(name),
                 label=label(name))
        if name != "embree":
            ax2.plot(xs, [p["references_per_triangle"] for p in sel], "o-", color=colour(name),
                     label=label(name))
        if peaks:
            axes[2].plot(xs, [p["peak_build_bytes_per_triangle"] for p in sel], "o-",
                         color=colour(name), label=label(name))
    panels = [(ax1, "structure + mesh (bytes/triangle)"),
              (ax2, "triangle references per triangle")]
    if peaks:
        panels.append((axes[2], "peak build memory, mesh not counted (bytes/triangle)"))
        # A small scene's fixed costs would flatten every other point on a linear axis.
        axes[2].set_yscale("log")
    for ax, title in panels:
        ax.set_xscale("log")
        ax.set_xlabel("triangles (%s, patches and arenas)" % results["scale"]["model"])
        ax.set_title(title, fontsize=10)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    path = os.path.join(out_dir, "memory_scaling.png")
    save(fig, path)
    return path


def dynamic(results, out_dir):
    scenes = results.get("dynamic") or []
    if not scenes:
        return None
    fig, axes = plt.subplots(1, len(scenes), figsize=(7.5 * len(scenes), 6), squeeze=False)
    for ax, d in zip(axes[0], scenes):
        measured = d["rays_per_frame"]
        top = max(measured[-1] * 10, 1e7)
        xs = [measured[0] / 10 * (10 ** (k / 20)) for k in range(0, 1000)]
        xs = [x for x in xs if x <= top]
        for s in d["structures"]:
            update, per_ray = frame_line(s, measured)
            style = "--" if s["structure"].endswith(("_refit", "_low")) else "-"
            inside = [x for x in xs if x <= measured[-1]]
            beyond = [x for x in xs if x >= measured[-1]]
            few = len(s["frames_run"]) < d["frames"]
            name = label(s["structure"]) + (" (%d frames)" % len(s["frames_run"]) if few else "")
            ax.plot(inside, [1e3 * (update + per_ray * x) for x in inside], style,
                    color=colour(s["structure"]), label=name)
            ax.plot(beyond, [1e3 * (update + per_ray * x) for x in beyond], style,
                    color=colour(s["structure"]), alpha=0.35)
            ax.plot(measured, [1e3 * t for t in s["frame_seconds_median"]], "o",
                    color=colour(s["structure"]), markersize=4)
        by_name = {s["structure"]: s for s in d["structures"]}
        ours = by_name.get("splitgrid")
        notes = []
        for other in ("embree", "embree_low", "embree_refit", "bvh", "bvh_refit"):
            if ours and other in by_name:
                x = crossing(ours, by_name[other], measured)
                if x and x <= top:
                    ax.axvline(x, color=colour(other), linewidth=0.6, alpha=0.5)
                    notes.append("%s at %.3g" % (label(other), x))
        ax.axvspan(measured[-1], top, color="#eeeeee", zorder=0)
        ax.text(measured[-1] * 1.1, 0.02, "extrapolated",
                transform=ax.get_xaxis_transform(), fontsize=8, color="#555555")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("path rays per frame (%d threads)" % d["threads"])
        ax.set_ylabel("time per frame: update + trace (ms, %s)" % (
            "median of frames 1-%d" % (d["frames"] - 1) if d["frames"] > 1 else "frame 0"))
        title = "%s: %s triangles, %s" % (d["scene"], "{:,}".format(d["triangles"]), d["motion"])
        if notes:
            title += "\nSplit Grid line crosses " + ", ".join(notes) + " rays"
        elif ours:
            title += "\nthe Split Grid's line crosses no Embree or BVH line up to %.0e rays" % top
        ax.set_title(title, fontsize=9)
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=7, loc="upper left")
    path = os.path.join(out_dir, "dynamic.png")
    save(fig, path)
    return path


def point_workloads(results, out_dir):
    scenes = [s for s in results["scenes"] if s.get("point_workloads")]
    if not scenes:
        return None
    threads = str(results["plan"]["thread_counts"][0])
    panels = []
    for scene in scenes:
        for w in scene["point_workloads"]:
            key = (w["query"], w["points"])
            if key not in panels:
                panels.append(key)
    # Only the methods timed somewhere (not Embree, which answers none of these queries).
    methods = list(dict.fromkeys(m["method"] for s in scenes for w in s["point_workloads"]
                                 for m in w["methods"] if m["queries_per_s"]))
    fig, axes = plt.subplots(len(panels), 1, figsize=(max(7, 1.2 * len(scenes) + 3),
                                                      2.6 * len(panels) + 1), squeeze=False)
    width = 0.8 / max(1, len(methods))
    handles = {}
    for ax, (query, points) in zip(axes[:, 0], panels):
        for k, name in enumerate(methods):
            xs, ys = [], []
            for i, scene in enumerate(scenes):
                for w in scene["point_workloads"]:
                    if (w["query"], w["points"]) != (query, points):
                        continue
                    for m in w["methods"]:
                        rate = m["queries_per_s"].get(threads)
                        if m["method"] == name and rate:
                            xs.append(i + (k - (len(methods) - 1) / 2) * width)
                            ys.append(rate)
            if xs:
                handles.setdefault(name, ax.bar(xs, ys, width=width, color=colour(name)))
        unit = "rays" if query == "count" else "points"
        ax.set_title("%s, %s %s (%s/s, %s thread%s; missing bar: not answered or wrong)"
                     % (query, points, unit, unit, threads, "" if threads == "1" else "s"),
                     fontsize=9)
        ax.set_yscale("log")
        ax.grid(axis="y", alpha=0.3)
        ax.set_xticks(range(len(scenes)))
        ax.set_xticklabels([])
    axes[-1, 0].set_xticklabels(["%s\n%s tris" % (s["scene"], human(s["triangles"]))
                                 for s in scenes], rotation=45, ha="right", fontsize=8)
    fig.legend([handles[m] for m in methods if m in handles],
               [label(m) for m in methods if m in handles], ncol=min(len(methods), 6),
               fontsize=8, loc="upper center", bbox_to_anchor=(0.5, 0.965))
    fig.suptitle("Point and multi-hit workloads: every method checked against brute force first")
    path = os.path.join(out_dir, "point_workloads.png")
    save(fig, path)
    return path


def inside_tests(results, out_dir, open3d=None):
    """Points per second (1 thread) against wrong answers on each inside test set. `open3d`:
    the sets' entries of scripts/bench_inside_open3d.py (wrong answers, not timed)."""
    tests = results.get("inside_tests") or []
    if not tests:
        return None
    markers = "osD^v<>Pp*hX"
    fig, ax = plt.subplots(figsize=(9, 6))
    sets = [t["set"] for t in tests]
    rates = [m["points_per_s"] for t in tests for m in t["methods"] if m["status"] == "ok"]
    not_timed = min(rates) / 4 if rates else 1.0
    for i, t in enumerate(tests):
        decided = max(1, t["points"] - t["undecided"])
        entries = [(m["method"], m["points_per_s"], m["wrong"]) for m in t["methods"]
                   if m["status"] == "ok"]
        for o in open3d or []:
            if o["set"] == t["set"]:
                entries.append(("open3d", not_timed, o["wrong_occupancy"]))
        for method, rate, wrong in entries:
            ax.scatter(rate, max(100.0 * wrong / decided, 0.01), s=55, color=colour(method),
                       marker=markers[i % len(markers)],
                       label="%s | %s" % (label(method), t["set"]))
    if open3d:
        ax.axvline(not_timed, color=colour("open3d"), linewidth=0.6, alpha=0.5)
        ax.text(not_timed * 1.05, 0.012, "Open3D: not timed (wrong)", fontsize=7,
                color=colour("open3d"), rotation=90, va="bottom")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("points per second (1 thread, median of passes)")
    ax.set_ylabel("wrong answers, % of the points the oracle decides (0 drawn at 0.01%)")
    ax.set_title("Inside tests: rays from the points meet edges and vertices (%d sets)"
                 % len(sets), fontsize=10)
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=6, loc="center left", bbox_to_anchor=(1.0, 0.5))
    path = os.path.join(out_dir, "inside_tests.png")
    save(fig, path)
    return path


def main(argv):
    if len(argv) != 3:
        sys.stderr.write("usage: bench_charts.py RESULTS_JSON OUT_DIR\n")
        return 1
    try:
        with open(argv[1]) as f:
            results = json.load(f)
    except (OSError, ValueError) as e:
        sys.stderr.write("error: %s: %s\n" % (argv[1], e))
        return 2
    if results.get("schema_version") != 1 or results.get("tool") != "sg-bench":
        sys.stderr.write("error: %s: not an sg-bench results file (schema_version 1)\n" % argv[1])
        return 2
    made = [p for p in (figure3(results, argv[2]), speed_vs_accuracy(results, argv[2]),
                        sweep(results, argv[2]), memory_scaling(results, argv[2]),
                        dynamic(results, argv[2]), point_workloads(results, argv[2]),
                        inside_tests(results, argv[2])) if p]
    for p in made:
        print("wrote %s" % p)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
