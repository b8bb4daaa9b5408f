"""./course bench bvh: chapter 14's BVH (the SAH's) against brute force, from 552 to a
million triangles, in one run.

Each Newell teapot (build/assets/meshes/teapot_N.obj) stands in the empty Cornell room
(a scene file written here: the room and one `mesh` line, placed as cornell_teapot
places its teapot). Two kinds of rays, each timed by the chapter itself (--json):
  primary  one ray through each pixel's centre (--view normals): coherent rays
  diffuse  random cosine-distributed rays from each pixel's first hit (--view bounce):
           the incoherent rays of a path's bounces; the first dispatch also traces the
           camera rays that find where they start (1 ray in spp + 1)
for the tree and for brute force (--brute-force). Brute force runs only where the GL's
loop limit, as the chapter measures it, lets it (Mesa 22's llvmpipe: 65 535 loop
iterations per invocation, about 32 000 triangles): the chapter refuses the rest with
exit code 4, and the table says so. Where there is no limit (Mesa 25's llvmpipe, a GPU),
a brute-force run that the previous size's speed says would take more than
BRUTE_FORCE_SECONDS is skipped, and the table says that too. Each figure is the median
of --repeat timed runs (after a warm-up), with their range in build/bench/bvh.json and
the widest spread under the table. Prints the speed-ups and the scaling, writes
build/bench/bvh.json and the log-log figure build/bench/bvh_scaling.png; with
update_book (./course bench --update-book) the figure book/docs/figures/bvh_scaling.png
and the table in book/docs/benchmarks.md as well."""

from __future__ import annotations

import json
import shutil
import subprocess
from pathlib import Path

from course_tools.bench import common as bench_common
from course_tools.paths import ROOT
from course_tools.program_output import last_json_line

PAGE = ROOT / "book" / "docs" / "benchmarks.md"
FIGURE = ROOT / "book" / "docs" / "figures" / "bvh_scaling.png"
START, END = "<!-- bench-bvh:start -->", "<!-- bench-bvh:end -->"
TEAPOTS = (552, 6320, 102080, 1015056)
SIZE = 96
# Dispatches per run: enough for a few seconds of work where it is fast, one or two
# where brute force takes seconds per dispatch.
SPP = {("primary", "bvh"): 32, ("primary", "brute_force"): 2,
       ("diffuse", "bvh"): 48, ("diffuse", "brute_force"): 3}
VIEWS = {"primary": "normals", "diffuse": "bounce"}
SCRATCH = ROOT / "build" / "bench"
REFUSED = 4  # the chapter's exit code for a scene beyond the GL's loop limit
BRUTE_FORCE_SECONDS = 300  # the longest a brute-force run may be expected to take


def loop_limit(binary: Path) -> str:
    """The GL's loop limit as the chapter measures it (--probe-loop-limit), in words."""
    result = subprocess.run([str(binary), "--headless", "--probe-loop-limit", "--json"],
                            capture_output=True, text=True)
    if result.returncode != 0:
        raise SystemExit(f"{binary} --probe-loop-limit failed:\n{result.stderr}")
    limit = last_json_line(result.stdout, str(binary))["loop_limit"]
    return "none" if limit == "none" else f"{limit:,.0f}".replace(",", " ")

ROOM = ROOT / "assets" / "scenes" / "cornell_room.scene"
PLACED = "white scale 0.28 rotate_y -30 translate 0 -1 0"  # as in tests/python/chapters/test_13_bvh.py


def scene_with(mesh: Path) -> Path:
    """The empty Cornell room with the mesh standing in it, as a scene file."""
    SCRATCH.mkdir(parents=True, exist_ok=True)
    path = SCRATCH / f"{mesh.stem}.scene"
    path.write_text(ROOM.read_text() + f"\nmesh {mesh} {PLACED}\n")
    return path


