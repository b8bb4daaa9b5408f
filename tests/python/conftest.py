"""Shared helpers for the chapter checks: run a chapter program from a temporary
folder (never the repository: shaders must be found through the built-in path), read
its images, and compare them with a reference."""

from __future__ import annotations

import json
import math
import os
import re
import shlex
import shutil
import subprocess
import sys
import threading
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

from course_tools import chapters, virtual_display
from python_prototypes.pfm import read_pfm  # noqa: F401  (the checks import it from here)
from python_prototypes.srgb import encode_8bit as srgb_encode_8bit  # noqa: F401

ROOT = Path(__file__).resolve().parents[2]
# COURSE_BIN_DIR: another build of the chapters (./course test --sanitize uses it).
BIN = Path(os.environ.get("COURSE_BIN_DIR", ROOT / "build" / "bin"))
# COURSE_PROGRAM_RUNNER: what runs a chapter's program, before its path: ./course
# windows-check runs the Windows build's .exe files through Wine ("env DISPLAY=:N wine").
RUNNER = shlex.split(os.environ.get("COURSE_PROGRAM_RUNNER", ""))

# The suite's clock: progress on stderr, and each check's time for the next estimate.
pytest_plugins = ["suite_clock"]

# The headless backends a build has: EGL and OSMesa on Linux; a hidden GLFW window on
# Windows (COURSE_BACKENDS=glfw, as ./course windows-check sets it).
BACKENDS = os.environ.get("COURSE_BACKENDS", "egl osmesa").split()
RUN_TIMEOUT = 300  # seconds; a chapter run that takes longer has hung


def pytest_configure(config):
    # One marker per checkpoint folder: chapters/02_first_pixels -> chapter02, and the
    # appendices' chapters/A2_... -> chapterA2.
    for folder in sorted((ROOT / "chapters").iterdir()):
        number = folder.name.split("_")[0]
        config.addinivalue_line("markers", f"chapter{number}: checks of {folder.name}")
    config.addinivalue_line("markers", "windows: a chapter's image check that ./course "
                            "windows-check also runs on the Windows build, under Wine")


def pytest_collection_modifyitems(items):
    # test_02_first_pixels.py -> marker chapter02, so ./course test 02 selects it
    # (test_A2_gl33_fragment.py -> chapterA2: ./course test A2).
    for item in items:
        match = re.match(r"test_(\d\d|A\d)_", Path(str(item.fspath)).name)
        if match:
            item.add_marker(getattr(pytest.mark, f"chapter{match.group(1)}"))
    longest_groups_first(items)


# The checks of the graders that share a chapter's build/grading/NN: the solution's
# grading test empties it first, so they must not run beside one another.
GRADER_CHECKS = {"test_grading.py", "test_grader_isolation.py"}
SHARED_BOOK = {"test_book.py", "test_book_browser.py", "test_editions.py",
               "test_layout.py", "test_portability.py"}
GRADER_CHAPTERS = {"01", "02", "04"}  # the chapters the grader's own checks grade


def work_group(nodeid: str) -> str:
    """The checks that run one after another in one worker when ./course test spreads
    the suite over the cores (pytest-xdist): a file's checks, which share its module
    fixtures; a chapter's gradings (its starter, its solution and its catalogue of
    variants), which share build/grading/NN; the grader's own checks with the gradings
    of the chapters they grade; the book's checks, which share book/site. Worked out
    from the check's id alone, which is all pytest-xdist's scheduler sees."""
    path, _, name = nodeid.partition("::")
    file = path.rsplit("/", 1)[-1]
    parameter = name[name.find("[") + 1:] if name.endswith("]") else ""
    graded = (file == "test_grading.py" and name.startswith("test_solution_full_marks")) \
        or (file == "test_grading_statistics.py" and name.startswith("test_catalogue_variant"))
    if graded and parameter:
        number = parameter[:2]
        return "grading-early" if number in GRADER_CHAPTERS else f"grading-{number}"
    if file in GRADER_CHECKS:
        return "grading-early"
    if file in SHARED_BOOK:
        return "book"
    return file


@pytest.hookimpl(optionalhook=True)
def pytest_xdist_make_scheduler(config, log):
    """pytest-xdist hands out whole work groups (work_group), in the order of the
    collection: longest first (longest_groups_first). Its own --dist loadgroup reads
    marks that pytest 9 no longer lets it write into the ids; this asks the id."""
    from xdist.scheduler import LoadScopeScheduling

    class ByWorkGroup(LoadScopeScheduling):
        def _split_scope(self, nodeid: str) -> str:
            return work_group(nodeid)
    return ByWorkGroup(config, log)


