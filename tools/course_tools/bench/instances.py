"""./course bench instances: chapter 26's two levels, a field of 10 000 teapots against
one, in one run.

Three scenes, written here into build/bench/instances/:
  one teapot, written out   the 6 320-triangle teapot as a `mesh` of the world, in the
                            empty Cornell room, placed as ./course bench bvh places it;
  one teapot, instanced     the same teapot as an object with one instance, placed the
                            same way: the price of the second level on its own;
  10 000 teapots            the object placed 10 000 times on a 100 x 100 grid, each turned
                            its own way, on a ground seen from above its corner out to
                            the horizon (63 million triangles placed, 6 320 kept).
Two kinds of rays, as the BVH bench times them (the chapter's own --json figures):
camera rays (--view normals) and random diffuse rays from each first hit (--view
bounce). Each figure is the median of --repeat runs, the scenes taking turns after an
untimed warm-up. Also from the chapter's --json: the bytes the objects, their trees,
the instances and the top-level tree take (instance_bytes) and the top level's build
time (instance_tree_ms: what a frame that moves the instances pays to build it again).

The targets (issue 30): the field's memory within 2x of one teapot's plus 64 bytes an
instance, and its rays per second at least half the single instanced teapot's.
Writes build/bench/instances.json and prints the table; writes it into
book/docs/benchmarks.md and chapter 26's page only with --update-book."""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

from course_tools.bench import common as bench_common
from course_tools.paths import ROOT

CHAPTERS = ROOT / "book" / "docs" / "chapters"
PAGES = {"benchmarks": (ROOT / "book" / "docs" / "benchmarks.md",
                        "<!-- bench-instances:start -->", "<!-- bench-instances:end -->"),
         "26": (CHAPTERS / "26_instances.md", "<!-- bench-instances:start -->",
                "<!-- bench-instances:end -->")}
OUT = ROOT / "build" / "bench"
ROOM = ROOT / "assets" / "scenes" / "cornell_room.scene"
TEAPOT = "teapot_6320.obj"
PLACED = "scale 0.28 rotate_y -30 translate 0 -1 0"  # as ./course bench bvh places it
GRID = 100          # teapots along each side of the field
SPACING = 0.5       # between neighbours' middles; a teapot is 0.32 wide at its scale
FIELD_SCALE = 0.05
INSTANCE_BYTES = 64  # gpu::Instance (shaders/26_instances/shared.h)
VIEWS = {"primary": "normals", "diffuse": "bounce"}
SPP = {"primary": 64, "diffuse": 64}  # runs of seconds: shorter ones scatter by 30%+


@dataclass(frozen=True)
class Scene:
    key: str
    label: str
    instances: int


SCENES = (Scene("written_out", "one teapot, written out", 0),
          Scene("one_instance", "one teapot, instanced", 1),
          Scene("field", "a field of teapots", GRID * GRID))


@dataclass
class Settings:
    size: int = 128
    repeat: int = 3
    grid: int = GRID


def scene_text(scene: Scene, teapot: Path, grid: int = GRID) -> str:
    """The scene file of one of SCENES, naming the teapot by its full path."""
    if scene.key == "written_out":
        return ROOM.read_text() + f"\nmesh {teapot} white {PLACED}\n"
    pot = f"\nobject pot begin\n  mesh {teapot} white\nend\n"
    if scene.key == "one_instance":
        return ROOM.read_text() + pot + f"instance pot {PLACED}\n"
    # The field: a camera above one corner looking across the grid's diagonal to the
    # horizon, a grey ground under it, a lamp high above (for a radiance picture).
    side = grid * SPACING
    lines = ["camera eye -1.5 2.5 -1.5 look 1 -0.45 1 up 0 1 0 focal 0.035 sensor 0.025",
             "material white albedo 0.8 0.8 0.8", "material ground albedo 0.5 0.5 0.5",
             "material lamp albedo 0 0 0 emission 5 5 5",
             f"quad -5 0 {side + 5}  {side + 10} 0 0  0 0 {-(side + 10)}  ground name ground",
             f"quad -50 40 -50  {side + 100} 0 0  0 0 {side + 100}  lamp name lamp"]
    for i in range(grid):
        for j in range(grid):
            turn = (37 * (i * grid + j)) % 360  # each its own way, the same every run
            lines.append(f"instance pot scale {FIELD_SCALE} rotate_y {turn} "
                         f"translate {SPACING * i:g} 0 {SPACING * j:g}")
    lines.insert(4, pot.strip())
    return "\n".join(lines) + "\n"


