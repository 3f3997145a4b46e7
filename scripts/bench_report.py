#!/usr/bin/python3
"""Writes the results report of an sg-bench run as Markdown.

Usage: bench_report.py RESULTS_JSON CHARTS_DIR IMAGE_PREFIX [DYNAMIC_JSON] > RESULTS.md

CHARTS_DIR holds the charts bench_charts.py made for the run; they are referred to as
IMAGE_PREFIX + name (e.g. "images/bench_" for docs/images/bench_figure3.png; scripts/bench.sh
copies them there). Every figure in the report comes from the JSON; the verdicts on the
poster's claims and the issue's targets are computed, not written by hand. DYNAMIC_JSON is
the results.json of a run of the dynamic workload alone (scripts/bench.sh makes one); its
section is written from it, and from RESULTS_JSON's own "dynamic" key when it has one. The report names
scene files relative to the folder that holds them all, never by a machine's absolute path.
"""

import json
import os
import statistics
import sys

from bench_common import crossing, frame_line, human, label

OURS = ["splitgrid", "splitgrid_poster", "uniform_grid", "kd_tree", "bvh"]


def structure(scene, name):
    for s in scene["structures"]:
        if s["structure"] == name:
            return s
    return None


def workload(s, name):
    for w in s["workloads"]:
        if w["workload"] == name:
            return w
    return None


def rate(s, name, threads):
    w = workload(s, name)
    return w["mrays_per_s"].get(threads, 0.0) if w else 0.0


def fmt(x, digits=2):
    return ("%%.%df" % digits) % x


def ratio(a, b):
    return a / b if b else float("nan")


ARENA_SOURCE = " arranged to "


# Where Debian's assimp-testmodels package puts its models (the CAD model of scripts/bench.sh).
ASSIMP_MODELS = "/usr/share/assimp/models/"


def scene_files(scenes):
    """The mesh file of every scene (its source, or for an arena the model it copies), but
    those of Debian's assimp-testmodels, which the report names by the package."""
    files = [s["source"].split(ARENA_SOURCE)[0] for s in scenes]
    return [f for f in files if not f.startswith(ASSIMP_MODELS)]


def common_folder(paths):
    """The folder that holds all `paths`, or None (no paths, or absolute and relative mixed)."""
    try:
        return os.path.commonpath([os.path.dirname(p) or "." for p in paths]) if paths else None
    except ValueError:
        return None


def shown_path(path, root):
    """`path` relative to `root`, so that a report carries no machine's absolute paths; a
    path outside `root` is reduced to its file name."""
    if path.startswith(ASSIMP_MODELS):
        return "assimp-testmodels: " + path[len(ASSIMP_MODELS):]
    if root is not None:
        relative = os.path.relpath(path, root)
        if not relative.startswith(".."):
            return relative
    return os.path.basename(path)


def shown_source(source, root):
    """A scene's source as the report shows it: its file relative to `root`, and for an arena
    the rest of the description after the model's file."""
    head, sep, tail = source.partition(ARENA_SOURCE)
    return shown_path(head, root) + sep + tail


def thread_count(t):
    """'1 thread', '2 threads' for a thread count given as a string."""
    return "%s thread%s" % (t, "" if t == "1" else "s")


def share(flags):
    """'n of m' for a list of booleans."""
    return "%d of %d" % (sum(1 for f in flags if f), len(flags))


# The targets of the issue "Trace fast": (label, figure, the figure before it, this issue's
# goal, the goal beyond it). "Before" is the 2-thread column of the full run that preceded the
# issue (17 scenes, format version 2, before welding and the shared kernels).
TRACE_TARGETS = [
    ("Split Grid / our BVH, primary / path / incoherent", "sg_bvh", "0.47 / 0.52 / 0.48",
     ">= 1.0", ">= 1.3"),
    ("Split Grid / Embree, primary", "sg_emb_primary", "0.22", ">= 0.6", ">= 1.0"),
    ("Split Grid / Embree, path / incoherent", "sg_emb_path_incoherent", "0.18 / 0.12",
     ">= 0.45 / 0.40", ">= 0.8"),
    ("Split Grid / Embree, shadow (any hit)", "sg_emb_shadow", "0.12", ">= 0.40", ">= 0.8"),
    ("our BVH / Embree, median of primary, path and incoherent", "bvh_emb", "0.32", ">= 0.6",
     ">= 0.8"),
    ("Split Grid triangles tested per path ray / BVH's", "tests", "3.7", "<= 2", "<= 1.2"),
    ("Split Grid structure + mesh bytes / BVH's", "bytes", "0.90", "<= 1.0",
     "the lowest of all"),
    ("Split Grid build time / Embree's, against the same ratio before (5.6)", "build", "1.0",
     "<= 1.5", ""),
]
# Split Grid build time / Embree MEDIUM's, 2 threads, before the issue (Embree built 1 / 0.18
# times faster). Embree is the reference whose builder does not change here.
BUILD_RATIO_BEFORE = 1 / 0.18