def run(binary: Path, mesh: Path, rays: str, method: str, repeat: int) -> list | None:
    """The chapter's --json statistics of each of `repeat` timed runs, or None when it
    refuses (the loop limit)."""
    command = [str(binary), "--headless", "--scene", str(scene_with(mesh)), "--width",
               str(SIZE), "--height", str(SIZE), "--spp", str(SPP[rays, method]), "--view",
               VIEWS[rays], "--out", str(SCRATCH / "bench.pfm"), "--json"]
    if method == "brute_force":
        command.append("--brute-force")
    # The first run of a shader compiles it (Mesa keeps it in its disk cache), and the
    # first run of a mesh reads it from disk: a warm-up run keeps both out of the timing.
    timed = []
    for attempt in range(1 + repeat):
        result = subprocess.run(command, capture_output=True, text=True)
        if result.returncode == REFUSED:
            return None
        if result.returncode != 0:
            raise SystemExit(f"{' '.join(command)} failed ({result.returncode}):\n"
                             f"{result.stderr}")
        if attempt > 0:
            timed.append(last_json_line(result.stdout, " ".join(command)))
    return timed


def expected_seconds(records: list, triangles: int, rays: str, repeat: int) -> float:
    """How long brute force should take at `triangles`, from its speed at the biggest
    size measured so far (its work grows with the triangles); 0 when there is none."""
    done = [r for r in records if r["rays"] == rays and r["method"] == "brute_force"]
    if not done:
        return 0.0
    last = max(done, key=lambda r: r["triangles"])
    speed = last["rays_per_second"] * last["triangles"] / triangles
    rays_per_run = SIZE * SIZE * SPP[rays, "brute_force"]
    return (1 + repeat) * rays_per_run / speed  # the warm-up run and the timed ones


def bench(binary: Path, meshes: Path, repeat: int = 3) -> dict:
    watch = bench_common.QuietWatch()
    records, builds, machine, skipped = [], {}, None, []
    for triangles in TEAPOTS:
        mesh = meshes / f"teapot_{triangles}.obj"
        for rays in ("primary", "diffuse"):
            for method in ("bvh", "brute_force"):
                print(f"{triangles:>8} triangles, {rays:<7} rays, {method:<11} ...",
                      end=" ", flush=True)
                expected = expected_seconds(records, triangles, rays, repeat)
                if method == "brute_force" and expected > BRUTE_FORCE_SECONDS:
                    print(f"skipped: would take about {expected / 60:.0f} minutes", flush=True)
                    skipped.append([triangles, rays])
                    continue
                runs = run(binary, mesh, rays, method, repeat)
                if runs is None:
                    print("refused: beyond the GL's loop limit", flush=True)
                    continue
                stats = runs[0]
                machine = machine or bench_common.describe_machine(stats)
                speeds = bench_common.summarise([r["rays_per_second"] for r in runs])
                print(f"{speeds['median']:>12,.0f} rays/s, median of {repeat}, range "
                      f"{bench_common.spread_words(speeds)}", flush=True)
                records.append({"triangles": triangles, "rays": rays, "method": method,
                                "rays_per_second": speeds["median"], "spread": speeds})
                builds[triangles] = {"build_ms": stats["bvh_build_ms"],
                                     "nodes": stats["bvh_nodes"],
                                     "node_bytes": stats["bvh_nodes"] * 64,
                                     "depth": stats["bvh_max_depth"],
                                     "sah_cost": stats["bvh_sah_cost"],
                                     "scene_triangles": stats["triangles"]}
    return {"date": bench_common.today(), "machine": machine,
            "title": machine["gl_renderer"] if machine else "", "size": SIZE,
            "repeat": repeat, "results": records, "builds": builds,
            "loop_limit": loop_limit(binary), "skipped": skipped,
            "quiet": watch.finish()}


def speed(report: dict, triangles: int, rays: str, method: str) -> float | None:
    for record in report["results"]:
        if (record["triangles"], record["rays"], record["method"]) == (triangles, rays,
                                                                        method):
            return record["rays_per_second"]
    return None


def widest_spread(report: dict) -> float:
    return max((record["spread"]["spread"] for record in report["results"]), default=0.0)


