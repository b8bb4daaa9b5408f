"""Set-up in layers (tools/course_tools/setup/machine_setup.py, tools/platforms.ini): every layer's pinned
Python packages resolve on every supported Python, every platform row is complete, and
each thing that can go wrong on a learner's machine gets its message and exit code."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import ROOT

from course_tools.setup import machine_setup
from course_tools.setup import platforms

# Ubuntu 22.04 and Gradescope (3.10), Debian 12 (3.11.2), Ubuntu 24.04 (3.12), Debian 13.
SUPPORTED_PYTHONS = ["3.10", "3.11.2", "3.12", "3.13"]
LAYER_FILES = sorted((ROOT / "requirements").glob("*.txt"))


def test_every_layer_has_a_requirements_file():
    assert sorted(p.stem for p in LAYER_FILES) == sorted(platforms.LAYERS)


@pytest.mark.parametrize("python", SUPPORTED_PYTHONS)
def test_every_layer_resolves_as_wheels_for_each_supported_python(python, tmp_path):
    """pip resolves each layer's file for that interpreter without building anything:
    what a learner's pip would install (it asks the package index: this needs the
    network). The four files are resolved at once."""
    runs = {}
    for requirements in LAYER_FILES:
        report = tmp_path / f"{requirements.stem}.json"
        runs[requirements] = (report, subprocess.Popen(
            [sys.executable, "-m", "pip", "install", "--dry-run", "--quiet",
             "--ignore-installed", "--disable-pip-version-check",
             "--target", str(tmp_path / requirements.stem), "--python-version", python,
             "--only-binary=:all:", "--report", str(report), "-r", str(requirements)],
            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True))
    for requirements, (report, process) in runs.items():
        _, errors = process.communicate(timeout=600)
        assert process.returncode == 0, f"{requirements.name} on {python}: {errors[-2000:]}"
        installed = {item["metadata"]["name"].lower() for item in
                     json.loads(report.read_text())["install"]}
        assert pinned(requirements) <= installed, requirements.name


def pinned(requirements: Path) -> set[str]:
    """The names a requirements file pins, with the files it includes."""
    names = set()
    for line in requirements.read_text().splitlines():
        line = line.split("#")[0].strip()
        if line.startswith("-r "):
            names |= pinned(requirements.parent / line[3:].strip())
        elif "==" in line:
            names.add(line.split("==")[0].strip().lower())
    return names


def test_every_pin_is_exact():
    for requirements in LAYER_FILES:
        for line in requirements.read_text().splitlines():
            line = line.split("#")[0].strip()
            if line and not line.startswith("-r "):
                assert "==" in line, f"{requirements.name}: '{line}' is not pinned"


def test_running_a_chapter_needs_no_test_tools():
    """A learner who only runs chapters never downloads Mitsuba, a browser or pytest."""
    run = pinned(ROOT / "requirements" / "run.txt")
    for heavy in ("mitsuba", "drjit", "playwright", "pytest", "mkdocs", "pyoidn"):
        assert heavy not in run
    grade = pinned(ROOT / "requirements" / "grade.txt")
    for heavy in ("mitsuba", "drjit", "playwright", "mkdocs", "pyoidn"):
        assert heavy not in grade
    for platform in platforms.read_table().values():
        for heavy in ("chromium", "clang", "libllvm19", "xvfb", "libgtest-dev"):
            assert heavy not in platform.packages["run"], platform.key


def test_every_platform_row_is_complete():
    table = platforms.read_table()
    for key in ("debian-12", "debian-13", "ubuntu-22.04", "ubuntu-24.04", "fedora", "arch",
                "macos", "windows"):
        assert key in table
    for platform in table.values():
        assert platform.installer in ("apt", "dnf", "pacman", "brew", "winget"), platform.key
        assert platform.packages["run"], platform.key
        if platform.key != "windows":  # the suite runs on Windows through WSL 2
            assert platform.packages["test"], platform.key
        assert platform.browser, platform.key


def test_windows_is_recognised_and_told_what_to_install(monkeypatch):
    """Windows installs nothing for you: winget's lines and vcpkg's clone are printed."""
    windows = platforms.detect({}, system="Windows")
    assert windows.key == "windows" and windows.installer == "winget"
    steps = windows.install_command(["cmake", "vcpkg"])
    assert steps[0] == "winget install --id Kitware.CMake --exact"
    assert any("bootstrap-vcpkg.bat" in step for step in steps)
    assert any("VCPKG_ROOT" in step for step in steps)
    monkeypatch.setattr(machine_setup, "is_root", lambda: True)
    monkeypatch.setattr(windows, "has", lambda package: package != "vcpkg")
    with pytest.raises(machine_setup.SetupError) as error:
        machine_setup.ensure_packages(windows, "run")
    assert error.value.code == machine_setup.MISSING_PACKAGES
    assert "bootstrap-vcpkg.bat" in str(error.value) and "sudo" not in str(error.value)


@pytest.mark.parametrize("release, expected", [
    ({"ID": "debian", "VERSION_ID": "12"}, "debian-12"),
    ({"ID": "debian", "VERSION_ID": "13"}, "debian-13"),
    ({"ID": "ubuntu", "VERSION_ID": "22.04"}, "ubuntu-22.04"),
    ({"ID": "ubuntu", "VERSION_ID": "24.04"}, "ubuntu-24.04"),
    ({"ID": "fedora", "VERSION_ID": "41"}, "fedora"),
    ({"ID": "arch"}, "arch"),
    ({"ID": "debian", "VERSION_ID": "11"}, None),
    ({"ID": "gentoo", "VERSION_ID": "2.15"}, None),
])
def test_platforms_are_recognised_from_os_release(release, expected):
    found = platforms.detect(release, system="Linux")
    assert (found.key if found else None) == expected


def test_macos_is_recognised():
    assert platforms.detect({}, system="Darwin").key == "macos"


def test_the_fuzzing_runtime_matches_each_debians_clang():
    """Debian ships libFuzzer's runtime apart from clang: 14 in bookworm, 19 in trixie."""
    table = platforms.read_table()
    assert "libclang-rt-14-dev" in table["debian-12"].packages["test"]
    assert "libclang-rt-19-dev" in table["debian-13"].packages["test"]
    for key in ("debian-12", "debian-13", "ubuntu-22.04", "ubuntu-24.04"):
        # FindOpenGL's EGL target needs libOpenGL (glvnd), which Debian 13 no longer
        # pulls in with libegl-dev.
        assert "libopengl-dev" in table[key].packages["run"], key


