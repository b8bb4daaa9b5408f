"""The Windows side of the course that can be checked without Windows: the cross-build's
staging (tools/course_tools/windows), the presets and vcpkg's manifest, the front doors,
and grading's refusal where a submission cannot be isolated. ./course windows-check
builds every chapter for Windows and runs the checks marked `windows` under Wine."""

from __future__ import annotations

import json
import re
import subprocess
from pathlib import Path

import pytest

from course_tools.cli import commands
from course_tools.windows import cross_build

ROOT = Path(__file__).resolve().parents[3]
CHAPTER_CHECKS = ROOT / "tests" / "python" / "chapters"


def test_every_chapter_has_an_image_check_run_on_windows():
    for folder in sorted((ROOT / "chapters").iterdir()):
        checks = CHAPTER_CHECKS / f"test_{folder.name}.py"
        assert checks.exists(), folder.name
        assert "@pytest.mark.windows" in checks.read_text(), \
            f"{checks.name}: no check marked windows, so ./course windows-check skips it"


OBJDUMP = """
There is an export table in .rdata at 0x1800360d0

Export Address Table -- Ordinal Base 1
\t[   0] +base[   1] 12f0 Export RVA

[Ordinal/Name Pointer] Table
\t[   0] glfwCreateWindow
\t[   1] glfwGetProcAddress
\t[   2] glfwTerminate

The Function Table (interpreted .pdata section contents)
"""


def test_the_import_library_lists_every_export(tmp_path, monkeypatch):
    ran = []

    def fake_run(command, **options):
        ran.append(command)
        return subprocess.CompletedProcess(command, 0, stdout=OBJDUMP)
    monkeypatch.setattr(cross_build.subprocess, "run", fake_run)
    assert cross_build.dll_exports(Path("glfw3.dll")) == [
        "glfwCreateWindow", "glfwGetProcAddress", "glfwTerminate"]
    cross_build.import_library(tmp_path / "glfw3.dll", tmp_path / "libglfw3dll.a")
    definitions = (tmp_path / "libglfw3dll.def").read_text().split()
    assert definitions[:3] == ["LIBRARY", "glfw3.dll", "EXPORTS"]
    assert "glfwTerminate" in definitions
    assert ran[-1][0].endswith("dlltool") and "--dllname" in ran[-1]


def test_a_dll_without_exports_is_refused(monkeypatch):
    monkeypatch.setattr(cross_build.subprocess, "run", lambda command, **options:
                        subprocess.CompletedProcess(command, 0, stdout="no table here"))
    with pytest.raises(cross_build.CrossBuildError):
        cross_build.dll_exports(Path("empty.dll"))


def test_the_glfw_wheel_is_pinned_by_hash(tmp_path, monkeypatch):
    """A wheel that is not the pinned one is deleted and refused, never staged."""
    wheel = tmp_path / cross_build.GLFW_WHEEL_FILE

    def fake_pip(command, **options):
        wheel.write_bytes(b"not the pinned wheel")
        return subprocess.CompletedProcess(command, 0)
    monkeypatch.setattr(cross_build.subprocess, "run", fake_pip)
    with pytest.raises(cross_build.CrossBuildError, match="SHA-256"):
        cross_build.fetch_glfw_wheel(tmp_path)
    assert not wheel.exists()


def test_the_staged_packages_name_what_common_finds():
    """The CMake packages the cross-build stages give the targets common/CMakeLists.txt
    links, as vcpkg's glfw3 and glm packages do."""
    common = (ROOT / "common" / "CMakeLists.txt").read_text()
    assert "find_package(glfw3 3.3 REQUIRED)" in common and "glfw" in common
    assert "find_package(glm REQUIRED)" in common and "glm::glm" in common
    assert "add_library(glfw SHARED IMPORTED)" in cross_build.GLFW_PACKAGE
    assert "glm::glm INTERFACE IMPORTED" in cross_build.GLM_PACKAGE
    manifest = json.loads((ROOT / "vcpkg.json").read_text())
    assert set(manifest["dependencies"]) == {"glfw3", "glm"}
    assert manifest["features"]["openexr"]["dependencies"] == ["openexr"]


def test_the_presets_point_at_files_that_exist():
    presets = json.loads((ROOT / "CMakePresets.json").read_text())
    names = {preset["name"] for preset in presets["configurePresets"]}
    assert {"windows-msvc", "windows-mingw", cross_build.PRESET} <= names
    cross = next(p for p in presets["configurePresets"] if p["name"] == cross_build.PRESET)
    toolchain = cross["toolchainFile"].replace("${sourceDir}", str(ROOT))
    assert Path(toolchain).exists()
    assert cross["binaryDir"].replace("${sourceDir}", str(ROOT)) == str(cross_build.TREE)
    for preset in presets["configurePresets"]:
        if preset["name"].startswith("windows-") and not preset.get("hidden"):
            assert preset["inherits"] == "windows-base"
    base = next(p for p in presets["configurePresets"] if p["name"] == "windows-base")
    assert base["toolchainFile"] == "$env{VCPKG_ROOT}/scripts/buildsystems/vcpkg.cmake"


def test_the_windows_front_doors_hand_over_to_the_same_python():
    batch = (ROOT / "course.cmd").read_bytes()
    assert b"\r\n" in batch and b"\n" not in batch.replace(b"\r\n", b"")  # CRLF only
    assert b'tools\\course.py" %*' in batch and b"exit /b 7" in batch
    powershell = (ROOT / "course.ps1").read_text()
    assert "tools\\course.py" in powershell and "exit 7" in powershell
    attributes = (ROOT / ".gitattributes").read_text()
    assert re.search(r"^\*\.cmd text eol=crlf$", attributes, re.M)


@pytest.mark.parametrize("verb", ["grade", "check"])
def test_grading_refuses_where_it_cannot_isolate(monkeypatch, capsys, verb):
    monkeypatch.setattr(commands.os, "name", "nt")
    with pytest.raises(SystemExit) as stop:
        commands.refuse_grading_without_isolation(verb)
    assert stop.value.code == commands.NO_ISOLATION
    message = capsys.readouterr().err
    assert "refuses" in message and "WSL 2" in message and f"./course {verb}" in message


POSIX_ONLY = re.compile(r"#include <(unistd|dlfcn|fcntl|sys/[a-z]+)\.h>|\b(getpid|dlopen|"
                        r"access|fork|mkstemp)\(")


def test_the_posix_check_can_fail():
    assert POSIX_ONLY.search("#include <unistd.h>") and POSIX_ONLY.search("x = getpid();")
    assert POSIX_ONLY.search("#include <sys/stat.h>") and not POSIX_ONLY.search("processId()")


def test_no_posix_only_call_without_a_windows_branch():
    """The calls Windows lacks appear in common/ and the chapters only beside their
    Windows branch (portable_files.cpp, render_progress.cpp) or in files Windows builds
    leave out."""
    windows_free = {"osmesa_context.cpp", "egl_context.cpp"}
    sources = [*(ROOT / "common").glob("*.cpp"), *(ROOT / "common").glob("course/*.h"),
               *(ROOT / "chapters").glob("*/*.cpp"), *(ROOT / "chapters").glob("*/*.h")]
    assert len(sources) > 100
    for source in sorted(sources):
        if source.name in windows_free:
            continue
        code = re.sub(r"//[^\n]*", "", source.read_text())  # comments may name them
        if "#ifdef _WIN32" in code:
            continue
        found = POSIX_ONLY.search(code)
        assert found is None, f"{source.name}: {found.group(0)}"
