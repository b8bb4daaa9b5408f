"""What the verbs of ./course do (the table of verbs, their options and the layer each
needs are in verbs.py). Each runs in the course's virtual environment .venv."""

from __future__ import annotations

import fcntl
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor
from contextlib import contextmanager
from pathlib import Path

from course_tools import chapters as chapter_list
from course_tools import cmake_cache
from course_tools.paths import ROOT

BUILD = ROOT / "build"
OUT = BUILD / "out"
BOOK = ROOT / "book"
GENERATED = BOOK / "docs" / "generated"


# ---------------------------------------------------------------- chapters

def chapters() -> list[str]:
    return chapter_list.names(ROOT)


def find_chapter(prefix: str) -> str:
    name = chapter_list.matching(prefix, ROOT)
    if name is None:
        die(f"no chapter '{prefix}'; ./course list shows them", code=2)
    return name


def die(message: str, code: int = 1):
    print(f"course: {message}", file=sys.stderr)
    sys.exit(code)


def say(message: str):
    print(f"course: {message}", file=sys.stderr, flush=True)


# ---------------------------------------------------------------- build

@contextmanager
def build_lock():
    """Two ./course commands at once share one build folder: take turns.
    COURSE_BUILD_LOCK names another lock file, so that two clones on one machine
    can take turns too (two builds at once on a small machine only slow both)."""
    BUILD.mkdir(exist_ok=True)
    with open(os.environ.get("COURSE_BUILD_LOCK", BUILD / ".lock"), "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        yield


def configure(build_type: str = "RelWithDebInfo", build_dir: Path = BUILD,
              options: dict[str, str] | None = None):
    """Configures build_dir unless it is configured with `options` already."""
    options = options or {}
    cached = cmake_cache.options(build_dir)
    if (build_dir / "build.ninja").exists() and all(
            cached.get(name) == value for name, value in options.items()):
        return
    say(f"configuring the CMake build in {build_dir.relative_to(ROOT)}")
    run_checked(["cmake", "-S", str(ROOT), "-B", str(build_dir), "-G", "Ninja",
                 f"-DCMAKE_BUILD_TYPE={build_type}",
                 f"-DPython3_EXECUTABLE={sys.executable}",
                 *(f"-D{name}={value}" for name, value in options.items())],
                stdout=sys.stderr)


# ./course test needs the C++ unit tests, which need the test layer's GoogleTest and
# tinyobjloader; other verbs build them only if those happen to be there.
WITH_UNIT_TESTS = {"COURSE_UNIT_TESTS": "ON"}


def build(targets: list[str] | None = None, options: dict[str, str] | None = None):
    with build_lock():
        configure(options=options)
        say("building" + (f" {' '.join(targets)}" if targets else " every chapter"))
        # Build output goes to stderr: stdout carries only results (a path, JSON).
        run_checked(["cmake", "--build", str(BUILD), *(["--target", *targets] if targets else [])],
                    stdout=sys.stderr)


def run_checked(command: list[str], **kwargs):
    result = subprocess.run(command, **kwargs)
    if result.returncode != 0:
        die(f"failed ({result.returncode}): {' '.join(command)}", code=result.returncode)
    return result


def binary(name: str) -> Path:
    return BUILD / "bin" / name


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


def chapter_manifests():
    """manifests/NN_name.ini of every chapter (tools/course_tools/manifests.py); a broken one is a
    clear message and exit code 3, like any bad input file."""
    from course_tools import manifests
    try:
        return manifests.load(ROOT, chapters())
    except manifests.ManifestError as error:
        die(str(error), code=3)


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
            say("on macOS, run the OpenGL 3.3 appendix instead: ./course run A1")
        sys.exit(result.returncode)
    if out is not None:
        print(out)

SANITIZED = BUILD / "sanitize"
FUZZ_BUILD = BUILD / "fuzz"
FUZZ_REGRESSIONS = ROOT / "tests" / "data" / "fuzz_regressions"
FUZZ_SECONDS_IN_TESTS = 20


def sanitizer_environment() -> dict:
    """ASan/UBSan settings: any error ends the program with a report; leaks from the
    GL driver (Mesa, LLVM) are not ours and are suppressed by name."""
    suppressions = ROOT / "tests" / "sanitizers" / "lsan.supp"
    return dict(os.environ,
                COURSE_BIN_DIR=str(SANITIZED / "bin"),
                ASAN_OPTIONS="detect_leaks=1:halt_on_error=1:abort_on_error=0",
                LSAN_OPTIONS=f"suppressions={suppressions}:print_suppressions=0",
                UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1")


def cmd_test(args):
    if args.sanitize:
        return test_sanitized(args)
    from course_tools.cli import suite_parts
    started = time.time()  # what this run writes is newer (--update-book)
    whole = not args.chapter and not args.k
    parts = suite_parts.SuiteParts(
        BUILD / "test-artifacts",
        ["build", "C++ unit tests (ctest)", "image checks and chapter tests (pytest)",
         "fuzzing", "sanitizers: build", "sanitizers: units and chapter runs"]
        if whole else ["build", "image checks and chapter tests (pytest)"])
    with parts.part("build"):
        build(options=WITH_UNIT_TESTS)
    passed = failed = 0
    if whole:
        with parts.part("C++ unit tests (ctest)"):
            passed, failed = run_ctest(BUILD)
    pytest = [sys.executable, "-m", "pytest", str(ROOT / "tests" / "python"), "-q",
              "-p", "no:cacheprovider", "-rfEs", *spread_over_cores()]
    if args.chapter:
        pytest += ["-m", f"chapter{find_chapter(args.chapter)[:2]}"]
    if args.k:
        pytest += ["-k", args.k]
    with parts.part("image checks and chapter tests (pytest)"):
        result = subprocess.run(pytest, stdout=subprocess.PIPE, text=True)
    print(result.stdout)
    counts = dict((kind, int(n)) for n, kind in
                  re.findall(r"(\d+) (passed|failed|error|errors|skipped)", result.stdout))
    passed += counts.get("passed", 0)
    failed += counts.get("failed", 0) + counts.get("error", 0) + counts.get("errors", 0)
    skipped = counts.get("skipped", 0)
    if result.returncode not in (0, 1) and failed == 0:
        failed += 1  # pytest itself broke (collection error, no tests)
    if whole:
        # Every fuzz target for a short, bounded time: kept crashes are replayed and a
        # new one fails the suite (./course fuzz runs longer).
        with parts.part("fuzzing"):
            say(f"fuzzing each parser for {FUZZ_SECONDS_IN_TESTS} s (libFuzzer)")
            for target, outcome in run_fuzzing(None, FUZZ_SECONDS_IN_TESTS).items():
                if outcome["passed"]:
                    passed += 1
                else:
                    failed += 1
        # The C++ units and a headless run of every chapter, built with ASan + UBSan
        # (./course test --sanitize runs the chapters' image checks under them too).
        with parts.part("sanitizers: build"):
            build_sanitized()
        with parts.part("sanitizers: units and chapter runs"):
            units = run_ctest(SANITIZED, sanitizer_environment(),
                              exclude=SLOW_WHEN_SANITIZED)
            for more_passed, more_failed in (units, sanitized_chapter_runs()):
                passed += more_passed
                failed += more_failed
    print(parts.report(suite_parts.this_run_durations(BUILD / "test-artifacts"),
                       whole=whole))
    # A skipped check is not a passed one: it counts as a failure here.
    print(f"{passed} passed, {failed + skipped} failed")
    if getattr(args, "update_book", False):
        if whole and failed + skipped == 0:
            from course_tools.cli import measured_pages
            measured_pages.write(BUILD / "test-artifacts", started)
        else:
            print("course: the pages are left as they are: --update-book writes them "
                  "only after a whole suite that passed", file=sys.stderr)
    sys.exit(0 if failed + skipped == 0 else 1)


def spread_over_cores() -> list[str]:
    """pytest-xdist's options: one worker per core (at most 8), each taking whole groups
    of checks (tests/python/conftest.py's work_group and its scheduler). Renders keep
    every core busy on their own, but much of the suite does not: compiling shaders,
    starting programs, numpy references, the grader's sandbox. COURSE_TEST_WORKERS=1
    runs in one process."""
    workers = int(os.environ.get("COURSE_TEST_WORKERS", 0)) or min(os.cpu_count() or 1, 8)
    try:
        import xdist  # noqa: F401
    except ImportError:
        return []
    return ["-n", str(workers), "--dist", "loadscope"] if workers > 1 else []


def run_ctest(build_dir: Path, env: dict | None = None,
              exclude: str | None = None) -> tuple[int, int]:
    """ctest in build_dir, without the tests matching `exclude`: (passed, failed). ctest
    counts a skipped test as passed; the course counts it as failed."""
    result = subprocess.run(["ctest", "--test-dir", str(build_dir), "--output-on-failure",
                             "-j", "2", *(["-E", exclude] if exclude else [])],
                            stdout=subprocess.PIPE, text=True, env=env)
    print(result.stdout)
    match = re.search(r"(\d+)% tests passed, (\d+) tests failed out of (\d+)", result.stdout)
    if not match:
        return 0, 1
    skipped = len(re.findall(r"\(Skipped\)", result.stdout))
    failed = int(match.group(2))
    return int(match.group(3)) - failed - skipped, failed + skipped


def build_sanitized():
    # Unoptimised (the sanitizers look at the host code; the GPU work is llvmpipe's and
    # not instrumented): compiling with ASan at -O2 takes four times as long.
    with build_lock():
        configure("Debug", build_dir=SANITIZED,
                  options={"COURSE_SANITIZE": "ON", **WITH_UNIT_TESTS})
        say("building with AddressSanitizer and UndefinedBehaviorSanitizer")
        run_checked(["cmake", "--build", str(SANITIZED)], stdout=sys.stderr)


# Three BVH tests are mostly brute-force reference work on big meshes (the 100 000- and
# 1 000 000-triangle teapots, thousands of rays against 6 320 triangles): 5.5 minutes
# unoptimised under ASan, seconds in the normal build, where they run. The sanitizer
# pass checks the same builder and traversal on the smaller meshes of the other tests.
SLOW_WHEN_SANITIZED = "BigTeapots|TraversalFindsWhatBruteForceFinds"

# What a chapter's sanitized run renders: small and quick; chapter 01 adds numbers, and
# chapter 20 runs its wavefront (the host code the megakernel does not use), in waves.
SANITIZER_RUN_ARGUMENTS = {"01_buffer_add": ["--count", "1000"]}
SANITIZER_EXTRA_ARGUMENTS = {"20_wavefront": ["--kernel", "wavefront", "--paths", "100"]}


def sanitized_chapter_runs() -> tuple[int, int]:
    """Every chapter's default scene, headless at 24 x 24, built with ASan + UBSan: any
    report (a bad read or write, undefined behaviour, a leak of ours) ends the program
    with a non-zero exit code. (passed, failed), one per chapter."""
    passed = failed = 0
    with tempfile.TemporaryDirectory(prefix="course-sanitize-") as folder:
        def run(name: str):
            arguments = SANITIZER_RUN_ARGUMENTS.get(name) or [
                "--width", "24", "--height", "24", "--out", f"{folder}/{name}.png"]
            command = [str(SANITIZED / "bin" / name), "--headless", *arguments,
                       *SANITIZER_EXTRA_ARGUMENTS.get(name, [])]
            return command, subprocess.run(command, capture_output=True, text=True,
                                           timeout=600, env=sanitizer_environment())
        # One at a time per core: a tiny render's time goes to starting the program and
        # compiling its shaders, on one core each.
        with ThreadPoolExecutor(max_workers=os.cpu_count() or 1) as pool:
            runs = list(pool.map(run, chapters()))
        for command, result in runs:
            if result.returncode == 0:
                passed += 1
            else:
                failed += 1
                print(f"FAILED under ASan + UBSan ({result.returncode}): {' '.join(command)}"
                      f"\n{result.stderr[-4000:]}")
    say(f"sanitized runs: {passed} of {passed + failed} chapters clean")
    return passed, failed


def test_sanitized(args):
    """Every chapter, the common layer and the parsers built with ASan + UBSan; the C++
    units and a headless run of every chapter (its image checks) under them."""
    build_sanitized()
    environment = sanitizer_environment()
    _, units_failed = run_ctest(SANITIZED, environment)  # every unit, the slow ones too
    chapter_checks = sorted(
        str(p) for p in (ROOT / "tests" / "python" / "chapters").glob("test_*.py")
        if re.match(r"test_(\d\d|A\d)_", p.name)
        or p.name in ("test_command_line.py", "test_bad_input_matrix.py"))
    pytest = subprocess.run([sys.executable, "-m", "pytest", *chapter_checks, "-q",
                             "-p", "no:cacheprovider", "-rfEs", "-x"], env=environment)
    sys.exit(0 if units_failed == 0 and pytest.returncode == 0 else 1)


def fuzz_seeds(target: str) -> list[Path]:
    if target == "fuzz_shader_include":
        return sorted(ROOT.glob("shaders/*/*.comp")) + sorted(ROOT.glob("shaders/*/*.glsl"))
    if target == "fuzz_obj_loader":
        return sorted((ROOT / "tests" / "data" / "obj").rglob("*.obj"))
    if target == "fuzz_scene_file":
        return sorted((ROOT / "assets" / "scenes").glob("*.scene")) + \
            [ROOT / "tests" / "data" / "scenes" / "materials.scene"]
    return []


def run_fuzzing(target_filter: str | None, seconds: int) -> dict[str, dict]:
    """Builds the libFuzzer targets, replays every kept crash input, then fuzzes each
    target for `seconds` from its seed corpus. A new crash input is copied into
    tests/data/fuzz_regressions/<target>/. Returns per target: executions, crashes,
    and whether it passed."""
    if not shutil.which("clang++"):
        die("fuzzing needs clang (apt install clang)", code=2)
    with build_lock():
        environment = dict(os.environ, CC="clang", CXX="clang++")
        if not (FUZZ_BUILD / "build.ninja").exists():
            run_checked(["cmake", "-S", str(ROOT), "-B", str(FUZZ_BUILD), "-G", "Ninja",
                         "-DCOURSE_FUZZ=ON", "-DCMAKE_BUILD_TYPE=RelWithDebInfo"],
                        env=environment, stdout=sys.stderr)
        run_checked(["cmake", "--build", str(FUZZ_BUILD)], stdout=sys.stderr)
    targets = sorted(p.name for p in (FUZZ_BUILD / "fuzz").iterdir() if p.is_file())
    if target_filter:
        targets = [t for t in targets if target_filter in t]
        if not targets:
            die(f"no fuzz target matching '{target_filter}'", code=2)
    def fuzz(target: str) -> tuple[dict, str]:
        """One target: its kept crashes replayed, then `seconds` of fuzzing. libFuzzer
        runs on one core, so the targets run side by side, one per core."""
        program = FUZZ_BUILD / "fuzz" / target
        passed, report = True, ""
        kept_folder = FUZZ_REGRESSIONS / target
        kept = sorted(kept_folder.glob("*")) if kept_folder.exists() else []
        if kept:
            say(f"{target}: replaying {len(kept)} kept crash inputs")
            replay = subprocess.run([str(program), *map(str, kept)], capture_output=True,
                                    text=True)
            if replay.returncode != 0:
                report += replay.stderr[-3000:] + "\n"
                passed = False
        corpus = FUZZ_BUILD / "corpus" / target
        crashes = FUZZ_BUILD / "crashes" / target
        for folder in (corpus, crashes):
            folder.mkdir(parents=True, exist_ok=True)
        for seed in fuzz_seeds(target):
            shutil.copyfile(seed, corpus / f"seed_{seed.parent.name}_{seed.name}")
        say(f"{target}: fuzzing for {seconds} s")
        result = subprocess.run(
            [str(program), str(corpus), f"-max_total_time={seconds}", "-timeout=10",
             "-rss_limit_mb=2048", "-print_final_stats=1", f"-artifact_prefix={crashes}/"],
            capture_output=True, text=True)
        executions = re.search(r"stat::number_of_executed_units:\s*(\d+)", result.stderr)
        found = sorted(crashes.iterdir())
        for crash in found:
            keep = kept_folder / crash.name
            keep.parent.mkdir(parents=True, exist_ok=True)
            shutil.copyfile(crash, keep)
        if found or result.returncode != 0:
            passed = False
            report += result.stderr[-3000:] + "\n"
        entry = {"seconds": seconds, "crashes": len(found), "passed": passed,
                 "executions": int(executions.group(1)) if executions else 0}
        report += (f"{target:24} {entry['executions']:>10} runs in {seconds} s, "
                   f"{len(found)} crashes")
        return entry, report

    with ThreadPoolExecutor(max_workers=os.cpu_count() or 1) as pool:
        outcomes = list(pool.map(fuzz, targets))
    summary = {}
    for target, (entry, report) in zip(targets, outcomes):
        summary[target] = entry
        print(report)
    (FUZZ_BUILD / "summary.json").write_text(json.dumps(summary, indent=2))
    return summary


def cmd_fuzz(args):
    summary = run_fuzzing(args.target, args.seconds)
    if not all(result["passed"] for result in summary.values()):
        die("fuzzing found a crash: the input is kept in tests/data/fuzz_regressions/")


def checkpoint_diff(a: str, b: str) -> list[tuple[str, list[str]]]:
    """Per file, the unified diff from checkpoint a to checkpoint b."""
    from course_tools.editions import editions
    return editions.checkpoint_diff(editions.checkpoint_texts(ROOT, a),
                                    editions.checkpoint_texts(ROOT, b), a, b)


def cmd_diff(args):
    a, b = find_chapter(args.a), find_chapter(args.b)
    diffs = checkpoint_diff(a, b)
    color = sys.stdout.isatty() and not args.no_color
    if args.stat:
        for key, lines in diffs:
            plus = sum(1 for l in lines if l.startswith("+") and not l.startswith("+++"))
            minus = sum(1 for l in lines if l.startswith("-") and not l.startswith("---"))
            print(f" {key:44} | +{plus} -{minus}")
        print(f" {len(diffs)} files changed from {a} to {b}")
        return
    paint = {"+": "\033[32m", "-": "\033[31m", "@": "\033[36m"}
    for _, lines in diffs:
        for line in lines:
            if color and line[:1] in paint and not line.startswith(("+++", "---")):
                print(f"{paint[line[0]]}{line}\033[0m")
            elif color and line.startswith(("+++", "---")):
                print(f"\033[1m{line}\033[0m")
            else:
                print(line)


def draft_arguments(arguments: list[str]) -> list[str]:
    """A quick version of a figure for checking the book builds: a quarter of the size
    and at most 4 samples per pixel, from the same program and options."""
    quick = list(arguments)
    for i, argument in enumerate(quick[:-1]):
        if argument in ("--width", "--height"):
            quick[i + 1] = str(max(16, int(quick[i + 1]) // 4))
        elif argument == "--spp":
            quick[i + 1] = str(min(4, int(quick[i + 1])))
    return quick


def figure_rows() -> list[tuple[str, str, str]]:
    """(figure, program, arguments) of every picture in the book: the [figures] of each
    chapter's manifest, in the chapters' order."""
    return [(f.name, f.program, f.arguments) for manifest in chapter_manifests().values()
            for f in manifest.figures]


def figure_programs(rows) -> list[str]:
    """The chapter programs that render these figures (the build targets they need)."""
    return sorted({find_chapter(program) for _, program, _ in rows
                   if not program.startswith("python_prototypes/")})


def figure_key(program: str, arguments: list[str]) -> str:
    """What makes a figure, as a reference cache key (tools/course_tools/reference_cache.py): for a
    chapter, what makes its grading references (grader.reference_maker: its sources,
    the common layer, build files, assets, compiler, GL and Mesa's settings); for a
    prototype, the prototypes and the Python, numpy and matplotlib that draw it; for
    both, the test data figures may name, and the arguments."""
    from course_tools import reference_cache
    if program.startswith("python_prototypes/"):
        import importlib.metadata
        versions = [importlib.metadata.version(p) for p in ("numpy", "matplotlib")]
        maker = reference_cache.key("prototype figure", reference_cache.tree_digest(
            ROOT / "python_prototypes", BUILD / "assets"), sys.version, *versions)
    else:
        from course_tools.grading import grader
        maker = grader.reference_maker(ROOT, BUILD, find_chapter(program))
    return reference_cache.key("book figure", maker, reference_cache.tree_digest(
        ROOT / "tests" / "data", scenes_as_read=True), program, *arguments)


def render_figures(rows, out: Path, draft: bool = False):
    """Renders figures (rows of figure_rows()) into `out`, with the real programs. A
    figure whose program and inputs are unchanged since it was rendered on this machine
    comes from the reference cache (figure_key)."""
    from course_tools import reference_cache
    out.mkdir(parents=True, exist_ok=True)
    for figure, program, arguments in rows:
        if program.startswith("python_prototypes/"):
            options = arguments.split()
            command = [sys.executable, str(ROOT / program), *options, "--figure",
                       str(out / figure)]
        else:
            options = arguments.split()
            options = draft_arguments(options) if draft else options
            command = [str(binary(find_chapter(program))), "--headless", "--out",
                       str(out / figure), *options]
        name = figure_key(program, options) + Path(figure).suffix
        kept = reference_cache.fetch(name)
        if kept is not None:
            (out / figure).write_bytes(kept)
            continue
        say(f"figure {figure}")
        run_checked(command, cwd=ROOT, stdout=subprocess.DEVNULL)
        reference_cache.store(name, (out / figure).read_bytes())


def render_book_figures(draft: bool = False):
    """Every picture in the book comes from the real programs, listed in the manifests."""
    render_figures(figure_rows(), GENERATED, draft)
    diffs = {(a, b): checkpoint_diff(a, b) for a, b in book_diff_pairs()}
    for (a, b), files in diffs.items():
        lines = [l for _, d in files for l in d]
        (GENERATED / f"diff_{a[:2]}_{b[:2]}.diff").write_text("\n".join(lines) + "\n")
    from course_tools.editions import editions
    (GENERATED / "diff_sizes.md").write_text(editions.diff_size_table(diffs))


def book_diff_pairs() -> list[tuple[str, str]]:
    """(from, to) of every diff the book includes: each numbered chapter against the
    one before it, each appendix against the chapter it was copied from (its manifest's
    `base`, not whatever comes before it in CMakeLists.txt)."""
    manifests = chapter_manifests()
    numbered = [name for name in manifests if name[:2].isdigit()]
    pairs = list(zip(numbered, numbered[1:]))
    return pairs + [(m.base, name) for name, m in manifests.items() if m.base]


def cmd_book(args):
    from course_tools.editions import editions
    build()
    if not args.figures_as_they_are:
        render_book_figures(draft=args.draft)
    os.environ["NO_MKDOCS_2_WARNING"] = "1"  # Material 9.7+ advertises its successor
    # book/hooks/edition.py reads this: the student edition's listings come from the
    # starters' code, without the answer notes, into book/site-student.
    os.environ[editions.EDITION_VARIABLE] = "student" if args.student else "instructors"
    mkdocs = [sys.executable, "-m", "mkdocs"]
    config = str(BOOK / "mkdocs.yml")
    if args.serve:
        run_checked([*mkdocs, "serve", "-f", config], cwd=ROOT)
    else:
        # cwd: snippet paths in the pages are relative to the repository root.
        run_checked([*mkdocs, "build", "--strict", "-q", "-f", config], cwd=ROOT)
        site = editions.STUDENT_SITE if args.student else BOOK / "site"
        print(site / "index.html")


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
        speed = [find_chapter("18"), find_chapter("19")]
        build([*speed, "course_benchmark_assets"])  # the million-triangle teapot
        settings = bench_speed.Settings(args.size, args.speed_spp, args.depth, args.repeat)
        status |= bench_speed.main({name[:2]: binary(name) for name in speed}, settings,
                                   update_book=args.update_book)
    if args.which in ("all", "wavefront"):
        from course_tools.bench import wavefront as bench_wavefront
        wavefront = find_chapter("20")
        build([wavefront])
        settings = bench_wavefront.Settings(args.speed_spp, args.depth, args.repeat)
        status |= bench_wavefront.main(binary(wavefront), settings,
                                       update_book=args.update_book)
    if args.which == "grading":  # minutes on one core: asked for by name only
        from course_tools.bench import grading as bench_grading
        graded = [find_chapter(c) for c in args.chapters] if args.chapters else \
            [c for c in chapters() if c[:2] in bench_grading.SPECS]
        build([*graded, "01_buffer_add"])
        probe = run_checked([str(binary(find_chapter("01"))), "--count", "1", "--json"],
                            capture_output=True, text=True)
        gl = json.loads(probe.stdout.strip().splitlines()[-1])
        status |= bench_grading.main(BUILD, graded, args.repeat, gl["renderer"],
                                     gl["gl_version"], update_book=args.update_book)
    sys.exit(status)


def bench_against_mitsuba(args) -> int:
    """The Cornell box through chapter 12 and through the newest chapter, the teapot
    through the newest chapter with a BVH, each against Mitsuba 3 (tools/course_tools/bench/mitsuba.py)."""
    from course_tools.bench import mitsuba as bench
    with_bvh = bench.newest_chapter_with_bvh(chapters())
    box_chapter = find_chapter("12")
    newest = [c for c in chapters() if c[:2].isdigit()][-1]
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


def cmd_grade(args):
    from course_tools.grading import grader
    from course_tools.grading import sandbox
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


def cmd_autograder(args):
    from course_tools.editions import classroom
    name = find_chapter(args.chapter)
    out = Path(args.out) if args.out else BUILD / "autograder" / f"{name}-autograder.zip"
    print(classroom.autograder_zip(ROOT, name, out.resolve()))