def targets(w, scenes, threads, median):
    """The targets table of "Trace fast", medians over the scenes, for each thread count."""
    w("## Targets of \"Trace fast\"\n")
    w("Medians over the scenes of per-scene ratios measured in this run. Speed ratios are "
      "Mrays/s over Mrays/s (above 1: the Split Grid is faster), tests per path ray over the "
      "workload, bytes are structure + mesh (everything tracing needs). The build figure is the "
      "Split Grid's build time over Embree's, divided by that ratio in the run before the "
      "issue, so that it compares builds within one run.\n")

    def per_scene(scene, t):
        sg, bvh, emb = (structure(scene, n) for n in ("splitgrid", "bvh", "embree"))
        if not (sg and bvh and emb):
            return None
        x = {}
        for n in ("primary", "path", "incoherent", "shadow"):
            x["sg_bvh_" + n] = ratio(rate(sg, n, t), rate(bvh, n, t))
            x["sg_emb_" + n] = ratio(rate(sg, n, t), rate(emb, n, t))
            x["bvh_emb_" + n] = ratio(rate(bvh, n, t), rate(emb, n, t))
        ws, wb = workload(sg, "path"), workload(bvh, "path")
        x["tests"] = ratio(ws["triangles_per_ray"], wb["triangles_per_ray"]) \
            if ws and wb and ws["counted"] and wb["counted"] else float("nan")
        x["bytes"] = ratio(sg["total_bytes_per_triangle"], bvh["total_bytes_per_triangle"])
        x["build"] = ratio(sg["build_seconds"][t], emb["build_seconds"][t]) / BUILD_RATIO_BEFORE
        return x

    columns = []
    for t in threads:
        rows = [x for x in (per_scene(s, t) for s in scenes) if x]
        med = {k: median([x[k] for x in rows if x[k] == x[k]]) for k in rows[0]} if rows else {}
        columns.append((t, med, len(rows)))
    if not columns or not columns[0][1]:
        w("No scene has the Split Grid, the BVH and Embree.\n")
        return

    def shown(key, med):
        if key == "sg_bvh":
            return " / ".join(fmt(med["sg_bvh_" + n]) for n in ("primary", "path", "incoherent"))
        if key == "sg_emb_primary":
            return fmt(med["sg_emb_primary"])
        if key == "sg_emb_path_incoherent":
            return "%s / %s" % (fmt(med["sg_emb_path"]), fmt(med["sg_emb_incoherent"]))
        if key == "sg_emb_shadow":
            return fmt(med["sg_emb_shadow"])
        if key == "bvh_emb":
            return fmt(median([med["bvh_emb_" + n] for n in ("primary", "path", "incoherent")]))
        return fmt(med[key])

    head = ["ratio", "before"] + ["now, " + thread_count(t) for t, _, _ in columns] + ["this issue", "beyond"]
    w("| " + " | ".join(head) + " |")
    w("|" + "---|" * len(head))
    for name, key, before, goal, beyond in TRACE_TARGETS:
        w("| %s | %s | %s | **%s** | %s |" % (name, before, " | ".join(
            shown(key, med) for _, med, _ in columns), goal, beyond))
    w("")
    w("Scenes counted: %s.\n" % ", ".join("%d at %s" % (n, thread_count(t))
                                          for t, _, n in columns))

    w("Per scene, %s (Split Grid over Embree, and over our BVH):\n" % thread_count(threads[-1]))
    t = threads[-1]
    head = ["scene", "primary", "path", "incoherent", "shadow", "primary vs BVH",
            "path vs BVH", "incoherent vs BVH", "tests vs BVH", "bytes vs BVH"]
    w("| " + " | ".join(head) + " |")
    w("|" + "---|" * len(head))
    for scene in scenes:
        x = per_scene(scene, t)
        if not x:
            continue
        w("| %s | %s |" % (scene["scene"], " | ".join(fmt(x[k]) for k in (
            "sg_emb_primary", "sg_emb_path", "sg_emb_incoherent", "sg_emb_shadow",
            "sg_bvh_primary", "sg_bvh_path", "sg_bvh_incoherent", "tests", "bytes"))))
    w("")


# Scenes from this many triangles on count in the build medians; smaller builds take
# milliseconds, where timer and task overheads dominate.
BUILD_MEDIAN_MIN_TRIANGLES = 100000


def measures_build_memory(scenes):
    """True for a run that measured peak build memory (and so timed every build after an
    untimed one)."""
    return bool(scenes) and all("peak_build_bytes" in s for s in scenes[0]["structures"])


