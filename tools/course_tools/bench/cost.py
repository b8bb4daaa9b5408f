"""./course bench cost: what a sample costs in CPU instructions, counted rather than timed.

Timed runs on a shared machine spread widely: on 2026-12-07 one teapot render ran at
anything from 0.93 to 1.33 million samples a second on the AMD EPYC of the notes, and two
renders side by side disagreed by up to a quarter. A change worth 5% hides in that. But
llvmpipe runs a shader as code that LLVM compiled for the CPU, and Valgrind's callgrind
counts every instruction the CPU executes, that code's among them: the count repeats
to within a few thousand in billions, busy machine or not.

Each figure comes from two renders of one scene that differ only in samples per pixel
(LOW_SPP and HIGH_SPP, one dispatch each): the difference between their counts,
divided by the samples it adds, is what a sample costs. Start-up, shader compilation and
read-back are in both counts and cancel out. Mesa's shader cache is off for both runs,
so that neither finds the other's compiled shader, and llvmpipe runs on the program's
own thread (LP_NUM_THREADS=0), so that no thread waiting for another is counted. The
renders are small (SIZE squared) and run side by side, one per core: a row takes about a
minute and a half, most of it compiling the shader under callgrind.

The rows: the teapot in the Cornell room and the Cornell box, through the newest chapter
with a BVH. Given folders of shaders (--shader-dirs: copies of the chapter's own,
changed), it counts each of them as well, as a multiple of the chapter's own: the way
to choose between two ways of writing the traversal on a noisy machine. Instructions are
not time (a load that misses the cache counts once, and an AVX-512 CPU runs different
instructions from an AVX2 one), so the timed benches (mitsuba, wavefront) have the last
word, and the table is kept per kind of CPU.

Needs valgrind (apt install valgrind), which only this bench uses; asked for by name
(./course bench cost). Writes build/bench/cost.json and prints the table; writes it into
book/docs/benchmarks.md only with --update-book."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
from dataclasses import dataclass
from pathlib import Path

from course_tools.bench import common as bench_common
from course_tools.paths import ROOT
from course_tools.program_output import last_json_line

PAGE = ROOT / "book" / "docs" / "benchmarks.md"
START, END = "<!-- bench-cost:start -->", "<!-- bench-cost:end -->"
OUT = ROOT / "build" / "bench" / "cost.json"
SCENES = {"cornell_teapot": "teapot (6 320 triangles)", "cornell_box": "Cornell box"}
SIZE = 64
LOW_SPP, HIGH_SPP = 4, 36  # both one dispatch: chapter 30 takes up to 64 samples in one
DEPTH = 6
# callgrind's summary on stderr: "==123== Collected : 1996938395"
COLLECTED = re.compile(r"^==\d+== Collected : (\d+)\s*$", re.MULTILINE)


@dataclass(frozen=True)
class Row:
    scene: str        # its file in assets/scenes, without .scene
    shader_dir: str   # "" for the chapter's own shaders, else a folder of them


def counting_environment() -> dict:
    """One thread for llvmpipe, and no shader cache: the same work in every run."""
    return dict(os.environ, LP_NUM_THREADS="0", MESA_SHADER_CACHE_DISABLE="true")


def command(valgrind: str, binary: Path, row: Row, spp: int, out: Path) -> list[str]:
    words = [valgrind, "--tool=callgrind", "--callgrind-out-file=/dev/null", str(binary),
             "--headless", "--scene", str(ROOT / "assets" / "scenes" / f"{row.scene}.scene"),
             "--width", str(SIZE), "--height", str(SIZE), "--spp", str(spp),
             "--depth", str(DEPTH), "--estimator", "mis", "--out", str(out), "--json"]
    return words + (["--shader-dir", row.shader_dir] if row.shader_dir else [])


def instructions(stderr: str, what: str) -> int:
    """The instructions callgrind counted, from its summary."""
    found = COLLECTED.findall(stderr)
    if not found:
        raise SystemExit(f"bench cost: no callgrind count in the output of {what}:\n"
                         f"{stderr[-2000:]}")
    return int(found[-1])


def count(valgrind: str, binary: Path, row: Row, work: Path) -> dict:
    """Both renders of a row, side by side, and what a sample and a ray cost."""
    runs = {}
    for spp in (LOW_SPP, HIGH_SPP):
        words = command(valgrind, binary, row, spp, work / f"{row.scene}-{spp}.pfm")
        runs[spp] = (words, subprocess.Popen(words, stdout=subprocess.PIPE,
                                             stderr=subprocess.PIPE, text=True,
                                             env=counting_environment()))
    counted, stats = {}, {}
    try:
        for spp, (words, process) in runs.items():
            stdout, stderr = process.communicate()
            what = " ".join(words)
            if process.returncode != 0:
                raise SystemExit(f"bench cost: {what} failed ({process.returncode}):\n"
                                 f"{stderr[-2000:]}")
            counted[spp] = instructions(stderr, what)
            stats[spp] = last_json_line(stdout, what)
    finally:  # a run that failed leaves no other counting on for a minute
        for _, process in runs.values():
            if process.poll() is None:
                process.kill()
                process.wait()
    redone = sum(int(stats[spp].get("dispatches_redone", 0)) for spp in stats)
    if redone:  # a dispatch run twice is counted twice: the difference means nothing
        raise SystemExit(f"bench cost: {row.scene}: {redone} dispatches were cut short and "
                         "run again; the counts are not comparable")
    added = counted[HIGH_SPP] - counted[LOW_SPP]
    samples = SIZE * SIZE * (HIGH_SPP - LOW_SPP)
    rays = int(stats[HIGH_SPP]["rays"]) - int(stats[LOW_SPP]["rays"])
    if added <= 0 or rays <= 0:
        raise SystemExit(f"bench cost: {row.scene}: {HIGH_SPP} samples a pixel counted "
                         f"{added} instructions more than {LOW_SPP}: not a cost")
    return {"scene": row.scene, "shader_dir": row.shader_dir,
            "instructions": {str(spp): counted[spp] for spp in counted},
            "samples": samples, "rays": rays,
            "per_sample": added / samples, "per_ray": added / rays,
            "program": stats[LOW_SPP]}


def valgrind_version(valgrind: str) -> str:
    result = subprocess.run([valgrind, "--version"], capture_output=True, text=True)
    return result.stdout.strip() or "valgrind"


def table(report: dict) -> str:
    # Mitsuba plays no part here: the machine without it.
    machine = {key: value for key, value in report["machine"].items()
               if not key.startswith("mitsuba")}
    lines = [f"Measured {report['date']} on {bench_common.machine_words(machine)}; "
             f"counted by {report['valgrind']} (callgrind), {SIZE}² pixels, depth {DEPTH}, "
             f"the instructions of {HIGH_SPP} samples a pixel less those of {LOW_SPP}, "
             f"through chapter {report['chapter']}.",
             "",
             "| scene | shaders | instructions a sample | instructions a ray "
             "| × the chapter's own |",
             "|---|---|---:|---:|---:|"]
    own = {row["scene"]: row["per_sample"] for row in report["rows"] if not row["shader_dir"]}
    for row in report["rows"]:
        shaders = f"`{row['shader_dir']}`" if row["shader_dir"] else "the chapter's own"
        lines.append(f"| {SCENES.get(row['scene'], row['scene'])} | {shaders} "
                     f"| {row['per_sample']:,.0f} | {row['per_ray']:,.0f} "
                     f"| {row['per_sample'] / own[row['scene']]:.3f} |")
    return "\n".join(lines) + "\n"


def rows_for(shader_dirs: list[str]) -> list[Row]:
    """The chapter's own shaders on every scene, then each folder on every scene."""
    return [Row(scene, folder) for folder in ["", *shader_dirs] for scene in SCENES]


