"""./course bench speed: the figures of chapters 19 (specialisation), 20 (memory paths)
and 21 (a tree priced as it runs), each the median of repeated runs that take turns, on
one machine, in one run of the bench.

- **The scenes** (19): the Cornell box (18 quads), the teapot in the Cornell room (6 320
  triangles through the tree) and the sky showcase (50 spheres, a quad, the sky),
  through chapter 18 (one generic shader, everything in storage buffers) and through
  chapter 19 with its automatic choice.
- **Specialisation** (19): the generic shader, every feature compiled in (--generic),
  against the same storage buffers specialised, and constants written out into the
  shader; the Cornell box and the showcase.
- **Where the scene is read from** (20): storage buffers, uniform blocks, buffer
  textures, constants written out; the tree's nodes and triangles from storage buffers
  or buffer textures (the teapot, and the million-triangle teapot in the same room).
- **The tree's price** (21): chapter 20's tree and walk against chapter 21's walk with
  leaves priced by count (chapter 14's tree) and priced as the four tests they run; the
  million's rays per second against the 6 320's.
- **Compile time**: the path tracer's shader compiled with Mesa's shader cache off
  (MESA_SHADER_CACHE_DISABLE), the whole run of a 16 x 16 image at 1 sample, for the
  Cornell box and the sky showcase each way.

After an untimed warm-up of each row, the rows take turns for --repeat rounds; each
figure is the median of its runs with their range. Speeds are samples per second as
the chapters count them (--json), and the GPU's own time (chapter 19's timestamps).
Writes build/bench/speed.json and prints the tables; writes each chapter's tables into
its page only with --update-book."""

from __future__ import annotations

import os
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

from course_tools.bench import common as bench_common

from course_tools.paths import ROOT

CHAPTERS = ROOT / "book" / "docs" / "chapters"
# The block of each page that the bench writes: page, start marker, end marker.
PAGES = {"19": (CHAPTERS / "19_specialisation.md", "<!-- speed:start -->", "<!-- speed:end -->"),
         "20": (CHAPTERS / "20_memory_paths.md", "<!-- memory:start -->", "<!-- memory:end -->"),
         "21": (CHAPTERS / "21_tree_price.md", "<!-- tree:start -->", "<!-- tree:end -->")}
OUT = ROOT / "build" / "bench"


@dataclass(frozen=True)
class Row:
    table: str     # which table it belongs to
    scene: str     # assets/scenes/NAME.scene
    label: str     # what the table calls it
    chapter: str   # "18" to "21"
    options: tuple = ()