def build_cost(w, scenes, names, threads):
    """Microseconds per triangle and thread of every builder, and its speed-up over threads."""
    first, last = threads[0], threads[-1]
    w("## Build cost per triangle and thread\n")
    warm = measures_build_memory(scenes)
    w("Build time x threads / triangles, in microseconds, on %s and on %s (a builder that "
      "scales perfectly has the same figure on both), and the speed-up from %s to %s "
      "(build time on %s over build time on %s).%s Medians over the scenes of at least %s "
      "triangles.\n"
      % (thread_count(first), thread_count(last), thread_count(first), thread_count(last),
         thread_count(first), thread_count(last),
         " Every timed build follows an untimed one of the same structure, with the structure "
         "built before released (BENCH.md, \"What is measured\")." if warm else "",
         "{:,}".format(BUILD_MEDIAN_MIN_TRIANGLES)))
    head = ["scene"] + ["%s us/tri.thread %st / %st, speed-up" % (label(n), first, last)
                        for n in names]
    w("| " + " | ".join(head) + " |")
    w("|" + "---|" * len(head))
    columns = {n: ([], [], []) for n in names}

    def per_tri(s, t, tris):
        return s["build_seconds"][t] * int(t) / tris * 1e6 if t in s["build_seconds"] else None

    for scene in scenes:
        tris = scene["triangles"]
        row = ["%s (%s)" % (scene["scene"], human(tris))]
        for n in names:
            s = structure(scene, n)
            a = per_tri(s, first, tris) if s and tris else None
            b = per_tri(s, last, tris) if s and tris else None
            if a is None or b is None:
                row.append("-")
                continue
            up = s["build_seconds"][first] / s["build_seconds"][last] if s["build_seconds"][last] else 0
            row.append("%.2f / %.2f, %.2f" % (a, b, up))
            if tris >= BUILD_MEDIAN_MIN_TRIANGLES:
                for col, v in zip(columns[n], (a, b, up)):
                    col.append(v)
        w("| " + " | ".join(row) + " |")
    row = ["**median, >= %s triangles**" % human(BUILD_MEDIAN_MIN_TRIANGLES)]
    for n in names:
        a, b, up = columns[n]
        row.append("**%.2f / %.2f, %.2f**" % (statistics.median(a), statistics.median(b),
                                              statistics.median(up)) if a else "-")
    w("| " + " | ".join(row) + " |")
    w("")


def build_memory(w, scenes, names, threads):
    """Peak build memory per triangle of every builder, and its ratio to Embree's."""
    if not measures_build_memory(scenes):
        return  # a run from before sg-bench measured it
    w("## Peak build memory\n")
    w("The most bytes one build held at once, per triangle, on %s (the input mesh not "
      "counted; our structures: every operator new and delete of the build; Embree: its "
      "memory monitor), with the ratio to Embree's in brackets; and the process's resident "
      "high-water mark over the same build in MiB (everything sg-bench holds, the scene and "
      "its workloads included). Medians over the scenes of at least %s triangles.\n"
      % (thread_count(threads[-1]), "{:,}".format(BUILD_MEDIAN_MIN_TRIANGLES)))
    head = ["scene"] + ["%s B/tri, process MiB" % label(n) for n in names]
    w("| " + " | ".join(head) + " |")
    w("|" + "---|" * len(head))
    ratios = {n: [] for n in names}
    for scene in scenes:
        tris = scene["triangles"]
        emb = structure(scene, "embree")
        row = ["%s (%s)" % (scene["scene"], human(tris))]
        for n in names:
            s = structure(scene, n)
            if not s or "peak_build_bytes_per_triangle" not in s:
                row.append("-")
                continue
            cell = "%.1f" % s["peak_build_bytes_per_triangle"]
            if emb and s is not emb and emb["peak_build_bytes_per_triangle"] > 0:
                q = s["peak_build_bytes_per_triangle"] / emb["peak_build_bytes_per_triangle"]
                cell += " (%.2fx)" % q
                if tris >= BUILD_MEDIAN_MIN_TRIANGLES:
                    ratios[n].append(q)
            hwm = s["process_high_water_bytes"]
            cell += ", %.0f" % (hwm / 2 ** 20) if hwm else ", -"
            row.append(cell)
        w("| " + " | ".join(row) + " |")
    row = ["**median ratio to Embree, >= %s triangles**" % human(BUILD_MEDIAN_MIN_TRIANGLES)]
    row += ["**%.2fx**" % statistics.median(ratios[n]) if ratios[n] else "-" for n in names]
    w("| " + " | ".join(row) + " |")
    w("")


