"""./course gpu-check (tools/gpu_check.sh): everything a first run on a real GPU should
say, in one command and one report, within ten minutes.

No GPU is lent to the project, so this is rehearsed on llvmpipe, the same way, in the
suite's machine: the first run on a GPU must not be the command's first run. It
1. builds the chapters;
2. asks the device what it is and allows (the EGL device, its renderer and OpenGL
   version, the limits the chapters rely on, the shader loop limit);
3. runs every chapter's image checks (tests/python/chapters/test_NN_*.py, the loop
   limit's and the GPU-readiness checks) with COURSE_GPU set, so that every chapter
   program the checks start renders on that device; a skipped check is a failure;
4. measures what matters on a GPU: every chapter's samples (and rays) per second on its
   default scene, the BVH at a million triangles, and the megakernel against the
   wavefront (median of --repeat runs each);
5. writes build/gpu-check/report.md and report.json, and with --update-book the
   device's row into book/docs/benchmarks.md.
Exit code 0 when every check passed; 1 when one failed."""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
import time
import xml.etree.ElementTree as ElementTree

from course_tools.bench import common as bench_common
from course_tools.cli.build import BUILD, binary, build, chapters, die, find_chapter, say
from course_tools.cli.suite import spread_over_cores
from course_tools.cli.suite_parts import minutes
from course_tools.paths import ROOT
from course_tools.program_output import last_json_line

OUT = BUILD / "gpu-check"
PAGE = ROOT / "book" / "docs" / "benchmarks.md"
START, END = "<!-- gpu-check:start -->", "<!-- gpu-check:end -->"
BUDGET_SECONDS = 600
CHECKS = ["test_loop_limit.py", "test_gpu_readiness.py"]  # beside every test_NN_*.py
SIZE = (256, 192)
SPP = 16
LIMITS = ("max_compute_storage_blocks", "max_compute_texture_units")
# The BVH at a million triangles, and the two ways of chapter 23 on two scenes.
MILLION = ("21", ("--scene", "cornell_teapot_million"))
KERNEL_SCENES = ("cornell_box", "sky_showcase")


def chapter_json(name: str, *args: str, env: dict) -> dict:
    """One run of a chapter with --json: its statistics (exit code 4 and the like end
    the check with the program's own message)."""
    command = [str(binary(name)), "--headless", "--json", *args]
    result = subprocess.run(command, capture_output=True, text=True, env=env, timeout=600)
    if result.returncode != 0:
        die(f"gpu-check: {' '.join(command)} failed (exit code {result.returncode}):\n"
            f"{result.stderr}")
    return last_json_line(result.stdout, " ".join(command))


def device(env: dict) -> dict:
    """What the device is and allows, as the chapters see it."""
    first = find_chapter("02")
    stats = chapter_json(first, "--width", "8", "--height", "8", "--out",
                         str(OUT / "device.pfm"), "--verbose", env=env)
    loop = chapter_json(find_chapter("07"), "--probe-loop-limit", env=env)
    listed = subprocess.run([str(binary(first)), "--headless", "--gpu", "15"],
                            capture_output=True, text=True, env=env)
    return {"backend": stats["backend"], "renderer": stats["renderer"],
            "gl_version": stats["gl_version"],
            "limits": {key: stats.get(key) for key in LIMITS},
            "loop_limit": loop.get("loop_limit"),
            "egl_devices": re.findall(r"egl device \d+ \([^)]*\)", listed.stderr)}


def image_checks(env: dict) -> dict:
    """Every chapter's checks with COURSE_GPU set: counts per chapter file, and failures."""
    folder = ROOT / "tests" / "python" / "chapters"
    files = sorted(str(p) for p in folder.glob("test_*.py")
                   if re.match(r"test_(\d\d|A\d)_", p.name) or p.name in CHECKS)
    junit = OUT / "checks.xml"
    command = [sys.executable, "-m", "pytest", *files, "-q", "-p", "no:cacheprovider",
               "-rfEs", f"--junitxml={junit}", *spread_over_cores()]
    result = subprocess.run(command, stdout=subprocess.PIPE, text=True, env=env,
                            cwd=ROOT)
    (OUT / "checks.txt").write_text(result.stdout)
    per_file: dict[str, dict] = {}
    failures = []
    if junit.exists():
        for case in ElementTree.parse(junit).getroot().iter("testcase"):
            file = case.get("classname", "").split(".")[-1]
            counts = per_file.setdefault(file, {"passed": 0, "failed": 0, "skipped": 0})
            outcome = "passed"
            for child in case:
                if child.tag in ("failure", "error"):
                    outcome = "failed"
                elif child.tag == "skipped":
                    outcome = "skipped"
            counts[outcome] += 1
            if outcome != "passed":
                failures.append(f"{file}::{case.get('name')} ({outcome})")
    total = {kind: sum(c[kind] for c in per_file.values())
             for kind in ("passed", "failed", "skipped")}
    if result.returncode not in (0, 1) and not failures:
        failures.append(f"pytest itself failed (exit code {result.returncode})")
    return {"per_file": per_file, "total": total, "failures": failures}


