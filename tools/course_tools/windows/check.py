"""./course windows-check: the Windows build of every chapter, made on this Linux machine
with MinGW-w64 (cross_build.py), run under Wine on a virtual X server, where Wine's
opengl32 reaches Mesa's llvmpipe, and judged by the chapters' own image checks (the
pytest checks marked `windows`, one or more per chapter), which run the .exe files
instead of the Linux programs.

Needs Debian's MinGW-w64, Wine and Xvfb (PACKAGES, installed when run as root)."""

from __future__ import annotations

import os
import shlex
import subprocess
import sys
import tempfile

from course_tools import virtual_display
from course_tools.paths import ROOT
from course_tools.setup import machine_setup, platforms
from course_tools.windows import cross_build

WINE_PREFIX = cross_build.WINDOWS / "wine"
# The marker of the chapter checks that run on the Windows build (tests/python/chapters).
MARKER = "windows"


def ensure_packages():
    platform = platforms.this_platform()
    if platform is None or platform.installer != "apt" or not platform.key.startswith("debian"):
        missing = cross_build.missing_tools()
        if missing:
            raise machine_setup.SetupError(
                "the Windows check is set up on Debian 12 or 13 (MinGW-w64, Wine, Xvfb "
                f"from Debian's packages); this machine lacks {', '.join(missing)}",
                machine_setup.MISSING_PACKAGES)
        return
    machine_setup.ensure_listed_packages(platform, list(cross_build.PACKAGES),
                                         "the Windows check")


def wine_environment(display: str) -> dict[str, str]:
    """Wine in a prefix of the course's own (build/windows/wine), quiet (WINEDEBUG=-all:
    its notes would mix with the programs' messages, which the checks read), on our
    X server."""
    return {"WINEPREFIX": str(WINE_PREFIX), "WINEDEBUG": "-all", "DISPLAY": display,
            "WINEDLLOVERRIDES": "mscoree,mshtml="}  # no Mono or Gecko installer dialogs


def prepare_wine(environment: dict[str, str]):
    """Makes the Wine prefix once (wineboot), then waits until its server is idle."""
    env = dict(os.environ, **environment)
    if not (WINE_PREFIX / "system.reg").exists():
        cross_build.say("making the Wine prefix build/windows/wine (once)")
        WINE_PREFIX.mkdir(parents=True, exist_ok=True)
        subprocess.run(["wineboot", "--init"], env=env, check=True,
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    subprocess.run(["wineserver", "--wait"], env=env, check=False)


def check_under_wine(bin_folder, chapter: str | None) -> subprocess.CompletedProcess:
    """The chapters' Windows-marked checks, run on the .exe files under Wine on an X
    server of our own (Xvfb: Wine's opengl32 needs a display)."""
    cross_build.WINDOWS.mkdir(parents=True, exist_ok=True)
    with virtual_display.xvfb(cross_build.WINDOWS / "xvfb.log", 60) as display:
        environment = wine_environment(display)
        prepare_wine(environment)
        runner = "env " + " ".join(f"{k}={shlex.quote(v)}" for k, v in environment.items())
        selection = f"{MARKER} and chapter{chapter}" if chapter else MARKER
        command = [sys.executable, "-m", "pytest", str(ROOT / "tests" / "python" / "chapters"),
                   "-q", "-p", "no:cacheprovider", "-rfE", "-m", selection,
                   "-n", "0"]
        cross_build.say(f"running the chapters' image checks on the Windows build, under "
                        f"Wine ({selection})")
        result = subprocess.run(command, cwd=tempfile.gettempdir(), env=dict(
            os.environ, COURSE_BIN_DIR=str(bin_folder), COURSE_BACKENDS="glfw",
            COURSE_TEST_ARTIFACTS=str(cross_build.WINDOWS / "test-artifacts"),
            # Wine adds its start to each run; the watchdog's limit is for hangs, not that.
            COURSE_GPU_TIMEOUT_SECONDS="120",
            COURSE_PROGRAM_RUNNER=f"{runner} wine"))
        subprocess.run(["wineserver", "--kill"], env=dict(os.environ, **environment),
                       check=False)
    return result


def cmd_windows_check(args):
    try:
        ensure_packages()
    except machine_setup.SetupError as error:
        print(f"course: {error}", file=sys.stderr)
        sys.exit(error.code)
    try:
        bin_folder = cross_build.build()
    except cross_build.CrossBuildError as error:
        print(f"course: {error}", file=sys.stderr)
        sys.exit(1)
    except subprocess.CalledProcessError as error:
        print(f"course: the Windows build failed ({error.returncode}): "
              f"{shlex.join(map(str, error.cmd))}", file=sys.stderr)
        sys.exit(1)
    try:
        result = check_under_wine(bin_folder, args.chapter)
    except virtual_display.VirtualDisplayError as error:
        print(f"course: the Windows check needs a virtual X server: {error}", file=sys.stderr)
        sys.exit(1)
    sys.exit(result.returncode)