# The targets of the issue "Build fast": (label, figure, the figure before it (the 2-thread
# column of the full run that preceded it), its goal, the goal beyond it). Build speed is
# 1 / build time, so "build speed / X" is X's build time over the Split Grid's.
BUILD_TARGETS = [
    ("Split Grid build speed / Embree MEDIUM", "emb", "0.18", ">= 1.0", ">= Embree LOW"),
    ("Split Grid build speed / our BVH", "bvh", "0.64", ">= 2.0", ""),
    ("speed-up from %s to %s threads, every scene (range)", "scaling", "1.65-1.99",
     ">= 1.8", ""),
    ("peak build memory / Embree's peak", "peak", "not measured", "<= 1.0", "<= 0.5"),
    ("largest arena: build time / Embree MEDIUM's", "arena", "4.6", "<= 1.0", ""),
]


def build_targets(w, scenes, threads):
    """The targets table of "Build fast", for both presets of the Split Grid."""
    t = threads[-1]
    big = [s for s in scenes if s["triangles"] >= BUILD_MEDIAN_MIN_TRIANGLES]
    arenas = [s for s in scenes if ARENA_SOURCE in s["source"]]
    arena = max(arenas, key=lambda s: s["triangles"]) if arenas else None
    w("## Targets of \"Build fast\"\n")
    w("Medians over the %d scenes of at least %s triangles, on %s; the targets hold for the "
      "default Split Grid, the poster preset's figures are beside them. Speed-ups are build "
      "time on %s over build time on %s.%s\n"
      % (len(big), "{:,}".format(BUILD_MEDIAN_MIN_TRIANGLES), thread_count(t),
         thread_count(threads[0]), thread_count(t),
         " Largest arena: %s (%s triangles)." % (arena["scene"], "{:,}".format(arena["triangles"]))
         if arena else ""))

    def figure(name, key):
        rows = []
        for scene in (big if key != "arena" else [arena] if arena else []):
            sg, emb, bvh = (structure(scene, n) for n in (name, "embree", "bvh"))
            if not sg:
                continue
            b = sg["build_seconds"]
            if key in ("emb", "arena") and emb and t in b:
                q = emb["build_seconds"][t] / b[t]
                rows.append(q if key == "emb" else 1 / q)
            elif key == "bvh" and bvh and t in b:
                rows.append(bvh["build_seconds"][t] / b[t])
            elif key == "scaling" and threads[0] in b and t in b and t != threads[0]:
                rows.append(b[threads[0]] / b[t])
            elif key == "peak" and emb and "peak_build_bytes" in sg and emb["peak_build_bytes"]:
                rows.append(sg["peak_build_bytes"] / emb["peak_build_bytes"])
        if not rows:
            return "-"
        if key == "scaling":
            return "%.2f-%.2f" % (min(rows), max(rows))
        return fmt(statistics.median(rows))

    head = ["figure", "before", "now: Split Grid", "now: poster preset", "this issue",
            "beyond"]
    w("| " + " | ".join(head) + " |")
    w("|" + "---|" * len(head))
    for name, key, filed, goal, beyond in BUILD_TARGETS:
        if "%s" in name:
            name = name % (threads[0], t)
        w("| %s | %s | %s | %s | **%s** | %s |" % (name, filed, figure("splitgrid", key),
                                                  figure("splitgrid_poster", key), goal, beyond))
    w("")


def embree_rate(scenes):
    """Embree's disagreements per million rays over the dynamic scenes, as a clause."""
    rays = differ = 0
    for d in scenes:
        per_frame = sum(d["rays_per_frame"])
        for s in d["structures"]:
            if s["structure"].startswith("embree"):
                rays += per_frame * len(s["frames_run"])
                differ += s["disagreements"]
    if not rays:
        return ""
    return " (Embree's: %.1f per million rays, from its triangle test, which is not ours)" % (
        1e6 * differ / rays)


