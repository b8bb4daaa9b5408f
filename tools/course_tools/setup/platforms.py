"""The platforms the course knows, read from tools/platforms.ini: which one this machine
is, which of a layer's packages it lacks, and the command that installs them.

Standard library only: ./course runs this with the system's Python before the course's
virtual environment exists."""

from __future__ import annotations

import configparser
import os
import platform as host
import shutil
import subprocess
from dataclasses import dataclass
from pathlib import Path

from course_tools.paths import ROOT

TABLE = ROOT / "tools" / "platforms.ini"
LAYERS = ("run", "book", "grade", "test")
# Each layer brings the layers it builds on: the suite builds the book and grades.
INCLUDES = {"run": ("run",), "book": ("run", "book"), "grade": ("run", "grade"),
            "test": ("run", "book", "grade", "test")}
# Homebrew formulae that are programs: any copy on PATH will do (the formula is "python").
BREW_PROGRAMS = {"cmake": "cmake", "ninja": "ninja", "python": "python3"}
# Windows: what each program of the row is on PATH, and the winget package that brings it
# (vcpkg is a clone of its repository, bootstrapped, named by VCPKG_ROOT).
WINDOWS_PROGRAMS = {"cmake": "cmake", "ninja": "ninja", "git": "git", "python": "python",
                    "vcpkg": "vcpkg"}
WINGET_IDS = {"cmake": "Kitware.CMake", "ninja": "Ninja-build.Ninja", "git": "Git.Git",
              "python": "Python.Python.3.12"}


@dataclass
class Platform:
    key: str
    name: str
    installer: str
    packages: dict[str, list[str]]
    browser: str
    libllvm: str
    tested: str

    def layer_packages(self, layer: str) -> list[str]:
        """The packages of `layer` and of every layer it builds on, in table order."""
        names: list[str] = []
        for part in INCLUDES[layer]:
            names += [p for p in self.packages[part] if p not in names]
        return names

    def missing(self, layer: str) -> list[str]:
        return [p for p in self.layer_packages(layer) if not self.has(p)]

    def has(self, package: str) -> bool:
        if self.installer == "brew" and package in BREW_PROGRAMS:
            return shutil.which(BREW_PROGRAMS[package]) is not None
        if self.installer == "winget":
            if package == "vcpkg" and os.environ.get("VCPKG_ROOT"):
                return (Path(os.environ["VCPKG_ROOT"]) / "vcpkg.exe").exists()
            return shutil.which(WINDOWS_PROGRAMS.get(package, package)) is not None
        query = {
            "apt": ["dpkg-query", "-W", "-f=${Status}", package],
            "dnf": ["rpm", "-q", "--whatprovides", package],
            "pacman": ["pacman", "-Q", package],
            "brew": ["brew", "list", "--versions", package],
        }[self.installer]
        try:
            result = subprocess.run(query, capture_output=True, text=True)
        except FileNotFoundError:
            return False
        if self.installer == "apt":
            return "ok installed" in result.stdout
        return result.returncode == 0

    def install_command(self, packages: list[str]) -> list[str]:
        """One shell command line per step, without sudo."""
        names = " ".join(packages)
        if self.installer == "winget":
            steps = [f"winget install --id {WINGET_IDS[name]} --exact"
                     for name in packages if name in WINGET_IDS]
            if "vcpkg" in packages:
                steps += ["git clone https://github.com/microsoft/vcpkg $HOME\\vcpkg",
                          "$HOME\\vcpkg\\bootstrap-vcpkg.bat -disableMetrics",
                          "[Environment]::SetEnvironmentVariable('VCPKG_ROOT', "
                          "\"$HOME\\vcpkg\", 'User')   # then open a new terminal"]
            return steps
        return {
            "apt": ["apt-get update", f"apt-get install -y --no-install-recommends {names}"],
            "dnf": [f"dnf install -y {names}"],
            "pacman": [f"pacman -S --needed --noconfirm {names}"],
            "brew": [f"brew install {names}"],
        }[self.installer]

    def package_manager(self) -> str:
        return {"apt": "apt-get", "dnf": "dnf", "pacman": "pacman", "brew": "brew",
                "winget": "winget"}[self.installer]