def write_scenes(folder: Path, teapot: Path, grid: int = GRID) -> dict:
    folder.mkdir(parents=True, exist_ok=True)
    paths = {}
    for scene in SCENES:
        paths[scene.key] = folder / f"{scene.key}.scene"
        paths[scene.key].write_text(scene_text(scene, teapot.resolve(), grid))
    return paths


def run(binary: Path, scene: Path, rays: str, size: int, spp: int, folder: Path) -> dict:
    """One render's --json statistics."""
    command = [str(binary), "--headless", "--scene", str(scene), "--width", str(size),
               "--height", str(size), "--spp", str(spp), "--view", VIEWS[rays], "--out",
               str(folder / "out.pfm"), "--json"]
    return bench_common.program_stats(command, "instances")


def bench(binary: Path, meshes: Path, settings: Settings, folder: Path = OUT / "instances"
          ) -> dict:
    watch = bench_common.QuietWatch()
    scenes = write_scenes(folder, meshes / TEAPOT, settings.grid)
    rows = [(scene, rays) for scene in SCENES for rays in VIEWS]
    print("bench instances: warm-up (not timed) ...", flush=True)
    first = None
    for scene, rays in rows:
        stats = run(binary, scenes[scene.key], rays, settings.size, 1, folder)
        first = first or stats
    runs = {f"{scene.key}: {rays}": [] for scene, rays in rows}
    for round_number in range(1, settings.repeat + 1):
        print(f"bench instances: round {round_number} of {settings.repeat} ...", flush=True)
        for scene, rays in rows:
            runs[f"{scene.key}: {rays}"].append(
                run(binary, scenes[scene.key], rays, settings.size, SPP[rays], folder))
    report_rows = {}
    for scene, rays in rows:
        done = runs[f"{scene.key}: {rays}"]
        report_rows[f"{scene.key}: {rays}"] = {
            "scene": scene.key, "rays": rays,
            "rays_per_second": bench_common.summarise([r["rays_per_second"] for r in done]),
            "instance_tree_ms": bench_common.summarise([r["instance_tree_ms"] for r in done]),
            "instance_bytes": done[0]["instance_bytes"], "bvh_bytes": done[0]["bvh_bytes"],
            "instances": done[0]["instances"], "placed_triangles": done[0]["placed_triangles"],
            "triangles": done[0]["triangles"]}
    return {"date": bench_common.today(), "machine": bench_common.describe_machine(first),
            "settings": vars(settings), "spp": SPP, "rows": report_rows,
            "quiet": watch.finish()}


def row(report: dict, scene: str, rays: str) -> dict:
    return report["rows"][f"{scene}: {rays}"]


def speed(report: dict, scene: str, rays: str) -> float:
    return row(report, scene, rays)["rays_per_second"]["median"]


def figures(report: dict) -> dict:
    """What the targets are about: the field's memory against one teapot's plus the
    instances', and its speed against one instanced teapot's."""
    one, field = row(report, "one_instance", "primary"), row(report, "field", "primary")
    allowance = one["instance_bytes"] + (field["instances"] - 1) * INSTANCE_BYTES
    return {"memory_ratio": field["instance_bytes"] / allowance, "allowance": allowance,
            "written_out_bytes": field["instances"] * one["instance_bytes"],
            **{f"{rays}_ratio": speed(report, "field", rays) / speed(report, "one_instance",
                                                                      rays)
               for rays in VIEWS}}


