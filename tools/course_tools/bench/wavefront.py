"""./course bench wavefront: the figures of chapters 22 (path regeneration), 23
(wavefront path tracing), 30 (checked regeneration) and 31 (a tree without a stack),
each the median of repeated runs that take turns, on one machine, in one run of the
bench.

- **The kernels**: chapter 22's megakernel (one invocation follows a pixel's path to
  its end) one sample a dispatch, as chapter 21 runs it; the same megakernel
  regenerating paths (as many samples a dispatch as it chooses: its default); and
  chapter 23's wavefront (a kernel per step over queues of paths); and chapter 30's
  megakernel, which regenerates paths through a tree too, its dispatches checked for
  loops the GL cut short (the scenes only); and chapter 31's, the same megakernel
  walking the tree without a stack (the scenes only, and the million-triangle teapot,
  with chapter 30's beside it). On scenes of one, two and four
  kinds of material: the Cornell box (18 quads, diffuse), the teapot in the Cornell
  room (6 320 triangles through the tree), the glass and metal spheres in the room,
  and the sky showcase (50 spheres of every kind, the sky).
- **The image's size**: the Cornell box at 64², 256² and 512². A wavefront runs some
  forty dispatches for each sample, whatever the image's size: its fixed cost shows
  in a small image.

After an untimed warm-up of each row, the rows take turns for --repeat rounds; each
figure is the median of its runs with their range. Speeds are samples per second as
the chapters count them (--json). Writes build/bench/wavefront.json and prints the
tables; writes them into the chapters' pages only with --update-book: the megakernel
one sample a dispatch and regenerating into chapter 22's, those and the wavefront into
23's, those and the checked megakernel into 30's, the checked and the stackless one
into 31's (as multiples of the checked one's)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from course_tools.bench import common as bench_common
from course_tools.bench.speed import run

from course_tools.paths import ROOT

CHAPTERS = ROOT / "book" / "docs" / "chapters"
# The block of each page that the bench writes (page, start marker, end marker), and the
# kernels its tables show.
PAGES = {"22": (CHAPTERS / "22_path_regeneration.md", "<!-- regeneration:start -->",
                "<!-- regeneration:end -->"),
         "23": (CHAPTERS / "23_wavefront.md", "<!-- wavefront:start -->",
                "<!-- wavefront:end -->"),
         "30": (CHAPTERS / "30_checked_regeneration.md", "<!-- checked:start -->",
                "<!-- checked:end -->"),
         "31": (CHAPTERS / "31_stackless_tree.md", "<!-- stackless:start -->",
                "<!-- stackless:end -->")}
OUT = ROOT / "build" / "bench"
# The ways of running the path tracer that the bench compares: the chapter whose
# program runs it, and its options.
KERNELS = {"megakernel": ("22", ("--samples-per-dispatch", "1")),
           "regenerating": ("22", ()),
           "wavefront": ("23", ("--kernel", "wavefront")),
           "checked": ("30", ()),
           "stackless": ("31", ())}
SHOWN = {"22": ("megakernel", "regenerating"),
         "23": ("megakernel", "regenerating", "wavefront"),
         "30": ("megakernel", "regenerating", "checked"),
         "31": ("checked", "stackless")}
SIZED = ("megakernel", "regenerating", "wavefront")  # the kernels of the sizes table
# Each page gives the speeds as multiples of this kernel's.
BASES = {"22": "megakernel", "23": "megakernel", "30": "megakernel", "31": "checked"}


@dataclass(frozen=True)
class Row:
    table: str    # "scenes" or "sizes"
    scene: str    # assets/scenes/NAME.scene
    kernel: str   # a key of KERNELS
    size: int     # width and height

    @property
    def chapter(self) -> str:
        return KERNELS[self.kernel][0]

    @property
    def options(self) -> tuple:
        return KERNELS[self.kernel][1]

    @property
    def key(self) -> str:
        return row_key(self.table, self.scene, self.size, self.kernel)


def row_key(table: str, scene: str, size: int, kernel: str) -> str:
    """A row's name in the report."""
    return f"{table}: {scene}: {size}: {kernel}"

SCENES = (("cornell_box", "1: diffuse"), ("cornell_teapot", "1: diffuse"),
          ("cornell_glass", "2: diffuse, glass"), ("sky_showcase", "4: every kind"))
SIZES = (64, 256, 512)
# A scene only the kernels that walk a tree with many samples a dispatch run: the
# million-triangle teapot, whose rays a second chapter 31's page compares with the
# teapot's.
TREES_ONLY = (("cornell_teapot_million", "1: diffuse"),)
TREE_KERNELS = ("checked", "stackless")
ROWS = tuple(Row("scenes", scene, kernel, 256) for scene, _ in SCENES for kernel in KERNELS) \
    + tuple(Row("scenes", scene, kernel, 256) for scene, _ in TREES_ONLY
            for kernel in TREE_KERNELS) \
    + tuple(Row("sizes", "cornell_box", kernel, size) for size in SIZES if size != 256
            for kernel in SIZED)


@dataclass
class Settings:
    spp: int = 32
    depth: int = 6
    repeat: int = 3


def bench(binaries: dict, settings: Settings) -> dict:
    watch = bench_common.QuietWatch()
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