def longest_groups_first(items):
    """Orders the groups by their checks' times in the last run, longest first, each
    group's checks kept in their order: pytest-xdist hands out groups in this order, so
    the long ones start early and the short ones fill in (unknown checks count a
    second)."""
    from suite_clock import read_durations
    durations = read_durations()
    groups: dict[str, list] = {}
    for item in items:
        groups.setdefault(work_group(item.nodeid), []).append(item)
    ranked = sorted(groups.values(), key=lambda group: -sum(
        durations.get(item.nodeid, 1.0) for item in group))
    items[:] = [item for group in ranked for item in group]


@dataclass
class Run:
    returncode: int
    stdout: str
    stderr: str


def chapter_name(prefix: str) -> str:
    """The chapter's name from the course's list (CMakeLists.txt), not from the build
    folder, which may still hold a program of a chapter since renamed."""
    name = chapters.matching(prefix, ROOT)
    assert name is not None, f"there is no chapter {prefix} in {ROOT / 'CMakeLists.txt'}"
    assert program_path(name).exists(), f"chapter {prefix} is not built in {BIN}"
    return name


def program_path(name: str) -> Path:
    """A chapter's program in BIN: NN_name, or NN_name.exe in a Windows build."""
    windows = BIN / f"{name}.exe"
    return windows if windows.exists() and not (BIN / name).exists() else BIN / name


def run_chapter(prefix: str, *args: str, cwd: Path | None = None, env: dict | None = None,
                timeout: float = RUN_TIMEOUT) -> Run:
    """Runs build/bin/<prefix>_* with args; the working folder is a scratch folder."""
    program = program_path(chapter_name(prefix))
    environment = dict(os.environ)
    environment.pop("DISPLAY", None)  # headless unless a test puts a display back
    environment.update(env or {})
    result = subprocess.run([*RUNNER, str(program), *map(str, args)], capture_output=True,
                            text=True,
                            cwd=cwd or Path.cwd(), env=environment, timeout=timeout)
    return Run(result.returncode, result.stdout, result.stderr)


# No GL is known to end shader loops sooner than Mesa 22's llvmpipe: common/course/
# loop_budget.h's kSmallestKnownLoopLimit, the most a chapter does without a probe.
SMALLEST_KNOWN_LOOP_LIMIT = 65535


def loop_limit(prefix: str, env: dict | None = None) -> int | None:
    """The loop limit the chapter measures for the shaders it runs (--probe-loop-limit):
    iterations per invocation (65 535 on Mesa 22's llvmpipe), or None when every
    iteration the probe asked for ran (Mesa 25's llvmpipe, a GPU). Tests choose what to
    expect from this measurement, never from the renderer's name."""
    result = run_chapter(prefix, "--headless", "--probe-loop-limit", "--json", env=env)
    assert result.returncode == 0, result.stderr
    limit = json.loads(result.stdout)["loop_limit"]
    return None if limit == "none" else int(limit)


@pytest.fixture(autouse=True)
def _scratch_folder(tmp_path, monkeypatch):
    """Every test runs in its own empty folder."""
    monkeypatch.chdir(tmp_path)


def render(prefix: str, out: Path, *args: str, **kwargs) -> np.ndarray:
    """Renders with the chapter, asserts success, returns the image (PFM: linear float;
    PNG: 8-bit sRGB as float 0..255)."""
    result = run_chapter(prefix, "--headless", "--out", out, *args, **kwargs)
    assert result.returncode == 0, result.stderr
    return read_image(out)


def read_image(path: Path) -> np.ndarray:
    path = Path(path)
    if path.suffix == ".pfm":
        return read_pfm(path)
    from PIL import Image
    return np.asarray(Image.open(path).convert("RGB"), dtype=np.float64)


def assert_images_agree(image: np.ndarray, reference: np.ndarray, *, within: float = 2.0,
                        fraction: float = 0.995, mean_below: float = 0.5, label: str = ""):
    """The course's image check for 8-bit images (book/docs/maintainers.md): at least
    99.5% of pixel channels within 2/255 of the reference and a mean absolute error
    below 0.5/255."""
    assert image.shape == reference.shape, f"{label}: shape {image.shape} != {reference.shape}"
    error = np.abs(image - reference)
    close = float(np.mean(np.all(error <= within, axis=-1)))
    mean = float(np.mean(error))
    assert close >= fraction and mean < mean_below, (
        f"{label}: {close:.2%} of pixels within {within}/255 (need {fraction:.1%}), "
        f"mean error {mean:.3f}/255 (need < {mean_below})")


def copy_shaders(prefix: str, destination: Path) -> Path:
    """A private copy of a checkpoint's shader folder, laid out as shaders/NN_name so
    that messages show the short path; returns the folder for --shader-dir."""
    name = chapter_name(prefix)
    target = destination / "shaders" / name
    shutil.copytree(ROOT / "shaders" / name, target)
    return target


# A region whose light fewer pixels than this carry (the light seen in a small mirror)
# is judged by the spread of the plain difference: see region_standard_error.
SPREAD_FOR_A_RATIO = 10


