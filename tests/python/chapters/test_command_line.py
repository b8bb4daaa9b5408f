"""The command line every chapter shares: bad usage is exit code 2 with a message and
writes nothing; a GL that is too old is exit code 4 with the way out."""

import re

import pytest

from conftest import BIN, ROOT, run_chapter

IMAGE_CHAPTERS = sorted(p.name[:2] for p in BIN.iterdir() if p.name[:2].isdigit()
                        and p.name[:2] != "01")
ALL_CHAPTERS = sorted(p.name[:2] for p in BIN.iterdir() if p.name[:2].isdigit())
# Appendices (A2: GL 3.3) share the command line, but not the 4.3 floor.
APPENDICES = sorted(p.name[:2] for p in BIN.iterdir() if re.fullmatch(r"A\d", p.name[:2]))

BAD_USAGE = [
    (["--width", "0"], "--width must be between 1 and 16384"),
    (["--width", "-5"], "--width must be between"),
    (["--width", "100000"], "--width must be between"),
    (["--height", "abc"], "--height expects a whole number"),
    (["--width", "16384", "--height", "16384"], "larger than"),
    (["--spp", "0"], "--spp must be between"),
    (["--bogus"], "unknown option '--bogus'"),
    (["--out"], "--out needs a value"),
    (["--out", "picture.jpg"], "must end in .png, .pfm or .exr"),
    (["--out", "/nonexistent/folder/x.png"], "does not exist"),
    (["--backend", "vulkan"], "--backend must be egl, osmesa or glfw"),
    (["--shader-dir", "/nonexistent"], "shader folder not found"),
]


@pytest.mark.parametrize("chapter", IMAGE_CHAPTERS + APPENDICES)
@pytest.mark.parametrize("args,message", BAD_USAGE, ids=[" ".join(a) for a, _ in BAD_USAGE])
def test_bad_usage_is_exit_2(tmp_path, chapter, args, message):
    result = run_chapter(chapter, "--headless", *args)
    assert result.returncode == 2, result.stderr
    assert message in result.stderr
    assert list(tmp_path.iterdir()) == []  # nothing written


@pytest.mark.parametrize("chapter", ALL_CHAPTERS + APPENDICES)
def test_help_lists_the_shared_options(chapter):
    result = run_chapter(chapter, "--help")
    assert result.returncode == 0
    for option in ["--headless", "--backend", "--json", "--seed"]:
        assert option in result.stdout


@pytest.mark.parametrize("chapter", ALL_CHAPTERS)
@pytest.mark.parametrize("backend", ["egl", "osmesa"])
def test_too_old_gl_is_exit_4_with_the_way_out(tmp_path, chapter, backend):
    result = run_chapter(chapter, "--headless", "--backend", backend,
                         env={"MESA_GL_VERSION_OVERRIDE": "3.3"})
    assert result.returncode == 4, result.stderr
    assert "needs OpenGL 4.3" in result.stderr
    assert "offers OpenGL 3.3" in result.stderr
    assert "appendix" in result.stderr
    assert list(tmp_path.iterdir()) == []


def test_window_without_display_is_exit_4(tmp_path):
    result = run_chapter("02", "--window", "--frames", "1", env={"DISPLAY": ""})
    assert result.returncode == 4
    assert "display" in result.stderr


def test_existing_output_survives_a_failed_run(tmp_path):
    out = tmp_path / "keep.png"
    out.write_bytes(b"precious")
    result = run_chapter("02", "--headless", "--out", out, "--shader-dir", tmp_path)
    assert result.returncode == 4  # the folder has no shaders
    assert out.read_bytes() == b"precious"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["keep.png"]
