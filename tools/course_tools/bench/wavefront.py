"""./course bench wavefront: the figures of chapter 20 (wavefront path tracing), each the
median of repeated runs that take turns, on one machine, in one run of the bench.

- **The kernels**: chapter 20's megakernel (one invocation follows a pixel's path to
  its end) one sample a dispatch, as chapter 19 runs it; the same megakernel
  regenerating paths (as many samples a dispatch as it chooses: its default); and its
  wavefront (a kernel per step over queues of paths). On scenes of one, two and four
  kinds of material: the Cornell box (18 quads, diffuse), the teapot in the Cornell
  room (6 320 triangles through the tree), the glass and metal spheres in the room,
  and the sky showcase (50 spheres of every kind, the sky).
- **The image's size**: the Cornell box at 64², 256² and 512². A wavefront runs some
  forty dispatches for each sample, whatever the image's size: its fixed cost shows
  in a small image.

After an untimed warm-up of each row, the rows take turns for --repeat rounds; each
figure is the median of its runs with their range. Speeds are samples per second as
the chapter counts them (--json). Writes build/bench/wavefront.json and prints the
tables; writes them into chapter 20's page only with --update-book."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from course_tools.bench import common as bench_common
from course_tools.bench.speed import run

from course_tools.paths import ROOT

PAGE = ROOT / "book" / "docs" / "chapters" / "20_wavefront.md"
START, END = "<!-- wavefront:start -->", "<!-- wavefront:end -->"
OUT = ROOT / "build" / "bench"
# The ways of running chapter 20 that the bench compares, and their options.
KERNELS = {"megakernel": ("--kernel", "megakernel", "--samples-per-dispatch", "1"),
           "regenerating": ("--kernel", "megakernel"),
           "wavefront": ("--kernel", "wavefront")}
BASE = "megakernel"  # the speeds are given as multiples of its


@dataclass(frozen=True)
class Row:
    table: str    # "scenes" or "sizes"
    scene: str    # assets/scenes/NAME.scene
    kernel: str   # a key of KERNELS
    size: int     # width and height
    chapter: str = "20"

    @property
    def options(self) -> tuple:
        return KERNELS[self.kernel]

    @property
    def key(self) -> str:
        return f"{self.table}: {self.scene}: {self.size}: {self.kernel}"

SCENES = (("cornell_box", "1: diffuse"), ("cornell_teapot", "1: diffuse"),
          ("cornell_glass", "2: diffuse, glass"), ("sky_showcase", "4: every kind"))
SIZES = (64, 256, 512)
ROWS = tuple(Row("scenes", scene, kernel, 256) for scene, _ in SCENES for kernel in KERNELS) \
    + tuple(Row("sizes", "cornell_box", kernel, size) for size in SIZES if size != 256
            for kernel in KERNELS)


@dataclass
class Settings:
    spp: int = 32
    depth: int = 6
    repeat: int = 3


def bench(binary: Path, settings: Settings) -> dict:
    watch = bench_common.QuietWatch()
    binaries = {"20": binary}
    runs = {row.key: [] for row in ROWS}
    print("bench wavefront: warm-up (1 spp, not timed) ...", flush=True)
    first = None
    for row in ROWS:
        stats = run(binaries, row, row.size, 1, settings.depth)
        first = first or stats
    for round_number in range(1, settings.repeat + 1):
        print(f"bench wavefront: round {round_number} of {settings.repeat} ...", flush=True)
        for row in ROWS:
            stats = run(binaries, row, row.size, settings.spp, settings.depth)
            runs[row.key].append(stats)
    return {"date": bench_common.today(), "machine": bench_common.describe_machine(first),
            "settings": vars(settings),
            "rows": {row.key: {"table": row.table, "scene": row.scene, "kernel": row.kernel,
                               "size": row.size, "samples_per_dispatch":
                                   runs[row.key][0]["samples_per_dispatch"],
                               "samples_per_second": bench_common.summarise(
                                   [r["samples_per_second"] for r in runs[row.key]]),
                               "rays_per_second": bench_common.summarise(
                                   [r["rays_per_second"] for r in runs[row.key]])}
                     for row in ROWS},
            "quiet": watch.finish()}


def speed(report: dict, table: str, scene: str, size: int, kernel: str) -> dict:
    return report["rows"][f"{table}: {scene}: {size}: {kernel}"]["samples_per_second"]


def table(report: dict, which: str) -> list[str]:
    kinds = dict(SCENES)
    first = "kinds of material" if which == "scenes" else "image"
    lines = [f"| scene | {first} | kernel | samples a dispatch | samples/s | "
             f"range of the runs (spread) | rays/s | ÷ {BASE} |",
             "| --- | --- | --- | ---: | ---: | ---: | ---: | ---: |"]
    for row in report["rows"].values():
        if row["table"] != which:
            continue
        samples = row["samples_per_second"]
        base = speed(report, which, row["scene"], row["size"], BASE)["median"]
        detail = kinds[row["scene"]] if which == "scenes" else f"{row['size']}²"
        lines.append(f"| {row['scene']} | {detail} | {row['kernel']} | "
                     f"{row['samples_per_dispatch']} | "
                     f"{samples['median']:,.0f} | {bench_common.spread_words(samples)} | "
                     f"{row['rays_per_second']['median']:,.0f} | "
                     f"{samples['median'] / base:.2f}× |")
    return lines


def ratio_rows(report: dict) -> list[str]:
    """The ratios a learner with a GPU compares with theirs (empty columns to fill): the
    scenes table's, each other kernel over the megakernel, at the size that table was
    run at."""
    kinds = dict(SCENES)
    others = [kernel for kernel in KERNELS if kernel != BASE]
    rows = [row for row in report["rows"].values() if row["table"] == "scenes"]
    size = rows[0]["size"] if rows else 0
    lines = [f"| samples/s ÷ {BASE}'s, {size}² | "
             + " | ".join(f"{kernel}: this machine | {kernel}: your GPU" for kernel in others)
             + " |", "| --- |" + " ---: | ---: |" * len(others)]
    for scene in dict.fromkeys(row["scene"] for row in rows):
        base = speed(report, "scenes", scene, size, BASE)["median"]
        ratios = [speed(report, "scenes", scene, size, kernel)["median"] / base
                  for kernel in others]
        cells = [cell for ratio in ratios for cell in (f"{ratio:.2f}", "")]
        lines.append(f"| {scene} ({kinds[scene]}) | " + " | ".join(cells) + " |")
    return lines


def page_table(report: dict) -> str:
    s, machine = report["settings"], report["machine"]
    heading = (f"Measured {report['date']} on {bench_common.machine_words(machine)}; "
               f"{s['spp']} spp, depth {s['depth']}. Each figure is the median of "
               f"{s['repeat']} runs, the rows taking turns, with the range of the runs. "
               f"{bench_common.quiet_words(report['quiet'])}")
    return "\n".join([heading, "", "The kernels, 256²:", "", *table(report, "scenes"), "",
                      "The Cornell box at other sizes:", "", *table(report, "sizes"), "",
                      "The ratios to compare with a GPU's (the same bench there):", "",
                      *ratio_rows(report)])


def main(binary: Path, settings: Settings, update_book: bool = False, page: Path = PAGE,
         out_folder: Path = OUT) -> int:
    report = bench(binary, settings)
    bench_common.publish(report, out_folder / "wavefront.json", page_table(report), update_book,
                         page, START, END)
    return 0