def region_standard_error(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The standard error (3,) of mean(a) - mean(b) for one region's pixels (n, 3) of
    two renders with independent noise, estimated from the spread of their differences.

    The plain difference a - b also spreads with the picture itself when a is wrong by a
    factor (a = c b: (c - 1) b varies from pixel to pixel), so a region only too dark
    or too bright widens its own error bar and may pass: a glossy sphere half as bright,
    whose pixels range from dark to the lamp's highlight, would. So the spread is taken of
    a - ratio b, ratio = mean(a) / mean(b): what is left is the noise, which is what the
    difference of the means is to be measured against (the ratio estimator's standard
    error). Where a few pixels carry most of the region's light, though, the ratio is
    theirs and their own noise cancels out of the spread; there the plain difference's
    spread is kept, which errs on the wide side (tests/python/prototypes/test_regions_agreeing.py
    shows both)."""
    n = len(a)
    brightness = (a + b).mean(axis=-1)
    pixels_carrying_light = brightness.sum() ** 2 / max((brightness ** 2).sum(), 1e-300)
    if pixels_carrying_light >= SPREAD_FOR_A_RATIO:
        mean_b = b.mean(axis=0)
        ratio = np.divide(a.mean(axis=0), mean_b, out=np.ones(3), where=mean_b > 0)
        difference = a - ratio * b
    else:
        difference = a - b
    return difference.std(axis=0) / math.sqrt(n)


def regions_agreeing(a: np.ndarray, b: np.ndarray, scene_file: Path,
                     sigmas: float = 4.5, mesh_folders=(),
                     most_relative: float | None = None) -> list[str]:
    """Two renders of one scene (linear, same size), compared region by region (the
    pixels that see only one named shape: python_prototypes/mitsuba_reference.py): each
    region's mean must differ by less than `sigmas` standard errors of the difference
    (region_standard_error), and, with most_relative, the means' brightness (RGB
    averaged) by less than that fraction of b's. Regions of fewer than 20 pixels have no
    useful spread and are left out. The masks are kept in the reference cache (numpy
    traces a mesh scene for seconds). Returns the regions compared, for the caller to
    check."""
    from course_tools import mitsuba_cache
    from python_prototypes import mitsuba_reference
    from python_prototypes import scene_io
    scene = scene_io.load_scene(str(scene_file), [str(f) for f in mesh_folders])
    masks = mitsuba_cache.kept_region_masks(scene, a.shape[1], a.shape[0])
    means_a = mitsuba_reference.region_means(a, masks)
    means_b = mitsuba_reference.region_means(b, masks)
    compared = []
    for region, mask in masks.items():
        if mask.sum() < 20:
            continue
        difference = np.abs(means_a[region] - means_b[region])
        error = region_standard_error(a[mask].astype(np.float64), b[mask].astype(np.float64))
        assert np.all(difference < sigmas * error + 1e-6), \
            (region, means_a[region], means_b[region], error)
        if most_relative is not None:
            relative = means_a[region].mean() / means_b[region].mean() - 1
            assert abs(relative) < most_relative, (region, relative)
        compared.append(region)
    return compared


# --- Window mode ------------------------------------------------------------------------
# A window test runs the chapter on a virtual X server of its own and goes step by step
# on what the program reports (--verbose: "watching FILE", "frame N drawn", "reloaded
# FILE", "kept the last good program of FILE"), never on guessed durations. The one
# time limit, WINDOW_SAFETY_TIMEOUT, only turns a hang into a failure.

WINDOW_SAFETY_TIMEOUT = 300  # seconds for any one step


def xvfb_available() -> bool:
    return shutil.which("Xvfb") is not None


@pytest.fixture
def window_env(tmp_path_factory):
    """The environment of a program that opens a window: DISPLAY on an Xvfb server
    started for this test alone, which picks a free display number itself (-displayfd:
    no race between tests running at the same time, unlike xvfb-run -a) and says when
    it is ready. The desktop session's variables are made up or removed: XDG_RUNTIME_DIR
    is a new private folder (Wayland clients insist on one) and WAYLAND_DISPLAY is
    unset, so that nothing opens on the desktop of whoever runs the tests."""
    folder = tmp_path_factory.mktemp("window")
    runtime = folder / "runtime"
    runtime.mkdir(mode=0o700)
    try:
        with virtual_display.xvfb(folder / "xvfb.log", WINDOW_SAFETY_TIMEOUT) as display:
            env = {k: v for k, v in os.environ.items() if k != "WAYLAND_DISPLAY"}
            env.update(DISPLAY=display, XDG_RUNTIME_DIR=str(runtime),
                       XDG_SESSION_TYPE="x11")
            yield env
    except virtual_display.VirtualDisplayError as error:
        pytest.fail(str(error))


def window_command(prefix: str, out: Path, *args) -> list[str]:
    """A chapter in a 32 x 32 window (run it with window_env), writing `out` at the end."""
    return [str(BIN / chapter_name(prefix)), "--window", "--width", "32", "--height", "32",
            "--out", str(out), "--json", *map(str, args)]


class ProgramLog:
    """The standard error of a running program, line by line, as it comes."""

    def __init__(self, process: subprocess.Popen):
        self.process = process
        self.lines: list[str] = []
        self.position = 0  # lines before this one have been waited for already
        self._changed = threading.Condition()
        self._ended = False
        threading.Thread(target=self._read, daemon=True).start()

    def _read(self):
        for line in self.process.stderr:
            with self._changed:
                self.lines.append(line.rstrip("\n"))
                self._changed.notify_all()
        with self._changed:
            self._ended = True
            self._changed.notify_all()

    def text(self) -> str:
        with self._changed:
            return "\n".join(self.lines)

    def wait_for(self, text: str) -> str:
        """The next line, after those already waited for, that contains `text`; fails
        if the program ends first (or after WINDOW_SAFETY_TIMEOUT: a hang)."""
        deadline = time.monotonic() + WINDOW_SAFETY_TIMEOUT
        with self._changed:
            while True:
                for index in range(self.position, len(self.lines)):
                    if text in self.lines[index]:
                        self.position = index + 1
                        return self.lines[index]
                self.position = len(self.lines)
                remaining = deadline - time.monotonic()
                if self._ended or remaining <= 0:
                    why = "ended" if self._ended else f"hung for {WINDOW_SAFETY_TIMEOUT} s"
                    pytest.fail(f"the program {why} before saying {text!r}:\n"
                                + "\n".join(self.lines))
                self._changed.wait(remaining)


def replace_file(path: Path, text: str):
    """Writes `path` whole in one step (a new file renamed over it, as many editors
    save), so that a reader sees the old text or the new, never half of it."""
    temporary = path.with_name(path.name + ".saving")
    temporary.write_text(text)
    os.replace(temporary, path)


def check_hot_reload(prefix: str, shaders: Path, shader: str, paint: tuple[str, str],
                     out: Path, *args, env: dict) -> np.ndarray:
    """Runs the chapter in a window with its shaders from `shaders` and edits `shader`
    while it runs, one step after the other as the program reports them:

    1. it watches `shader` and has drawn a frame: swap the line paint[0] for paint[1],
       which paints every pixel a fixed colour;
    2. it says "reloaded" and draws a frame with the new program: plant a compile error;
    3. it names the error's file and line, keeps the last good program, and goes on
       drawing frames: close the window (SIGTERM, as Ctrl+C would).

    Returns the image the window wrote when it closed (linear), for the caller to check
    the colour."""
    path = shaders / shader
    shown = f"shaders/{shaders.name}/{shader}"
    good = path.read_text()
    painted = good.replace(*paint)
    assert painted != good, f"{paint[0]!r} is not in {shader}"
    lines = painted.splitlines()
    broken_line = next(i for i, line in enumerate(lines) if "void main() {" in line) + 1
    lines[broken_line - 1] += " int broken = ;"
    broken = "\n".join(lines) + "\n"

    process = subprocess.Popen(
        window_command(prefix, out, "--verbose", "--shader-dir", shaders, *args),
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
    log = ProgramLog(process)
    try:
        log.wait_for(f"watching {shown}")
        log.wait_for(" drawn")
        replace_file(path, painted)
        log.wait_for(f"reloaded {shown}")
        log.wait_for(" drawn")
        replace_file(path, broken)
        log.wait_for(f"{shown}:{broken_line}: ")
        log.wait_for(f"kept the last good program of {shown}")
        log.wait_for(" drawn")
        assert process.poll() is None, "the broken shader ended the program"
        process.terminate()
        process.wait(timeout=WINDOW_SAFETY_TIMEOUT)
        stdout = process.stdout.read()  # one line of JSON: the pipe holds it
    finally:
        if process.poll() is None:
            process.kill()
            process.wait()
    assert process.returncode == 0, log.text()
    log.wait_for("window closed after")
    assert json.loads(stdout.strip().splitlines()[-1])["out"] == str(out)
    return read_pfm(out)[..., :3]


@pytest.fixture(scope="session")
def built_book():
    """Builds the book once per test run: every figure rendered by the real programs
    (as drafts: smaller, fewer samples — the full figures are ./course book's job, and
    the chapters' own checks test the pictures), then mkdocs --strict."""
    result = subprocess.run([sys.executable, str(ROOT / "tools" / "course.py"), "book",
                             "--draft"],
                            capture_output=True, text=True, timeout=900, cwd=ROOT)
    assert result.returncode == 0, result.stderr[-3000:]
    return ROOT / "book" / "site"
