"""./course bench instances, its second part: chapter 27's twisting teapot, its tree
refitted against one built afresh, in one run.

For each twist (the teapot of cornell_twist.scene at the shutter's closing:
--instant 1 --twist DEGREES), the chapter reports (--json) the refitted tree's SAH
cost and a fresh tree's over the same triangles, and how long the refit and the build
took. The bench also times rays through each tree, camera rays (--view normals) and
diffuse rays (--view bounce): the refitted one, and a fresh one, the same twisted
triangles written out (python_prototypes/instances.twisted_about_middle) as the mesh
of a still object, whose tree the chapter builds when it loads it. Each figure is the
median of --repeat runs, taking turns after an untimed warm-up. Writes
build/bench/refit.json and prints the table; writes it into book/docs/benchmarks.md
and chapter 27's page only with --update-book."""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

from course_tools.bench import common as bench_common
from course_tools.paths import ROOT

CHAPTERS = ROOT / "book" / "docs" / "chapters"
PAGES = {"benchmarks": (ROOT / "book" / "docs" / "benchmarks.md",
                        "<!-- bench-refit:start -->", "<!-- bench-refit:end -->"),
         "27": (CHAPTERS / "27_motion.md", "<!-- bench-refit:start -->",
                "<!-- bench-refit:end -->")}
OUT = ROOT / "build" / "bench"
SCENE = ROOT / "assets" / "scenes" / "cornell_twist.scene"
TEAPOT = "teapot_6320.obj"
TWISTS = (22.5, 45.0, 90.0, 180.0)
VIEWS = {"primary": "normals", "diffuse": "bounce"}
SPP = {"primary": 64, "diffuse": 64}  # runs of seconds: shorter ones scatter by 30%+


@dataclass
class Settings:
    size: int = 128
    repeat: int = 3
    twists: tuple = TWISTS


def fresh_scene(folder: Path, meshes: Path, degrees: float) -> Path:
    """cornell_twist.scene with the teapot twisted by `degrees` written out: its tree
    is built afresh when the chapter loads it."""
    from python_prototypes import instances, obj_io, teapot
    positions, normals, corners, corner_normals = obj_io.read_obj(meshes / TEAPOT)
    if normals is None or corner_normals is None or (corners != corner_normals).any():
        raise SystemExit(f"bench refit: {meshes / TEAPOT} needs one normal a corner")
    mesh = folder / f"teapot_twisted_{degrees:g}.obj"
    teapot.write_obj(mesh, *instances.twisted_about_middle(positions, normals, degrees),
                     corners)
    scene = folder / f"fresh_{degrees:g}.scene"
    scene.write_text(SCENE.read_text().replace(f"meshes/{TEAPOT}", str(mesh.resolve())))
    return scene


def run(binary: Path, arguments: list, rays: str, size: int, spp: int,
        folder: Path) -> dict:
    return bench_common.program_stats(
        [binary, "--headless", *arguments, "--width", size, "--height", size, "--spp", spp,
         "--view", VIEWS[rays], "--out", folder / "out.pfm", "--json"], "refit")


def bench(binary: Path, meshes: Path, settings: Settings, folder: Path = OUT / "refit"
          ) -> dict:
    watch = bench_common.QuietWatch()
    folder.mkdir(parents=True, exist_ok=True)
    rows = []
    for degrees in settings.twists:
        rows.append((degrees, "refitted", ["--scene", SCENE, "--instant", 1, "--twist",
                                           degrees]))
        rows.append((degrees, "fresh", ["--scene", fresh_scene(folder, meshes, degrees)]))
    print("bench refit: warm-up (not timed) ...", flush=True)
    first = run(binary, rows[0][2], "primary", settings.size, 1, folder)
    for _, _, arguments in rows[1:]:
        run(binary, arguments, "primary", settings.size, 1, folder)
    runs = {(degrees, tree, rays): [] for degrees, tree, _ in rows for rays in VIEWS}
    for round_number in range(1, settings.repeat + 1):
        print(f"bench refit: round {round_number} of {settings.repeat} ...", flush=True)
        for degrees, tree, arguments in rows:
            for rays in VIEWS:
                runs[degrees, tree, rays].append(
                    run(binary, arguments, rays, settings.size, SPP[rays], folder))
    report_rows = []
    for degrees in settings.twists:
        refitted = runs[degrees, "refitted", "primary"]
        row = {"twist": degrees,
               "refitted_sah_cost": refitted[0]["object_sah_cost"],
               "rebuilt_sah_cost": refitted[0]["rebuilt_sah_cost"],
               "refit_ms": bench_common.summarise([r["refit_ms"] for r in refitted]),
               "rebuild_ms": bench_common.summarise([r["rebuild_ms"] for r in refitted])}
        for tree in ("refitted", "fresh"):
            for rays in VIEWS:
                row[f"{tree}_{rays}"] = bench_common.summarise(
                    [r["rays_per_second"] for r in runs[degrees, tree, rays]])
        report_rows.append(row)
    return {"date": bench_common.today(), "machine": bench_common.describe_machine(first),
            "settings": {**vars(settings), "twists": list(settings.twists)}, "spp": SPP,
            "rows": report_rows, "quiet": watch.finish()}


def page_table(report: dict) -> str:
    s = report["settings"]
    lines = [f"Measured {report['date']} on "
             f"{bench_common.machine_words(report['machine'])}; {s['size']}² pixels, "
             f"{report['spp']['primary']} camera rays and {report['spp']['diffuse']} diffuse "
             f"rays a pixel, the teapot of `cornell_twist.scene` twisted at its top. Each "
             f"figure is the median of {s['repeat']} runs, taking turns. "
             f"{bench_common.quiet_words(report['quiet'])}", "",
             "| twist | SAH cost, refitted | rebuilt | ÷ | refit | build "
             "| camera rays/s, refitted | fresh tree | ÷ | diffuse rays/s, refitted "
             "| fresh tree | ÷ |",
             "| ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: "
             "| ---: |"]
    for row in report["rows"]:
        cells = [f"{row['twist']:g}°", f"{row['refitted_sah_cost']:.2f}",
                 f"{row['rebuilt_sah_cost']:.2f}",
                 f"{row['refitted_sah_cost'] / row['rebuilt_sah_cost']:.2f}",
                 f"{row['refit_ms']['median']:.2f} ms", f"{row['rebuild_ms']['median']:.1f} ms"]
        for rays in VIEWS:
            refitted, fresh = (row[f"{tree}_{rays}"]["median"] for tree in ("refitted", "fresh"))
            cells += [f"{refitted:,.0f}", f"{fresh:,.0f}", f"{refitted / fresh:.2f}"]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def publish(report: dict, update_book: bool = False, pages: dict = PAGES,
            out_folder: Path = OUT):
    """The report in out_folder (refit.json), the table printed, and written into the
    pages (the benchmarks page, chapter 27's) only with update_book."""
    table = page_table(report)
    out = out_folder / "refit.json"
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(report, indent=2) + "\n")
    print(table)
    print(f"bench: wrote {out}")
    for page, start, end in pages.values():
        bench_common.book_or_not(update_book, page, start, end, table, report["machine"])


def main(binary: Path, meshes: Path, settings: Settings, update_book: bool = False,
         pages: dict = PAGES, out_folder: Path = OUT) -> int:
    publish(bench(binary, meshes, settings, out_folder / "refit"), update_book, pages,
            out_folder)
    return 0
