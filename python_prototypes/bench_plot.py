"""Plot how ray tracing speed scales with the number of triangles: brute force against
the BVH (chapter 13), for camera (primary) rays and diffuse bounce rays, on log-log axes.

The input is a JSON file of measurements, either a list of records or an object whose
"results" holds that list (and an optional "title", e.g. the GL renderer):

    {"title": "llvmpipe (LLVM 15.0.6, 256 bits)",
     "results": [
        {"triangles": 6320, "rays": "primary", "method": "brute_force",
         "rays_per_second": ...},
        {"triangles": 6320, "rays": "primary", "method": "bvh", "rays_per_second": ...},
        ...]}

    rays:    "primary" or "diffuse"
    method:  "brute_force" or "bvh"

A combination may be missing (brute force is refused beyond a GL's loop limit);
where both methods were measured, the right panel shows the BVH's speed-up.

    python python_prototypes/bench_plot.py --input bench.json --figure scaling.png
"""

import argparse
import json
import math
import sys
from pathlib import Path

RAY_KINDS = ("primary", "diffuse")
METHODS = ("brute_force", "bvh")
METHOD_LABELS = {"brute_force": "brute force", "bvh": "BVH"}
RAY_LABELS = {"primary": "camera rays", "diffuse": "diffuse bounces"}


class BenchmarkError(ValueError):
    """The input file is not what this tool reads; the message says where."""


def load_results(path):
    """(title, records) from the JSON file; every record checked."""
    try:
        data = json.loads(Path(path).read_text())
    except (OSError, json.JSONDecodeError) as error:
        raise BenchmarkError(f"{path}: {error}") from error
    title = ""
    if isinstance(data, dict):
        title = str(data.get("title", ""))
        data = data.get("results")
    if not isinstance(data, list) or not data:
        raise BenchmarkError(f"{path}: expected a non-empty list of results")
    records = []
    for number, record in enumerate(data):
        where = f"{path}: result {number}"
        if not isinstance(record, dict):
            raise BenchmarkError(f"{where}: not an object")
        missing = {"triangles", "rays", "method", "rays_per_second"} - record.keys()
        if missing:
            raise BenchmarkError(f"{where}: missing {', '.join(sorted(missing))}")
        if record["rays"] not in RAY_KINDS:
            raise BenchmarkError(f"{where}: rays must be one of {', '.join(RAY_KINDS)}")
        if record["method"] not in METHODS:
            raise BenchmarkError(f"{where}: method must be one of {', '.join(METHODS)}")
        triangles, speed = record["triangles"], record["rays_per_second"]
        if not isinstance(triangles, (int, float)) or not triangles > 0:
            raise BenchmarkError(f"{where}: triangles must be a positive number")
        if not isinstance(speed, (int, float)) or not speed > 0 or not math.isfinite(speed):
            raise BenchmarkError(f"{where}: rays_per_second must be a positive number")
        records.append({"triangles": int(triangles), "rays": record["rays"],
                        "method": record["method"], "rays_per_second": float(speed)})
    return title, records


def series(records, rays, method):
    """[(triangles, rays per second)] of one kind of ray and one method, sorted; the
    mean where a triangle count was measured more than once."""
    by_count = {}
    for record in records:
        if record["rays"] == rays and record["method"] == method:
            by_count.setdefault(record["triangles"], []).append(record["rays_per_second"])
    return [(count, sum(speeds) / len(speeds)) for count, speeds in sorted(by_count.items())]


def speedups(records, rays):
    """[(triangles, BVH rays/s divided by brute force rays/s)] where both were measured."""
    brute = dict(series(records, rays, "brute_force"))
    return [(count, speed / brute[count])
            for count, speed in series(records, rays, "bvh") if count in brute]


def draw_figure(title, records, path=None):
    import matplotlib
    if path:
        matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter

    def plain_log_axis(axis, suffix=""):
        # 1 000, 10 000, ... rather than 10^3, and no labels on the minor ticks.
        axis.set_major_locator(LogLocator(base=10))
        axis.set_major_formatter(FuncFormatter(lambda value, _: f"{value:,.0f}{suffix}"
                                               .replace(",", " ")))
        axis.set_minor_formatter(NullFormatter())

    has_speedups = any(speedups(records, rays) for rays in RAY_KINDS)
    figure, panels = plt.subplots(1, 2 if has_speedups else 1,
                                  figsize=(12, 4.8) if has_speedups else (6.5, 4.8),
                                  squeeze=False)
    speed_axes = panels[0][0]
    colours = {"brute_force": "tab:red", "bvh": "tab:blue"}
    styles = {"primary": ("o", "-"), "diffuse": ("s", "--")}
    for method in METHODS:
        for rays in RAY_KINDS:
            points = series(records, rays, method)
            if not points:
                continue
            marker, line = styles[rays]
            speed_axes.plot(*zip(*points), marker=marker, linestyle=line,
                            color=colours[method],
                            label=f"{METHOD_LABELS[method]}, {RAY_LABELS[rays]}")
    speed_axes.set_xscale("log")
    speed_axes.set_yscale("log")
    speed_axes.set_xlabel("triangles")
    speed_axes.set_ylabel("rays per second")
    speed_axes.set_title("Rays per second against the size of the mesh", fontsize=11)
    plain_log_axis(speed_axes.xaxis)
    speed_axes.grid(True, which="both", alpha=0.3)
    speed_axes.legend(fontsize=9)

    if has_speedups:
        ratio_axes = panels[0][1]
        for rays in RAY_KINDS:
            points = speedups(records, rays)
            if not points:
                continue
            marker, line = styles[rays]
            ratio_axes.plot(*zip(*points), marker=marker, linestyle=line, color="tab:purple",
                            label=RAY_LABELS[rays])
            for count, ratio in points:
                ratio_axes.annotate(f"{ratio:.0f}x" if ratio >= 10 else f"{ratio:.1f}x",
                                    (count, ratio), textcoords="offset points",
                                    xytext=(0, 7), ha="center", fontsize=9)
        ratio_axes.set_xscale("log")
        ratio_axes.set_yscale("log")
        ratio_axes.set_xlim(speed_axes.get_xlim())  # the same triangle counts line up
        ratio_axes.margins(y=0.15)
        plain_log_axis(ratio_axes.xaxis)
        plain_log_axis(ratio_axes.yaxis, suffix="x")
        ratio_axes.set_xlabel("triangles")
        ratio_axes.set_ylabel("BVH rays per second / brute force rays per second")
        ratio_axes.set_title("How many times faster the BVH is", fontsize=11)
        ratio_axes.grid(True, which="both", alpha=0.3)
        ratio_axes.legend(fontsize=9)

    if title:
        figure.suptitle(title, fontsize=12)
    figure.tight_layout()
    if path:
        figure.savefig(path, dpi=120, bbox_inches="tight")
        plt.close(figure)
    else:
        plt.show()


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--input", required=True, help="JSON file of measurements")
    parser.add_argument("--figure", help="write the figure to this file (else show it)")
    args = parser.parse_args(argv)
    try:
        title, records = load_results(args.input)
    except BenchmarkError as error:
        print(f"error: {error}", file=sys.stderr)
        return 3
    draw_figure(title, records, args.figure)
    if args.figure:
        print(args.figure)
    return 0


if __name__ == "__main__":
    sys.exit(main())
