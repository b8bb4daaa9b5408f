"""./course bench speed: the figures of chapter 19 (speed), each the median of repeated
runs that take turns, on one machine, in one run of the bench.

- **The scenes**: the Cornell box (18 quads), the teapot in the Cornell room (6 320
  triangles through the tree) and the sky showcase (50 spheres, a quad, the sky),
  through chapter 18 (one generic shader, everything in storage buffers) and through
  chapter 19 with its automatic choice.
- **Where the scene is read from** (the Cornell box): storage buffers, uniform blocks,
  buffer textures, constants written out into the shader; and the generic shader,
  every feature compiled in (--generic), against the same storage buffers specialised.
- **The tree** (the teapot, and the million-triangle teapot in the same room): its
  nodes and triangles from storage buffers or buffer textures, and its leaves priced as
  the four tests they run or by count (chapter 14's tree); the million's rays per second
  against the 6 320's.
- **Compile time**: the path tracer's shader compiled with Mesa's shader cache off
  (MESA_SHADER_CACHE_DISABLE), the whole run of a 16 x 16 image at 1 sample, for the
  Cornell box and the sky showcase each way.

After an untimed warm-up of each row, the rows take turns for --repeat rounds; each
figure is the median of its runs with their range. Speeds are samples per second as
the chapters count them (--json), and the GPU's own time (chapter 19's timestamps).
Writes build/bench/speed.json and prints the tables; writes them into the speed
chapter's page only with --update-book."""

from __future__ import annotations

import json
import os
import subprocess
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

from course_tools.bench import common as bench_common

from course_tools.paths import ROOT

PAGE = ROOT / "book" / "docs" / "chapters" / "19_speed.md"
START, END = "<!-- speed:start -->", "<!-- speed:end -->"
OUT = ROOT / "build" / "bench"


@dataclass(frozen=True)
class Row:
    table: str     # which table it belongs to
    scene: str     # assets/scenes/NAME.scene
    label: str     # what the table calls it
    chapter: str   # "18" or "19"
    options: tuple = ()


# The tree rows whose leaves are priced as chapter 14 priced them (--bvh-leaves-by-count).
LEAVES_BY_COUNT = "leaves priced by count (chapter 14's tree)"
ROWS = (
    Row("scenes", "cornell_box", "chapter 18", "18"),
    Row("scenes", "cornell_box", "chapter 19 (automatic)", "19"),
    Row("scenes", "cornell_teapot", "chapter 18", "18"),
    Row("scenes", "cornell_teapot", "chapter 19 (automatic)", "19"),
    Row("scenes", "sky_showcase", "chapter 18", "18"),
    Row("scenes", "sky_showcase", "chapter 19 (automatic)", "19"),
    Row("memory", "cornell_box", "generic shader, storage buffers", "19", ("--generic",)),
    Row("memory", "cornell_box", "storage buffers", "19", ("--scene-memory", "storage")),
    Row("memory", "cornell_box", "uniform blocks", "19", ("--scene-memory", "uniform")),
    Row("memory", "cornell_box", "buffer textures", "19", ("--scene-memory", "texture")),
    Row("memory", "cornell_box", "constants, written out", "19",
        ("--scene-memory", "constants")),
    Row("memory", "sky_showcase", "buffer textures", "19", ("--scene-memory", "texture")),
    Row("memory", "sky_showcase", "constants, written out", "19",
        ("--scene-memory", "constants")),
    Row("tree", "cornell_teapot", "tree in storage buffers", "19",
        ("--bvh-memory", "storage")),
    Row("tree", "cornell_teapot", "tree in buffer textures", "19",
        ("--bvh-memory", "texture")),
    Row("tree", "cornell_teapot_million", "tree in storage buffers", "19",
        ("--bvh-memory", "storage")),
    Row("tree", "cornell_teapot_million", "tree in buffer textures", "19",
        ("--bvh-memory", "texture")),
    Row("tree", "cornell_teapot", LEAVES_BY_COUNT, "19",
        ("--bvh-memory", "texture", "--bvh-leaves-by-count")),
    Row("tree", "cornell_teapot_million", LEAVES_BY_COUNT, "19",
        ("--bvh-memory", "texture", "--bvh-leaves-by-count")),
)
COMPILED = [row for row in ROWS if row.table == "memory"] + \
    [Row("compile", "cornell_box", "chapter 18", "18"),
     Row("compile", "sky_showcase", "chapter 18", "18")]


