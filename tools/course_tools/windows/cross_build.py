"""The Windows build of the course, made on Linux: Debian's MinGW-w64 compiles every
chapter into a Windows .exe against GLFW's Windows DLL, in build/windows/tree.

What a Windows learner gets from vcpkg (vcpkg.json) is staged here by hand, in
build/windows/prefix, from pinned sources:
  - GLFW's Windows DLL from the `glfw` wheel for win_amd64 (pinned by version and
    SHA-256; the wheel carries glfw3.dll, GLFW 3.4, built with Visual C++, and its
    runtime msvcr120.dll), with an import library made from the DLL's own exports;
  - GLFW's and GLM's headers from this machine's libglfw3-dev and libglm-dev (GLFW's
    3.3 API is a part of 3.4's; GLM is headers only);
  - a CMake package for each (glfw, glm::glm), as vcpkg's would provide.
stb comes from third_party/stb (the course's pinned copies), OpenEXR is left out (.exr
refused with a reason), and there is no EGL or OSMesa on Windows: headless runs use a
hidden GLFW window (common/gl_context.cpp)."""

from __future__ import annotations

import hashlib
import os
import re
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

from course_tools.paths import ROOT

WINDOWS = ROOT / "build" / "windows"
PREFIX = WINDOWS / "prefix"
TREE = WINDOWS / "tree"
BIN = TREE / "bin"
PRESET = "linux-mingw-cross"  # CMakePresets.json: the toolchain file, this prefix, TREE
MINGW = "x86_64-w64-mingw32"

GLFW_WHEEL = "glfw==2.11.0"
GLFW_WHEEL_FILE = "glfw-2.11.0-py2.py3-none-win_amd64.whl"
GLFW_WHEEL_SHA256 = "bd39c1adb57b7273813e33b9768bed88d1ea656abfc914b4a6424ec0c5d62674"
# What the programs load at run time, copied beside them.
RUNTIME_DLLS = ("glfw3.dll", "msvcr120.dll")
# Where this machine's packages put the headers (libglfw3-dev, libglm-dev).
SYSTEM_HEADERS = {"GLFW": Path("/usr/include/GLFW"), "glm": Path("/usr/include/glm")}

# The Debian packages the cross-check needs beyond the test layer's.
PACKAGES = ("g++-mingw-w64-x86-64-posix", "binutils-mingw-w64-x86-64", "wine", "wine64",
            "xvfb", "xauth", "libglfw3-dev", "libglm-dev")


class CrossBuildError(Exception):
    pass


def say(message: str):
    print(f"course: {message}", file=sys.stderr, flush=True)