def dynamic_section(w, scenes, charts, prefix):
    """The dynamic workload: per scene, each structure's update and trace times, and where
    the Split Grid's time per frame crosses the others'."""
    w("## Dynamic scenes\n")
    w("Every frame, each structure is brought up to date with the moved vertices (rebuilt, or "
      "refitted where the name says so) and then traces one frame of the path workload at "
      "each ray budget. Times in ms per frame, medians over the frames after the first (the "
      "first is everyone's initial build); *per ray* is the largest budget's trace time per "
      "ray, in ns. Disagreements: closest hits unlike the reference's (our BVH, refitted every "
      "frame), on every ray of every frame: exact for our structures, t within 1e-4 for "
      "Embree's%s. How it is run: [BENCH.md](BENCH.md#dynamic-scenes).\n" % embree_rate(scenes))
    root = common_folder([d["source"].partition(", ")[0] for d in scenes])
    if os.path.exists(os.path.join(charts, "dynamic.png")):
        w("![time per frame against rays per frame](%sdynamic.png)\n" % prefix)
    for d in scenes:
        budgets = d["ray_budgets"]
        measured = d["rays_per_frame"]
        w("### %s (%s triangles, %d frames, %s)\n" % (
            d["scene"], "{:,}".format(d["triangles"]), d["frames"], thread_count(str(d["threads"]))))
        # "FILE, how it moves": the file named as every scene file is.
        model, _, motion = d["source"].partition(", ")
        w("Source: %s, %s.\n" % (shown_path(model, root), motion))
        head = ["structure", "frames", "first build (s)", "update"] + \
            ["trace %s" % human(b) for b in budgets] + ["frame %s" % human(b) for b in budgets] + \
            ["per ray (ns)", "disagree"]
        w("| " + " | ".join(head) + " |")
        w("|---|" + "---:|" * (len(head) - 1))
        for s in d["structures"]:
            _, per_ray = frame_line(s, measured)
            cells = [label(s["structure"]), str(len(s["frames_run"])),
                     fmt(s["first_update_seconds"], 3), fmt(1e3 * s["update_seconds_median"], 1)]
            cells += [fmt(1e3 * t, 1) for t in s["trace_seconds_median"]]
            cells += [fmt(1e3 * t, 1) for t in s["frame_seconds_median"]]
            cells += [fmt(1e9 * per_ray, 0), str(s["disagreements"])]
            w("| " + " | ".join(cells) + " |")
        w("")
        by_name = {s["structure"]: s for s in d["structures"]}
        ours = by_name.get("splitgrid")
        if not ours:
            continue
        for other in ("embree", "embree_low", "embree_refit", "bvh", "bvh_refit"):
            if other not in by_name:
                continue
            o = by_name[other]
            x = crossing(ours, o, measured)
            u_ours, c_ours = frame_line(ours, measured)
            u_other, c_other = frame_line(o, measured)
            if x is None:
                # The lines keep their order at every positive ray count: the one ahead
                # with no rays is ahead everywhere.
                faster = (u_ours, c_ours) <= (u_other, c_other)
                w("- against %s: no crossing; %s at every ray count." % (
                    label(other), "the Split Grid is ahead" if faster else label(other) + " is ahead"))
                continue
            below = "the Split Grid" if u_ours < u_other else label(other)
            above = label(other) if u_ours < u_other else "the Split Grid"
            if x > 10 * measured[-1]:
                w("- against %s: the lines would cross only at %s rays per frame, %.0f times "
                  "the largest budget, far beyond what was measured; up to there %s is ahead."
                  % (label(other), "{:.2g}".format(x), x / measured[-1], below))
                continue
            where = "within the measured range" if x <= measured[-1] else "extrapolated"
            w("- against %s: the lines cross at %s rays per frame (%s): %s is ahead below, "
              "%s above." % (label(other), "{:,.0f}".format(x), where, below, above))
        w("")


