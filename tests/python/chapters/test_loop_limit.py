"""The loop limit, measured (common/course/loop_budget.h). Mesa 22's llvmpipe ends a
shader invocation after 65 535 loop iterations; Mesa 25's llvmpipe and a GPU's driver
do not. The chapters act on what a probe shader measures, never on the renderer's name:
the probe runs only when some work needs more than 65 535 iterations, once per GL, and
its answer is kept in a cache file that may be missing, unwritable or corrupt without
harm. Every test here passes on either kind of GL; where the answer matters, the test
reads it from the program."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from conftest import SMALLEST_KNOWN_LOOP_LIMIT, run_chapter

GL33 = {"MESA_GL_VERSION_OVERRIDE": "3.3", "MESA_GLSL_VERSION_OVERRIDE": "330"}
CACHE = Path("gpu-ray-tracing-course") / "loop-limits.tsv"
PROBED = 262144  # the iterations the probe asks for (kLoopProbeIterations)
# Mesa 22 counts a loop's iterations per vector of 8 invocations; the probe runs one
# invocation and measures exactly 65 535, but a count off by a few lanes is the same limit.
LANES = 8


def cache_env(folder: Path) -> dict:
    return {"XDG_CACHE_HOME": str(folder)}


def probe(chapter: str, env: dict) -> dict:
    result = run_chapter(chapter, "--headless", "--probe-loop-limit", "--json", env=env)
    assert result.returncode == 0, result.stderr
    return json.loads(result.stdout)


def data_lines(path: Path) -> list[list[str]]:
    return [line.split("\t") for line in path.read_text().splitlines()
            if line and not line.startswith("#")]


def big_mesh(folder: Path) -> tuple[Path, int]:
    """40 000 copies of one triangle: with the floor, 80 004 loop iterations a pixel,
    beyond Mesa 22's limit (chapter 07 tests every triangle for the camera and the shadow
    ray), and quick to draw anywhere else."""
    path = folder / "stack.obj"
    path.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\n" + "f 1 2 3\n" * 40000)
    return path, 2 * (40000 + 2)


def render_big(tmp_path: Path, env: dict):
    mesh, _ = big_mesh(tmp_path)
    out = tmp_path / "big.png"
    out.unlink(missing_ok=True)
    result = run_chapter("07", "--headless", "--width", 8, "--height", 6, "--obj", mesh,
                         "--out", out, env=env)
    return result, out


@pytest.mark.parametrize("chapter, env, stage", [
    ("07", {}, "compute"),
    ("A2", GL33, "fragment"),  # a GL 3.3 context: the fragment-shader probe
    ("A2", {}, "fragment"),    # the appendix loops in fragment shaders on any GL
])
def test_the_probe_measures_mesa_22s_limit_or_none(tmp_path, chapter, env, stage):
    stats = probe(chapter, {**env, **cache_env(tmp_path)})  # a new cache: measured now
    assert stats["loop_limit_stage"] == stage
    assert stats["loop_probe_iterations"] == PROBED
    limit = stats["loop_limit"]
    assert limit == "none" or (SMALLEST_KNOWN_LOOP_LIMIT - LANES <= limit
                               <= SMALLEST_KNOWN_LOOP_LIMIT), stats


def test_the_words_say_the_limit_and_the_gl(tmp_path):
    result = run_chapter("07", "--headless", "--probe-loop-limit", env=cache_env(tmp_path))
    assert result.returncode == 0, result.stderr
    stats = probe("07", cache_env(tmp_path))
    assert "loop limit of compute shaders: " in result.stdout
    assert stats["renderer"] in result.stdout and stats["gl_version"] in result.stdout
    if stats["loop_limit"] == "none":
        assert f"no limit up to {PROBED} loop iterations" in result.stdout
    else:
        assert f"{stats['loop_limit']} loop iterations per invocation" in result.stdout


def test_a_run_within_the_smallest_known_limit_does_not_probe(tmp_path):
    # The default teapot: 1 108 iterations a pixel. No probe, so no cache file.
    result = run_chapter("07", "--headless", "--width", 8, "--height", 6, "--out",
                         tmp_path / "x.png", env=cache_env(tmp_path))
    assert result.returncode == 0, result.stderr
    assert not (tmp_path / CACHE).exists()
    # Beyond it, the chapter probes (and refuses or renders as the answer says).
    result, _ = render_big(tmp_path, cache_env(tmp_path))
    assert result.returncode in (0, 4), result.stderr
    assert [line[3] for line in data_lines(tmp_path / CACHE)] == ["compute"]


def test_the_answer_is_remembered_per_gl_and_shader_stage(tmp_path):
    env = cache_env(tmp_path)
    compute = probe("07", env)
    fragment = probe("A2", {**env, **GL33})
    lines = data_lines(tmp_path / CACHE)
    # vendor, renderer, version, stage, limit, probed
    assert [(line[1], line[2], line[3]) for line in lines] == [
        (compute["renderer"], compute["gl_version"], "compute"),
        (fragment["renderer"], fragment["gl_version"], "fragment")]
    for line, stats in zip(lines, (compute, fragment)):
        assert line[4:] == [str(stats["loop_limit"]), str(PROBED)]
    # The next run reads the file instead of measuring, and leaves it as it was.
    before = (tmp_path / CACHE).read_text()
    result = run_chapter("07", "--headless", "--probe-loop-limit", "--verbose", env=env)
    assert result.returncode == 0, result.stderr
    assert str(tmp_path / CACHE) in result.stderr and "measured on" not in result.stderr
    assert (tmp_path / CACHE).read_text() == before


@pytest.mark.parametrize("remembered, refused", [
    ("none", False),     # as on Mesa 25's llvmpipe or a GPU
    ("100000", False),   # a limit above the mesh's 80 004 iterations
    ("70000", True),     # a limit below them
])
def test_the_chapter_acts_on_the_remembered_answer(tmp_path, remembered, refused):
    # The program trusts its cache file, so a remembered answer, whatever this GL's
    # own, takes each path of the check here; on this GL (Mesa 22's llvmpipe) a render
    # beyond its real limit is wrong, so only the exit code is checked.
    env = cache_env(tmp_path)
    probe("07", env)
    lines = data_lines(tmp_path / CACHE)
    lines[0][4] = remembered
    (tmp_path / CACHE).write_text("".join("\t".join(line) + "\n" for line in lines))
    result, out = render_big(tmp_path, env)
    if refused:
        assert result.returncode == 4, result.stderr
        assert "80004 loop iterations per pixel" in result.stderr
        assert f"after {remembered} (measured)" in result.stderr
        assert not out.exists()
    else:
        assert result.returncode == 0, result.stderr
        assert out.exists()


def test_a_corrupt_cache_is_ignored_and_rewritten(tmp_path):
    fresh = probe("07", cache_env(tmp_path / "fresh"))
    key = data_lines(tmp_path / "fresh" / CACHE)[0][:4]
    cache = tmp_path / "corrupt" / CACHE
    cache.parent.mkdir(parents=True)
    with open(cache, "wb") as file:
        file.write(b"garbage\n\x00\xff\xfe binary\n")
        file.write("\t".join(key + ["lots", str(PROBED)]).encode() + b"\n")  # no number
        file.write("\t".join(key + [str(PROBED), str(PROBED)]).encode() + b"\n")  # = probed
        file.write("\t".join(key + ["123"]).encode() + b"\n")  # a field short
        file.write("\t".join(key[:3] + ["vertex", "none", "1"]).encode())  # no such stage
    stats = probe("07", cache_env(tmp_path / "corrupt"))
    assert stats["loop_limit"] == fresh["loop_limit"]  # measured again
    assert data_lines(cache) == data_lines(tmp_path / "fresh" / CACHE)


def test_an_unusable_cache_never_fails_the_program(tmp_path):
    fresh = probe("07", cache_env(tmp_path / "fresh"))
    in_the_way = tmp_path / "file"
    in_the_way.write_text("a file where the cache folder would be\n")
    for env in (cache_env(in_the_way),                    # cannot be made
                cache_env(in_the_way / "below"),          # cannot be made either
                {"XDG_CACHE_HOME": "relative/cache", "HOME": str(in_the_way)}):  # ignored
        stats = probe("07", env)
        assert stats["loop_limit"] == fresh["loop_limit"], env
        result, out = render_big(tmp_path, env)
        assert result.returncode == (0 if fresh["loop_limit"] == "none" else 4), result.stderr
    assert in_the_way.read_text().startswith("a file")


def test_a_relative_xdg_cache_home_falls_back_to_home(tmp_path):
    # The XDG rule: a relative XDG_CACHE_HOME is ignored, and ~/.cache is used.
    probe("07", {"XDG_CACHE_HOME": "relative/cache", "HOME": str(tmp_path)})
    assert (tmp_path / ".cache" / CACHE).exists()
    # (Mesa may put its own shader cache there: only the course's file is ours.)
    assert not (tmp_path / "relative" / "cache" / CACHE).exists()