def page_table(report: dict) -> str:
    lines = [f"Measured {report['date']} on "
             f"{bench_common.machine_words(report['machine'])}; {report['size']}² pixels, "
             "the teapot in the Cornell room (6 quads). Each figure is the median of "
             f"{report['repeat']} runs; the widest range of a figure's runs was "
             f"{100 * widest_spread(report):.0f}% of its median. "
             f"{bench_common.quiet_words(report['quiet'])}", "",
             "| triangles | camera rays/s, BVH | brute force | speed-up "
             "| diffuse rays/s, BVH | brute force | speed-up |",
             "| ---: | ---: | ---: | ---: | ---: | ---: | ---: |"]
    for triangles in TEAPOTS:
        cells = [f"{triangles:,}"]
        for rays in ("primary", "diffuse"):
            tree = speed(report, triangles, rays, "bvh")
            brute = speed(report, triangles, rays, "brute_force")
            cells.append(f"{tree:,.0f}" if tree else "—")
            was_skipped = [triangles, rays] in report.get("skipped", [])
            cells.append(f"{brute:,.0f}" if brute else "skipped²" if was_skipped
                         else "refused¹")
            cells.append(f"{tree / brute:,.0f}×" if tree and brute else "—")
        lines.append("| " + " | ".join(cells) + " |")
    limit = report.get("loop_limit", "65 535")
    if any("refused¹" in line for line in lines):
        lines += ["", f"¹ Beyond the GL's loop limit, {limit} iterations per invocation as "
                  "the chapter measures it: brute force would need more triangle tests than "
                  "that, and the chapter refuses to draw a wrong picture (exit code 4)."]
    if report.get("skipped"):
        lines += ["", f"² Not run: at the speed measured for fewer triangles it would take "
                  f"more than {BRUTE_FORCE_SECONDS // 60} minutes."]
    lines += ["",
              "| triangles | build | nodes | node array | depth | SAH cost |",
              "| ---: | ---: | ---: | ---: | ---: | ---: |"]
    for triangles in TEAPOTS:
        b = report["builds"].get(str(triangles)) or report["builds"].get(triangles)
        if b:
            lines.append(f"| {triangles:,} | {b['build_ms']:,.1f} ms | {b['nodes']:,.0f} | "
                         f"{b['node_bytes'] / 2**20:,.2f} MiB | {b['depth']:.0f} | "
                         f"{b['sah_cost']:.1f} |")
    ratio = lambda rays: (speed(report, 6320, rays, "bvh") or 0) / max(
        speed(report, TEAPOTS[-1], rays, "bvh") or float("inf"), 1e-9)
    lines += ["", f"From 6 320 to 1 015 056 triangles (160× more), camera rays slow down "
              f"{ratio('primary'):.2f}× and diffuse rays {ratio('diffuse'):.2f}×."]
    return "\n".join(lines)


def main(binary: Path, meshes: Path, repeat: int = 3, update_book: bool = False,
         page: Path = PAGE, figure: Path = FIGURE) -> int:
    SCRATCH.mkdir(parents=True, exist_ok=True)
    report = bench(binary, meshes, repeat)
    out = SCRATCH / "bvh.json"
    out.write_text(json.dumps(report, indent=2) + "\n")
    from python_prototypes import bench_plot
    drawn = SCRATCH / FIGURE.name
    bench_plot.draw_figure(report["title"], report["results"], drawn)
    table = page_table(report)
    print(table)
    print(f"bench: wrote {out} and {drawn}")
    if update_book:
        figure.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(drawn, figure)
        print(f"bench: wrote {figure}")
    bench_common.book_or_not(update_book, page, START, END, table, report["machine"])
    # The targets of the chapter (issue #6), checked where both sides could run.
    primary = (speed(report, 6320, "primary", "bvh") or 0) / (
        speed(report, 6320, "primary", "brute_force") or float("inf"))
    diffuse = (speed(report, 6320, "diffuse", "bvh") or 0) / (
        speed(report, 6320, "diffuse", "brute_force") or float("inf"))
    scaling = (speed(report, 6320, "primary", "bvh") or 0) / (
        speed(report, TEAPOTS[-1], "primary", "bvh") or float("inf"))
    checks = [(f"camera rays at 6 320 triangles: BVH {primary:.0f}x brute force", primary >= 50),
              (f"diffuse rays at 6 320 triangles: BVH {diffuse:.0f}x brute force", diffuse >= 20),
              (f"1M triangles within 2x of 6 320 (camera rays): {scaling:.2f}x", scaling <= 2)]
    for text, ok in checks:
        print(f"{'ok  ' if ok else 'MISS'} {text}")
    return 0 if all(ok for _, ok in checks) else 1