@dataclass
class Settings:
    size: int = 256
    spp: int = 32
    depth: int = 6
    repeat: int = 3


def run(binaries: dict, row: Row, size: int, spp: int, depth: int,
        env: dict | None = None) -> dict:
    """One render; its --json statistics, with the whole process's seconds."""
    with tempfile.TemporaryDirectory() as folder:
        command = [str(binaries[row.chapter]), "--headless", "--scene", row.scene,
                   "--width", str(size), "--height", str(size), "--spp", str(spp),
                   "--depth", str(depth), "--out", str(Path(folder) / "out.pfm"),
                   "--json", *row.options]
        start = time.perf_counter()
        result = subprocess.run(command, capture_output=True, text=True,
                                env={**os.environ, **(env or {})})
        seconds = time.perf_counter() - start
    if result.returncode != 0:
        raise SystemExit(f"bench speed: {' '.join(command)} failed "
                         f"({result.returncode}):\n{result.stderr}")
    stats = json.loads(result.stdout.strip().splitlines()[-1])
    stats["process_seconds"] = seconds
    return stats


def key(row: Row) -> str:
    return f"{row.table}: {row.scene}: {row.label}"


def bench(binaries: dict, settings: Settings) -> dict:
    watch = bench_common.QuietWatch()
    runs = {key(row): [] for row in ROWS}
    print("bench speed: warm-up (1 spp, not timed) ...", flush=True)
    first = None
    for row in ROWS:
        stats = run(binaries, row, settings.size, 1, settings.depth)
        first = first or stats
    for round_number in range(1, settings.repeat + 1):
        print(f"bench speed: round {round_number} of {settings.repeat} ...", flush=True)
        for row in ROWS:
            stats = run(binaries, row, settings.size, settings.spp, settings.depth)
            runs[key(row)].append({"samples_per_second": stats["samples_per_second"],
                                   "rays_per_second": stats["rays_per_second"],
                                   "chosen": stats.get("scene_memory", "storage")})
    compiles = {key(row): [] for row in COMPILED}
    print("bench speed: compile times (Mesa's shader cache off) ...", flush=True)
    for _ in range(settings.repeat):
        for row in COMPILED:
            stats = run(binaries, row, 16, 1, settings.depth,
                        env={"MESA_SHADER_CACHE_DISABLE": "true"})
            compiles[key(row)].append(stats["process_seconds"])
    return {"date": bench_common.today(), "machine": bench_common.describe_machine(first),
            "settings": vars(settings),
            "rows": {key(row): {"table": row.table, "scene": row.scene,
                                "label": row.label.replace(
                                    "automatic", "automatic: " + runs[key(row)][0]["chosen"]),
                                "chapter": row.chapter, "options": list(row.options),
                                "samples_per_second": bench_common.summarise(
                                    [r["samples_per_second"] for r in runs[key(row)]]),
                                "rays_per_second": bench_common.summarise(
                                    [r["rays_per_second"] for r in runs[key(row)]])}
                     for row in ROWS},
            "compile_seconds": {k: bench_common.summarise(v) for k, v in compiles.items()},
            "quiet": watch.finish()}


def median(report: dict, table: str, scene: str, label: str) -> float:
    return report["rows"][f"{table}: {scene}: {label}"]["samples_per_second"]["median"]


def compile_words(report: dict, row_key: str) -> str:
    figure = report["compile_seconds"].get(row_key)
    return f"{figure['median']:.1f}" if figure else "—"


def table(report: dict, which: str, baseline: str) -> list[str]:
    """Rows of one table; speeds relative to `baseline` (a label) in the same scene."""
    lines = ["| scene | shader | samples/s | range of the runs (spread) | rays/s | "
             f"÷ {baseline} | compile, s |", "| --- | --- | ---: | ---: | ---: | ---: | ---: |"]
    for row_key, row in report["rows"].items():
        if row["table"] != which:
            continue
        samples = row["samples_per_second"]
        base = median(report, which, row["scene"], baseline)
        compile_key = f"compile: {row['scene']}: chapter 18" if row["chapter"] == "18" \
            and which == "scenes" else row_key
        lines.append(f"| {row['scene']} | {row['label']} | {samples['median']:,.0f} | "
                     f"{bench_common.spread_words(samples)} | "
                     f"{row['rays_per_second']['median']:,.0f} | "
                     f"{samples['median'] / base:.2f}× | {compile_words(report, compile_key)} |")
    return lines