def checks(report: dict) -> list[tuple[str, bool]]:
    f = figures(report)
    return [(f"memory of the field: {f['memory_ratio']:.2f}x one teapot's plus 64 bytes an "
             "instance (at most 2x)", f["memory_ratio"] <= 2.0),
            *((f"{rays} rays through the field: {f[rays + '_ratio']:.2f}x one instanced "
               "teapot's (at least 0.5x)", f[rays + "_ratio"] >= 0.5) for rays in VIEWS)]


def megabytes(count: float) -> str:
    return f"{count / 2**20:,.2f} MiB" if count < 2**30 else f"{count / 2**30:,.1f} GiB"


def page_table(report: dict) -> str:
    s, machine = report["settings"], report["machine"]
    lines = [f"Measured {report['date']} on {bench_common.machine_words(machine)}; "
             f"{s['size']}² pixels, {report['spp']['primary']} camera rays and "
             f"{report['spp']['diffuse']} diffuse rays a pixel. Each figure is the median of "
             f"{s['repeat']} runs, the scenes taking turns, with the range of the runs. "
             f"{bench_common.quiet_words(report['quiet'])}", "",
             "| scene | instances | triangles placed | kept | camera rays/s | range "
             "| diffuse rays/s | range | objects + instances + top level | top level built |",
             "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"]
    for scene in SCENES:
        primary, diffuse = row(report, scene.key, "primary"), row(report, scene.key, "diffuse")
        placed = primary["placed_triangles"] or primary["triangles"]
        what = megabytes(primary["instance_bytes"]) if scene.instances else "—"
        label = (f"{primary['instances']:,} teapots" if scene.key == "field"
                 else scene.label)
        build = (f"{primary['instance_tree_ms']['median']:,.2f} ms" if scene.instances
                 else "—")
        lines.append(
            f"| {label} | {primary['instances']:,} | {placed:,} | "
            f"{primary['triangles']:,} | {primary['rays_per_second']['median']:,.0f} | "
            f"{bench_common.spread_words(primary['rays_per_second'])} | "
            f"{diffuse['rays_per_second']['median']:,.0f} | "
            f"{bench_common.spread_words(diffuse['rays_per_second'])} | {what} | {build} |")
    f = figures(report)
    lines += ["", f"The field keeps {megabytes(row(report, 'field', 'primary')['instance_bytes'])}"
              f": {f['memory_ratio']:.2f}× one teapot's objects and trees plus "
              f"{INSTANCE_BYTES} bytes an instance ({megabytes(f['allowance'])}); written "
              f"out, its teapots would need about {megabytes(f['written_out_bytes'])}. "
              f"Its camera rays run at {f['primary_ratio']:.2f}× and its diffuse rays at "
              f"{f['diffuse_ratio']:.2f}× the speed of one instanced teapot's."]
    return "\n".join(lines)


def publish(report: dict, update_book: bool = False, pages: dict = PAGES,
            out_folder: Path = OUT):
    """The report in out_folder (instances.json), the table printed, and written into
    the pages (the benchmarks page, chapter 26's) only with update_book."""
    table = page_table(report)
    out = out_folder / "instances.json"
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(report, indent=2) + "\n")
    print(table)
    print(f"bench: wrote {out}")
    for page, start, end in pages.values():
        bench_common.book_or_not(update_book, page, start, end, table, report["machine"])


def main(binary: Path, meshes: Path, settings: Settings, update_book: bool = False,
         pages: dict = PAGES, out_folder: Path = OUT) -> int:
    report = bench(binary, meshes, settings, out_folder / "instances")
    publish(report, update_book, pages, out_folder)
    results = checks(report)
    for text, ok in results:
        print(f"{'ok  ' if ok else 'MISS'} {text}")
    return 0 if all(ok for _, ok in results) else 1
