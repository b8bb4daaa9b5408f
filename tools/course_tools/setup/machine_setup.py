"""Set-up in layers: what a verb of ./course needs, and nothing more, installed once.

    run    the distribution's build packages, then .venv with requirements/run.txt and
           the course's own packages (pyproject.toml, editable)
    book   + requirements/book.txt (MkDocs, the figures' matplotlib)
    grade  + requirements/grade.txt (what an autograder image needs)
    test   + the suite's packages (GoogleTest, Xvfb, a browser, clang's fuzzing runtime,
           the libLLVM Mitsuba uses) and requirements/test.txt

Each step is skipped when it is done. What cannot be done gets one message with the next
step and its own exit code (SetupError.code). Standard library only: this runs with the
system's Python, before .venv exists."""

from __future__ import annotations

import hashlib
import os
import shutil
import subprocess
import sys
from pathlib import Path

from course_tools.setup import platforms

from course_tools.paths import ROOT

VENV = ROOT / ".venv"
REQUIREMENTS = ROOT / "requirements"
OLDEST_PYTHON = (3, 10)

# Exit codes of set-up (the chapter programs use 2, 3 and 4 for their own errors).
UNKNOWN_PLATFORM = 2   # as for bad usage: the user must say what to do
MISSING_PACKAGES = 5   # not root: the command to run is printed
NO_PACKAGE_MANAGER = 6
PYTHON_TOO_OLD = 7     # or without venv
PIP_FAILED = 8         # usually no network or no proxy
BROWSER_DOWNLOAD_FAILED = 9  # Playwright's Chromium (Ubuntu's book check) out of reach


class SetupError(Exception):
    def __init__(self, message: str, code: int):
        super().__init__(message)
        self.code = code


def say(message: str):
    print(f"course: {message}", file=sys.stderr, flush=True)


def venv_python() -> Path:
    return VENV / ("Scripts" if os.name == "nt" else "bin") / "python"


def ensure(layer: str):
    """Everything `layer` needs, system packages first, then Python packages."""
    if sys.version_info < OLDEST_PYTHON:
        raise SetupError(f"Python {'.'.join(map(str, OLDEST_PYTHON))} or newer is needed; "
                         f"this is {sys.version.split()[0]} ({sys.executable})", PYTHON_TOO_OLD)
    try:
        platform = platforms.this_platform()
    except platforms.UnknownPlatform as unknown:
        raise SetupError(str(unknown), UNKNOWN_PLATFORM) from None
    if platform is not None:
        ensure_packages(platform, layer)
    ensure_venv(layer)
    if platform is not None and layer == "test" and platform.browser == "playwright":
        ensure_playwright_browser()


def is_root() -> bool:
    return hasattr(os, "geteuid") and os.geteuid() == 0


def ensure_packages(platform: platforms.Platform, layer: str):
    install_missing(platform, platform.missing(layer), f"the '{layer}' layer")


def ensure_listed_packages(platform: platforms.Platform, packages: list[str], purpose: str):
    """Installs those of `packages` this machine lacks (as root), or stops with the
    command to run; `purpose` says what needs them ("the Windows check")."""
    install_missing(platform, [p for p in packages if not platform.has(p)], purpose)


def install_missing(platform: platforms.Platform, missing: list[str], purpose: str):
    if not missing:
        return
    steps = platform.install_command(missing)
    if platform.installer in ("brew", "winget") or not is_root():
        sudo = "" if platform.installer in ("brew", "winget") else (
            "sudo " if shutil.which("sudo") else None)
        if sudo is None:
            lines = "\n".join(f"  su -c '{step}'" for step in steps)
            how = "there is no sudo here: as root,"
        else:
            lines = "\n".join(f"  {sudo}{step}" for step in steps)
            how = "install them with"
        raise SetupError(f"{platform.name} lacks what {purpose} needs: "
                         f"{' '.join(missing)}\n{how}\n{lines}\nthen run ./course again",
                         MISSING_PACKAGES)
    if not shutil.which(platform.package_manager()):
        raise SetupError(f"{platform.name} should have {platform.package_manager()}, but it "
                         f"is not on PATH; install these some other way: {' '.join(missing)}",
                         NO_PACKAGE_MANAGER)
    say(f"installing for {purpose}: {' '.join(missing)}")
    environment = dict(os.environ, DEBIAN_FRONTEND="noninteractive")
    for step in steps:
        if subprocess.run(step.split(), env=environment, stdout=sys.stderr).returncode != 0:
            raise SetupError(f"'{step}' failed (no network, or a package this {platform.name} "
                             "does not have?)", MISSING_PACKAGES)


