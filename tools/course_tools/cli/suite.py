"""./course test and ./course fuzz: the build, the C++ units, pytest over the cores, the
fuzzers, and the sanitizers' build and runs, with the suite's clock."""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

from course_tools.cli.build import (
    BUILD,
    WITH_UNIT_TESTS,
    build,
    build_lock,
    chapters,
    configure,
    die,
    find_chapter,
    run_checked,
    say,
)
from course_tools.paths import ROOT

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
    if os.name == "nt":
        return test_on_windows(args)
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
# chapter 23 runs its wavefront (the host code the megakernel does not use), in waves,
# and chapters 20 and 21 the teapot (the tree's corners copied out, its leaves priced).
SANITIZER_RUN_ARGUMENTS = {"01_buffer_add": ["--count", "1000"]}
SANITIZER_EXTRA_ARGUMENTS = {"20_memory_paths": ["--scene", "cornell_teapot"],
                             "21_tree_price": ["--scene", "cornell_teapot"],
                             "23_wavefront": ["--kernel", "wavefront", "--paths", "100"]}


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


def test_on_windows(args):
    """Windows natively: every chapter built with the preset's compiler, then the
    chapters' image checks marked `windows` on its programs, through a hidden GLFW
    window on the driver's OpenGL (what ./course windows-check runs under Wine). The
    rest of the suite (the units, fuzzing, sanitizers, the grader, the book's checks)
    needs Linux: in WSL 2, ./course test runs all of it."""
    if args.sanitize:
        die("--sanitize needs Linux (AddressSanitizer with UBSan): run it in WSL 2", code=2)
    build()
    say("Windows: the chapters' image checks marked 'windows'; the whole suite runs on "
        "Linux or in WSL 2")
    selection = "windows" + (f" and chapter{find_chapter(args.chapter)[:2]}"
                             if args.chapter else "")
    command = [sys.executable, "-m", "pytest", str(ROOT / "tests" / "python" / "chapters"),
               "-q", "-p", "no:cacheprovider", "-rfE", "-m", selection]
    if args.k:
        command += ["-k", args.k]
    result = subprocess.run(command, env=dict(os.environ, COURSE_BACKENDS="glfw"))
    sys.exit(result.returncode)


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
    if target == "fuzz_volume_grid":
        return [ROOT / "tests" / "fuzz" / "seeds" / "small.vol"]
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


