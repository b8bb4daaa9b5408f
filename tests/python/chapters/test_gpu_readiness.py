"""What a real GPU's driver may do that llvmpipe does not, checked here on llvmpipe.

- Limits: a driver may give a compute shader as few storage blocks as OpenGL 4.3
  guarantees (8). Each chapter asks the GL (common/gpu_limits.cpp); the limits are
  lowered for the test with COURSE_GL_LIMIT_<NAME>, as a smaller GL would give them.
  A chapter that needs more says which limit, what it needs and what it has (exit code
  4); the number it gives is its real need: with the limit at that number it runs.
- The GPU: --gpu N (or COURSE_GPU=N) renders on EGL device N and no other.
- Bits: integer fields of the scene must not travel through float texels (a driver may
  flush a denormal or rewrite a NaN); the buffer textures are RGBA32UI, and the unit
  test test_gpu_limits.cpp reads NaN and denormal patterns back through one."""

from __future__ import annotations

import json
import re

import pytest
from conftest import ROOT, run_chapter

from course_tools import chapters

SMALL = ("--width", "32", "--height", "24", "--spp", "1")
GL43_STORAGE_BLOCKS = 8  # GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS' guaranteed minimum
LIMIT = "COURSE_GL_LIMIT_MAX_COMPUTE_SHADER_STORAGE_BLOCKS"
NEED = re.compile(r"its compute shader uses (\d+) storage blocks, but this GL allows (\d+) "
                  r"\(GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS, as " + LIMIT + r" sets it\)")
COMPUTE_CHAPTERS = [c for c in chapters.names(ROOT) if not c.startswith("A")]


def prefix(chapter: str) -> str:
    return chapter.split("_")[0]


@pytest.mark.parametrize("chapter", COMPUTE_CHAPTERS)
def test_a_chapter_runs_within_its_storage_blocks_or_says_what_it_needs(chapter, tmp_path):
    out = tmp_path / "image.pfm"
    image_args = () if chapter.startswith("01") else (*SMALL, "--out", out)
    lowered = run_chapter(prefix(chapter), *image_args,
                          env={LIMIT: str(GL43_STORAGE_BLOCKS)})
    if lowered.returncode == 0:
        return  # fits in what every OpenGL 4.3 gives
    assert lowered.returncode == 4, lowered.stderr
    assert not out.exists(), "a refused run must not leave an image behind"
    said = NEED.search(lowered.stderr)
    assert said, lowered.stderr
    need, allowed = int(said[1]), int(said[2])
    assert allowed == GL43_STORAGE_BLOCKS and need > allowed
    assert "newer driver" in lowered.stderr and "OpenGL 3.3 appendix" in lowered.stderr
    # The need it names is its real need: given exactly that many, it runs.
    exact = run_chapter(prefix(chapter), *image_args, env={LIMIT: str(need)})
    assert exact.returncode == 0, exact.stderr


def test_the_storage_blocks_of_the_appendix_fragment_shader_are_counted(tmp_path):
    # OpenGL 4.3 guarantees a fragment shader no storage block at all.
    result = run_chapter("A1", *SMALL, "--out", tmp_path / "x.png",
                         env={"COURSE_GL_LIMIT_MAX_FRAGMENT_SHADER_STORAGE_BLOCKS": "0"})
    assert result.returncode == 4, result.stderr
    assert "its fragment shader uses 7 storage blocks, but this GL allows 0" in result.stderr


@pytest.mark.parametrize("limit, said", [
    ("MAX_COMPUTE_TEXTURE_IMAGE_UNITS=4",
     "its compute shader reads 6 textures (texture units), but this GL allows 4"),
    ("MAX_COMPUTE_WORK_GROUP_COUNT=1", "work groups along x, but this GL allows 1"),
    ("MAX_SHADER_STORAGE_BUFFER_BINDINGS=4", "but this GL allows 4"),
    ("MAX_COMPUTE_WORK_GROUP_INVOCATIONS=8", "invocations, but this GL allows 8"),
])
def test_each_limit_a_chapter_relies_on_is_asked(tmp_path, limit, said):
    name, value = limit.split("=")
    # Chapter 20 reads its default scene through six buffer textures.
    result = run_chapter("20", *SMALL, "--out", tmp_path / "x.png",
                         env={"COURSE_GL_LIMIT_" + name: value})
    assert result.returncode == 4, result.stderr
    assert said in result.stderr and "GL_" + name in result.stderr, result.stderr