def main(argv):
    if len(argv) not in (4, 5):
        sys.stderr.write("usage: bench_report.py RESULTS_JSON CHARTS_DIR IMAGE_PREFIX "
                         "[DYNAMIC_JSON]\n")
        return 1
    with open(argv[1]) as f:
        r = json.load(f)
    dynamic = list(r.get("dynamic") or [])
    if len(argv) == 5:
        with open(argv[4]) as f:
            dynamic += json.load(f).get("dynamic") or []
    charts, prefix = argv[2], argv[3]
    plan = r["plan"]
    threads = [str(t) for t in plan["thread_counts"]]
    t1, tn = threads[0], threads[-1]
    scenes = r["scenes"]
    have_embree = any(structure(s, "embree") for s in scenes)
    out = []
    w = out.append

    root = common_folder(scene_files(scenes))
    w("# sg-bench results\n")
    w("Generated by `scripts/bench_report.py` from the `results.json` of one sg-bench run "
      "(`scripts/bench.sh`; what is measured and how: [BENCH.md](BENCH.md)). Do not edit by "
      "hand: run the script again. Scene files are named relative to the folder that holds "
      "them all (`../shared/meshes` for `scripts/bench.sh`).\n")
    w("- machine: %s, %d hardware threads; %s; our kernels on %s" % (
        r["machine"]["cpu"], r["machine"]["hardware_threads"], r["machine"]["compiler"],
        r["machine"].get("kernel_isa", "sse2")))
    w("- splitgrid %s, Embree %s" % (r["splitgrid_version"], r["embree_version"] or "not built"))
    w("- run time %.0f s%s; thread counts %s; %d builds and %d passes per figure (median)"
      % (r["run_seconds"], " (quick mode: small workloads, not for conclusions)"
         if plan["quick"] else "", ", ".join(threads), plan["build_repeats"],
         plan["trace_repeats"]))
    w("- workloads: %dx%d primary rays, path tracing with %d diffuse bounces, %s incoherent "
      "rays, shadow rays from every primary hit" % (plan["image_width"], plan["image_height"],
                                                    plan["bounces"],
                                                    human(plan["incoherent_rays"])))
    cfg = plan["split_grid_config"]
    w("- Split Grid parameters: " + ", ".join("%s %s" % (k, v) for k, v in cfg.items()
                                              if k != "threads"))
    w("")

    # --- Per scene ---------------------------------------------------------------------
    w("## Every scene\n")
    w("Build in seconds, memory as structure + mesh bytes per triangle, speed in Mrays/s on "
      "%s (the ratio to Embree in brackets), and disagreements with brute force "
      "(sample) and with the Split Grid (all rays); Embree's hits agree within 1e-4 in t.\n"
      % thread_count(tn))
    names = [s["structure"] for s in scenes[0]["structures"]] if scenes else []
    wl_names = [x["name"] for x in scenes[0]["workloads"]] if scenes else []
    for scene in scenes:
        w("### %s (%s triangles)\n" % (scene["scene"], "{:,}".format(scene["triangles"])))
        w("Source: %s.\n" % shown_source(scene["source"], root))
        head = ["structure"] + ["build %st" % t for t in threads] + ["B/tri", "refs/tri"] + \
            ["%s" % n for n in wl_names] + ["disagree"]
        w("| " + " | ".join(head) + " |")
        w("|" + "---|" * len(head))
        emb = structure(scene, "embree")
        for s in scene["structures"]:
            row = [label(s["structure"])]
            row += [fmt(s["build_seconds"][t], 3) for t in threads]
            row += [fmt(s["total_bytes_per_triangle"], 1), fmt(s["references_per_triangle"], 2)]
            for n in wl_names:
                v = rate(s, n, tn)
                cell = fmt(v)
                if emb and s is not emb and rate(emb, n, tn) > 0:
                    cell += " (%.2fx)" % (v / rate(emb, n, tn))
                row.append(cell)
            dis = sum(x["oracle_disagreements"] + x["reference_disagreements"]
                      for x in s["workloads"])
            row.append(str(dis))
            w("| " + " | ".join(row) + " |")
        w("")

    # --- Build cost -------------------------------------------------------------------------
    build_cost(w, scenes, names, threads)
    build_memory(w, scenes, names, threads)

    # --- Work per ray -------------------------------------------------------------------
    w("## Work per ray\n")
    w("Mean traversal work per ray over the path workload (every ray, or an even stride of "
      "131,072 of them) "
      "(`TraversalCounters`: for the Split Grid nodes entered, cells stepped, triangles "
      "tested; for the BVH wide nodes (up to eight children each) and leaves; for the kd-tree "
      "nodes and leaves; for the "
      "uniform grid cells). This is what the timings come from.\n")
    head = ["scene"] + ["%s nodes / cells / tests" % label(n) for n in OURS if n in names]
    w("| " + " | ".join(head) + " |")
    w("|" + "---|" * len(head))
    for scene in scenes:
        row = [scene["scene"]]
        for n in OURS:
            s = structure(scene, n)
            if not s:
                continue
            x = workload(s, "path")
            row.append("%.1f / %.1f / %.1f" % (x["nodes_per_ray"], x["cells_per_ray"],
                                               x["triangles_per_ray"]) if x and x["counted"]
                       else "-")
        w("| " + " | ".join(row) + " |")
    w("")

    # --- Figure 3 and the charts --------------------------------------------------------
    w("## Charts\n")
    for name, title in (("figure3", "The poster's Figure 3: path-tracing time, build time and "
                                    "memory per structure and scene"),
                        ("speed_vs_accuracy", "Speed against accuracy: leaks per million rays "
                                              "from inside a closed sphere"),
                        ("sweep_build_vs_trace", "Split Grid parameter sweep: build time "
                                                 "against trace speed"),
                        ("memory_scaling", "Memory against scene size")):
        if os.path.exists(os.path.join(charts, name + ".png")):
            w("%s:\n\n![%s](%s%s.png)\n" % (title, title, prefix, name))

    # --- Claims ---------------------------------------------------------------------------
    w("## The poster's claims, measured here\n")
    sg_scenes = [s for s in scenes if structure(s, "splitgrid")]

    def path_time(s):
        v = rate(s, "path", t1)
        return workload(s, "path")["rays"] / (v * 1e6) if v else float("inf")

    on_par, lowest, faster_kd, two_thirds = [], [], [], []
    trav_ratios, mem_detail, kd_ratios, bvh_ratios = [], [], [], []
    for scene in sg_scenes:
        sg = structure(scene, "splitgrid")
        others = [structure(scene, n) for n in ("bvh", "kd_tree") if structure(scene, n)]
        if others:
            best = min(path_time(o) for o in others)
            ratio_sg = path_time(sg) / best
            trav_ratios.append(ratio_sg)
            on_par.append(ratio_sg <= 1.1)
        # The default Split Grid against the other structures (not against its own poster
        # preset, which is also a Split Grid).
        mems = {n: structure(scene, n)["total_bytes_per_triangle"]
                for n in names if structure(scene, n) and n != "splitgrid_poster"}
        lowest.append(min(mems, key=mems.get) == "splitgrid")
        mem_detail.append(min(mems, key=mems.get))
        kd = structure(scene, "kd_tree")
        if kd:
            q = kd["build_seconds"][tn] / sg["build_seconds"][tn]
            kd_ratios.append(q)
            faster_kd.append(q > 1.0)
        bvh = structure(scene, "bvh")
        if bvh:
            q = bvh["build_seconds"][tn] / sg["build_seconds"][tn]
            bvh_ratios.append(q)
            two_thirds.append(q >= 0.66)

    def median(xs):
        return statistics.median(xs) if xs else float("nan")

    w("| claim | holds here | figures |")
    w("|---|---|---|")
    w("| traversal on par with the kd-tree and the BVH (path workload, %s thread; within 10%% "
      "of the faster) | %s scenes | Split Grid time / faster of BVH and kd-tree: median %.2f, "
      "range %.2f-%.2f |" % (t1, share(on_par), median(trav_ratios),
                             min(trav_ratios, default=float("nan")),
                             max(trav_ratios, default=float("nan"))))
    w("| lowest memory of all structures (structure + mesh) | %s scenes | lowest was: %s |"
      % (share(lowest), ", ".join("%s %s" % (s["scene"], label(m))
                                  for s, m in zip(sg_scenes, mem_detail))))
    w("| faster build than the kd-tree (%s threads) | %s scenes | kd-tree time / Split Grid "
      "time: median %.2f |" % (tn, share(faster_kd), median(kd_ratios)))
    w("| at least 66%% of the BVH's build speed (%s threads) | %s scenes | BVH time / Split "
      "Grid time: median %.2f |" % (tn, share(two_thirds), median(bvh_ratios)))
    w("")

    # --- Targets ("Trace fast", "Build fast") ----------------------------------------------
    if have_embree:
        targets(w, sg_scenes, threads, median)
    build_targets(w, scenes, threads)

    # --- Correctness --------------------------------------------------------------------
    w("## Correctness\n")
    total = {}
    for scene in scenes:
        for s in scene["structures"]:
            d = sum(x["oracle_disagreements"] for x in s["workloads"])
            x = sum(x["reference_disagreements"] for x in s["workloads"])
            n = sum(x["oracle_rays"] for x in s["workloads"])
            a = total.setdefault(s["structure"], [0, 0, 0])
            a[0] += d
            a[1] += x
            a[2] += n
    w("| structure | brute-force sample rays | disagreements with brute force | "
      "disagreements with the Split Grid (all rays) |")
    w("|---|---:|---:|---:|")
    for n, (d, x, rays) in total.items():
        w("| %s | %s | %d | %d |" % (label(n), "{:,}".format(rays), d, x))
    w("")

    if r["accuracy"]:
        w("## Speed against accuracy\n")
        w("Rays from inside a closed sphere of %s triangles (%s rays per position, a sixth "
          "aimed at vertices, a sixth at edge midpoints); a miss is a leak. Mrays/s on one "
          "thread at the origin.\n" % ("{:,}".format(plan["watertight_triangles"]),
                                       "{:,}".format(plan["watertight_rays"])))
        w("| structure | variant | leaks/M at origin | leaks/M far away | of which at vertices "
          "/ edges (far) | Mrays/s |")
        w("|---|---|---:|---:|---|---:|")
        for a in r["accuracy"]:
            if a["position"] != "origin":
                continue
            far = next((b for b in r["accuracy"] if b["position"] == "far" and
                        b["structure"] == a["structure"] and b["variant"] == a["variant"]), None)
            w("| %s | %s | %.1f | %s | %s | %.2f |" % (
                label(a["structure"]), a["variant"], a["misses_per_million"],
                "%.1f" % far["misses_per_million"] if far else "-",
                "%d / %d" % (far["misses_vertex"], far["misses_edge"]) if far else "-",
                a["mrays_per_s"]))
        w("")

    point_section(w, r, charts, prefix)

    if r["sweep"]["points"]:
        w("## Split Grid parameter sweep on %s (%d threads)\n" % (r["sweep"]["scene"],
                                                                  r["sweep"]["threads"]))
        w("| parameter | value | build s | Mrays/s (path) | B/tri | refs/tri | disagreements |")
        w("|---|---|---:|---:|---:|---:|---:|")
        for p in r["sweep"]["points"]:
            w("| %s | %s | %.3f | %.3f | %.1f | %.2f | %d |" % (
                p["parameter"], p["value"] or "-", p["build_seconds"], p["mrays_per_s"],
                p["total_bytes_per_triangle"], p["references_per_triangle"],
                p["disagreements"]))
        w("")

    if r["scale"]["points"]:
        w("## Memory against scene size (from %s)\n" % r["scale"]["model"])
        sizes = sorted({p["triangles"] for p in r["scale"]["points"]})
        snames = list(dict.fromkeys(p["structure"] for p in r["scale"]["points"]))
        w("Structure + mesh bytes per triangle (references per triangle in brackets), and "
          "the build time in seconds on %s threads.\n" % tn)
        w("| triangles | " + " | ".join(label(n) for n in snames) + " |")
        w("|---:|" + "---|" * len(snames))
        for n in sizes:
            cells = []
            for s in snames:
                p = next((x for x in r["scale"]["points"]
                          if x["triangles"] == n and x["structure"] == s), None)
                cells.append("%.1f (%.2f), %.2f s" % (p["total_bytes_per_triangle"],
                                                      p["references_per_triangle"],
                                                      p["build_seconds"]) if p else "-")
            w("| %s | %s |" % ("{:,}".format(n), " | ".join(cells)))
        w("")
    if dynamic:
        dynamic_section(w, dynamic, charts, prefix)
    sys.stdout.write("\n".join(out) + "\n")
    return 0


