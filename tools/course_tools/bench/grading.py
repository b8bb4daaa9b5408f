"""./course bench grading: how long grading one submission takes on one core.

Gradescope gives an autograder one container, often a single core, so each chapter's
solution is graded as a student's submission would be: copied out of the tree, every
.cpp file changed by a comment (so no object compiled earlier is reused, as for a
student's edited files), the grader and everything it starts pinned to core 0
(sched_setaffinity, inherited like `taskset -c 0`). Its references are made first and
not timed: an autograder image renders them at set-up (--prepare). Each chapter is
graded --repeat times and the median printed with the range of the runs; the solution
must score full marks, or the bench exits with 1. Writes build/bench/grading.json and
prints the table; writes it into book/docs/instructors.md only with update_book
(./course bench grading --update-book)."""

from __future__ import annotations

import json
import os
import platform
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from course_tools.bench import common as bench_common
from course_tools.grading import grader
from course_tools.grading.grading_specs import SPECS
from course_tools.paths import ROOT
from course_tools.program_output import last_json_line

PAGE = ROOT / "book" / "docs" / "instructors.md"
START, END = "<!-- bench-grading:start -->", "<!-- bench-grading:end -->"


def solution_as_submission(chapter: str, folder: Path, nonce: str) -> Path:
    for top in ("chapters", "shaders"):
        shutil.copytree(ROOT / top / chapter, folder / top / chapter)
    for source in (folder / "chapters" / chapter).glob("*.cpp"):
        with source.open("a") as out:
            out.write(f"\n// graded for the bench: {nonce}\n")
    return folder


def grade_on_one_core(build: Path, chapter: str, submission: Path, out: Path) -> dict:
    """One grading in a child process pinned to core 0 (its sandboxed compiler and
    program runs inherit the affinity)."""
    code = ("import json, os, sys\n"
            "from pathlib import Path\n"
            "os.sched_setaffinity(0, {0})\n"
            "from course_tools.grading import grader\n"
            f"results = grader.grade(Path({str(ROOT)!r}), Path({str(build)!r}), "
            f"{chapter!r}, Path({str(submission)!r}), Path({str(out)!r}))\n"
            "import resource\n"
            "peak = max(resource.getrusage(who).ru_maxrss for who in "
            "(resource.RUSAGE_SELF, resource.RUSAGE_CHILDREN))\n"
            "print(json.dumps({'results': results, 'peak_kib': peak}))\n")
    started = time.monotonic()
    finished = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    seconds = time.monotonic() - started
    if finished.returncode != 0:
        raise RuntimeError(f"grading {chapter} failed:\n{finished.stderr[-3000:]}")
    printed = last_json_line(finished.stdout, f"grading {chapter}")
    results = printed["results"]
    return {"seconds": seconds, "peak_mib": printed["peak_kib"] / 1024,
            "score": results["score"],
            "max_score": sum(t["max_score"] for t in results["tests"])}


def page_table(report: dict) -> str:
    vectors = f", {report['vectors']}" if report.get("vectors") else ""
    lines = [f"Measured {report['date']} by `./course bench grading` on {report['cpu']}"
             f"{vectors}, one core (of {report['cores']}), `{report['gl_renderer']}`, OpenGL "
             f"{report['gl_version']}; each chapter's solution graded as a submission, "
             f"median of {report['repeat']}. {bench_common.quiet_words(report['quiet'])}",
             "",
             "| chapter | tests | runs of the program | seconds (one core) | "
             "range of the gradings | largest process (MiB) |",
             "| --- | ---: | ---: | ---: | ---: | ---: |"]
    for row in report["chapters"]:
        lines.append(f"| {row['chapter']} | {row['tests']} | {row['runs']} | "
                     f"{row['seconds']:.1f} | "
                     f"{bench_common.spread_words(row['spread'], digits=1)} | "
                     f"{row['peak_mib']:.0f} |")
    slowest = max(report["chapters"], key=lambda row: row["seconds"])
    lines += ["", f"The slowest, chapter {slowest['chapter'][:2]}, takes "
              f"{slowest['seconds']:.0f} s: within the 3-minute target, and far within "
              "Gradescope's default time-out (10 minutes, on half a virtual CPU: twice "
              "these times). The largest process, "
              f"{max(row['peak_mib'] for row in report['chapters']):.0f} MiB, is the "
              "resident memory of one program or compiler run (or of the grader), within "
              "Gradescope's default 768 MB per container."]
    return "\n".join(lines)


def program_runs(chapter: str) -> int:
    runs = 0
    for test in SPECS[chapter[:2]]:
        runs += test.sampling.runs if test.sampling is not None else \
            (2 if test.kind == "traversal" else 1)
    return runs


def main(build: Path, chapters: list[str], repeat: int, gl_renderer: str,
         gl_version: str, update_book: bool = False, page: Path = PAGE) -> int:
    watch = bench_common.QuietWatch()
    status = 0
    rows = []
    for chapter in chapters:
        grader.prepare_references(ROOT, build, chapter)  # set-up time, not grading time
        times, peaks = [], []
        for attempt in range(repeat):
            with tempfile.TemporaryDirectory(prefix=f"bench-grading-{chapter[:2]}-") as tmp:
                os.chmod(tmp, 0o755)
                submission = solution_as_submission(chapter, Path(tmp) / "submission",
                                                    f"{time.time_ns()}-{attempt}")
                result = grade_on_one_core(build, chapter, submission, Path(tmp) / "graded")
            times.append(result["seconds"])
            peaks.append(result["peak_mib"])
            if result["score"] < result["max_score"]:
                print(f"bench: the solution of {chapter} scored {result['score']} of "
                      f"{result['max_score']}", file=sys.stderr)
                status = 1
        spread = bench_common.summarise(times)
        row = {"chapter": chapter, "tests": len(SPECS[chapter[:2]]),
               "runs": program_runs(chapter), "seconds": spread["median"],
               "spread": spread, "peak_mib": max(peaks), "all_seconds": times}
        rows.append(row)
        print(f"{chapter:22} {row['seconds']:7.1f} s  "
              f"({', '.join(f'{t:.1f}' for t in times)})", flush=True)
    report = {"date": time.strftime("%Y-%m-%d"), "cpu": bench_common.cpu_model(),
              "cores": os.cpu_count(), "vectors": bench_common.vector_extension(),
              "gl_renderer": gl_renderer,
              "gl_version": gl_version, "mesa": bench_common.mesa_version(gl_version),
              "llvm": bench_common.llvm_version(gl_renderer), "repeat": repeat,
              "python": platform.python_version(), "chapters": rows,
              "quiet": watch.finish()}
    out = build / "bench" / "grading.json"
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(report, indent=2))
    print(page_table(report))
    print(out)
    bench_common.book_or_not(update_book, page, START, END, page_table(report), report)
    return status