def speed(report: dict, table: str, scene: str, size: int, kernel: str,
          figure: str = "samples_per_second") -> dict:
    return report["rows"][row_key(table, scene, size, kernel)][figure]


def has(report: dict, table: str, scene: str, size: int, kernel: str) -> bool:
    return row_key(table, scene, size, kernel) in report["rows"]


def table(report: dict, which: str, kernels: tuple, base_kernel: str) -> list[str]:
    kinds = dict(SCENES + TREES_ONLY)
    first = "kinds of material" if which == "scenes" else "image"
    lines = [f"| scene | {first} | kernel | samples a dispatch | samples/s | "
             f"range of the runs (spread) | rays/s | ÷ {base_kernel} |",
             "| --- | --- | --- | ---: | ---: | ---: | ---: | ---: |"]
    for row in report["rows"].values():
        if row["table"] != which or row["kernel"] not in kernels or \
                not has(report, which, row["scene"], row["size"], base_kernel):
            continue
        samples = row["samples_per_second"]
        base = speed(report, which, row["scene"], row["size"], base_kernel)["median"]
        detail = kinds[row["scene"]] if which == "scenes" else f"{row['size']}²"
        lines.append(f"| {row['scene']} | {detail} | {row['kernel']} | "
                     f"{row['samples_per_dispatch']} | "
                     f"{samples['median']:,.0f} | {bench_common.spread_words(samples)} | "
                     f"{row['rays_per_second']['median']:,.0f} | "
                     f"{samples['median'] / base:.2f}× |")
    return lines


def ratio_rows(report: dict, kernels: tuple, base_kernel: str) -> list[str]:
    """The ratios a learner with a GPU compares with theirs (empty columns to fill): the
    scenes table's, each other kernel over the base kernel, at the size that table was
    run at."""
    kinds = dict(SCENES + TREES_ONLY)
    others = [kernel for kernel in kernels if kernel != base_kernel]
    rows = [row for row in report["rows"].values() if row["table"] == "scenes" and
            has(report, "scenes", row["scene"], row["size"], base_kernel)]
    size = rows[0]["size"] if rows else 0
    lines = [f"| samples/s ÷ {base_kernel}'s, {size}² | "
             + " | ".join(f"{kernel}: this machine | {kernel}: your GPU" for kernel in others)
             + " |", "| --- |" + " ---: | ---: |" * len(others)]
    for scene in dict.fromkeys(row["scene"] for row in rows):
        base = speed(report, "scenes", scene, size, base_kernel)["median"]
        ratios = [speed(report, "scenes", scene, size, kernel)["median"] / base
                  for kernel in others]
        cells = [cell for ratio in ratios for cell in (f"{ratio:.2f}", "")]
        lines.append(f"| {scene} ({kinds[scene]}) | " + " | ".join(cells) + " |")
    return lines


def page_table(report: dict, page: str) -> str:
    kernels, base = SHOWN[page], BASES[page]
    s, machine = report["settings"], report["machine"]
    heading = (f"Measured {report['date']} on {bench_common.machine_words(machine)}; "
               f"{s['spp']} spp, depth {s['depth']}. Each figure is the median of "
               f"{s['repeat']} runs, the rows taking turns, with the range of the runs. "
               f"{bench_common.quiet_words(report['quiet'])}")
    return "\n".join([heading, "", "The kernels, 256²:", "",
                      *table(report, "scenes", kernels, base),
                      "", *sizes_table(report, kernels, base),
                      *million_lines(report, kernels),
                      "The ratios to compare with a GPU's (the same bench there):", "",
                      *ratio_rows(report, kernels, base)])


def million_lines(report: dict, kernels: tuple) -> list[str]:
    """The million-triangle teapot's rays a second over the teapot's, for each kernel
    of the page that ran both (issue 33 asks for 0.7 or more)."""
    rays = {}
    for kernel in kernels:
        sizes = [row["size"] for row in report["rows"].values()
                 if row["scene"] == "cornell_teapot_million" and row["kernel"] == kernel]
        if not sizes or not has(report, "scenes", "cornell_teapot", sizes[0], kernel):
            continue
        million, small = (speed(report, "scenes", scene, sizes[0], kernel,
                                "rays_per_second")["median"]
                          for scene in ("cornell_teapot_million", "cornell_teapot"))
        rays[kernel] = million / small
    if not rays:
        return []
    return ["The million-triangle teapot's rays a second ÷ the teapot's: " +
            ", ".join(f"{kernel} {ratio:.2f}" for kernel, ratio in rays.items()) + ".", ""]


def sizes_table(report: dict, kernels: tuple, base: str) -> list[str]:
    """The Cornell box at other sizes, for the pages whose kernels were run so."""
    if base not in SIZED:
        return []
    return ["The Cornell box at other sizes:", "", *table(report, "sizes", kernels, base), ""]


def publish(report: dict, update_book: bool = False, pages: dict = PAGES,
            out_folder: Path = OUT):
    """The report in out_folder (wavefront.json), its tables printed, and each page's block
    written into the page only with update_book."""
    bench_common.publish_pages(report, out_folder / "wavefront.json",
                               {number: page_table(report, number) for number in pages},
                               pages, update_book)


def main(binaries: dict, settings: Settings, update_book: bool = False,
         pages: dict = PAGES, out_folder: Path = OUT) -> int:
    publish(bench(binaries, settings), update_book, pages, out_folder)
    return 0