def point_section(w, r, charts, prefix):
    """The point and multi-hit workloads (thousands of queries per second of every method on
    one thread, or why it has none) and the inside tests' wrong answers (docs/BENCH.md)."""
    scenes = [s for s in r["scenes"] if s.get("point_workloads")]
    tests = r.get("inside_tests") or []
    if not scenes and not tests:
        return
    t1 = str(r["plan"]["thread_counts"][0])
    if scenes:
        w("## Point and multi-hit workloads\n")
        w("Thousands of queries per second on %s thread%s (median of passes), each method's "
          "answers checked against brute force first (docs/BENCH.md); CGAL %s.\n"
          % (t1, "" if t1 == "1" else "s", r.get("cgal_version") or "not in this build"))
        methods = list(dict.fromkeys(m["method"] for s in scenes for x in s["point_workloads"]
                                     for m in x["methods"]))
        w("| scene | workload | " + " | ".join(label(m) for m in methods) + " |")
        w("|---|---|" + "---:|" * len(methods))
        for s in scenes:
            for x in s["point_workloads"]:
                cells = []
                for name in methods:
                    m = next((m for m in x["methods"] if m["method"] == name), None)
                    if m is None:
                        cells.append("-")
                    elif m["queries_per_s"]:
                        cells.append("%.1f" % (m["queries_per_s"][t1] / 1e3))
                    else:
                        cells.append("wrong" if m["status"] == "wrong" else "n/a")
                w("| %s | %s %s | %s |" % (s["scene"], x["query"], x["points"],
                                           " | ".join(cells)))
        w("")
        if os.path.exists(os.path.join(charts, "point_workloads.png")):
            w("![point workloads](%spoint_workloads.png)\n" % prefix)
    if tests:
        w("## Inside tests\n")
        w("Points whose rays meet edges and vertices: wrong answers against the oracle, and "
          "thousands of points per second on one thread.\n")
        methods = list(dict.fromkeys(m["method"] for t in tests for m in t["methods"]))
        # Open3D's wrong answers, when scripts/bench_inside_open3d.py has run beside the charts.
        open3d_file = os.path.join(charts, "inside_open3d.json")
        open3d = {}
        if os.path.exists(open3d_file):
            with open(open3d_file) as f:
                open3d = {e["set"]: e for e in json.load(f)["sets"]}
        extra = ["Open3D compute_occupancy (not timed)"] if open3d else []
        w("| set | points | inside | " + " | ".join([label(m) for m in methods] + extra) + " |")
        w("|---|---:|---:|" + "---|" * (len(methods) + len(extra)))
        for t in tests:
            cells = []
            for name in methods:
                m = next((m for m in t["methods"] if m["method"] == name), None)
                if m is None:
                    cells.append("-")
                elif m["status"] == "ok":
                    cells.append("%d (%.0f)" % (m["wrong"], m["points_per_s"] / 1e3))
                else:
                    cells.append("n/a")
            if open3d:
                cells.append("%d" % open3d[t["set"]]["wrong_occupancy"] if t["set"] in open3d
                             else "-")
            w("| %s | %s | %s | %s |" % (t["set"], "{:,}".format(t["points"]),
                                         "{:,}".format(t["inside"]), " | ".join(cells)))
        w("")
        if os.path.exists(os.path.join(charts, "inside_tests.png")):
            w("![inside tests](%sinside_tests.png)\n" % prefix)


if __name__ == "__main__":
    sys.exit(main(sys.argv))