def million_words(report: dict) -> list[str]:
    """The million-triangle teapot's rays per second against the 6 320-triangle one's,
    both through buffer textures: how the tree's cost grows with the mesh."""
    rows = report["rows"]
    big = rows.get("tree: cornell_teapot_million: tree in buffer textures")
    small = rows.get("tree: cornell_teapot: tree in buffer textures")
    if not big or not small:
        return []
    ratio = big["rays_per_second"]["median"] / small["rays_per_second"]["median"]
    words = (f"Through buffer textures, the million-triangle teapot traces {ratio:.2f} "
             "times the rays per second of the 6 320-triangle one.")
    by_count = {scene: rows.get(f"tree: {scene}: {LEAVES_BY_COUNT}")
                for scene in ("cornell_teapot", "cornell_teapot_million")}
    if all(by_count.values()):
        gain = [row["rays_per_second"]["median"] / by_count[scene]["rays_per_second"]["median"]
                for scene, row in (("cornell_teapot", small), ("cornell_teapot_million", big))]
        before = (by_count["cornell_teapot_million"]["rays_per_second"]["median"] /
                  by_count["cornell_teapot"]["rays_per_second"]["median"])
        words += (f" Leaves priced as the four tests they run made the teapot {gain[0]:.2f} "
                  f"times and the million {gain[1]:.2f} times as fast as leaves priced by "
                  f"count; priced by count, the million traced {before:.2f} times the "
                  "6 320's rays per second.")
    return [words, ""]

RATIOS = (  # (what, scene, numerator's label, denominator's label), from the tables
    ("storage buffers ÷ buffer textures", "cornell_box", "storage buffers", "buffer textures"),
    ("uniform blocks ÷ buffer textures", "cornell_box", "uniform blocks", "buffer textures"),
    ("constants ÷ buffer textures", "cornell_box", "constants, written out",
     "buffer textures"),
    ("generic ÷ specialised, both storage buffers", "cornell_box",
     "generic shader, storage buffers", "storage buffers"),
)


def ratio_rows(report: dict) -> list[str]:
    """The ratios a learner with a GPU compares with theirs (an empty column to fill)."""
    lines = ["| the Cornell box, samples/s | this machine | your GPU |",
             "| --- | ---: | ---: |"]
    for what, scene, top, bottom in RATIOS:
        ratio = median(report, "memory", scene, top) / median(report, "memory", scene, bottom)
        lines.append(f"| {what} | {ratio:.2f} | |")
    return lines


def page_table(report: dict) -> str:
    s, machine = report["settings"], report["machine"]
    heading = (f"Measured {report['date']} on {bench_common.machine_words(machine)}; "
               f"{s['size']}², {s['spp']} spp, depth {s['depth']}. Each figure is the median "
               f"of {s['repeat']} runs, the rows taking turns, with the range of the runs; "
               "compile times are whole runs of a 16 × 16 image at 1 sample with Mesa's "
               f"shader cache off, median of {s['repeat']}. "
               f"{bench_common.quiet_words(report['quiet'])}")
    return "\n".join([heading, "", "The scenes, chapter 18 against chapter 19:", "",
                      *table(report, "scenes", "chapter 18"), "",
                      "Where the scene is read from, and specialisation:", "",
                      *table(report, "memory", "buffer textures"), "",
                      "The tree's nodes and triangles:", "",
                      *table(report, "tree", "tree in storage buffers"), "",
                      *million_words(report),
                      "The ratios to compare with a GPU's (the same bench there):", "",
                      *ratio_rows(report)])


def main(binaries: dict, settings: Settings, update_book: bool = False, page: Path = PAGE,
         out_folder: Path = OUT) -> int:
    report = bench(binaries, settings)
    bench_common.publish(report, out_folder / "speed.json", page_table(report), update_book,
                         page, START, END)
    return 0