def requirement_files(layer: str) -> list[Path]:
    return [REQUIREMENTS / f"{part}.txt" for part in platforms.INCLUDES[layer]]


def fingerprint(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def ensure_venv(layer: str):
    if not venv_python().exists():
        say("creating the Python environment in .venv")
        result = subprocess.run([sys.executable, "-m", "venv", str(VENV)],
                                capture_output=True, text=True)
        if result.returncode != 0:
            shutil.rmtree(VENV, ignore_errors=True)
            raise SetupError(f"{sys.executable} cannot make a virtual environment "
                             f"(Debian/Ubuntu: apt-get install python3-venv):\n"
                             f"{result.stderr.strip()}", PYTHON_TOO_OLD)
    for requirements in requirement_files(layer):
        stamp = VENV / f".{requirements.stem}.sha256"
        wanted = fingerprint(requirements)
        if stamp.exists() and stamp.read_text() == wanted:
            continue
        say(f"installing the '{requirements.stem}' layer's Python packages "
            f"(requirements/{requirements.name})")
        result = subprocess.run([str(venv_python()), "-m", "pip", "install", "--quiet",
                                 "--disable-pip-version-check", "-r", str(requirements)],
                                stdout=sys.stderr)
        if result.returncode != 0:
            raise SetupError(f"pip could not install requirements/{requirements.name} (its "
                             "message is above: no network, or a proxy pip needs to know "
                             "of?)", PIP_FAILED)
        stamp.write_text(wanted)
    ensure_course_installed()


def ensure_course_installed():
    """The course's own Python (tools/course_tools, python_prototypes) installed into
    .venv, editable, from pyproject.toml: scripts, tests and the book's hooks import it
    by name from there. Again only when pyproject.toml changes."""
    stamp = VENV / ".course-project.sha256"
    wanted = fingerprint(ROOT / "pyproject.toml") + " " + str(ROOT)
    if stamp.exists() and stamp.read_text() == wanted:
        return
    say("installing the course's own Python packages into .venv (pyproject.toml)")
    result = subprocess.run([str(venv_python()), "-m", "pip", "install", "--quiet",
                             "--disable-pip-version-check", "--no-deps", "--editable",
                             str(ROOT)], stdout=sys.stderr)
    if result.returncode != 0:
        raise SetupError("pip could not install the course itself (pyproject.toml; its "
                         "message is above: pip fetches setuptools to do it, so no network "
                         "or a proxy pip needs to know of?)", PIP_FAILED)
    stamp.write_text(wanted)


def ensure_playwright_browser():
    """Where the distribution's Chromium is a snap wrapper (Ubuntu), which fails in
    containers, the book is checked in Playwright's own build of Chromium."""
    stamp = VENV / ".playwright-chromium"
    if stamp.exists():
        return
    say("installing Playwright's Chromium for the book's browser check")
    command = [str(venv_python()), "-m", "playwright", "install", "chromium"]
    if is_root():
        command.insert(-1, "--with-deps")
    if subprocess.run(command, stdout=sys.stderr).returncode != 0:
        raise SetupError("Playwright could not download its Chromium for the book's browser "
                         "check (its message is above): Playwright fetches it from its own "
                         "servers, not from pip's index, so a network that reaches pip may "
                         "still not reach them; everything before the test layer's browser "
                         "is set up", BROWSER_DOWNLOAD_FAILED)
    stamp.write_text("installed\n")


def browser_executable() -> str | None:
    """The Chromium the book's browser check drives: a path, or None for Playwright's own."""
    try:
        platform = platforms.this_platform()
    except platforms.UnknownPlatform:
        platform = None
    if platform is not None and platform.browser and platform.browser != "playwright":
        return platform.browser
    if platform is None:
        return shutil.which("chromium") or shutil.which("chromium-browser")
    return None