def sha256(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def fetch_glfw_wheel(folder: Path) -> Path:
    """The pinned wheel, by pip (its index and proxy settings), checked by SHA-256."""
    wheel = folder / GLFW_WHEEL_FILE
    if wheel.exists() and sha256(wheel) == GLFW_WHEEL_SHA256:
        return wheel
    result = subprocess.run(
        [sys.executable, "-m", "pip", "download", "--quiet", "--disable-pip-version-check",
         "--no-deps", "--only-binary=:all:", "--platform", "win_amd64", "--dest",
         str(folder), GLFW_WHEEL], stdout=sys.stderr)
    if result.returncode != 0 or not wheel.exists():
        raise CrossBuildError(f"pip could not download {GLFW_WHEEL} for win_amd64 (its "
                              "message is above)")
    if sha256(wheel) != GLFW_WHEEL_SHA256:
        wheel.unlink()
        raise CrossBuildError(f"{GLFW_WHEEL_FILE} does not have the SHA-256 the course "
                              f"pins ({GLFW_WHEEL_SHA256}): refused")
    return wheel


def dll_exports(dll: Path) -> list[str]:
    """The names a DLL exports, from objdump's export table."""
    listing = subprocess.run([f"{MINGW}-objdump", "-p", str(dll)], capture_output=True,
                             text=True, check=True).stdout
    table = listing.split("[Ordinal/Name Pointer] Table", 1)
    if len(table) < 2:
        raise CrossBuildError(f"{dll.name} has no export table")
    return re.findall(r"^\s*\[\s*\d+\]\s+(\w+)\s*$", table[1], flags=re.MULTILINE)


def import_library(dll: Path, library: Path):
    """An import library for `dll`, as Visual Studio's .lib or MinGW's lib*.dll.a is:
    the linker takes the DLL's functions from it, the program loads the DLL."""
    exports = dll_exports(dll)
    definitions = library.with_suffix(".def")
    definitions.write_text(f"LIBRARY {dll.name}\nEXPORTS\n" +
                           "".join(f"  {name}\n" for name in exports))
    subprocess.run([f"{MINGW}-dlltool", "--input-def", str(definitions), "--dllname",
                    dll.name, "--output-lib", str(library)], check=True)


GLFW_PACKAGE = """\
# GLFW {version} for Windows, staged by tools/course_tools/windows/cross_build.py
# (the DLL from the pinned glfw wheel; on Windows, vcpkg's glfw3 package provides this).
get_filename_component(_glfw_prefix "${{CMAKE_CURRENT_LIST_DIR}}/../../.." ABSOLUTE)
if(NOT TARGET glfw)
  add_library(glfw SHARED IMPORTED)
  set_target_properties(glfw PROPERTIES
    IMPORTED_LOCATION "${{_glfw_prefix}}/bin/glfw3.dll"
    IMPORTED_IMPLIB "${{_glfw_prefix}}/lib/libglfw3dll.a"
    INTERFACE_INCLUDE_DIRECTORIES "${{_glfw_prefix}}/include")
endif()
set(glfw3_FOUND TRUE)
"""

VERSION_FILE = """\
set(PACKAGE_VERSION "{version}")
if(PACKAGE_FIND_VERSION VERSION_GREATER PACKAGE_VERSION)
  set(PACKAGE_VERSION_COMPATIBLE FALSE)
else()
  set(PACKAGE_VERSION_COMPATIBLE TRUE)
endif()
"""

GLM_PACKAGE = """\
# GLM's headers, staged by tools/course_tools/windows/cross_build.py (vcpkg's glm on
# Windows).
get_filename_component(_glm_prefix "${CMAKE_CURRENT_LIST_DIR}/../../.." ABSOLUTE)
if(NOT TARGET glm::glm)
  add_library(glm::glm INTERFACE IMPORTED)
  set_target_properties(glm::glm PROPERTIES
    INTERFACE_INCLUDE_DIRECTORIES "${_glm_prefix}/include")
endif()
set(glm_FOUND TRUE)
"""


def stage_prefix(prefix: Path = PREFIX) -> Path:
    """build/windows/prefix: GLFW's DLL, import library and headers, GLM's headers, and
    a CMake package for each. Made again only when the pinned wheel changes."""
    stamp = prefix / ".staged"
    if stamp.exists() and stamp.read_text() == GLFW_WHEEL_SHA256:
        return prefix
    for name, folder in SYSTEM_HEADERS.items():
        if not folder.is_dir():
            raise CrossBuildError(f"{folder} is missing: the cross-build takes {name}'s "
                                  "headers from libglfw3-dev and libglm-dev")
    shutil.rmtree(prefix, ignore_errors=True)
    for part in ("bin", "lib/cmake/glfw3", "lib/cmake/glm", "include"):
        (prefix / part).mkdir(parents=True, exist_ok=True)
    downloads = WINDOWS / "downloads"
    downloads.mkdir(parents=True, exist_ok=True)
    wheel = fetch_glfw_wheel(downloads)
    with zipfile.ZipFile(wheel) as archive:
        for dll in RUNTIME_DLLS:
            (prefix / "bin" / dll).write_bytes(archive.read(f"glfw/{dll}"))
    import_library(prefix / "bin" / "glfw3.dll", prefix / "lib" / "libglfw3dll.a")
    for name, folder in SYSTEM_HEADERS.items():
        shutil.copytree(folder, prefix / "include" / name)
    version = "3.4.0"
    (prefix / "lib/cmake/glfw3/glfw3Config.cmake").write_text(
        GLFW_PACKAGE.format(version=version))
    (prefix / "lib/cmake/glfw3/glfw3ConfigVersion.cmake").write_text(
        VERSION_FILE.format(version=version))
    (prefix / "lib/cmake/glm/glmConfig.cmake").write_text(GLM_PACKAGE)
    (prefix / "lib/cmake/glm/glmConfigVersion.cmake").write_text(
        VERSION_FILE.format(version="0.9.9"))
    stamp.write_text(GLFW_WHEEL_SHA256)
    return prefix


def missing_tools() -> list[str]:
    return [tool for tool in (f"{MINGW}-g++-posix", f"{MINGW}-dlltool",
                              f"{MINGW}-objdump", "wine", "Xvfb")
            if shutil.which(tool) is None]


def build(targets: list[str] | None = None) -> Path:
    """Configures (once) and builds build/windows/tree; returns its bin folder, with the
    DLLs the programs load copied beside them."""
    prefix = stage_prefix()
    environment = dict(os.environ, COURSE_WINDOWS_PREFIX=str(prefix))
    if not (TREE / "build.ninja").exists():
        # The preset a maintainer would use by hand (CMakePresets.json): the check
        # proves it, with the Python this command runs in.
        say(f"configuring the Windows cross-build in build/windows/tree (cmake --preset {PRESET})")
        subprocess.run(["cmake", "--preset", PRESET, f"-DPython3_EXECUTABLE={sys.executable}"],
                       cwd=ROOT, env=environment, stdout=sys.stderr, check=True)
    say("building the chapters for Windows" + (f": {' '.join(targets)}" if targets else ""))
    subprocess.run(["cmake", "--build", str(TREE), *(["--target", *targets] if targets
                                                      else [])],
                   env=environment, stdout=sys.stderr, check=True)
    BIN.mkdir(parents=True, exist_ok=True)
    for dll in RUNTIME_DLLS:
        shutil.copy2(prefix / "bin" / dll, BIN / dll)
    return BIN
