"""What every verb of ./course stands on: the chapters, messages, the CMake build folder
(one build at a time) and the programs it makes."""

from __future__ import annotations

import os
import subprocess
import sys
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
    with open(os.environ.get("COURSE_BUILD_LOCK", BUILD / ".lock"), "a+") as lock:
        if os.name == "nt":
            import msvcrt  # Windows: a lock on the file's first byte, retried until free
            lock.seek(0)
            while True:
                try:
                    msvcrt.locking(lock.fileno(), msvcrt.LK_LOCK, 1)
                    break
                except OSError:  # LK_LOCK gives up after 10 s; wait on
                    continue
        else:
            import fcntl
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
    if os.name == "nt" and build_dir == BUILD:
        # Windows: a preset of CMakePresets.json, whose vcpkg toolchain brings GLFW and
        # GLM (vcpkg.json) at this first configure.
        run_checked(["cmake", "--preset", windows_preset(), "-DCMAKE_BUILD_TYPE=" + build_type,
                     f"-DPython3_EXECUTABLE={sys.executable}",
                     *(f"-D{name}={value}" for name, value in options.items())],
                    cwd=ROOT, stdout=sys.stderr)
        return
    run_checked(["cmake", "-S", str(ROOT), "-B", str(build_dir), "-G", "Ninja",
                 f"-DCMAKE_BUILD_TYPE={build_type}",
                 f"-DPython3_EXECUTABLE={sys.executable}",
                 *(f"-D{name}={value}" for name, value in options.items())],
                stdout=sys.stderr)


def windows_preset() -> str:
    """The preset for this Windows terminal: COURSE_PRESET when set, else Visual
    Studio's compiler when cl is on PATH (the Developer PowerShell), else MinGW-w64's."""
    import shutil
    chosen = os.environ.get("COURSE_PRESET")
    if chosen:
        return chosen
    if os.environ.get("VCPKG_ROOT") is None:
        die("VCPKG_ROOT is not set: the Windows build takes GLFW and GLM from vcpkg "
            "(book: Setup, Windows)", code=5)
    if shutil.which("cl"):
        return "windows-msvc"
    if shutil.which("g++"):
        return "windows-mingw"
    die("no C++ compiler on PATH: open the Developer PowerShell for VS 2022 (MSVC), or "
        "put MinGW-w64's g++ on PATH (book: Setup, Windows)", code=5)


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
    return BUILD / "bin" / (name + (".exe" if os.name == "nt" else ""))



def chapter_manifests():
    """manifests/NN_name.ini of every chapter (tools/course_tools/manifests.py); a broken one is a
    clear message and exit code 3, like any bad input file."""
    from course_tools import manifests
    try:
        return manifests.load(ROOT, chapters())
    except manifests.ManifestError as error:
        die(str(error), code=3)