def main(binary: Path, shader_dirs: list[str], update_book: bool = False,
         valgrind: str | None = None, out: Path = OUT, page: Path = PAGE) -> int:
    """Counts every row (rows_for), prints the table and writes the report to `out`; the
    page gets the table only with update_book, and only the chapter's own counts."""
    valgrind = valgrind or shutil.which("valgrind")
    if not valgrind:
        raise SystemExit("bench cost: valgrind not found; it counts the instructions "
                         "(Debian and Ubuntu: sudo apt install valgrind)")
    if shader_dirs and update_book:  # the page is the course's, not an experiment's
        raise SystemExit("bench cost: --update-book writes the chapter's own counts: "
                         "run it without --shader-dirs")
    for folder in shader_dirs:
        if not Path(folder).is_dir():
            raise SystemExit(f"bench cost: no folder of shaders at {folder}")
    work = out.parent / "cost"  # the renders' images
    work.mkdir(parents=True, exist_ok=True)
    rows = []
    for row in rows_for([str(Path(folder).resolve()) for folder in shader_dirs]):
        shaders = row.shader_dir or "the chapter's own shaders"
        print(f"bench cost: {row.scene}, {shaders} ...", flush=True)
        rows.append(count(valgrind, binary, row, work))
    report = {"date": bench_common.today(), "chapter": binary.name[:2],
              "machine": bench_common.describe_machine(rows[0]["program"]),
              "valgrind": valgrind_version(valgrind), "rows": rows}
    bench_common.publish(report, out, table(report), update_book, page, START, END)
    return 0