def timed(name: str, args: tuple, repeat: int, env: dict) -> dict:
    """Samples and rays per second of one chapter's render, median of `repeat` runs."""
    runs = [chapter_json(name, *args, "--out", str(OUT / "bench.pfm"), env=env)
            for _ in range(repeat)]
    figures = {"wall_ms": bench_common.summarise([r["wall_ms"] for r in runs])}
    for key in ("samples_per_second", "rays_per_second"):
        if all(key in r for r in runs):
            figures[key] = bench_common.summarise([r[key] for r in runs])
    if "samples_per_second" not in figures:  # before the path tracer: a pixel, once
        figures["samples_per_second"] = bench_common.summarise(
            [r["width"] * r["height"] * r.get("samples_per_pixel", 1) / (r["wall_ms"] / 1000)
             for r in runs])
    return figures


def benches(repeat: int, env: dict) -> dict:
    size = ("--width", str(SIZE[0]), "--height", str(SIZE[1]), "--spp", str(SPP))
    speeds = {}
    for name in chapters():
        if name.startswith("01"):
            continue  # adds numbers, makes no picture
        speeds[name] = timed(name, size, repeat, env)
        say(f"gpu-check: {name}: {speeds[name]['samples_per_second']['median']:,.0f} "
            "samples/s")
    million_name = find_chapter(MILLION[0])
    million = timed(million_name, (*size, *MILLION[1]), repeat, env)
    kernels = {}
    wave = find_chapter("23")
    for scene in KERNEL_SCENES:
        for kernel in ("megakernel", "wavefront"):
            kernels[f"{scene}: {kernel}"] = timed(
                wave, (*size, "--scene", scene, "--kernel", kernel), repeat, env)
    return {"chapters": speeds, "million": {"chapter": million_name, **million},
            "kernels": kernels}


def wavefront_ratio(report: dict, scene: str) -> float:
    kernels = report["benches"]["kernels"]
    return (kernels[f"{scene}: wavefront"]["samples_per_second"]["median"]
            / kernels[f"{scene}: megakernel"]["samples_per_second"]["median"])


def markdown(report: dict) -> str:
    d, checks = report["device"], report["checks"]
    lines = [f"# GPU check, {report['date']}", "",
             f"- Device: {d['backend']}: `{d['renderer']}`, OpenGL {d['gl_version']}",
             f"- EGL devices: {', '.join(d['egl_devices']) or 'none listed'}",
             f"- Limits: {d['limits']['max_compute_storage_blocks']} storage blocks and "
             f"{d['limits']['max_compute_texture_units']} texture units a compute shader; "
             f"loop limit {d['loop_limit']}",
             f"- Machine: {bench_common.machine_words(report['machine'])}",
             f"- Image checks: {checks['total']['passed']} passed, "
             f"{checks['total']['failed']} failed, {checks['total']['skipped']} skipped",
             "", "| phase | time |", "|---|---:|"]
    lines += [f"| {phase} | {minutes(seconds)} |" for phase, seconds in report["phases"].items()]
    lines += [f"| **in all** | **{minutes(report['seconds'])}** (budget "
              f"{minutes(BUDGET_SECONDS)}) |", ""]
    if checks["failures"]:
        lines += ["## Failed checks", ""] + [f"- {f}" for f in checks["failures"]] + [""]
    lines += ["## Checks per file", "", "| file | passed | failed | skipped |", "|---|---:|---:|---:|"]
    lines += [f"| {f} | {c['passed']} | {c['failed']} | {c['skipped']} |"
              for f, c in sorted(checks["per_file"].items())]
    b = report["benches"]
    lines += ["", f"## Speed ({SIZE[0]}x{SIZE[1]}, {SPP} spp, default scenes; median of "
              f"{report['repeat']})", "", "| chapter | samples/s | rays/s |", "|---|---:|---:|"]
    for name, figures in b["chapters"].items():
        rays = figures.get("rays_per_second", {}).get("median")
        lines.append(f"| {name} | {figures['samples_per_second']['median']:,.0f} | "
                     f"{f'{rays:,.0f}' if rays else '-'} |")
    lines += ["", f"- A million triangles (chapter {b['million']['chapter']}, "
              f"cornell_teapot_million): "
              f"{b['million'].get('rays_per_second', {}).get('median', 0):,.0f} rays/s"]
    for scene in KERNEL_SCENES:
        lines.append(f"- {scene}: the wavefront at {wavefront_ratio(report, scene):.2f}x "
                     "the megakernel's samples per second")
    return "\n".join(lines) + "\n"


