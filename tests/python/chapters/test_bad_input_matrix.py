"""One table of bad inputs, run against every chapter program that accepts them: each
row asserts the exit code, that the message names the culprit, and that no output file
(not even a partial or temporary one) is left behind. Rows apply to a chapter when its
--help lists the option they need, so new chapters are covered automatically."""

from __future__ import annotations

import os
import re
from dataclasses import dataclass
from pathlib import Path

import pytest

from conftest import BIN, copy_shaders, loop_limit, run_chapter

# Numbered chapters and appendices (A2_gl33_fragment: "A2").
CHAPTERS = sorted(p.name[:2] for p in BIN.iterdir()
                  if p.name[:2].isdigit() or re.fullmatch(r"A\d", p.name[:2]))


def help_text(chapter: str) -> str:
    return run_chapter(chapter, "--help").stdout


HELP = {chapter: help_text(chapter) for chapter in CHAPTERS}


@dataclass
class Row:
    name: str
    needs: str            # an option the chapter's --help must list ("" for all)
    args: list            # may contain {tmp}, {file:NAME} placeholders
    code: int
    culprit: str          # a text the message must contain ({tmp} allowed)


def make_inputs(tmp: Path) -> dict[str, Path]:
    inputs = tmp / "inputs"
    inputs.mkdir()
    (inputs / "empty.obj").write_bytes(b"")
    (inputs / "binary.obj").write_bytes(bytes(range(256)) * 4)
    (inputs / "folder.obj").mkdir()
    unreadable = inputs / "unreadable.obj"
    unreadable.write_text("v 0 0 0\n")
    unreadable.chmod(0)
    return {p.name: p for p in inputs.iterdir()}


ROWS = [
    Row("huge width", "--width", ["--width", "100000"], 2, "--width"),
    Row("zero spp", "--spp", ["--spp", "0"], 2, "--spp"),
    Row("negative spp", "--spp", ["--spp", "-4"], 2, "--spp"),
    Row("out in a missing folder", "--out", ["--out", "{tmp}/missing/x.png"], 2,
        "{tmp}/missing"),
    Row("out in a read-only file system", "--out", ["--out", "/proc/x.png"], 2, "/proc/x.png"),
    Row("out is a folder", "--out", ["--out", "{tmp}"], 2, "{tmp}"),
    Row("unknown scene", "--scene", ["--scene", "no_such_scene"], 2, "no_such_scene"),
    Row("NaN camera", "--camera-eye", ["--camera-eye", "nan,0,0"], 2, "--camera-eye"),
    Row("missing OBJ", "--obj", ["--obj", "{tmp}/nope.obj"], 3, "{tmp}/nope.obj"),
    Row("empty OBJ", "--obj", ["--obj", "{file:empty.obj}"], 3, "empty.obj"),
    Row("binary OBJ", "--obj", ["--obj", "{file:binary.obj}"], 3, "binary.obj:1"),
    Row("folder as OBJ", "--obj", ["--obj", "{file:folder.obj}"], 3, "folder.obj"),
]
if os.geteuid() != 0:  # root reads anything: the row only means something for users
    ROWS.append(Row("unreadable OBJ", "--obj", ["--obj", "{file:unreadable.obj}"], 3,
                    "unreadable.obj"))

CASES = [(chapter, row) for chapter in CHAPTERS for row in ROWS
         if not row.needs or row.needs in HELP[chapter]]


@pytest.mark.parametrize("chapter,row", CASES, ids=[f"{c}-{r.name}" for c, r in CASES])
def test_bad_input(tmp_path, chapter, row):
    files = make_inputs(tmp_path)
    work = tmp_path / "work"
    work.mkdir()

    def expand(text: str) -> str:
        text = text.replace("{tmp}", str(work))
        if text.startswith("{file:"):
            text = str(files[text[6:-1]])
        return text

    result = run_chapter(chapter, "--headless", *map(expand, row.args), cwd=work)
    assert result.returncode == row.code, result.stderr
    assert expand(row.culprit) in result.stderr, result.stderr
    assert list(work.iterdir()) == [], "nothing may be written"


@pytest.mark.parametrize("chapter", [c for c in CHAPTERS if c != "01"])
def test_existing_output_is_never_truncated_by_a_failure(tmp_path, chapter):
    out = tmp_path / "keep.png"
    out.write_bytes(b"precious")
    result = run_chapter(chapter, "--headless", "--out", out, "--spp", "0")
    assert result.returncode == 2
    result = run_chapter(chapter, "--headless", "--out", out, "--shader-dir", tmp_path)
    assert result.returncode == 4
    assert out.read_bytes() == b"precious"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["keep.png"]


