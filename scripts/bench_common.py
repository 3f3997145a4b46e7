"""What bench_charts.py and bench_report.py share: the structures' names and colours, numbers
for people, and the dynamic workload's per-frame model (docs/BENCH.md, "Dynamic scenes").
sg-bench sorts the ray budgets, so the last one is the largest."""

STRUCTURE_LABELS = {
    "splitgrid": "Split Grid",
    "splitgrid_poster": "Split Grid (poster)",
    "uniform_grid": "uniform grid",
    "kd_tree": "kd-tree",
    "bvh": "BVH",
    "embree": "Embree 3",
    "bvh_refit": "BVH, refitted",
    "embree_low": "Embree 3 LOW",
    "embree_refit": "Embree 3, refitted",
    "cgal": "CGAL 5.5",
    "splitgrid_no_tie_break": "Split Grid, no tie-break",
    "open3d": "Open3D 0.16",
}
STRUCTURE_COLOURS = {
    "splitgrid": "#d62728",
    "splitgrid_poster": "#ff9896",
    "uniform_grid": "#7f7f7f",
    "kd_tree": "#2ca02c",
    "bvh": "#1f77b4",
    "embree": "#9467bd",
    "bvh_refit": "#17becf",
    "embree_low": "#c5b0d5",
    "embree_refit": "#8c564b",
    "cgal": "#bcbd22",
    "splitgrid_no_tie_break": "#ff7f0e",
    "open3d": "#e377c2",
}


def label(name):
    return STRUCTURE_LABELS.get(name, name)


def colour(name):
    return STRUCTURE_COLOURS.get(name, "#000000")


def human(n):
    """1500000 -> '1.5M', 20000 -> '20k'."""
    for unit, scale in (("M", 1e6), ("k", 1e3)):
        if n >= scale:
            return "%.3g%s" % (n / scale, unit)
    return str(n)


def frame_line(s, rays_per_frame):
    """A structure's time per frame against rays per frame, as a line: the update (median
    over the frames after the first) plus the trace time per ray of the largest budget (the
    most rays, so the least noise) times the rays. Returns (update seconds, seconds per ray).
    """
    rays = rays_per_frame[-1]
    per_ray = s["trace_seconds_median"][-1] / rays if rays else 0.0
    return s["update_seconds_median"], per_ray


def frame_seconds(s, rays_per_frame, rays):
    update, per_ray = frame_line(s, rays_per_frame)
    return update + per_ray * rays


def crossing(a, b, rays_per_frame):
    """Rays per frame at which structure a's frame time equals b's, on their frame lines:
    None if the lines do not cross at a positive ray count (one is ahead everywhere)."""
    ua, ca = frame_line(a, rays_per_frame)
    ub, cb = frame_line(b, rays_per_frame)
    if ca == cb:
        return None
    rays = (ub - ua) / (ca - cb)
    return rays if rays > 0 else None