STORAGE, CONSTANTS = ("--scene-memory", "storage"), ("--scene-memory", "constants")
# The tree rows whose leaves are priced as chapter 14 priced them (--bvh-leaves-by-count).
LEAVES_BY_COUNT = "leaves priced by count (chapter 14's tree)"
LEAVES_AS_RUN = "leaves priced as the walk runs them"
CHAPTER_20_TREE = "chapter 20 (chapter 18's walk)"
ROWS = (
    *(Row("scenes", scene, label, chapter)
      for scene in ("cornell_box", "cornell_teapot", "sky_showcase")
      for label, chapter in (("chapter 18", "18"), ("chapter 19 (automatic)", "19"))),
    Row("specialisation", "cornell_box", "generic shader, storage buffers", "19",
        ("--generic",)),
    Row("specialisation", "cornell_box", "storage buffers", "19", STORAGE),
    Row("specialisation", "cornell_box", "constants, written out", "19", CONSTANTS),
    Row("specialisation", "sky_showcase", "storage buffers", "19", STORAGE),
    Row("specialisation", "sky_showcase", "constants, written out", "19", CONSTANTS),
    Row("memory", "cornell_box", "storage buffers", "20", STORAGE),
    Row("memory", "cornell_box", "uniform blocks", "20", ("--scene-memory", "uniform")),
    Row("memory", "cornell_box", "buffer textures", "20", ("--scene-memory", "texture")),
    Row("memory", "cornell_box", "constants, written out", "20", CONSTANTS),
    Row("memory", "sky_showcase", "buffer textures", "20", ("--scene-memory", "texture")),
    Row("memory", "sky_showcase", "constants, written out", "20", CONSTANTS),
    *(Row("tree", scene, f"tree in {where}", "20", ("--bvh-memory", memory))
      for scene in ("cornell_teapot", "cornell_teapot_million")
      for where, memory in (("storage buffers", "storage"), ("buffer textures", "texture"))),
    *(Row("price", scene, label, chapter, options)
      for scene in ("cornell_teapot", "cornell_teapot_million")
      for label, chapter, options in ((CHAPTER_20_TREE, "20", ()),
                                      (LEAVES_BY_COUNT, "21", ("--bvh-leaves-by-count",)),
                                      (LEAVES_AS_RUN, "21", ()))),
)
COMPILED = [row for row in ROWS if row.table in ("specialisation", "memory")] + \
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
        stats = bench_common.program_stats(command, "speed", {**os.environ, **(env or {})})
        stats["process_seconds"] = time.perf_counter() - start
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
    for each tree and walk: how the tree's cost grows with the mesh, and what pricing the
    leaves as the walk runs them gains."""
    rows = report["rows"]
    figure = {(scene, label): rows.get(f"price: {scene}: {label}")
              for scene in ("cornell_teapot", "cornell_teapot_million")
              for label in (CHAPTER_20_TREE, LEAVES_BY_COUNT, LEAVES_AS_RUN)}
    if not all(figure.values()):
        return []

    def rays(scene, label):
        return figure[(scene, label)]["rays_per_second"]["median"]
    growth = {label: rays("cornell_teapot_million", label) / rays("cornell_teapot", label)
              for label in (CHAPTER_20_TREE, LEAVES_AS_RUN)}
    gain = {scene: rays(scene, LEAVES_AS_RUN) / rays(scene, LEAVES_BY_COUNT)
            for scene in ("cornell_teapot", "cornell_teapot_million")}
    return [f"Leaves priced as the four tests they run made the teapot {gain['cornell_teapot']:.2f} "
            f"times and the million {gain['cornell_teapot_million']:.2f} times as fast as "
            "leaves priced by count, both walked this chapter's way. The million-triangle "
            f"teapot traces {growth[LEAVES_AS_RUN]:.2f} times the rays per second of the "
            f"6 320-triangle one here, and {growth[CHAPTER_20_TREE]:.2f} times in chapter 20.",
            ""]


RATIOS = {  # page: (what, table, scene, numerator's label, denominator's label)
    "19": (("generic ÷ specialised, both storage buffers", "specialisation", "cornell_box",
            "generic shader, storage buffers", "storage buffers"),
           ("constants ÷ storage buffers", "specialisation", "cornell_box",
            "constants, written out", "storage buffers")),
    "20": (("storage buffers ÷ buffer textures", "memory", "cornell_box", "storage buffers",
            "buffer textures"),
           ("uniform blocks ÷ buffer textures", "memory", "cornell_box", "uniform blocks",
            "buffer textures"),
           ("constants ÷ buffer textures", "memory", "cornell_box", "constants, written out",
            "buffer textures")),
    "21": (("leaves priced as run ÷ by count, the teapot", "price", "cornell_teapot",
            LEAVES_AS_RUN, LEAVES_BY_COUNT),
           ("leaves priced as run ÷ by count, the million", "price", "cornell_teapot_million",
            LEAVES_AS_RUN, LEAVES_BY_COUNT)),
}


def ratio_rows(report: dict, page: str) -> list[str]:
    """The ratios a learner with a GPU compares with theirs (an empty column to fill)."""
    lines = ["| samples/s | this machine | your GPU |", "| --- | ---: | ---: |"]
    for what, which, scene, top, bottom in RATIOS[page]:
        if f"{which}: {scene}: {top}" not in report["rows"] or \
                f"{which}: {scene}: {bottom}" not in report["rows"]:
            continue
        ratio = median(report, which, scene, top) / median(report, which, scene, bottom)
        lines.append(f"| {what} | {ratio:.2f} | |")
    return lines


# Each page's tables: (caption, table, baseline label).
TABLES = {"19": (("The scenes, chapter 18 against chapter 19:", "scenes", "chapter 18"),
                 ("Specialisation, and a small scene written out:", "specialisation",
                  "storage buffers")),
          "20": (("Where the scene is read from:", "memory", "buffer textures"),
                 ("The tree's nodes and triangles:", "tree", "tree in storage buffers")),
          "21": (("The tree's leaves priced two ways, and chapter 20's walk:", "price",
                  LEAVES_BY_COUNT),)}


def page_table(report: dict, page: str) -> str:
    """One page's block: the machine and settings, its tables, its ratios."""
    s, machine = report["settings"], report["machine"]
    heading = (f"Measured {report['date']} on {bench_common.machine_words(machine)}; "
               f"{s['size']}², {s['spp']} spp, depth {s['depth']}. Each figure is the median "
               f"of {s['repeat']} runs, the rows taking turns, with the range of the runs; "
               "compile times are whole runs of a 16 × 16 image at 1 sample with Mesa's "
               f"shader cache off, median of {s['repeat']}. "
               f"{bench_common.quiet_words(report['quiet'])}")
    lines = [heading, ""]
    for caption, which, baseline in TABLES[page]:
        if any(row["table"] == which for row in report["rows"].values()):
            lines += [caption, "", *table(report, which, baseline), ""]
    if page == "21":
        lines += million_words(report)
    return "\n".join([*lines, "The ratios to compare with a GPU's (the same bench there):",
                      "", *ratio_rows(report, page)])


def publish(report: dict, update_book: bool = False, pages: dict = PAGES,
            out_folder: Path = OUT):
    """The report in out_folder (speed.json), its tables printed, and each page's block
    written into the page only with update_book."""
    bench_common.publish_pages(report, out_folder / "speed.json",
                               {number: page_table(report, number) for number in pages},
                               pages, update_book)


def main(binaries: dict, settings: Settings, update_book: bool = False,
         pages: dict = PAGES, out_folder: Path = OUT) -> int:
    publish(bench(binaries, settings), update_book, pages, out_folder)
    return 0