def test_ubuntus_snap_chromium_is_not_used():
    table = platforms.read_table()
    for key in ("ubuntu-22.04", "ubuntu-24.04"):
        assert table[key].browser == "playwright"
        assert "chromium" not in table[key].packages["test"]


def course(*args, env=None, cwd=ROOT):
    return subprocess.run([str(ROOT / "course"), *args], capture_output=True, text=True,
                          env=env, cwd=cwd, timeout=120)


def test_an_unknown_platform_is_named_with_what_to_install(tmp_path):
    release = tmp_path / "os-release"
    release.write_text('ID=gentoo\nVERSION_ID="2.15"\n')
    result = course("setup", env=dict(os.environ, COURSE_OS_RELEASE=str(release),
                                      COURSE_LAYER_READY=""))
    assert result.returncode == machine_setup.UNKNOWN_PLATFORM, result.stderr
    assert "gentoo 2.15" in result.stderr and "GLFW" in result.stderr
    assert "Traceback" not in result.stderr


def test_packages_prints_the_layers_packages_for_a_named_platform():
    result = course("packages", "test", env=dict(os.environ, COURSE_PLATFORM="debian-13"))
    assert result.returncode == 0, result.stderr
    assert "libclang-rt-19-dev" in result.stdout.split()
    assert "libglfw3-dev" in result.stdout.split()


def test_a_python_older_than_3_10_is_refused(tmp_path):
    fake = tmp_path / "python3"
    fake.write_text("#!/bin/sh\n[ \"$1\" = -V ] && echo 'Python 3.9.2' && exit 0\nexit 1\n")
    fake.chmod(0o755)
    result = course("run", env=dict(os.environ, PATH=f"{tmp_path}:/usr/bin:/bin"))
    assert result.returncode == machine_setup.PYTHON_TOO_OLD, result.stderr
    assert "3.10 or newer" in result.stderr and "3.9.2" in result.stderr


def test_no_python_at_all_is_named(tmp_path):
    (tmp_path / "bash").symlink_to("/bin/bash")
    (tmp_path / "dirname").symlink_to("/usr/bin/dirname")
    result = subprocess.run(["/bin/bash", str(ROOT / "course"), "run"], capture_output=True,
                            text=True, env={"PATH": str(tmp_path)})
    assert result.returncode == machine_setup.PYTHON_TOO_OLD
    assert "no python3" in result.stderr