def test_a_limit_override_only_lowers(tmp_path):
    result = run_chapter("18", *SMALL, "--out", tmp_path / "x.png", "--json",
                         env={LIMIT: "100000"})
    assert result.returncode == 0, result.stderr
    assert json.loads(result.stdout)["max_compute_storage_blocks"] < 100000
    bad = run_chapter("18", *SMALL, "--out", tmp_path / "x.png", env={LIMIT: "eight"})
    assert bad.returncode == 2 and LIMIT in bad.stderr, bad.stderr


# --- --gpu ---

def egl_devices() -> list[str]:
    listed = run_chapter("02", "--gpu", "15", "--out", "never.png")
    assert listed.returncode == 2, listed.stderr
    return re.findall(r"egl device (\d+) \(", listed.stderr)


def test_gpu_names_the_devices_there_are_when_asked_for_one_that_is_not():
    result = run_chapter("02", "--gpu", "15", "--out", "never.png")
    assert result.returncode == 2, result.stderr
    assert "--gpu 15: there is no EGL device 15" in result.stderr


def test_gpu_renders_on_the_device_it_names_and_says_so(tmp_path):
    devices = egl_devices()
    assert devices, "Mesa lists its software renderer as an EGL device"
    result = run_chapter("02", "--gpu", devices[0], "--out", tmp_path / "x.png", "--json",
                         "--verbose")
    assert result.returncode == 0, result.stderr
    stats = json.loads(result.stdout)
    assert stats["backend"].startswith(f"egl device {devices[0]} ("), stats
    assert f"found egl device {devices[0]}" in result.stderr
    chosen = run_chapter("02", "--out", tmp_path / "y.png", "--json",
                         env={"COURSE_GPU": devices[0]})
    assert json.loads(chosen.stdout)["backend"] == stats["backend"]


@pytest.mark.parametrize("args, env, said", [
    (("--gpu", "0", "--backend", "osmesa"), {}, "not with --backend osmesa"),
    (("--gpu", "16"), {}, "--gpu must be between 0 and 15"),
    ((), {"COURSE_GPU": "first"}, "COURSE_GPU expects a whole number"),
])
def test_gpu_refuses_what_cannot_be_honoured(tmp_path, args, env, said):
    result = run_chapter("02", *args, "--out", tmp_path / "x.png", env=env)
    assert result.returncode == 2, result.stderr
    assert said in result.stderr


def test_course_gpu_leaves_other_backends_alone(tmp_path):
    result = run_chapter("02", "--backend", "osmesa", "--out", tmp_path / "x.png", "--json",
                         env={"COURSE_GPU": "0"})
    assert result.returncode == 0, result.stderr
    assert json.loads(result.stdout)["backend"] == "osmesa"


# --- bits ---

FLOAT_VIEW = re.compile(r"\bsamplerBuffer\b")
BITS_FROM_FLOATS = re.compile(r"floatBitsTo(?:Uint|Int)\s*\(\s*(?:texelFetch|texel)\b")


@pytest.mark.parametrize("chapter", chapters.names(ROOT))
def test_no_integer_travels_through_a_float_texel(chapter):
    """Float buffer textures are left to the GL 3.3 appendix, whose scene is floats."""
    for path in sorted((ROOT / "shaders" / chapter).iterdir()):
        text = path.read_text()
        assert not BITS_FROM_FLOATS.search(text), f"{path.name} reads bits from a float texel"
        if FLOAT_VIEW.search(text) and not chapter.startswith("A2"):
            raise AssertionError(f"shaders/{chapter}/{path.name}: a float buffer texture "
                                 "(usamplerBuffer reads bits as bits)")