def read_table(path: Path = TABLE) -> dict[str, Platform]:
    table = configparser.ConfigParser(interpolation=None, inline_comment_prefixes=None)
    table.read(path)
    platforms = {}
    for key in table.sections():
        row = table[key]
        platforms[key] = Platform(
            key=key, name=row["name"], installer=row["installer"],
            packages={layer: row.get(layer, "").split() for layer in LAYERS},
            browser=row.get("browser", ""), libllvm=row.get("libllvm", ""),
            tested=row.get("tested", "not yet"))
        platforms[key].match = row["match"].split()  # type: ignore[attr-defined]
    return platforms


def os_release(path: Path | None = None) -> dict[str, str]:
    """The KEY=value lines of os-release (COURSE_OS_RELEASE names another file: the
    tests use it to play other platforms), unquoted."""
    path = path or Path(os.environ.get("COURSE_OS_RELEASE", "/etc/os-release"))
    fields = {}
    try:
        text = path.read_text()
    except OSError:
        return fields
    for line in text.splitlines():
        key, sep, value = line.partition("=")
        if sep:
            fields[key.strip()] = value.strip().strip("'\"")
    return fields


def identify(release: dict[str, str] | None = None, system: str | None = None) -> tuple[str, str]:
    """(ID, VERSION_ID) of this machine: ("debian", "12"), ("darwin", "14.5"), ..."""
    system = system or host.system()
    if system == "Darwin":
        return "darwin", host.mac_ver()[0]
    if system == "Windows":
        return "windows", host.release()
    release = os_release() if release is None else release
    return release.get("ID", "unknown"), release.get("VERSION_ID", "")


def detect(release: dict[str, str] | None = None, system: str | None = None,
           table: dict[str, Platform] | None = None) -> Platform | None:
    """This machine's row of the table, or None for a platform the course does not know."""
    ident, version = identify(release, system)
    for platform in (table or read_table()).values():
        want_id, want_version = platform.match  # type: ignore[attr-defined]
        if ident == want_id and want_version in ("*", version):
            return platform
    return None


def describe_unknown(release: dict[str, str] | None = None, system: str | None = None) -> str:
    """What to tell someone on a platform the table does not have."""
    ident, version = identify(release, system)
    known = ", ".join(p.name for p in read_table().values())
    return (f"this platform ({ident} {version}) is not one the course knows ({known}).\n"
            "Install the equivalents of: a C++17 compiler, CMake >= 3.22, Ninja, "
            "pkg-config, git, Python >= 3.10 with venv, and the development files of "
            "GLFW 3.3, GLM, EGL and libOpenGL (glvnd), Mesa's EGL, DRI and OSMesa "
            "drivers, and stb; then run ./course with COURSE_PLATFORM=none, which skips "
            "the package check, or COURSE_PLATFORM=<the closest row of "
            "tools/platforms.ini>.")


class UnknownPlatform(Exception):
    pass


NO_PACKAGE_CHECK = "none"


def this_platform() -> Platform | None:
    """detect(), unless COURSE_PLATFORM names a row to use instead, or is "none" (the
    packages are the user's business: None). Raises UnknownPlatform with what to do."""
    forced = os.environ.get("COURSE_PLATFORM")
    if forced == NO_PACKAGE_CHECK:
        return None
    if forced:
        table = read_table()
        if forced not in table:
            raise UnknownPlatform(f"COURSE_PLATFORM={forced} is not a row of {TABLE.name} "
                                  f"({', '.join(table)}, or {NO_PACKAGE_CHECK})")
        return table[forced]
    found = detect()
    if found is None:
        raise UnknownPlatform(describe_unknown())
    return found