def fake_platform(installer="apt") -> platforms.Platform:
    platform = platforms.read_table()["debian-12"]
    platform.installer = installer
    platform.missing = lambda layer: ["libglfw3-dev", "libstb-dev"]  # type: ignore
    return platform


def test_without_root_the_exact_install_command_is_printed(monkeypatch):
    monkeypatch.setattr(machine_setup, "is_root", lambda: False)
    monkeypatch.setattr(machine_setup.shutil, "which", lambda name: "/usr/bin/sudo")
    with pytest.raises(machine_setup.SetupError) as error:
        machine_setup.ensure_packages(fake_platform(), "run")
    assert error.value.code == machine_setup.MISSING_PACKAGES
    assert "sudo apt-get install -y --no-install-recommends libglfw3-dev libstb-dev" in \
        str(error.value)


def test_without_root_or_sudo_the_root_command_is_printed(monkeypatch):
    monkeypatch.setattr(machine_setup, "is_root", lambda: False)
    monkeypatch.setattr(machine_setup.shutil, "which", lambda name: None)
    with pytest.raises(machine_setup.SetupError) as error:
        machine_setup.ensure_packages(fake_platform(), "run")
    assert error.value.code == machine_setup.MISSING_PACKAGES
    assert "no sudo" in str(error.value) and "su -c 'apt-get update'" in str(error.value)


def test_a_missing_package_manager_is_named(monkeypatch):
    monkeypatch.setattr(machine_setup, "is_root", lambda: True)
    monkeypatch.setattr(machine_setup.shutil, "which", lambda name: None)
    with pytest.raises(machine_setup.SetupError) as error:
        machine_setup.ensure_packages(fake_platform("dnf"), "run")
    assert error.value.code == machine_setup.NO_PACKAGE_MANAGER
    assert "dnf" in str(error.value)


def test_pip_without_a_package_index_is_a_clear_failure(tmp_path, monkeypatch):
    """No network for pip: exit 8 naming the requirements file, not a traceback."""
    requirements = tmp_path / "requirements"
    requirements.mkdir()
    (requirements / "run.txt").write_text("glad2==2.0.8\n")
    monkeypatch.setattr(machine_setup, "VENV", tmp_path / "venv")
    monkeypatch.setattr(machine_setup, "REQUIREMENTS", requirements)
    monkeypatch.setenv("PIP_INDEX_URL", "http://127.0.0.1:9/simple")
    monkeypatch.setenv("PIP_RETRIES", "0")
    monkeypatch.setenv("PIP_TIMEOUT", "2")
    with pytest.raises(machine_setup.SetupError) as error:
        machine_setup.ensure_venv("run")
    assert error.value.code == machine_setup.PIP_FAILED
    assert "requirements/run.txt" in str(error.value)
    assert not (tmp_path / "venv" / ".run.sha256").exists()


def test_a_browser_download_out_of_reach_is_its_own_failure(tmp_path, monkeypatch):
    """Playwright's Chromium comes from Playwright's servers, not pip's index: when they
    cannot be reached, exit 9 says so, and nothing is marked as installed."""
    monkeypatch.setattr(machine_setup, "VENV", tmp_path / "venv")
    (tmp_path / "venv").mkdir()
    ran = []

    def refused(command, **options):
        ran.append(command)
        return machine_setup.subprocess.CompletedProcess(command, 1)
    monkeypatch.setattr(machine_setup.subprocess, "run", refused)
    with pytest.raises(machine_setup.SetupError) as error:
        machine_setup.ensure_playwright_browser()
    assert error.value.code == machine_setup.BROWSER_DOWNLOAD_FAILED
    assert "Playwright" in str(error.value) and "Chromium" in str(error.value)
    assert ran and ran[0][1:4] == ["-m", "playwright", "install"]
    assert not (tmp_path / "venv" / ".playwright-chromium").exists()


def test_exit_codes_of_set_up_are_distinct():
    codes = [machine_setup.UNKNOWN_PLATFORM, machine_setup.MISSING_PACKAGES,
             machine_setup.NO_PACKAGE_MANAGER, machine_setup.PYTHON_TOO_OLD,
             machine_setup.PIP_FAILED, machine_setup.BROWSER_DOWNLOAD_FAILED]
    assert len(set(codes)) == len(codes)
    assert not set(codes) & {0, 1, 3, 4}  # 3 and 4 are the chapter programs' own
