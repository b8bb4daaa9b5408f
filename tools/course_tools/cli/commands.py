"""What the other verbs of ./course do: set-up, build, list, run, bench, release, grade
and autograder (the table of verbs, their options and layers: verbs.py)."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

from course_tools import chapters as chapter_list
from course_tools.cli.book import figure_programs, figure_rows, render_figures
from course_tools.cli.build import (
    BOOK,
    BUILD,
    OUT,
    binary,
    build,
    build_lock,
    chapter_manifests,
    chapters,
    configure,
    die,
    find_chapter,
    run_checked,
    say,
)
from course_tools.paths import ROOT
from course_tools.program_output import last_json_line

# ---------------------------------------------------------------- verbs

def cmd_setup(args):
    with build_lock():
        configure()
    say(f"set up: the '{args.layer}' layer's packages, .venv and the CMake build folder "
        "are ready")


def cmd_packages(args):
    """The distribution packages of a layer on this platform, one line, for scripts
    (e.g. a workflow's `sudo apt-get install $(./course packages test)`)."""
    from course_tools.setup import platforms
    try:
        platform = platforms.this_platform()
    except platforms.UnknownPlatform as unknown:
        die(str(unknown), code=2)
    if platform is None:
        die("COURSE_PLATFORM=none: the packages are yours to choose", code=2)
    print(" ".join(platform.layer_packages(args.layer)))


def cmd_build(args):
    build()


def cmd_list(args):
    for name in chapters():
        print(f"{name:24} {chapter_list.summary(name, ROOT)}")


def cmd_run(args):
    numbered = [name for name in chapters() if name[:2].isdigit()]  # not the appendices
    name = find_chapter(args.chapter) if args.chapter else numbered[-1]
    build([name])
    # With no options, the manifest's: Monte Carlo chapters need samples to look like
    # their book page (about half a minute on llvmpipe).
    options = list(args.options) or list(chapter_manifests()[name].run)
    if "--window" not in options and "--headless" not in options:
        options.insert(0, "--headless")
    out = None
    if "--out" not in options and "--window" not in options and name != "01_buffer_add":
        OUT.mkdir(parents=True, exist_ok=True)
        out = OUT / f"{name}.png"
        options += ["--out", str(out)]
    say(f"running {name} {' '.join(options)}")
    result = subprocess.run([str(binary(name)), *options], stdout=subprocess.PIPE, text=True)
    if result.stdout and (out is None or "--json" in options):
        print(result.stdout, end="")
    if result.returncode != 0:
        if result.returncode == 4 and sys.platform == "darwin" and name[:2].isdigit():
            # macOS stops at OpenGL 4.1: the numbered chapters need compute shaders.
            say("on macOS, run the OpenGL 3.3 appendix instead: ./course run A2")
        sys.exit(result.returncode)
    if out is not None:
        print(out)


def cmd_bench(args):
    if args.repeat < 1:
        die("--repeat needs at least 1 run", code=2)
    status = 0
    if args.which in ("all", "mitsuba"):
        status |= bench_against_mitsuba(args)
    if args.which in ("all", "bvh"):
        # The 100 000- and 1 000 000-triangle teapots are made only for this.
        build(["14_bvh_sah", "course_benchmark_assets"])
        from course_tools.bench import bvh as bench_bvh
        status |= bench_bvh.main(binary(find_chapter("14")), BUILD / "assets" / "meshes",
                                 args.repeat, update_book=args.update_book)
    if args.which in ("all", "speed"):
        from course_tools.bench import speed as bench_speed
        speed = [find_chapter(number) for number in ("18", "19", "20", "21")]
        build([*speed, "course_benchmark_assets"])  # the million-triangle teapot
        settings = bench_speed.Settings(args.size, args.speed_spp, args.depth, args.repeat)
        status |= bench_speed.main({name[:2]: binary(name) for name in speed}, settings,
                                   update_book=args.update_book)
    if args.which in ("all", "wavefront"):
        from course_tools.bench import wavefront as bench_wavefront
        kernels = [find_chapter(number) for number in ("22", "23", "30", "31")]
        build([*kernels, "course_benchmark_assets"])  # the million-triangle teapot
        settings = bench_wavefront.Settings(args.speed_spp, args.depth, args.repeat)
        status |= bench_wavefront.main({name[:2]: binary(name) for name in kernels}, settings,
                                       update_book=args.update_book)
    if args.which in ("all", "instances"):
        from course_tools.bench import instances as bench_instances
        build([find_chapter("26")])
        settings = bench_instances.Settings(repeat=args.repeat)
        status |= bench_instances.main(binary(find_chapter("26")), BUILD / "assets" / "meshes",
                                       settings, update_book=args.update_book)
        from course_tools.bench import refit as bench_refit  # chapter 27's twisting teapot
        build([find_chapter("27")])
        status |= bench_refit.main(binary(find_chapter("27")), BUILD / "assets" / "meshes",
                                   bench_refit.Settings(repeat=args.repeat),
                                   update_book=args.update_book)
    if args.which in ("all", "denoise"):
        from course_tools.bench import denoise as bench_denoise
        build([find_chapter("28")])
        status |= bench_denoise.main(binary(find_chapter("28")), BUILD / "assets" / "meshes",
                                     bench_denoise.Settings(repeat=args.repeat),
                                     update_book=args.update_book)
    if args.which == "grading":  # minutes on one core: asked for by name only
        from course_tools.bench import grading as bench_grading
        graded = [find_chapter(c) for c in args.chapters] if args.chapters else \
            [c for c in chapters() if c[:2] in bench_grading.SPECS]
        build([*graded, "01_buffer_add"])
        probe = run_checked([str(binary(find_chapter("01"))), "--count", "1", "--json"],
                            capture_output=True, text=True)
        gl = last_json_line(probe.stdout, "chapter 01")
        status |= bench_grading.main(BUILD, graded, args.repeat, gl["renderer"],
                                     gl["gl_version"], update_book=args.update_book)
    if args.which == "cost":  # needs valgrind, and minutes: asked for by name only
        from course_tools.bench import cost as bench_cost
        from course_tools.bench.mitsuba import newest_chapter_with_bvh
        with_bvh = newest_chapter_with_bvh(chapters())
        build([with_bvh])
        status |= bench_cost.main(binary(with_bvh), args.shader_dirs,
                                  update_book=args.update_book)
    sys.exit(status)


def bench_against_mitsuba(args) -> int:
    """The Cornell box through chapter 12 and through the newest chapter on the main
    line, the teapot through the newest chapter with a BVH, each against Mitsuba 3
    (tools/course_tools/bench/mitsuba.py)."""
    from course_tools.bench import mitsuba as bench
    with_bvh = bench.newest_chapter_with_bvh(chapters())
    box_chapter = find_chapter("12")
    newest = bench.newest_main_line_chapter(chapters())
    build([box_chapter, with_bvh, newest])
    scenes = [bench.Scene("cornell_box", "Cornell box", binary(box_chapter)),
              bench.Scene("cornell_box", "Cornell box, newest chapter", binary(newest),
                          key="cornell_box_newest"),
              bench.Scene("cornell_teapot", "teapot (6 320 triangles)",
                          binary(with_bvh))]
    settings = bench.Settings(args.size, args.spp, args.depth, args.repeat)
    return bench.main(scenes, settings, update_book=args.update_book,
                      mesh_folders=(BUILD / "assets",))


def cmd_release(args):
    from course_tools.editions import classroom, solution_markers
    name = find_chapter(args.chapter)
    if not classroom.has_exercises(ROOT, name):
        die(f"{name} has no SOLUTION blocks to take out: there is no starter to release",
            code=2)
    out = Path(args.out) if args.out else BUILD / "release" / f"{name}-starter"
    try:
        solution_markers.check_all_markers(ROOT)
    except solution_markers.MarkerError as error:
        die(str(error), code=3)
    # The starter's page shows the chapter's figures: rendered here by the solution's
    # programs (pictures to reproduce, not code), like the book's.
    from course_tools.editions import editions
    page = BOOK / "docs" / "chapters" / f"{name}.md"
    wanted = editions.page_figures(page.read_text()) if page.exists() else []
    rows = [row for row in figure_rows() if row[0] in wanted]
    build([name, "course_assets", *figure_programs(rows)])
    figures = BUILD / "release" / f"{name}-figures"
    if figures.exists():
        shutil.rmtree(figures)
    render_figures(rows, figures, draft=args.draft)
    classroom.release(ROOT, name, out.resolve(), figures=figures)
    print(out.resolve())


# Exit code of a grading refused because this system cannot isolate a submission.
NO_ISOLATION = 11


def refuse_grading_without_isolation(verb: str):
    """Grading runs a submission's code, which is untrusted: the sandbox (grading/
    sandbox.py) isolates it with what Linux gives (another user, namespaces without a
    network, resource limits). Where that cannot be had, no grading rather than an
    unisolated one."""
    if os.name == "nt":
        die(f"./course {verb} runs a submission's code, and isolates it with what Linux "
            "gives (another user, no network, resource limits); Windows has none of these "
            "here, so it refuses rather than run the code unisolated. Grade on Linux, or in "
            f"WSL 2 (Ubuntu 24.04): wsl ./course {verb} ...", code=NO_ISOLATION)


def cmd_grade(args):
    refuse_grading_without_isolation("grade")
    from course_tools.grading import grader, sandbox
    name = find_chapter(args.chapter)
    if name[:2] not in grader.SPECS:
        die(f"chapter {name} has no grading tests yet (tools/course_tools/grading/grading_specs.py)", code=2)
    folder = Path(args.submission or args.submissions or ".").resolve()
    if not args.prepare and not folder.is_dir():
        die(f"--submission{'s' if args.submissions else ''} {folder}: not a folder", code=2)
    if (ROOT / "chapters" / name).is_dir():
        build([name])
    elif not grader.is_prepared(BUILD, name):
        die(f"chapters/{name} is gone and its references were never prepared "
            f"(./course grade {name[:2]} --prepare, before the sources are removed)", code=2)
    else:  # an autograder image: the solution's sources were removed after --prepare
        say(f"grading without chapters/{name}: its references were prepared")
        if args.keep_runs:
            die("--keep-runs keys the kept runs by the solution's sources, and "
                f"chapters/{name} is gone", code=2)
    try:
        if args.prepare:
            for reference in grader.prepare(ROOT, BUILD, name):
                print(reference)
        elif args.submissions:
            out = Path(args.out).resolve() if args.out else BUILD / "grades" / folder.name
            summary = grader.grade_class(ROOT, BUILD, name, folder, out, args.jobs,
                                         args.show_hidden, progress=say,
                                         keep_runs=args.keep_runs)
            print(summary)
        else:
            out = Path(args.out).resolve() if args.out else BUILD / "grades" / folder.name
            counts = {}
            results = grader.grade(ROOT, BUILD, name, folder, out, args.show_hidden,
                                   keep_runs=args.keep_runs, kept_counts=counts)
            grader.print_table(results)
            if counts:
                say(f"runs replayed from an earlier grading of the same files: "
                    f"{counts['replayed']}, run and kept: {counts['made']}")
            print(f"report: {out / 'report.md'}\nresults: {out / 'results.json'}")
    except sandbox.SandboxError as error:
        if args.submission and not args.prepare:
            # Gradescope shows results.json, not our stderr: the reason goes there too,
            # with no points, so a refusal is never mistaken for a grade.
            out = Path(args.out).resolve() if args.out else BUILD / "grades" / folder.name
            out.mkdir(parents=True, exist_ok=True)
            failed = grader.failed_results(name, f"not graded: {error}")
            (out / "results.json").write_text(json.dumps(failed, indent=2))
        die(str(error))


def cmd_check(args):
    """./course check NN FOLDER: a learner's own work (a folder shaped like a starter,
    chapters/NN_name/ and shaders/NN_name/) graded as a class's grader would, hidden
    tests shown, against this repository's solution; a failing result says which
    catalogued mistake its pictures look like (tools/course_tools/grading/diagnosis.py)."""
    refuse_grading_without_isolation("check")
    from course_tools.grading import diagnosis, grader
    name = find_chapter(args.chapter)
    if name[:2] not in grader.SPECS:
        die(f"chapter {name} has no grading tests yet "
            "(tools/course_tools/grading/grading_specs.py)", code=2)
    if not (ROOT / "grading_catalogue").is_dir():
        die(f"./course check compares your work with the solution, so it runs in the "
            f"course's full repository, not in a starter: there, run ./course check "
            f"{name[:2]} {Path(args.folder).resolve()}", code=2)
    folder = Path(args.folder).resolve()
    missing = [f"{top}/{name}" for top in ("chapters", "shaders")
               if not (folder / top / name).is_dir()]
    if missing:
        die(f"{folder}: no {' or '.join(missing)} there. Give the folder of your work on "
            f"chapter {name[:2]} (a starter: ./course release {name[:2]} --out DIR)", code=2)
    if folder == ROOT.resolve():
        die(f"{folder} is the course's own tree, whose chapters/{name} is the solution "
            "the check compares with; give the folder of your own work", code=2)
    build([name])
    out = Path(args.out).resolve() if args.out else BUILD / "checks" / name
    say(f"rendering the solution's references for chapter {name[:2]} (kept for next time)")
    grader.prepare_references(ROOT, BUILD, name)
    grader.prepare_signatures(ROOT, BUILD, name, progress=say)
    results = grader.grade(ROOT, BUILD, name, folder, out, show_hidden=True)
    grader.print_table(results)
    found = results.get("extra_data", {}).get("diagnosis")
    if found is not None:
        print()
        print(diagnosis.describe(found))
    print(f"report: {out / 'report.md'}\nresults: {out / 'results.json'}")
    total = sum(t["max_score"] for t in results["tests"])
    if results["score"] < total:
        sys.exit(1)


def cmd_autograder(args):
    from course_tools.editions import classroom
    name = find_chapter(args.chapter)
    out = Path(args.out) if args.out else BUILD / "autograder" / f"{name}-autograder.zip"
    print(classroom.autograder_zip(ROOT, name, out.resolve()))