def page_row(report: dict) -> str:
    d, b = report["device"], report["benches"]
    newest = [name for name in b["chapters"] if name[:2].isdigit()][-1]  # not an appendix
    cornell = b["chapters"].get(find_chapter("12"), {}).get("samples_per_second", {})
    return (f"| `{d['renderer']}` | {report['machine']['cpu']} "
            f"({report['machine']['vectors']}) | {report['date'][:10]} | "
            f"{report['checks']['total']['passed']} / {report['checks']['total']['failed']} | "
            f"{cornell.get('median', 0):,.0f} | "
            f"{b['chapters'][newest]['samples_per_second']['median']:,.0f} | "
            f"{b['million'].get('rays_per_second', {}).get('median', 0):,.0f} | "
            f"{wavefront_ratio(report, 'sky_showcase'):.2f} | {minutes(report['seconds'])} |")


HEADER = ("| device | CPU | date | checks passed / failed | chapter 12 samples/s | "
          "newest chapter samples/s | 1M triangles rays/s | wavefront ÷ megakernel (sky) "
          "| check took |\n|---|---|---|---:|---:|---:|---:|---:|---:|")


def update_page(report: dict):
    """One row per device in the benchmarks page: this device's row replaced, the
    others kept."""
    text = PAGE.read_text()
    start, end = text.index(START) + len(START), text.index(END)
    renderer = f"| `{report['device']['renderer']}` |"
    rows = [line for line in text[start:end].splitlines()
            if line.startswith("| `") and not line.startswith(renderer)]
    block = "\n".join([HEADER, *sorted(rows + [page_row(report)])])
    PAGE.write_text(text[:start] + "\n" + block + "\n" + text[end:])
    say(f"gpu-check: wrote this device's row into {PAGE.relative_to(ROOT)}")


def cmd_gpu_check(args):
    OUT.mkdir(parents=True, exist_ok=True)
    env = dict(os.environ)
    env.pop("DISPLAY", None)
    if args.gpu is not None:
        env["COURSE_GPU"] = str(args.gpu)
    started = time.monotonic()
    phases = {}

    def phase(name: str, work):
        began = time.monotonic()
        say(f"gpu-check: {name}")
        result = work()
        phases[name] = time.monotonic() - began
        return result

    phase("build", build)
    found = phase("device", lambda: device(env))
    say(f"gpu-check: rendering on {found['backend']}: {found['renderer']}")
    checks = phase("image checks", lambda: image_checks(env))
    figures = phase("benches", lambda: benches(args.repeat, env))
    report = {"date": bench_common.today(), "device": found,
              "machine": bench_common.describe_machine(found), "checks": checks,
              "benches": figures, "repeat": args.repeat, "phases": phases,
              "seconds": time.monotonic() - started}
    (OUT / "report.json").write_text(json.dumps(report, indent=1))
    (OUT / "report.md").write_text(markdown(report))
    print(markdown(report))
    if report["seconds"] > BUDGET_SECONDS:
        say(f"gpu-check: took {minutes(report['seconds'])}, over its budget of "
            f"{minutes(BUDGET_SECONDS)}")
    if args.update_book:
        update_page(report)
    print(f"wrote {OUT / 'report.md'}")
    failed = checks["total"]["failed"] + checks["total"]["skipped"] + \
        (1 if checks["failures"] and not checks["total"]["failed"] else 0)
    sys.exit(1 if failed else 0)