def insert_after_main(shaders: Path, line_text: str) -> list[str]:
    """Inserts `line_text` as the first line of main() in every compute shader of the
    chapter, or fragment shader of an appendix (whichever the program loads first must
    fail); returns "file:line" of each."""
    places = []
    for shader in sorted([*shaders.glob("*.comp"), *shaders.glob("*.frag")]):
        lines = shader.read_text().splitlines()
        mains = [i for i, line in enumerate(lines) if "void main()" in line]
        if not mains:
            continue
        lines.insert(mains[0] + 1, line_text)
        shader.write_text("\n".join(lines) + "\n")
        places.append(f"shaders/{shaders.name}/{shader.name}:{mains[0] + 2}:")
    return places


def small_run_args(chapter: str, work: Path) -> list:
    if chapter == "01":
        return ["--count", "10"]
    return ["--width", "32", "--height", "24", "--out", work / "x.png"]


@pytest.mark.parametrize("chapter", CHAPTERS)
def test_shader_compile_error_names_file_and_line(tmp_path, chapter):
    shaders = copy_shaders(chapter, tmp_path)
    places = insert_after_main(shaders, "    this is not glsl;")
    work = tmp_path / "work"
    work.mkdir()
    result = run_chapter(chapter, "--headless", "--shader-dir", shaders,
                         *small_run_args(chapter, work), cwd=work)
    assert result.returncode == 4, result.stderr
    assert any(place in result.stderr for place in places), (places, result.stderr)
    assert list(work.iterdir()) == []


@pytest.mark.parametrize("chapter", CHAPTERS)
def test_a_shader_that_loops_forever_ends_in_time(tmp_path, chapter):
    """Where the GL ends long loops itself (as the chapter measures: Mesa 22's llvmpipe,
    after 65535 iterations), the endless loop is cut off and the run ends with a wrong
    result but no error (exit code 0, or 1 where the chapter checks its sums). Where it
    does not (Mesa 25's llvmpipe, a GPU), the course's own watchdog ends the program:
    COURSE_GPU_TIMEOUT_SECONDS, set here to 15 s (the honest run takes well under one),
    then exit code 4. Either way the run must end without a half-written file."""
    limit = loop_limit(chapter)
    shaders = copy_shaders(chapter, tmp_path)
    assert insert_after_main(shaders, "    while (true) {}")
    work = tmp_path / "work"
    work.mkdir()
    result = run_chapter(chapter, "--headless", "--shader-dir", shaders,
                         *small_run_args(chapter, work), cwd=work,
                         env={"COURSE_GPU_TIMEOUT_SECONDS": "15"}, timeout=300)
    if limit is None:
        # No loop limit: the watchdog ends the program (exit 4, saying so), unless the
        # shader compiler removed the empty loop first, as Mesa 25's does (measured on
        # Debian 13: the dispatch returns at once and the results are simply wrong).
        assert result.returncode in (0, 1, 4), result.stderr
        if result.returncode == 4:
            assert "finished no step of the render for 15 s" in result.stderr
    else:
        assert result.returncode in (0, 1), result.stderr
    leftovers = [p.name for p in work.iterdir() if ".tmp" in p.name]
    assert leftovers == []


def test_a_first_compile_is_not_taken_for_an_endless_step(tmp_path):
    """Mesa's llvmpipe compiles a compute shader on the CPU at its first dispatch:
    chapter 25's path tracer takes ~10 s without Mesa's shader cache (Intel Xeon, Mesa
    22), and took over 30 s on a busy Debian 13 machine, where the watchdog took it for
    an endless step and ended correct renders. ShaderProgram compiles before the first
    step, under a compile's own allowance (ten steps). With steps of 0.1 s and no shader
    cache, a GL that compiles at first use must be stopped in the compile, by name; one
    that compiled at link renders. Never is the compile counted as a step."""
    out = tmp_path / "cloud.pfm"
    result = run_chapter("25", "--headless", "--width", 8, "--height", 8, "--spp", 1,
                         "--out", out, env={"COURSE_GPU_TIMEOUT_SECONDS": "0.1",
                                            "MESA_SHADER_CACHE_DISABLE": "true"})
    assert "finished no step" not in result.stderr
    if result.returncode == 0:
        assert out.exists()
    else:
        assert result.returncode == 4, result.stderr
        assert "compiling shaders/25_grid_media/" in result.stderr, result.stderr
        assert not out.exists()
